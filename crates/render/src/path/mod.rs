//! The physically based path tracer (`--integrator path`): unidirectional path tracing
//! with next-event estimation and multiple importance sampling, built to converge to
//! what Mitsuba 3's `path` integrator computes from the same scene (docs/rendering.md,
//! "Path tracer").
//!
//! One path per pixel sample, as Mitsuba's `path.cpp` walks it:
//! 1. at each hit, emitted radiance (area lights, front side only) is added, weighted by
//!    MIS against the light sampling of the previous vertex (weight 1 after the camera
//!    or a delta bounce); an escaping ray adds the environment the same way;
//! 2. if another segment is allowed (`depth + 1 < max_depth`), one emitter sample
//!    (`lights.rs`) with a shadow ray, weighted by the power heuristic (`mis.rs`) unless
//!    the light is a delta;
//! 3. one BSDF sample (`bsdf.rs`) continues the path; from depth [`RR_DEPTH`] on,
//!    Russian roulette keeps it with probability `min(max(throughput) · η², 0.95)`.
//!
//! `max_depth` counts path segments, as Mitsuba's does: 1 shows emitters only, 2 is
//! direct lighting, `D` lets light bounce `D − 1` times. It is read from the frame's
//! [`Settings::max_recursion_level`](dynray_scene::Settings) as `level + 1` (the Whitted
//! level that counts the same light paths; `render --integrator path --max-depth D` and
//! Mitsuba files set `level = D − 1`).
//!
//! Rays leave a surface from its point offset along the geometric normal, to the side
//! they go, by `(1 + max |p|) · 8.9e-5` (Mitsuba's `RayEpsilon`), and shadow rays stop
//! short of the light by the same relative margin ×10 (its `ShadowEpsilon`).
//!
//! Every random number comes from the pixel sample's [`Sampler`], so images do not
//! depend on threads or tiles.
//!
//! Textures are filtered by the path's [`RayCone`]: the camera ray's pixel footprint,
//! continued from the width it reached at each hit with the camera's spread, through
//! specular and rough bounces alike (docs/rendering.md, "Texture filtering").

// `!(x > 0.0)` is deliberate here and in the submodules: it is true for NaN, which must
// take the rejecting branch (hostile files, degenerate geometry).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod bsdf;
mod fresnel;
mod lights;
mod local;
mod microfacet;
mod mis;
mod tables;

use crate::{CameraRays, Integrator, RayCone, RayCounts, Sampler, SceneIntersector};
use bsdf::Bsdf;
use dynray_geom::{Ray, Vec3};
use dynray_scene::{Color, Frame};
use lights::Lights;
use local::Local;
use mis::power_heuristic;
pub use tables::{BsdfDesc, EmitterDesc, EmitterTable, LobeDesc};

/// Depth (segments traced so far) from which Russian roulette may end a path: Mitsuba's
/// default `rr_depth`.
pub const RR_DEPTH: u32 = 5;

/// Longest path, in segments, whatever the settings ask (a cap on work per sample;
/// Russian roulette ends almost every path long before).
pub const MAX_PATH_DEPTH: u32 = 1024;

/// Mitsuba's `RayEpsilon` for single precision: `1500 · 2⁻²⁴`.
const RAY_EPSILON: f32 = 1500.0 / 16_777_216.0;
/// Mitsuba's `ShadowEpsilon`: shadow rays end this fraction short of the light.
const SHADOW_EPSILON: f32 = RAY_EPSILON * 10.0;

/// How light is gathered. [`Strategy::Mis`] is the integrator; the others exist to check
/// it (each converges to the same image, with more noise).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Strategy {
    /// Light sampling and BSDF sampling combined by the power heuristic.
    #[default]
    Mis,
    /// Light sampling only: emitters count when hit by the camera ray or after a delta
    /// bounce (where no light sample can reach), never after a smooth one.
    Light,
    /// BSDF sampling only: emitters count only when a path hits them (point and
    /// directional lights, which no ray can hit, then give nothing).
    Bsdf,
}

/// The path tracer over one frame.
pub struct PathTracer<'a> {
    scene: &'a SceneIntersector<'a>,
    lights: Lights<'a>,
    max_depth: u32,
    env_ior: f32,
    strategy: Strategy,
    /// The footprint of a camera ray of one sample per pixel.
    pixel_cone: RayCone,
}

impl<'a> PathTracer<'a> {
    /// A path tracer for `frame` (emitters, settings, environment) tracing through
    /// `scene`, the intersector over the frame's geometry.
    pub fn new(frame: &'a Frame, scene: &'a SceneIntersector<'a>) -> Self {
        let ior = frame.environment.ior;
        Self {
            scene,
            lights: Lights::new(frame),
            max_depth: frame.settings.max_recursion_level.saturating_add(1).min(MAX_PATH_DEPTH),
            env_ior: if ior.is_finite() && ior > 0.0 { ior } else { 1.0 },
            strategy: Strategy::Mis,
            pixel_cone: CameraRays::new(&frame.camera, frame.settings.width, frame.settings.height).pixel_cone(),
        }
    }

