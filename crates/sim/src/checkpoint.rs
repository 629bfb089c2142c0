//! A world's state as bytes, so a run can start from a saved instant instead of time 0
//! (docs/animate.md, "Physics checkpoints"): the step count and each body's positions,
//! velocities and plastic strains, which are everything [`Body::step`] reads that changes
//! over time. Restoring a checkpoint and stepping on gives bit-identical states to never
//! having stopped.
//!
//! Layout, little-endian: the 16-byte magic (name and version), the world's fingerprint
//! (u64), the step count (u64), the body count (u32), then per body its phyxel count (u32)
//! and `pos`, `vel` (3 f64 each) and `plastic` (9 f64) of every phyxel; last, an FNV-1a
//! checksum (u64) of everything before it. The fingerprint covers what the state is only
//! meaningful with (rest shape, masses, time step, gravity), so a checkpoint of another
//! scene or of other settings is refused rather than silently continued.
//!
//! [`Body::step`]: crate::Body::step

use crate::world::World;
use crate::SimError;
use glam::{DMat3, DVec3};

const MAGIC: &[u8; 16] = b"dynray-physics\0\x01";

/// FNV-1a over 64 bits: a checksum against truncation and a fingerprint of the setup,
/// not a cryptographic hash.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 = (self.0 ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn f64(&mut self, x: f64) {
        self.bytes(&x.to_bits().to_le_bytes());
    }
}

impl World {
    /// What a checkpoint of this world must have been written by: the bodies' rest
    /// positions and masses, the time step and gravity.
    pub fn fingerprint(&self) -> u64 {
        let mut h = Fnv::new();
        h.f64(self.dt());
        for x in self.gravity().to_array() {
            h.f64(x);
        }
        h.bytes(&(self.bodies().len() as u64).to_le_bytes());
        for b in self.bodies() {
            h.bytes(&(b.len() as u64).to_le_bytes());
            for p in &b.rest {
                p.to_array().into_iter().for_each(|x| h.f64(x));
            }
            b.mass.iter().for_each(|&m| h.f64(m));
        }
        h.0
    }

    /// The state now, as bytes ([`World::restore`] reads them back).
    pub fn checkpoint(&self) -> Vec<u8> {
        let phyxels: usize = self.bodies().iter().map(|b| b.len()).sum();
        let mut out = Vec::with_capacity(48 + self.bodies().len() * 4 + phyxels * 15 * 8);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&self.fingerprint().to_le_bytes());
        out.extend_from_slice(&self.steps().to_le_bytes());
        out.extend_from_slice(&(self.bodies().len() as u32).to_le_bytes());
        for b in self.bodies() {
            out.extend_from_slice(&(b.len() as u32).to_le_bytes());
            for v in b.pos.iter().chain(&b.vel) {
                v.to_array().into_iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
            }
            for m in &b.plastic {
                m.to_cols_array().into_iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
            }
        }
        let mut h = Fnv::new();
        h.bytes(&out);
        out.extend_from_slice(&h.0.to_le_bytes());
        out
    }

    /// Replaces the state with the checkpoint's. Nothing changes unless the whole
    /// checkpoint is intact, finite and of this world.
    pub fn restore(&mut self, bytes: &[u8]) -> Result<(), SimError> {
        let bad = |why: String| SimError::Checkpoint(why);
        if bytes.len() < MAGIC.len() + 8 || &bytes[..MAGIC.len()] != MAGIC {
            return Err(bad("not a dynray physics checkpoint (or one of another version)".into()));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        let mut h = Fnv::new();
        h.bytes(body);
        if h.0.to_le_bytes() != sum {
            return Err(bad("damaged or truncated (checksum mismatch)".into()));
        }
        let mut r = Reader { bytes: &body[MAGIC.len()..] };
        if r.u64()? != self.fingerprint() {
            return Err(bad(
                "written for another scene or other physics settings (bodies, phyxels, masses, step or gravity differ)"
                    .into(),
            ));
        }
        let steps = r.u64()?;
        let count = r.u32()? as usize;
        if count != self.bodies().len() {
            return Err(bad(format!("holds {count} bodies, the scene has {}", self.bodies().len())));
        }
        let mut states = Vec::with_capacity(count);
        for (i, b) in self.bodies().iter().enumerate() {
            let n = r.u32()? as usize;
            if n != b.len() {
                return Err(bad(format!("body {i} has {n} phyxels, the scene's has {}", b.len())));
            }
            let pos = r.vectors(n)?;
            let vel = r.vectors(n)?;
            let plastic =
                (0..n).map(|_| r.floats::<9>().map(|c| DMat3::from_cols_array(&c))).collect::<Result<_, _>>()?;
            states.push((pos, vel, plastic));
        }
        if !r.bytes.is_empty() {
            return Err(bad(format!("{} bytes past the last body", r.bytes.len())));
        }
        self.set_state(steps, states);
        Ok(())
    }
}

