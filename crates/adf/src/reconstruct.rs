//! Reconstruction (seed 001 eq. 3-4): trilinear interpolation inside the 2×2×2 sub-block
//! of the leaf holding the point — the child `o` of the deepest internal cell reads
//! texels `origin + o + {0,1}^3` — and the field's gradient by central differences.
//!
//! The interpolation is done here in `f32` from 8 fetches rather than by a texture
//! unit's fixed-point filter, so CPU and GPU can agree to float precision.

use crate::{Adf, Located, Search};
use dynray_geom::Vec3;

impl Adf {
    /// The point's unit-cube coordinates.
    #[inline]
    pub fn unit(&self, p: Vec3) -> Vec3 {
        (p - self.cube.origin) / self.cube.size
    }

    /// The reconstructed signed distance at world point `p` (world units), `None` outside
    /// the cube.
    pub fn distance(&self, p: Vec3, search: Search) -> Option<f32> {
        let u = self.unit(p);
        if !(u.cmpge(Vec3::ZERO).all() && u.cmple(Vec3::ONE).all()) {
            return None;
        }
        let mut hint = 0;
        Some(self.distance_unit(u, search, &mut hint))
    }

    /// The reconstructed distance at unit-cube point `u` (clamped into the cube).
    #[inline]
    pub(crate) fn distance_unit(&self, u: Vec3, search: Search, hint: &mut u32) -> f32 {
        self.sample_unit(u, search, hint).0
    }

    /// The reconstructed distance at unit-cube point `u` (clamped into the cube), the
    /// deepest internal cell it was read from and the point's finest-level coordinates.
    #[inline]
    pub(crate) fn sample_unit(&self, u: Vec3, search: Search, hint: &mut u32) -> (f32, Located, [u32; 3]) {
        let u = u.clamp(Vec3::ZERO, Vec3::ONE);
        let q = self.fine_coords(u);
        let cell = self.locate_fine(q, search, hint);
        let leaf = cell.level + 1;
        let idx = q.map(|c| c >> (self.max_level - leaf));
        let scale = (1u32 << leaf) as f32;
        let t = [0, 1, 2].map(|k| (u[k] * scale - idx[k] as f32).clamp(0.0, 1.0));
        (crate::build::trilinear(&self.leaf_corners(cell, q), t), cell, q)
    }

    /// The 8 samples of the leaf holding fine coordinates `q`, child of `cell`.
    #[inline]
    pub(crate) fn leaf_corners(&self, cell: Located, q: [u32; 3]) -> impl Fn(u32, u32, u32) -> f32 + '_ {
        let idx = q.map(|c| c >> (self.max_level - cell.level - 1));
        let o = self.voxels.origin(cell.block);
        move |x: u32, y: u32, z: u32| {
            self.voxels.texel(o[0] + (idx[0] & 1) + x, o[1] + (idx[1] & 1) + y, o[2] + (idx[2] & 1) + z)
        }
    }

    /// Gradient of the reconstructed field at world point `p` (central differences half a
    /// finest cell wide, kept inside the cube), the surface normal where it is not zero.
    pub fn gradient(&self, p: Vec3, hint: &mut u32) -> Vec3 {
        let h = 0.5 / (1u32 << self.max_level) as f32;
        let u = self.unit(p).clamp(Vec3::splat(h), Vec3::splat(1.0 - h));
        let mut g = [0.0f32; 3];
        for (k, gk) in g.iter_mut().enumerate() {
            let mut e = Vec3::ZERO;
            e[k] = h;
            let hi = self.distance_unit(u + e, Search::CoherentLinear, hint);
            let lo = self.distance_unit(u - e, Search::CoherentLinear, hint);
            *gk = (hi - lo) / (2.0 * h * self.cube.size);
        }
        Vec3::from_array(g)
    }
}
