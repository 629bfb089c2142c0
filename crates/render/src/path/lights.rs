//! The path tracer's emitters and how next-event estimation samples them.
//!
//! - **Area lights**: the triangles whose material has [`Material::emission`], grouped by
//!   actor (one Mitsuba `shape` is one emitter, as in Mitsuba), one-sided: they emit on
//!   the side their geometric normal (the winding's) points to. A group is sampled
//!   uniformly by area (a triangle by its share of the area, then a uniform point on
//!   it).
//! - **Point, spot and directional lights** ([`dynray_scene::Light`]): delta emitters.
//!   A light's colour is the radiance a white Lambertian surface facing it reflects at
//!   unit distance (Whitted's convention), so its radiant intensity (or, for a
//!   directional light, its irradiance) is `π · colour`; attenuation follows the light's
//!   `falloff` exponent (2 for physical lights). A light marked
//!   [`Light::emitter_stand_in`] is skipped: it is the Whitted integrators' point-light
//!   approximation of an emissive surface (an OBJ `Ke` lamp), and that surface is
//!   already an area light here.
//! - **The environment**: a constant radiance (the frame's background) from every
//!   direction, sampled uniformly over the sphere, when it is not black.
//!
//! Next-event estimation picks one emitter uniformly (Mitsuba's default, every
//! `sampling_weight` 1) and one point or direction on it; [`Lights::pdf_area`] and
//! [`Lights::pdf_environment`] give the density with which it would have picked what a
//! BSDF-sampled ray hit, for multiple importance sampling.
//!
//! [`Material::emission`]: dynray_scene::Material::emission
//! [`Light::emitter_stand_in`]: dynray_scene::Light::emitter_stand_in

use super::local::{uniform_sphere, uniform_triangle};
use crate::{Sampler, SurfaceHit};
use dynray_geom::Vec3;
use dynray_scene::{Color, Frame, LightKind};
use std::f32::consts::PI;

/// One emissive actor's triangles.
pub(crate) struct AreaGroup {
    /// Triangle indices into the frame's mesh.
    pub tris: Vec<u32>,
    /// Running sum of their areas (the last one is the total).
    pub cdf: Vec<f32>,
}

impl AreaGroup {
    pub fn area(&self) -> f32 {
        self.cdf.last().copied().unwrap_or(0.0)
    }
}

#[derive(Clone, Copy)]
pub(crate) enum Emitter {
    Area(usize),
    Point { position: Vec3, intensity: Color, falloff: i32, kind: LightKind },
    Directional { towards_light: Vec3, irradiance: Color },
    Environment,
}

/// A light sample seen from a shading point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightSample {
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// Distance to the sampled point (infinite for directional and environment light).
    pub dist: f32,
    /// Radiance arriving, divided by the sample's density (selection included).
    pub weight: Color,
    /// Density per solid angle, selection included (unused for deltas).
    pub pdf: f32,
    /// From a point or directional light: no BSDF sample can hit it.
    pub delta: bool,
}

/// Every emitter of a frame.
pub(crate) struct Lights<'a> {
    frame: &'a Frame,
    pub emitters: Vec<Emitter>,
    pub groups: Vec<AreaGroup>,
    /// Per actor, the index into `emitters` of its area light, if it has one.
    pub emitter_of_actor: Vec<Option<u32>>,
    environment: Color,
}

impl<'a> Lights<'a> {
    pub fn new(frame: &'a Frame) -> Self {
        let mut emitters = Vec::new();
        let mut groups = Vec::new();
        let mut emitter_of_actor = vec![None; frame.actor_ranges.len()];
        for (a, range) in frame.actor_ranges.iter().enumerate() {
            let mut g = AreaGroup { tris: Vec::new(), cdf: Vec::new() };
            let mut total = 0.0f32;
            for prim in range.clone() {
                if emission(frame, prim).max_element() > 0.0 {
                    let area =
                        triangle(frame, prim).map_or(0.0, |(p0, p1, p2)| 0.5 * (p1 - p0).cross(p2 - p0).length());
                    if area > 0.0 && area.is_finite() {
                        total += area;
                        g.tris.push(prim);
                        g.cdf.push(total);
                    }
                }
            }
            if !g.tris.is_empty() && total.is_finite() {
                emitter_of_actor[a] = Some(emitters.len() as u32);
                emitters.push(Emitter::Area(groups.len()));
                groups.push(g);
            }
        }
        // A stand-in's surface is among the area lights above; both would count it twice.
        for l in frame.lights.iter().filter(|l| !l.emitter_stand_in) {
            let c = l.color * PI;
            if !(c.max_element() > 0.0) || !c.is_finite() {
                continue;
            }
            match l.kind {
                LightKind::Point { position, falloff } | LightKind::Spot { position, falloff, .. } => {
                    emitters.push(Emitter::Point { position, intensity: c, falloff, kind: l.kind })
                }
                LightKind::Directional { direction } => {
                    let d = direction.normalize_or_zero();
                    if d != Vec3::ZERO {
                        emitters.push(Emitter::Directional { towards_light: -d, irradiance: c });
                    }
                }
            }
        }
        let bg = frame.environment.background;
        let environment = if bg.is_finite() { bg.max(Color::ZERO) } else { Color::ZERO };
        if environment.max_element() > 0.0 {
            emitters.push(Emitter::Environment);
        }
        Self { frame, emitters, groups, emitter_of_actor, environment }
    }

