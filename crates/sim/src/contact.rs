//! Contact of phyxels with the ground plane and with the scene's static geometry. Each
//! phyxel is a sphere of the contact radius `r` (half the sampling spacing: where the
//! surface lies beyond the outermost grid layer). Contact is a projection after the
//! position update — the phyxel is put back at distance `r` from the plane it crossed
//! and its velocity into that plane removed — which is unconditionally stable and adds
//! no stiffness to the time-step bound. It is frictionless and perfectly inelastic.
//!
//! Static geometry is queried through the acceleration structure: a ray from the old
//! position along the step's motion, `r` longer than the motion, finds the surface the
//! phyxel would cross or come within `r` of.

use dynray_accel::{Accel, Bvh, BvhParams};
use dynray_geom::{Ray, TriangleMesh};
use glam::DVec3;
use rayon::prelude::*;

/// What phyxels collide with.
pub struct Contact {
    /// Height of the horizontal floor, if any.
    pub ground: Option<f64>,
    statics: Option<(Bvh, TriangleMesh)>,
}

impl Contact {
    /// A floor at `ground` (if any) and the triangles of `statics` (world space).
    pub fn new(ground: Option<f64>, statics: Option<TriangleMesh>) -> Result<Self, dynray_accel::BuildError> {
        let statics = match statics {
            Some(m) if m.triangle_count() > 0 => Some((Bvh::build(&m, &BvhParams::default())?, m)),
            _ => None,
        };
        Ok(Self { ground, statics })
    }

    /// Whether there is static geometry to collide with.
    pub fn has_statics(&self) -> bool {
        self.statics.is_some()
    }

    /// Projects the phyxels that moved from `old` to `pos` out of the floor and the
    /// static triangles, removing the velocity into them.
    pub fn resolve(&self, old: &[DVec3], pos: &mut [DVec3], vel: &mut [DVec3], r: f64) {
        pos.par_iter_mut().zip(vel.par_iter_mut()).zip(old).for_each(|((p, v), o)| {
            if let Some((bvh, mesh)) = &self.statics {
                statics(bvh, mesh, *o, p, v, r);
            }
            if let Some(g) = self.ground {
                if p.y < g + r {
                    p.y = g + r;
                    v.y = v.y.max(0.0);
                }
            }
        });
    }
}

fn statics(bvh: &Bvh, mesh: &TriangleMesh, old: DVec3, p: &mut DVec3, v: &mut DVec3, r: f64) {
    let delta = *p - old;
    let len = delta.length();
    if len <= 0.0 || !len.is_finite() {
        return;
    }
    let dir = delta / len;
    let hit = bvh.intersect(&Ray::with_interval(old.as_vec3(), dir.as_vec3(), 0.0, (len + r) as f32));
    if !hit.is_hit() {
        return;
    }
    let tri = mesh.triangle(hit.prim as usize);
    let (a, b, c) = (tri.p0.as_dvec3(), tri.p1.as_dvec3(), tri.p2.as_dvec3());
    let mut n = (b - a).cross(c - a).normalize_or_zero();
    if n == DVec3::ZERO {
        return;
    }
    // The side the phyxel comes from.
    if n.dot(dir) > 0.0 {
        n = -n;
    }
    let depth = r - (*p - a).dot(n);
    if depth > 0.0 {
        *p += n * depth;
        let vn = v.dot(n);
        if vn < 0.0 {
            *v -= n * vn;
        }
    }
}
