//! One bounce pass of the cumulative wavefront: every live path is traced one segment,
//! its local term added into its sample's sum, and its continuing children appended to
//! the next list, which therefore holds live paths only (module docs of `cumulative`).

// `!(x > y)` is deliberate: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::paths::Paths;
use crate::choice_random;
use crate::shading::{no_nan, Child, WhittedShading};
use crate::RayCounts;
use dynray_scene::Color;

/// What one pass needs besides the lists.
pub(crate) struct Bounce<'s, 'a> {
    pub shading: &'s WhittedShading<'a>,
    /// Level of the rays of `live` (camera rays: 1).
    pub level: u32,
    /// Whether hits of this pass expand both children (`level <= branch depth`) or
    /// choose one.
    pub expand: bool,
}

impl Bounce<'_, '_> {
    /// Traces every path of `live`, adding `P · I(x)` (or `P ·` background on a miss)
    /// into `sums[owner]`, and appends the children that continue to `next` in path
    /// order, reflection before refraction. A choice compares
    /// [`choice_random`]`(keys[owner], level, id)` with the reflection's probability.
    pub fn run(&self, live: &Paths, next: &mut Paths, sums: &mut [Color], keys: &[u32], counts: &mut RayCounts) {
        let sh = self.shading;
        for i in 0..live.len() {
            let (ray, product, weight, owner, id) =
                (&live.ray[i], live.product[i], live.weight[i], live.owner[i], live.id[i]);
            let o = owner as usize;
            let Some(s) = sh.intersect(ray, &live.cone[i]) else {
                sums[o] += no_nan(product * sh.background());
                continue;
            };
            let d = ray.dir.normalize_or_zero();
            let eps = sh.eps(s.hit.p);
            sums[o] += no_nan(product * sh.local(d, &s, eps, counts));
            if self.level >= sh.max_level {
                continue;
            }
            let scatter = sh.scatter(d, &s);
            // Children go on from the footprint the cone reached at the hit.
            let cone = live.cone[i].advance(s.hit.t * ray.dir.length());
            let traced = |c: Option<Child>| c.and_then(|c| Some((c, sh.child_weight(weight, &c)?)));
            let mut go = |c: &Child, w: f32, p: Color, id: u32, counts: &mut RayCounts| {
                counts.secondary += 1;
                next.push(sh.child_ray(&s, c.dir, eps), cone, p, w, owner, id);
            };
            match (traced(scatter.reflect), traced(scatter.refract)) {
                (Some((r, wr)), Some((t, wt))) if !self.expand => {
                    let pr = reflect_probability(&r, &t);
                    if choice_random(keys[o], self.level, id) < pr {
                        go(&r, wr, product * r.coef / pr, id, counts);
                    } else {
                        go(&t, wt, product * t.coef / (1.0 - pr), id, counts);
                    }
                }
                (r, t) if self.expand => {
                    for (k, (c, w)) in [r, t].into_iter().flatten().enumerate() {
                        go(&c, w, product * c.coef, id.wrapping_mul(2).wrapping_add(k as u32), counts);
                    }
                }
                // Past the branch depth with at most one child: it continues, no draw.
                (r, t) => {
                    for (c, w) in [r, t].into_iter().flatten() {
                        go(&c, w, product * c.coef, id, counts);
                    }
                }
            }
        }
    }
}

/// Probability of continuing into the reflected child `r` rather than the refracted `t`:
/// the share of the reflected coefficient's largest component (for glass, the Fresnel
/// reflectance). An even split where the coefficients give no usable share.
pub(crate) fn reflect_probability(r: &Child, t: &Child) -> f32 {
    let (a, b) = (r.coef.max_element().max(0.0), t.coef.max_element().max(0.0));
    let p = a / (a + b);
    if p > 0.0 && p < 1.0 {
        p
    } else if !(a + b > 0.0) || !p.is_finite() {
        0.5
    } else {
        // One share vanishes beside the other (a tiny coefficient): keep both possible
        // so the estimator stays unbiased.
        p.clamp(f32::EPSILON, 1.0 - f32::EPSILON)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_geom::Vec3;

    fn child(c: Color) -> Child {
        Child { dir: Vec3::Y, coef: c }
    }

    #[test]
    fn glass_chooses_by_fresnel() {
        let (f, tr) = (0.1f32, 0.9f32);
        let p = reflect_probability(&child(Color::splat(tr * f)), &child(Color::splat(tr * (1.0 - f))));
        assert!((p - f).abs() < 1e-6, "{p}");
        // Coloured coefficients: the largest component of each.
        let p = reflect_probability(&child(Color::new(0.2, 0.6, 0.1)), &child(Color::new(0.3, 0.1, 0.0)));
        assert!((p - 2.0 / 3.0).abs() < 1e-6, "{p}");
    }

    #[test]
    fn degenerate_shares_stay_valid_probabilities() {
        for (a, b) in [(0.0, 0.0), (f32::NAN, 1.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1e-30), (f32::INFINITY, 1.0)] {
            let p = reflect_probability(&child(Color::splat(a)), &child(Color::splat(b)));
            assert!(p > 0.0 && p < 1.0, "({a}, {b}): {p}");
        }
    }
}
