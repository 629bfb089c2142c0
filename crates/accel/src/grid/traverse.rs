//! Grid traversal: the 3-D DDA of Amanatides & Woo over the ray clipped to the grid,
//! with a small per-ray mailbox and the grid rule for early exit.
//!
//! Robustness, in the order a ray meets the problems:
//! - The start cell is taken from the entry point moved back by 1e-3 cell against the
//!   direction, so rounding can only start one cell early (a harmless extra visit,
//!   whose exit is then ≈ the entry), never one cell late.
//! - Each crossing distance is computed afresh from the plane coordinate (no running
//!   sums), and an axis with a zero direction component never crosses (no 0·∞).
//! - When two or three crossings are within rounding of each other (the ray passes
//!   near a cell edge or corner), the cells beside the DDA's path are visited as well,
//!   so no cell the exact ray touches is skipped; insertion slack (`INSERT_SLACK`)
//!   covers the rest.
//! - A hit is final only when it is not beyond the conservatively narrowed exit of the
//!   current cell: a triangle spanning several cells can be hit beyond the current
//!   one, where a nearer triangle of a later cell may still be found. Traversal stops
//!   when the next cells' (widened) entry is *greater* than the best hit.

use super::shape::GridShape;
use super::Grid;
use crate::rebase::{cull, Rebased};
use crate::Counter;
use dynray_geom::{Hit, PreparedRay, Ray};
use std::cmp::Ordering;

/// Relative widening of cell-crossing distances, the slab test's: see `Aabb::clip`.
const CROSS_MARGIN: f32 = dynray_geom::SLAB_MARGIN;

/// Crossings closer than this (relative) count as simultaneous: the ray passes within
/// rounding of a cell edge. Several times the crossing error so no tie is missed.
const TIE_MARGIN: f32 = 8.0 * CROSS_MARGIN;

/// Mailbox size: the last triangles tested by this ray. Triangles spanning cells are
/// met again in the next few cells, so a handful of entries catches most repeats.
const MAILBOX: usize = 8;

struct Dda {
    cell: [u32; 3],
    step: [i32; 3],
    /// Distance at which the ray leaves the current cell through each axis (∞ if never).
    next: [f32; 3],
}

impl GridShape {
    /// Distance at which the ray crosses plane `k` of axis `a`; ∞ for a ray parallel to it.
    #[inline(always)]
    fn crossing(&self, r: &PreparedRay, a: usize, k: u32) -> f32 {
        let inv = r.inv_dir[a];
        if inv.is_infinite() {
            f32::INFINITY
        } else {
            (self.plane(a, k) - r.ray.origin[a]) * inv
        }
    }

    /// Exit distance through axis `a` of a ray in cell `c` going `step`.
    #[inline(always)]
    fn exit(&self, r: &PreparedRay, a: usize, c: u32, step: i32) -> f32 {
        self.crossing(r, a, if step > 0 { c + 1 } else { c })
    }
}

