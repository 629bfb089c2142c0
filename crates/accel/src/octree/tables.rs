//! The seed's constant tables (Eq. 8 `outFacesLookup`, Eq. 9 `faceToNeighborIndex`) and
//! the face / vertex / neighbour-order convention under which they are true.
//!
//! Figure 4 of the paper, which fixed the numbering, is lost; the notes (§2.7.3) rebuild
//! "convention A", the one that regenerates both tables exactly from geometry:
//! faces `0 = +y, 1 = +x, 2 = −y, 3 = −x, 4 = +z, 5 = −z`; the exit vertex of a box is
//! `v = [dx>0] | [dy>0]<<1 | [dz>0]<<2` (bit set = max side on that axis); a Plücker bit
//! is set when the side value `(P − O) × d` is negative on that axis (the IEEE sign bit,
//! so −0.0 counts as negative); and the four neighbours across a face are stored in the
//! order `j = [p_u < c_u] + 2·[p_w < c_w]` with `(u, w)` the in-face axes in x < y < z
//! order and `c` the face centre. The unit tests at the bottom re-derive every table
//! entry from slab distances, so a wrong entry or convention fails loudly.

use glam::Vec3;

/// Axis (0 = x, 1 = y, 2 = z) each face is perpendicular to.
pub const FACE_AXIS: [usize; 6] = [1, 0, 1, 0, 2, 2];

/// True for faces on the max side of their axis (+x, +y, +z).
pub const FACE_POSITIVE: [bool; 6] = [true, true, false, false, true, false];

/// `FACE_OF[axis][positive as usize]`: the face id of a side of the box.
pub const FACE_OF: [[usize; 2]; 3] = [[3, 1], [2, 0], [5, 4]];

/// Eq. (8): `OUT_FACES_LOOKUP[exit_vertex][plucker_code]` is the face a ray leaves the box
/// through; 7 marks the two codes per row that no ray can produce.
pub const OUT_FACES_LOOKUP: [[u8; 8]; 8] = [
    [7, 2, 5, 2, 3, 3, 5, 7],
    [5, 7, 1, 1, 5, 2, 7, 2],
    [3, 3, 7, 5, 0, 7, 0, 5],
    [0, 5, 0, 7, 7, 5, 1, 1],
    [2, 4, 2, 7, 7, 4, 3, 3],
    [1, 1, 7, 4, 2, 7, 2, 4],
    [4, 7, 3, 3, 4, 0, 7, 0],
    [7, 0, 4, 0, 1, 1, 4, 7],
];

/// Eq. (9): `FACE_TO_NEIGHBOR_INDEX[face][plucker_code at the face centre]` is the slot
/// (0..4) of the neighbour the ray enters when the face has four; the bit of the face's
/// own axis is ignored.
pub const FACE_TO_NEIGHBOR_INDEX: [[u8; 8]; 6] = [
    [1, 3, 1, 3, 0, 2, 0, 2],
    [2, 2, 0, 0, 3, 3, 1, 1],
    [2, 0, 2, 0, 3, 1, 3, 1],
    [1, 1, 3, 3, 0, 0, 2, 2],
    [2, 0, 3, 1, 2, 0, 3, 1],
    [1, 3, 0, 2, 1, 3, 0, 2],
];

/// Table row of a direction: the box corner every exit face of the ray touches.
#[inline(always)]
pub fn exit_vertex(d: Vec3) -> usize {
    (d.x > 0.0) as usize | ((d.y > 0.0) as usize) << 1 | ((d.z > 0.0) as usize) << 2
}

/// The three Plücker side tests of the ray `(o, d)` against the +x, +y and +z lines
/// through `p` (Eqs. 4–5, which reduce to `(p − o) × d`), packed as sign bits
/// (x = bit 0, y = bit 1, z = bit 2; Eq. 6).
#[inline(always)]
pub fn plucker_code(p: Vec3, o: Vec3, d: Vec3) -> usize {
    let s = (p - o).cross(d);
    s.x.is_sign_negative() as usize | (s.y.is_sign_negative() as usize) << 1 | (s.z.is_sign_negative() as usize) << 2
}

