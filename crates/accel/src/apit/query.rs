//! Closest-hit and any-hit queries, shared by the A-buffer and the A-PIT: test the near
//! list, clip the ray to the mesh bounds, walk the frustums and test the candidates that
//! each frustum's organisation (a plain list or a pseudo-interval tree) returns.

use super::build::Base;
use super::walk::{walk, Visitor};
use crate::Counter;
use dynray_geom::{Hit, PreparedRay, Ray, Triangle};
use std::ops::ControlFlow;

/// How a structure finds, in one pixel, the fragments whose depth interval meets a query.
pub trait Candidates {
    /// Calls `visit` with the triangle of every fragment of `pixel` meeting `[qa, qb]`
    /// (counting each as a triangle test) until it breaks.
    fn candidates<C: Counter>(
        &self,
        pixel: usize,
        qa: f32,
        qb: f32,
        c: &mut C,
        visit: impl FnMut(u32) -> ControlFlow<()>,
    ) -> ControlFlow<()>;
}

struct Closest<'a, S, C> {
    tris: &'a [Triangle],
    s: &'a S,
    r: PreparedRay,
    best: Hit,
    c: &'a mut C,
}

/// Tests triangle `k`, keeping the engine's closest-hit order (ties: lower index).
#[inline(always)]
fn consider(tris: &[Triangle], r: &PreparedRay, k: u32, best: &mut Hit) {
    if let Some((t, u, v)) = tris[k as usize].intersect(r, best.t.min(r.ray.tmax)) {
        if Hit::is_closer(t, k, best) {
            *best = Hit { t, u, v, prim: k };
        }
    }
}

impl<S: Candidates, C: Counter> Visitor for Closest<'_, S, C> {
    fn bound(&self) -> f32 {
        self.best.t.min(self.r.ray.tmax)
    }

    fn visit(&mut self, pixel: usize, qa: f32, qb: f32) -> bool {
        self.c.node();
        let (tris, r, best) = (self.tris, &self.r, &mut self.best);
        let _ = self.s.candidates(pixel, qa, qb, self.c, |k| {
            consider(tris, r, k, best);
            ControlFlow::Continue(())
        });
        false
    }
}

/// Closest hit of `ray`.
pub fn closest<S: Candidates, C: Counter>(base: &Base, s: &S, ray: &Ray, c: &mut C) -> Hit {
    let r = PreparedRay::new(ray);
    let mut best = Hit::MISS;
    c.triangles(base.near.len() as u32);
    for &k in &base.near {
        consider(&base.tris, &r, k, &mut best);
    }
    let Some((t0, t1)) = base.cube.bounds.clip(&r, ray.tmin, ray.tmax) else {
        return best;
    };
    let mut v = Closest { tris: &base.tris, s, r, best, c };
    walk(&base.cube, ray, t0, t1, &mut v);
    v.best
}

struct AnyHit<'a, S> {
    tris: &'a [Triangle],
    s: &'a S,
    r: PreparedRay,
}

impl<S: Candidates> Visitor for AnyHit<'_, S> {
    fn bound(&self) -> f32 {
        self.r.ray.tmax
    }

    fn visit(&mut self, pixel: usize, qa: f32, qb: f32) -> bool {
        let (tris, r) = (self.tris, &self.r);
        self.s
            .candidates(pixel, qa, qb, &mut crate::NoCount, |k| {
                if tris[k as usize].intersect(r, r.ray.tmax).is_some() {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            })
            .is_break()
    }
}

/// True when anything lies on `ray` within `[tmin, tmax]`; stops at the first hit.
pub fn any<S: Candidates>(base: &Base, s: &S, ray: &Ray) -> bool {
    let r = PreparedRay::new(ray);
    if base.near.iter().any(|&k| base.tris[k as usize].intersect(&r, ray.tmax).is_some()) {
        return true;
    }
    let Some((t0, t1)) = base.cube.bounds.clip(&r, ray.tmin, ray.tmax) else {
        return false;
    };
    walk(&base.cube, ray, t0, t1, &mut AnyHit { tris: &base.tris, s, r })
}
