//! The result of a closest-hit query.

use crate::{PreparedRay, Triangle};

/// A closest hit: distance `t`, barycentrics `(u, v)` and the triangle index `prim`
/// in the mesh's order. The hit point is `(1-u-v)·p0 + u·p1 + v·p2`.
///
/// A miss is `prim == u32::MAX` and `t == f32::INFINITY` ([`Hit::MISS`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f32,
    /// Triangle index in the mesh, `u32::MAX` on a miss.
    pub prim: u32,
}

impl Hit {
    /// No hit.
    pub const MISS: Hit = Hit { t: f32::INFINITY, u: 0.0, v: 0.0, prim: u32::MAX };

    /// True when something was hit.
    #[inline]
    pub fn is_hit(&self) -> bool {
        self.prim != u32::MAX
    }

    /// The engine's closest-hit order: smaller `t` wins, equal `t` goes to the lower
    /// triangle index. Every structure must use this to stay identical to brute force.
    #[inline]
    pub fn is_closer(t: f32, prim: u32, than: &Hit) -> bool {
        t < than.t || (t == than.t && prim < than.prim)
    }

    /// The leaf loop every structure shares: tests each `(triangle, mesh index)` against
    /// `r` up to the current best `t` (and `tmax`) and keeps a hit that
    /// [`Hit::is_closer`] says wins, so every structure breaks ties as brute force does.
    /// Structures that store triangles in leaf order pass their copies with the ids.
    #[inline(always)]
    pub fn closest_of<'a>(&mut self, r: &PreparedRay, leaf: impl IntoIterator<Item = (&'a Triangle, u32)>) {
        for (tri, prim) in leaf {
            if let Some((t, u, v)) = tri.intersect(r, self.t.min(r.ray.tmax)) {
                if Hit::is_closer(t, prim, self) {
                    *self = Hit { t, u, v, prim };
                }
            }
        }
    }

    /// True when both hits name the same triangle at the same `t` bits (or both miss).
    pub fn same_as(&self, other: &Hit) -> bool {
        self.prim == other.prim && self.t.to_bits() == other.t.to_bits()
    }
}

impl Default for Hit {
    fn default() -> Self {
        Self::MISS
    }
}
