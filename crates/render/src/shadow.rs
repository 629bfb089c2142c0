//! Shadow rays that let light through transparent surfaces, the usual treatment of a
//! Whitted tracer: glass casts a lighter, tinted shadow instead of a black one, opaque
//! surfaces still block.
//!
//! The rule: light reaching a point along a shadow ray is multiplied, for every surface
//! the ray crosses before the light, by that surface's *filter*: its transparency
//! coefficient times its colour, the diffuse colour scaled so its largest component is 1
//! (white when the diffuse colour is black, as for clear glass). A surface with no
//! transparency stops the light. Each crossing counts, so a closed glass sphere filters
//! twice (in and out). No refraction: shadow rays go straight to the light, so glass does
//! not focus light into caustics (a Whitted tracer cannot), it only dims and tints it.
//!
//! A frame without transparent materials answers with one any-hit `occluded` query per
//! shadow ray, exactly as before this rule existed.

// `!(x > y)` is deliberate: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::{RayCounts, SceneIntersector};
use dynray_geom::Ray;
use dynray_scene::{Color, Frame, Material};

/// Most surfaces one shadow ray crosses before the light is taken as blocked: bounds the
/// work for a ray through a stack of thin glass panes.
pub const MAX_SHADOW_CROSSINGS: u32 = 64;

/// How one frame's shadow rays are answered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shadows {
    /// Whether any material of the frame lets light through.
    any_transparent: bool,
}

impl Shadows {
    /// The shadow rule for `frame`'s materials.
    pub fn new(frame: &Frame) -> Self {
        Self { any_transparent: frame.materials.iter().any(|m| filter(m) != Color::ZERO) }
    }

    /// The fraction of light (per channel) that arrives along `ray` within its
    /// `[tmin, tmax]`: 1 when nothing is in the way, 0 when something opaque is, the
    /// product of the crossed surfaces' filters otherwise (module docs). Counts every
    /// segment traced as a shadow ray.
    pub fn light_through(&self, scene: &SceneIntersector<'_>, ray: &Ray, counts: &mut RayCounts) -> Color {
        counts.shadow += 1;
        if !self.any_transparent {
            return if scene.occluded(ray) { Color::ZERO } else { Color::ONE };
        }
        let mut through = Color::ONE;
        let mut segment = *ray;
        for crossing in 0..MAX_SHADOW_CROSSINGS {
            if crossing > 0 {
                counts.shadow += 1;
            }
            let Some(hit) = scene.intersect(&segment) else {
                return through;
            };
            through *= filter(hit.material);
            if through.max_element() <= 0.0 || !through.is_finite() {
                return Color::ZERO;
            }
            // Go on just past this hit. The same triangle answers with the same `t` bits,
            // so the next float excludes it; a neighbour sharing the crossed edge at that
            // same `t` is the same crossing and is rightly skipped too.
            segment.tmin = next_up(hit.t);
            if !(segment.tmin <= segment.tmax) {
                return through;
            }
        }
        Color::ZERO
    }
}

/// A surface's shadow filter: transparency × its colour normalised to a largest
/// component of 1 (module docs). Zero for opaque surfaces.
pub fn filter(m: &Material) -> Color {
    let transparency = m.transparency.max(Color::ZERO);
    if !(transparency.max_element() > 0.0) {
        return Color::ZERO;
    }
    let peak = m.diffuse.max_element();
    let tint = if peak > 0.0 && peak.is_finite() { (m.diffuse / peak).max(Color::ZERO) } else { Color::ONE };
    transparency * tint
}

/// The smallest `f32` above `t` (for `t >= 0`; `+inf` stays).
fn next_up(t: f32) -> f32 {
    if t.is_nan() || t == f32::INFINITY {
        t
    } else if t == 0.0 {
        f32::from_bits(1)
    } else if t > 0.0 {
        f32::from_bits(t.to_bits() + 1)
    } else {
        f32::from_bits(t.to_bits() - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_scene::Finish;

    #[test]
    fn clear_glass_filters_by_transparency_and_tinted_glass_by_colour() {
        let clear =
            Material::from_finish("g", Color::ONE, &Finish { diffuse: 0.0, transparency: 0.9, ..Default::default() });
        assert_eq!(filter(&clear), Color::splat(0.9));
        let red = Material::from_finish(
            "r",
            Color::new(1.0, 0.5, 0.0),
            &Finish { diffuse: 0.4, transparency: 0.8, ..Default::default() },
        );
        assert_eq!(filter(&red), Color::new(0.8, 0.4, 0.0));
        assert_eq!(filter(&Material::default()), Color::ZERO);
    }

    #[test]
    fn next_up_is_the_next_float() {
        assert_eq!(next_up(1.0), 1.0 + f32::EPSILON);
        assert!(next_up(0.0) > 0.0);
        assert_eq!(next_up(f32::INFINITY), f32::INFINITY);
        assert!(next_up(-1.0) > -1.0);
    }
}
