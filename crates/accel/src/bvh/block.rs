//! The leaf block: 4 triangles in SoA order, their raw `f32` vertices and mesh ids, so the
//! block test reads one coordinate of 4 triangles with one load and computes exactly what
//! the scalar test computes on the same numbers.

use bytemuck::{Pod, Zeroable};
use dynray_geom::{Aabb, Triangle, Vec3};

/// Triangles per block (the f64 lanes of one AVX2 register).
pub const LANES: usize = 4;

/// Id of a padding lane.
pub const PAD_ID: u32 = u32::MAX;

/// Four triangles: `v[vertex][axis][lane]` is coordinate `axis` of vertex `vertex`
/// (`p0`, `p1`, `p2`) of the lane's triangle; `ids[lane]` its mesh index.
///
/// Padding: a leaf of `n` triangles fills `⌈n/4⌉` blocks; the unused lanes of its last
/// block have NaN vertices and id `PAD_ID` (`u32::MAX`). Such a lane can never hit: every value the
/// test derives from its vertices is NaN, so the sign test and `det == 0` reject nothing,
/// and the final `t >= tmin && t <= tmax` is false for `t = NaN` whatever the ray
/// (`pad_lanes_never_hit` in kernel.rs checks it on adversarial rays).
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct TriBlock {
    /// Vertex coordinates, SoA.
    pub v: [[[f32; LANES]; 3]; 3],
    /// Mesh triangle index per lane, `PAD_ID` (`u32::MAX`) for padding.
    pub ids: [u32; LANES],
}

// 9 × 16 bytes of coordinates + 16 of ids = 5 × 32: each coordinate row is one 16-byte
// load, and a block never shares a 32-byte half line with the next.
const _: () = assert!(std::mem::size_of::<TriBlock>() == 160);

impl TriBlock {
    /// A block of padding lanes only.
    pub const PAD: TriBlock = TriBlock { v: [[[f32::NAN; LANES]; 3]; 3], ids: [PAD_ID; LANES] };

    /// Blocks holding `tris` (with their mesh ids) in order, the last one padded.
    pub fn pack(tris: &[Triangle], ids: &[u32], out: &mut Vec<TriBlock>) {
        debug_assert_eq!(tris.len(), ids.len());
        for (chunk, id_chunk) in tris.chunks(LANES).zip(ids.chunks(LANES)) {
            let mut b = TriBlock::PAD;
            for (lane, (t, &id)) in chunk.iter().zip(id_chunk).enumerate() {
                b.set(lane, t, id);
            }
            out.push(b);
        }
    }

    /// Stores triangle `t` with mesh index `id` in `lane`.
    pub fn set(&mut self, lane: usize, t: &Triangle, id: u32) {
        for (k, p) in [t.p0, t.p1, t.p2].into_iter().enumerate() {
            for a in 0..3 {
                self.v[k][a][lane] = p[a];
            }
        }
        self.ids[lane] = id;
    }

    /// True for a padding lane.
    #[inline(always)]
    pub fn is_pad(&self, lane: usize) -> bool {
        self.ids[lane] == PAD_ID
    }

    /// The triangle of `lane`, as the scalar test takes it.
    #[inline(always)]
    pub fn triangle(&self, lane: usize) -> Triangle {
        let p = |k: usize| Vec3::new(self.v[k][0][lane], self.v[k][1][lane], self.v[k][2][lane]);
        Triangle::new(p(0), p(1), p(2))
    }

    /// Box of the real (non-padding) lanes.
    pub fn bounds(&self) -> Aabb {
        (0..LANES).filter(|&l| !self.is_pad(l)).fold(Aabb::EMPTY, |b, l| b.union(&self.triangle(l).bounds()))
    }

    /// Real triangles in the block.
    pub fn real_lanes(&self) -> usize {
        (0..LANES).filter(|&l| !self.is_pad(l)).count()
    }
}