impl Grid {
    /// Visits, in order along the ray, every cell the ray's interval touches. `cell(c)`
    /// tests cell `c` and returns the cull distance (best hit so far), or `None` to stop.
    #[inline(always)]
    fn walk<C: Counter>(&self, r: &PreparedRay, c: &mut C, mut cell: impl FnMut(usize, &mut C) -> Option<f32>) {
        let ray = &r.ray;
        let s = &self.shape;
        let Some((t0, t1)) = s.bounds.clip(r, ray.tmin, ray.tmax) else {
            return;
        };
        let p = ray.origin + ray.dir * t0;
        let mut d = Dda { cell: [0; 3], step: [0; 3], next: [f32::INFINITY; 3] };
        for a in 0..3 {
            let neg = r.inv_dir[a].is_sign_negative();
            d.step[a] = if neg { -1 } else { 1 };
            let bias = if r.inv_dir[a].is_infinite() {
                0.0
            } else if neg {
                1.0e-3
            } else {
                -1.0e-3
            };
            d.cell[a] = s.cell_of(a, p[a], bias);
            d.next[a] = s.exit(r, a, d.cell[a], d.step[a]);
        }
        loop {
            c.node();
            let Some(cull) = cell(s.index(d.cell), c) else { return };
            let m = argmin(&d.next);
            let exit = d.next[m];
            // The ray's interval ends in this cell, or everything after it is farther
            // than the best hit (equal is not farther: a lower index may still win).
            // (NaN exit, from a NaN direction, also ends the walk.)
            let next_entry = exit * if exit > 0.0 { 1.0 - CROSS_MARGIN } else { 1.0 + CROSS_MARGIN };
            let ends_here = !matches!(exit.partial_cmp(&t1), Some(Ordering::Less | Ordering::Equal));
            if ends_here || next_entry > cull {
                return;
            }
            let tie = exit.abs() * TIE_MARGIN;
            let ties = (0..3).filter(|&a| d.next[a] <= exit + tie).fold(0u32, |bits, a| bits | 1 << a);
            if ties.count_ones() > 1 {
                // Cells beside the path: step every non-empty subset of the tied axes
                // except `{m}`, which is where the DDA goes next.
                for sub in 1..8u32 {
                    if sub & !ties != 0 || sub == 1 << m {
                        continue;
                    }
                    if let Some(side) = self.neighbour(&d, sub) {
                        c.node();
                        if cell(s.index(side), c).is_none() {
                            return;
                        }
                    }
                }
            }
            let next = d.cell[m] as i64 + d.step[m] as i64;
            if next < 0 || next >= s.res[m] as i64 {
                return;
            }
            d.cell[m] = next as u32;
            d.next[m] = s.exit(r, m, d.cell[m], d.step[m]);
        }
    }

    /// The cell reached by stepping every axis in the bit set `axes`, if inside.
    fn neighbour(&self, d: &Dda, axes: u32) -> Option<[u32; 3]> {
        let mut c = d.cell;
        for (a, ca) in c.iter_mut().enumerate() {
            if axes & 1 << a != 0 {
                let k = *ca as i64 + d.step[a] as i64;
                if k < 0 || k >= self.shape.res[a] as i64 {
                    return None;
                }
                *ca = k as u32;
            }
        }
        Some(c)
    }

    /// Closest hit, identical to brute force.
    pub(super) fn closest<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        let r = PreparedRay::new(ray);
        // Cells are walked from near the grid for a far origin (rebase.rs); triangles
        // are tested against the ray as given.
        let rebased = Rebased::new(ray, &self.shape.bounds);
        let w = rebased.as_ref().map(|b| PreparedRay::new(&b.ray));
        let mut best = Hit::MISS;
        let mut mailbox = [u32::MAX; MAILBOX];
        let mut slot = 0;
        self.walk(w.as_ref().unwrap_or(&r), c, |cell, c| {
            for &prim in self.cell_refs(cell) {
                if mailbox.contains(&prim) {
                    continue;
                }
                mailbox[slot] = prim;
                slot = (slot + 1) % MAILBOX;
                c.triangles(1);
                if let Some((t, u, v)) = self.tris[prim as usize].intersect(&r, best.t.min(ray.tmax)) {
                    if Hit::is_closer(t, prim, &best) {
                        best = Hit { t, u, v, prim };
                    }
                }
            }
            Some(cull(&rebased, best.t))
        });
        best
    }

    /// Any hit in `[tmin, tmax]`, stopping at the first.
    pub(super) fn any<C: Counter>(&self, ray: &Ray, c: &mut C) -> bool {
        let r = PreparedRay::new(ray);
        let w = Rebased::new(ray, &self.shape.bounds).map(|b| PreparedRay::new(&b.ray));
        let mut found = false;
        self.walk(w.as_ref().unwrap_or(&r), c, |cell, c| {
            let refs = self.cell_refs(cell);
            c.triangles(refs.len() as u32);
            found = refs.iter().any(|&p| self.tris[p as usize].intersect(&r, ray.tmax).is_some());
            if found {
                None
            } else {
                Some(f32::INFINITY)
            }
        });
        found
    }
}

/// Index of the smallest of three distances (the lower axis on ties; NaN never wins).
#[inline(always)]
fn argmin(v: &[f32; 3]) -> usize {
    let mut m = 0;
    for a in 1..3 {
        if v[a] < v[m] || v[m].is_nan() {
            m = a;
        }
    }
    m
}