    /// The same tracer gathering light with `strategy`.
    pub fn with_strategy(self, strategy: Strategy) -> Self {
        Self { strategy, ..self }
    }

    /// Longest path in segments (Mitsuba's `max_depth`).
    pub fn max_depth(&self) -> u32 {
        self.max_depth
    }

    fn trace(&self, camera_ray: &Ray, sampler: &mut Sampler, counts: &mut RayCounts) -> Color {
        let mut result = Color::ZERO;
        let mut throughput = Color::ONE;
        let mut eta = 1.0f32;
        let mut ray = *camera_ray;
        let mut cone = self.pixel_cone.for_samples(sampler.pattern_count());
        // The previous vertex: its point, the BSDF sample's density, whether a delta.
        let mut prev: Option<(Vec3, f32, bool)> = None;
        let mis_bsdf = |prev: Option<(Vec3, f32, bool)>, light_pdf: &dyn Fn(Vec3) -> f32| -> f32 {
            match (prev, self.strategy) {
                (None, _) | (Some((_, _, true)), _) | (_, Strategy::Bsdf) => 1.0,
                (_, Strategy::Light) => 0.0,
                (Some((p, pdf, false)), Strategy::Mis) => power_heuristic(pdf, light_pdf(p)),
            }
        };
        let mut depth = 0u32;
        loop {
            let Some(hit) = self.scene.intersect_cone(&ray, &cone) else {
                let env = self.lights.environment();
                if env.max_element() > 0.0 {
                    let w = mis_bsdf(prev, &|_| self.lights.pdf_environment());
                    result += throughput * env * w;
                }
                break;
            };
            let wo = -ray.dir.normalize_or_zero();
            let emitted = Lights::emitted(&hit, wo);
            if emitted.max_element() > 0.0 {
                let w = mis_bsdf(prev, &|p| self.lights.pdf_area(&hit, p));
                result += throughput * emitted * w;
            }
            if depth + 1 >= self.max_depth {
                break;
            }
            let bsdf = Bsdf::at(&hit, self.env_ior);
            let frame = Local::new(hit.ns);
            let wo_local = frame.to_local(wo);

            // Next-event estimation.
            if self.strategy != Strategy::Bsdf && bsdf.has_smooth() && !self.lights.is_empty() {
                if let Some(ls) = self.lights.sample(hit.p, sampler) {
                    let wi_local = frame.to_local(ls.wi);
                    let f = bsdf.eval(wo_local, wi_local);
                    if f.max_element() > 0.0 {
                        let origin = offset(hit.p, hit.ng, ls.wi);
                        let tmax = if ls.dist.is_finite() {
                            (ls.dist - (origin - hit.p).length()) * (1.0 - SHADOW_EPSILON)
                        } else {
                            f32::INFINITY
                        };
                        counts.shadow += 1;
                        if tmax > 0.0 && !self.scene.occluded(&Ray::with_interval(origin, ls.wi, 0.0, tmax)) {
                            let w = if ls.delta || self.strategy == Strategy::Light {
                                1.0
                            } else {
                                power_heuristic(ls.pdf, bsdf.pdf(wo_local, wi_local))
                            };
                            result += throughput * f * ls.weight * w;
                        }
                    }
                }
            }

            // The next segment only matters if it can gather emission or shade again.
            if !self.lights.any_hittable() && depth + 2 >= self.max_depth {
                break;
            }
            let u1 = sampler.next_f32();
            let u2 = sampler.next_2d();
            let Some(s) = bsdf.sample(wo_local, u1, u2) else { break };
            let wi = frame.to_world(s.wi).normalize_or_zero();
            if wi == Vec3::ZERO || !s.weight.is_finite() {
                break;
            }
            throughput *= s.weight;
            eta *= s.eta;
            prev = Some((hit.p, s.pdf, s.delta));
            cone = cone.advance(hit.t * ray.dir.length());
            ray = Ray::new(offset(hit.p, hit.ng, wi), wi);
            counts.secondary += 1;
            depth += 1;

            let t_max = throughput.max_element();
            if !(t_max > 0.0) {
                break;
            }
            if depth >= RR_DEPTH {
                let q = (t_max * eta * eta).min(0.95);
                if sampler.next_f32() >= q {
                    break;
                }
                throughput /= q;
            }
        }
        result
    }
}

/// `p` moved off its surface (geometric normal `ng`) to the side `d` goes.
fn offset(p: Vec3, ng: Vec3, d: Vec3) -> Vec3 {
    let mag = (1.0 + p.abs().max_element()) * RAY_EPSILON;
    let mag = if mag.is_finite() { mag } else { 0.0 };
    if ng.dot(d) >= 0.0 {
        p + ng * mag
    } else {
        p - ng * mag
    }
}

