//! What both structures build the same way: the cube, the triangle copies, the near list
//! and the fragments of every triangle filed by pixel (counting sort, triangle order kept).

use super::cube::Cube;
use super::node::{Fragment, NONE};
use super::params::{ApitParams, Observer};
use super::raster::{coverage_bound, is_near, rasterize, RawFrag};
use crate::BuildError;
use crate::StructureParams;
use dynray_geom::{Aabb, Triangle, TriangleMesh};
use rayon::prelude::*;

/// The part of a built structure that does not depend on how a pixel's fragments are
/// organised.
#[derive(Clone, Debug)]
pub struct Base {
    /// Parameters it was built with.
    pub params: ApitParams,
    /// Geometry of the cube.
    pub cube: Cube,
    /// The mesh's triangles, in mesh order (fragments name them by index).
    pub tris: Vec<Triangle>,
    /// Triangles tested on every ray instead of being rasterised, ascending: those that
    /// may meet the box around the observer, and the widest ones when the fragments
    /// would exceed the budget (`ApitParams::fragment_budget`).
    pub near: Vec<u32>,
}

/// A base plus the fragments sorted by pixel: pixel `p` owns `frags[offsets[p]..offsets[p+1]]`.
pub struct Filed {
    /// Shared part.
    pub base: Base,
    /// Start of each pixel's fragments; one more entry than pixels.
    pub offsets: Vec<u32>,
    /// Fragments, pixel after pixel, in triangle order within a pixel; `next` = [`NONE`].
    pub frags: Vec<Fragment>,
}

/// Checks parameters and mesh, rasterises every triangle and files the fragments.
pub fn build_filed(mesh: &TriangleMesh, params: &ApitParams) -> Result<Filed, BuildError> {
    mesh.validate()?;
    params.validate()?;
    let tris: Vec<Triangle> = mesh.triangles().collect();
    let bounds = tris.iter().fold(Aabb::EMPTY, |b, t| b.union(&t.bounds()));
    // `validate` rejected non-finite points; `Eye` without an eye yet means the centre.
    let observer = match params.observer {
        Observer::BoundsCenter | Observer::Eye => bounds.center(),
        Observer::Point(p) => p,
    };
    let cube = Cube::new(observer, params.resolution, bounds);
    let pixels = cube.pixels();
    let mut near_flags: Vec<bool> = tris.par_iter().map(|t| is_near(&cube, t)).collect();
    // Budget: A-buffer memory grows with the pixels every triangle covers, which is
    // unbounded for many large triangles close to the observer (100k copies of one
    // triangle cover the same thousands of pixels). Past the budget, the triangles with
    // the largest coverage bound are tested by every ray instead: still exact.
    let est: Vec<u64> =
        tris.par_iter().zip(&near_flags).map(|(t, &n)| if n { 0 } else { coverage_bound(&cube, t) }).collect();
    let budget = params.fragment_budget as u64 * tris.len() as u64 + pixels as u64;
    let mut total_est: u64 = est.iter().sum();
    if total_est > budget {
        let mut widest: Vec<u32> = (0..tris.len() as u32).filter(|&i| !near_flags[i as usize]).collect();
        widest.sort_unstable_by_key(|&i| (std::cmp::Reverse(est[i as usize]), i));
        for i in widest {
            if total_est <= budget {
                break;
            }
            near_flags[i as usize] = true;
            total_est -= est[i as usize];
        }
    }
    let near: Vec<u32> = (0..tris.len() as u32).filter(|&i| near_flags[i as usize]).collect();
    let chunks: Vec<Vec<RawFrag>> = tris
        .par_chunks(1024)
        .enumerate()
        .map(|(c, chunk)| {
            let mut out = Vec::new();
            for (k, t) in chunk.iter().enumerate() {
                let i = c * 1024 + k;
                if !near_flags[i] {
                    rasterize(&cube, t, i as u32, &mut out);
                }
            }
            out
        })
        .collect();
    let total: usize = chunks.iter().map(Vec::len).sum();
    if total >= NONE as usize {
        return Err(BuildError::Limit(format!(
            "{total} fragments at resolution {}: fragment indices are u32",
            params.resolution
        )));
    }
    // Counting sort by pixel; chunks are in triangle order, so each pixel's list is too.
    let mut offsets = vec![0u32; pixels + 1];
    for f in chunks.iter().flatten() {
        offsets[f.pixel as usize + 1] += 1;
    }
    for p in 0..pixels {
        offsets[p + 1] += offsets[p];
    }
    let mut cursor = offsets.clone();
    let mut frags = vec![Fragment { zmin: 0.0, zmax: 0.0, tri: 0, next: NONE }; total];
    for f in chunks.iter().flatten() {
        let slot = &mut cursor[f.pixel as usize];
        frags[*slot as usize] = Fragment { zmin: f.zmin, zmax: f.zmax, tri: f.tri, next: NONE };
        *slot += 1;
    }
    Ok(Filed { base: Base { params: *params, cube, tris, near }, offsets, frags })
}

impl Base {
    /// Bytes of the triangle copies and the always-tested list.
    pub fn memory_bytes(&self) -> usize {
        self.tris.len() * std::mem::size_of::<Triangle>() + self.near.len() * 4
    }

    /// Figures both structures report.
    pub fn extra(&self, fragments: usize, nonempty: usize) -> Vec<(String, String)> {
        let o = self.cube.observer_f32;
        vec![
            ("resolution".into(), format!("6 x {0}x{0}", self.cube.res)),
            ("observer".into(), format!("({}, {}, {})", o.x, o.y, o.z)),
            ("fragments".into(), fragments.to_string()),
            ("fragments/triangle".into(), format!("{:.2}", fragments as f64 / self.tris.len().max(1) as f64)),
            ("non-empty pixels".into(), format!("{nonempty} of {}", self.cube.pixels())),
            ("always-tested triangles".into(), self.near.len().to_string()),
        ]
    }

    /// `leaf_sizes` histogram: pixels holding k fragments (last bucket: 32 or more).
    pub fn histogram(offsets_len: impl Iterator<Item = usize>) -> Vec<usize> {
        let mut h = vec![0usize; 33];
        for n in offsets_len {
            h[n.min(32)] += 1;
        }
        h
    }
}