/// Little-endian fields read off the front of a slice; running out is an error.
struct Reader<'a> {
    bytes: &'a [u8],
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], SimError> {
        if self.bytes.len() < N {
            return Err(SimError::Checkpoint("ends before its last body".into()));
        }
        let (head, rest) = self.bytes.split_at(N);
        self.bytes = rest;
        Ok(head.try_into().expect("split at N"))
    }
    fn u32(&mut self) -> Result<u32, SimError> {
        self.take::<4>().map(u32::from_le_bytes)
    }
    fn u64(&mut self) -> Result<u64, SimError> {
        self.take::<8>().map(u64::from_le_bytes)
    }
    fn floats<const N: usize>(&mut self) -> Result<[f64; N], SimError> {
        let mut out = [0.0; N];
        for x in &mut out {
            *x = f64::from_le_bytes(self.take::<8>()?);
            if !x.is_finite() {
                return Err(SimError::Checkpoint("holds a non-finite value".into()));
            }
        }
        Ok(out)
    }
    fn vectors(&mut self, n: usize) -> Result<Vec<DVec3>, SimError> {
        // Checked against what is left before allocating: a lying count cannot ask for more.
        if self.bytes.len() / 24 < n {
            return Err(SimError::Checkpoint("ends before its last body".into()));
        }
        (0..n).map(|_| self.floats::<3>().map(DVec3::from_array)).collect()
    }
}

#[cfg(test)]
mod tests {
    use crate::World;
    use dynray_scene::parse_scn_str;

    fn world(young: &str) -> World {
        let scene = parse_scn_str(
            "test",
            &format!(
                "physics {{ ground 0 substeps 2 }} settings {{ frames 8 frame_rate 24 }}
                 box {{ center <0, 1, 0> orientation <0, 0, 0> scale <0.5, 0.5, 0.5>
                        elastic {{ young {young} phyxels 64 velocity <1, 0, 0> }} }}"
            ),
            std::path::Path::new("."),
        )
        .unwrap();
        World::from_scene(&scene).unwrap().unwrap()
    }

    fn state(w: &World) -> Vec<u64> {
        let b = &w.bodies()[0];
        b.pos.iter().chain(&b.vel).flat_map(|v| v.to_array()).map(f64::to_bits).collect()
    }

    #[test]
    fn a_restored_world_steps_on_bit_for_bit() {
        let mut straight = world("2e4");
        straight.advance_to(6.0 / 24.0).unwrap();
        let mut first = world("2e4");
        first.advance_to(3.0 / 24.0).unwrap();
        let saved = first.checkpoint();
        let mut second = world("2e4");
        second.restore(&saved).unwrap();
        assert_eq!(second.steps(), first.steps());
        second.advance_to(6.0 / 24.0).unwrap();
        assert_eq!(state(&second), state(&straight));
        assert_eq!(second.steps(), straight.steps());
    }

    #[test]
    fn damaged_foreign_and_short_checkpoints_are_refused_and_change_nothing() {
        let mut w = world("2e4");
        w.advance_to(2.0 / 24.0).unwrap();
        let saved = w.checkpoint();
        let mut fresh = world("2e4");
        let before = state(&fresh);
        let mut flipped = saved.clone();
        flipped[40] ^= 1;
        for (bytes, why) in [
            (&saved[..saved.len() - 9], "checksum"),
            (&flipped[..], "checksum"),
            (&b"not a checkpoint at all"[..], "not a dynray physics checkpoint"),
        ] {
            let e = fresh.restore(bytes).unwrap_err().to_string();
            assert!(e.contains(why), "{e}");
        }
        let e = world("3e4").restore(&saved).unwrap_err().to_string();
        assert!(e.contains("another scene"), "{e}");
        assert_eq!(state(&fresh), before);
        assert_eq!(fresh.steps(), 0);
    }
}