impl Integrator for PathTracer<'_> {
    fn name(&self) -> &'static str {
        "path"
    }

    fn radiance(&self, ray: &Ray, sampler: &mut Sampler, counts: &mut RayCounts) -> Color {
        let c = self.trace(ray, sampler, counts);
        // A NaN or infinity from a hostile file must not poison the pixel.
        Color::from_array(c.to_array().map(|x| if x.is_finite() { x } else { 0.0 }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_accel::Brute;
    use dynray_geom::TriangleMesh;
    use dynray_scene::{Actor, Bsdf as Desc, Material, Scene};

    /// Two emissive quads at different distances and sizes plus a point light.
    fn lamp_frame() -> Frame {
        let quad = |x: f32, y: f32, s: f32| TriangleMesh {
            positions: vec![[x - s, y, -s], [x + s, y, -s], [x + s, y, s], [x - s, y, s]],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            normals: None,
            uvs: None,
        };
        let lamp = Material {
            emission: Color::new(2.0, 1.0, 0.5),
            bsdf: Some(Desc::diffuse(Color::ZERO)),
            ..Material::default()
        };
        let mut s = Scene { materials: vec![lamp], ..Default::default() };
        // No environment light: every non-delta sample is on a lamp.
        s.environment.background = Color::ZERO;
        s.actors.push(Actor::new(None, quad(0.0, 2.0, 0.5), 0));
        s.actors.push(Actor::new(None, quad(-4.0, 3.0, 1.5), 0));
        s.lights.push(dynray_scene::Light {
            kind: dynray_scene::LightKind::Point { position: Vec3::new(1.0, 1.0, 0.0), falloff: 2 },
            color: Color::ONE,
            emitter_stand_in: false,
        });
        s.frame(0.0)
    }

    /// What makes MIS weights sum to one in the integrator: the density a light sample
    /// reports for a direction is the one `pdf_area` computes when a BSDF-sampled ray
    /// hits that same point, so the two power-heuristic weights of one path add up to 1.
    #[test]
    fn light_and_bsdf_densities_agree_so_mis_weights_sum_to_one() {
        let frame = lamp_frame();
        let accel = Brute::build(&frame.mesh).unwrap();
        let scene = SceneIntersector::triangles(&frame, &accel);
        let lights = Lights::new(&frame);
        let p = Vec3::new(0.2, 0.0, -0.1);
        let bsdf_pdf = 0.3f32;
        let (mut area_samples, mut deltas) = (0, 0);
        for i in 0..400 {
            let mut sampler = Sampler::new(1, 1, 0, 0, i, 1);
            let Some(ls) = lights.sample(p, &mut sampler) else { continue };
            if ls.delta {
                deltas += 1;
                continue;
            }
            let hit = scene.intersect(&Ray::new(p, ls.wi)).expect("a light sample points at its lamp");
            assert!((hit.t - ls.dist).abs() < 1e-4 * ls.dist, "sample {i}: hit at {} vs sampled {}", hit.t, ls.dist);
            let pdf = lights.pdf_area(&hit, p);
            assert!((pdf - ls.pdf).abs() <= 1e-3 * ls.pdf, "sample {i}: light pdf {} vs pdf at the hit {pdf}", ls.pdf);
            let sum = power_heuristic(ls.pdf, bsdf_pdf) + power_heuristic(bsdf_pdf, pdf);
            assert!((sum - 1.0).abs() < 2e-3, "sample {i}: weights sum to {sum}");
            area_samples += 1;
        }
        // Both quads face down (wound counter-clockwise seen from below) and are chosen
        // with the point light one time in three each.
        assert!(area_samples > 200 && deltas > 100, "{area_samples} area, {deltas} delta samples");
    }

    /// Emitters are one-sided: a quad whose normal faces away from the point is never
    /// sampled from there, and emits nothing towards it.
    #[test]
    fn area_lights_are_one_sided() {
        let frame = lamp_frame();
        let lights = Lights::new(&frame);
        let above = Vec3::new(0.0, 5.0, 0.0);
        for i in 0..200 {
            let mut sampler = Sampler::new(2, 1, 0, 0, i, 1);
            if let Some(ls) = lights.sample(above, &mut sampler) {
                assert!(ls.delta, "sample {i}: the lamps face down, away from a point above them");
            }
        }
    }

    /// A light that stands in for an emissive surface (an OBJ `Ke` lamp's point light,
    /// [`dynray_scene::Light::emitter_stand_in`]) is Whitted's: the path tracer samples
    /// the surface's triangles, not the stand-in, here and in the GPU's emitter table.
    #[test]
    fn emitter_stand_ins_are_left_to_whitted() {
        let mut frame = lamp_frame();
        assert_eq!(Lights::new(&frame).emitters.len(), 3, "two lamps and the point light");
        frame.lights[0].emitter_stand_in = true;
        let lights = Lights::new(&frame);
        assert_eq!(lights.emitters.len(), 2);
        assert!(lights.emitters.iter().all(|e| matches!(e, lights::Emitter::Area(_))));
        let table = EmitterTable::new(&frame);
        assert_eq!(table.emitters.len(), 2);
        assert!(table.emitters.iter().all(|e| matches!(e, EmitterDesc::Area { .. })));
    }
}
