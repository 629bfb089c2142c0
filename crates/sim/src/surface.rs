//! The surface (the seed's surfels and "surface"): the mesh's vertices follow the
//! phyxels by MLS interpolation of the displacement field (Müller et al. 2004, §6). Each
//! vertex `p` is bound once, at rest, to the phyxels `j` whose support contains it,
//! with weights `w(|p − x_j|, h_j)` normalised to sum 1; each frame it moves to
//!
//! `p' = p + Σ_j w_j (u_j + ∇u_j (p − x_j))`
//!
//! (each phyxel's first-order displacement field, blended). Normals are recomputed from
//! the deformed triangles every frame, as the seed does.

use crate::hash::SpatialHash;
use crate::kernel::poly6;
use dynray_geom::TriangleMesh;
use glam::{DMat3, DVec3, Vec3};

/// Vertices bound to phyxels.
#[derive(Clone, Debug)]
pub struct Surface {
    /// Rest positions of the vertices.
    pub rest: Vec<DVec3>,
    /// The mesh's triangles (indices into `rest`), for normals.
    pub indices: Vec<[u32; 3]>,
    start: Vec<u32>,
    phyxel: Vec<u32>,
    weight: Vec<f64>,
}

impl Surface {
    /// Binds the vertices of `mesh` to the phyxels at `rest` with supports `support`
    /// (`hash` bins `rest`). A vertex outside every support follows its nearest phyxel.
    pub fn new(mesh: &TriangleMesh, rest: &[DVec3], support: &[f64], hash: &SpatialHash) -> Self {
        let hmax = support.iter().copied().fold(0.0, f64::max);
        let verts: Vec<DVec3> = mesh.positions.iter().map(|p| Vec3::from_array(*p).as_dvec3()).collect();
        let mut start = vec![0u32];
        let (mut phyxel, mut weight) = (Vec::new(), Vec::new());
        let mut near = Vec::new();
        for p in &verts {
            hash.within(rest, *p, hmax, &mut near);
            let first = phyxel.len();
            for &j in &near {
                let w = poly6(rest[j as usize].distance_squared(*p), support[j as usize]);
                if w > 0.0 {
                    phyxel.push(j);
                    weight.push(w);
                }
            }
            if phyxel.len() == first {
                let nearest = (0..rest.len())
                    .min_by(|&a, &b| rest[a].distance_squared(*p).total_cmp(&rest[b].distance_squared(*p)));
                phyxel.push(nearest.unwrap_or(0) as u32);
                weight.push(1.0);
            }
            let sum: f64 = weight[first..].iter().sum();
            weight[first..].iter_mut().for_each(|w| *w /= sum);
            start.push(phyxel.len() as u32);
        }
        Self { rest: verts, indices: mesh.indices.clone(), start, phyxel, weight }
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.rest.len()
    }

    /// The deformed vertex positions for phyxels at `pos` (rest `rest`) with gradients
    /// `grads`, into `out`.
    pub fn deform(&self, rest: &[DVec3], pos: &[DVec3], grads: &[DMat3], out: &mut [[f32; 3]]) {
        use rayon::prelude::*;
        out.par_iter_mut().enumerate().for_each(|(v, o)| {
            let p = self.rest[v];
            let mut u = DVec3::ZERO;
            for k in self.start[v] as usize..self.start[v + 1] as usize {
                let j = self.phyxel[k] as usize;
                u += (pos[j] - rest[j] + grads[j] * (p - rest[j])) * self.weight[k];
            }
            *o = (p + u).as_vec3().to_array();
        });
    }

    /// Area-weighted vertex normals of the triangles at `positions`, into `out`; a
    /// vertex of only degenerate triangles gets a zero normal (shading then uses the
    /// triangle's own).
    pub fn normals(&self, positions: &[[f32; 3]], out: &mut [[f32; 3]]) {
        let mut acc = vec![DVec3::ZERO; positions.len()];
        for t in &self.indices {
            let [a, b, c] = t.map(|i| Vec3::from_array(positions[i as usize]).as_dvec3());
            let n = (b - a).cross(c - a);
            for &i in t {
                acc[i as usize] += n;
            }
        }
        for (o, n) in out.iter_mut().zip(&acc) {
            *o = n.normalize_or_zero().as_vec3().to_array();
        }
    }
}