/// The two in-face axes of a face, in x < y < z order.
#[inline(always)]
pub fn in_face_axes(face: usize) -> (usize, usize) {
    match FACE_AXIS[face] {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// Neighbour slot of the child cell lying on the `upper_u` / `upper_w` halves of a face.
#[inline(always)]
pub fn neighbor_slot(upper_u: bool, upper_w: bool) -> usize {
    (!upper_u) as usize + 2 * (!upper_w) as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::SmallRng, Rng, SeedableRng};

    /// Slab exit distance of a ray from inside the unit-ish box through each face.
    fn face_exit_t(lo: Vec3, hi: Vec3, o: Vec3, d: Vec3, face: usize) -> f32 {
        let a = FACE_AXIS[face];
        let plane = if FACE_POSITIVE[face] { hi[a] } else { lo[a] };
        let t = (plane - o[a]) / d[a];
        if (d[a] > 0.0) == FACE_POSITIVE[face] && d[a] != 0.0 {
            t
        } else {
            f32::INFINITY
        }
    }

    fn random_case(rng: &mut SmallRng, octant: usize) -> (Vec3, Vec3, Vec3, Vec3) {
        let lo = Vec3::new(rng.gen_range(-2.0..0.0), rng.gen_range(-2.0..0.0), rng.gen_range(-2.0..0.0));
        let hi = lo + Vec3::new(rng.gen_range(0.5..3.0), rng.gen_range(0.5..3.0), rng.gen_range(0.5..3.0));
        let f = Vec3::new(rng.gen_range(0.02..0.98), rng.gen_range(0.02..0.98), rng.gen_range(0.02..0.98));
        let o = lo + (hi - lo) * f;
        let mut d = Vec3::new(rng.gen_range(0.05..1.0), rng.gen_range(0.05..1.0), rng.gen_range(0.05..1.0));
        for a in 0..3 {
            if octant >> a & 1 == 0 {
                d[a] = -d[a];
            }
        }
        (lo, hi, o, d)
    }

    /// For every exit vertex (direction octant) and every code a ray produces, the table's
    /// face is an exit face of that ray: its slab distance is the smallest of the three.
    #[test]
    fn out_faces_lookup_matches_geometry() {
        let mut rng = SmallRng::seed_from_u64(11);
        let mut seen = [[false; 8]; 8];
        for octant in 0..8 {
            for _ in 0..20_000 {
                let (lo, hi, o, d) = random_case(&mut rng, octant);
                let v = exit_vertex(d);
                assert_eq!(v, octant);
                let corner = Vec3::select(glam::BVec3::new(v & 1 != 0, v & 2 != 0, v & 4 != 0), hi, lo);
                let code = plucker_code(corner, o, d);
                let face = OUT_FACES_LOOKUP[v][code] as usize;
                assert!(face < 6, "vertex {v} code {code:03b} gave the unreachable marker for o={o} d={d}");
                let ts: Vec<f32> = (0..6).map(|f| face_exit_t(lo, hi, o, d, f)).collect();
                let best = ts.iter().cloned().fold(f32::INFINITY, f32::min);
                // Exact ties are measure-zero; allow rounding only.
                assert!(
                    ts[face] <= best * (1.0 + 1e-5),
                    "v {v} code {code:03b}: face {face} t {} > exit {best}",
                    ts[face]
                );
                seen[v][code] = true;
            }
        }
        // Every entry the table calls reachable was produced, and no other: two codes per
        // row are cyclic orderings that no ray gives (000 and 111 for the rows of the
        // octants where all direction signs agree, others elsewhere).
        for v in 0..8 {
            for code in 0..8 {
                let reachable = OUT_FACES_LOOKUP[v][code] != 7;
                assert_eq!(seen[v][code], reachable, "vertex {v} code {code:03b}");
            }
            assert_eq!(seen[v].iter().filter(|&&s| s).count(), 6, "vertex {v}");
        }
    }

    /// For every face and every code at its centre, the table's slot is the quarter of the
    /// face the ray really leaves through, under the storage order of [`neighbor_slot`].
    #[test]
    fn face_to_neighbor_index_matches_geometry() {
        let mut rng = SmallRng::seed_from_u64(12);
        let mut seen = [[false; 4]; 6];
        for _ in 0..200_000 {
            let octant = rng.gen_range(0..8);
            let (lo, hi, o, d) = random_case(&mut rng, octant);
            let ts: Vec<f32> = (0..6).map(|f| face_exit_t(lo, hi, o, d, f)).collect();
            let face = (0..6).min_by(|&a, &b| ts[a].total_cmp(&ts[b])).unwrap();
            let t = ts[face];
            let p = o + d * t;
            let c = (lo + hi) * 0.5;
            let mut centre = c;
            let a = FACE_AXIS[face];
            centre[a] = if FACE_POSITIVE[face] { hi[a] } else { lo[a] };
            let (u, w) = in_face_axes(face);
            // Skip rays within rounding of a median line: either slot is right there.
            let scale = (hi - lo).max_element();
            if (p[u] - c[u]).abs() < 1e-4 * scale || (p[w] - c[w]).abs() < 1e-4 * scale {
                continue;
            }
            let want = neighbor_slot(p[u] > c[u], p[w] > c[w]);
            let got = FACE_TO_NEIGHBOR_INDEX[face][plucker_code(centre, o, d)] as usize;
            assert_eq!(got, want, "face {face}: o={o} d={d} exit {p}");
            seen[face][want] = true;
        }
        assert!(seen.iter().all(|s| s.iter().all(|&x| x)), "not every slot exercised: {seen:?}");
    }

    #[test]
    fn face_ids_are_consistent() {
        for f in 0..6 {
            assert_eq!(FACE_OF[FACE_AXIS[f]][FACE_POSITIVE[f] as usize], f);
        }
    }
}