    /// Radiance of rays that escape the scene.
    pub fn environment(&self) -> Color {
        self.environment
    }

    /// True when some emitter can be hit by a ray (an area light or the environment):
    /// BSDF-sampled rays can only gather light then.
    pub fn any_hittable(&self) -> bool {
        !self.groups.is_empty() || self.environment.max_element() > 0.0
    }

    /// True when there is nothing to sample.
    pub fn is_empty(&self) -> bool {
        self.emitters.is_empty()
    }

    fn selection_pdf(&self) -> f32 {
        1.0 / self.emitters.len() as f32
    }

    /// One light sample for shading point `p` (occlusion not tested).
    pub fn sample(&self, p: Vec3, sampler: &mut Sampler) -> Option<LightSample> {
        let n = self.emitters.len();
        if n == 0 {
            return None;
        }
        let pick = ((sampler.next_f32() * n as f32) as usize).min(n - 1);
        let sel = self.selection_pdf();
        let u = sampler.next_2d();
        let u3 = sampler.next_f32();
        match self.emitters[pick] {
            Emitter::Area(g) => {
                let g = &self.groups[g];
                let total = g.area();
                let target = u3 * total;
                let i = g.cdf.partition_point(|&c| c <= target).min(g.tris.len() - 1);
                let prim = g.tris[i];
                let (p0, p1, p2) = triangle(self.frame, prim)?;
                let (b1, b2) = uniform_triangle(u);
                let q = p0 * (1.0 - b1 - b2) + p1 * b1 + p2 * b2;
                let n = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                let to = q - p;
                let d2 = to.length_squared();
                let dist = d2.sqrt();
                if !(dist > 0.0) {
                    return None;
                }
                let wi = to / dist;
                let cos_l = -n.dot(wi);
                if !(cos_l > 0.0) {
                    return None;
                }
                let pdf = sel * d2 / (cos_l * total);
                let weight = emission(self.frame, prim) / pdf;
                (pdf.is_finite() && weight.is_finite()).then_some(LightSample { wi, dist, weight, pdf, delta: false })
            }
            Emitter::Point { position, intensity, falloff, kind } => {
                let to = position - p;
                let dist = to.length();
                if !(dist > 0.0 && dist.is_finite()) {
                    return None;
                }
                let wi = to / dist;
                let att = dist.powi(falloff.clamp(-8, 8));
                let weight = intensity * kind.cone_factor(-wi) / (att * sel);
                (weight.is_finite()).then_some(LightSample { wi, dist, weight, pdf: 1.0, delta: true })
            }
            Emitter::Directional { towards_light, irradiance } => Some(LightSample {
                wi: towards_light,
                dist: f32::INFINITY,
                weight: irradiance / sel,
                pdf: 1.0,
                delta: true,
            }),
            Emitter::Environment => {
                let wi = uniform_sphere(u);
                let pdf = sel / (4.0 * PI);
                Some(LightSample { wi, dist: f32::INFINITY, weight: self.environment / pdf, pdf, delta: false })
            }
        }
    }

    /// Radiance `hit` emits towards `wo` (unit, pointing away from the surface): its
    /// material's emission on the front side of its triangle, nothing on the back.
    pub fn emitted(hit: &SurfaceHit<'_>, wo: Vec3) -> Color {
        let e = hit.material.emission;
        if e.max_element() > 0.0 && hit.ng.dot(wo) > 0.0 && e.is_finite() {
            e
        } else {
            Color::ZERO
        }
    }

    /// Density (per solid angle at `from`, selection included) with which [`Self::sample`]
    /// picks the point of `hit`, reached from `from`.
    pub fn pdf_area(&self, hit: &SurfaceHit<'_>, from: Vec3) -> f32 {
        if hit.at.geometry != 0 {
            return 0.0;
        }
        let Some(e) = self.frame.actor_of(hit.at.prim).and_then(|a| self.emitter_of_actor[a]) else { return 0.0 };
        let Emitter::Area(g) = self.emitters[e as usize] else { return 0.0 };
        let to = hit.p - from;
        let d2 = to.length_squared();
        let cos_l = hit.ng.dot(to).abs() / d2.sqrt();
        if !(cos_l > 0.0) {
            return 0.0;
        }
        self.selection_pdf() * d2 / (cos_l * self.groups[g].area())
    }

    /// Density with which [`Self::sample`] picks a given environment direction.
    pub fn pdf_environment(&self) -> f32 {
        if self.environment.max_element() > 0.0 {
            self.selection_pdf() / (4.0 * PI)
        } else {
            0.0
        }
    }
}

fn emission(frame: &Frame, prim: u32) -> Color {
    frame.materials_of.get(prim as usize).and_then(|&m| frame.materials.get(m as usize)).map_or(Color::ZERO, |m| {
        if m.emission.is_finite() {
            m.emission.max(Color::ZERO)
        } else {
            Color::ZERO
        }
    })
}

fn triangle(frame: &Frame, prim: u32) -> Option<(Vec3, Vec3, Vec3)> {
    let [a, b, c] = *frame.mesh.indices.get(prim as usize)?;
    let p = |i: u32| frame.mesh.positions.get(i as usize).map(|p| Vec3::from_array(*p));
    Some((p(a)?, p(b)?, p(c)?))
}
