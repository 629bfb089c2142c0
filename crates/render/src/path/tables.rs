//! The path tracer's emitters and BSDFs as plain tables, for a device that runs the same
//! integrator (the GPU wavefront's `path` mode, crates/gpu): converted from the very
//! structures [`PathTracer`](super::PathTracer) samples ([`Lights::new`], [`Bsdf::of`]),
//! so there is one scene path and one set of rules (which triangles emit, how a group is
//! sampled by area, the Phong mapping's lobes and weights, the clamped roughness).

use super::bsdf::{Bsdf, Lobe};
use super::lights::{Emitter, Lights};
use dynray_geom::Vec3;
use dynray_scene::{Color, Frame, LightKind, Material, Microfacet};

/// One emitter, in the order light sampling picks among them (uniformly).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EmitterDesc {
    /// An emissive actor: triangles `first..first + count` of [`EmitterTable::area_tris`]
    /// (with their running area sums in [`EmitterTable::area_cdf`]), `total` their area.
    Area {
        /// First of its triangles in the table.
        first: u32,
        /// How many.
        count: u32,
        /// Their total area.
        total: f32,
    },
    /// A point or spot light: radiant intensity `π · colour`, `1/d^falloff`, the spot's
    /// cone from `kind`.
    Point {
        /// Where it is.
        position: Vec3,
        /// Radiant intensity, `π · colour`.
        intensity: Color,
        /// Exponent of the distance attenuation.
        falloff: i32,
        /// The light's kind (a spot's cone).
        kind: LightKind,
    },
    /// A directional light: unit direction towards it, its irradiance.
    Directional {
        /// Unit direction towards the light.
        towards_light: Vec3,
        /// Irradiance, `π · colour`.
        irradiance: Color,
    },
    /// The constant environment ([`EmitterTable::environment`]).
    Environment,
}

/// Every emitter of a frame as [`PathTracer`](super::PathTracer) sees them.
#[derive(Clone, Debug, PartialEq)]
pub struct EmitterTable {
    /// The emitters light sampling picks among, uniformly.
    pub emitters: Vec<EmitterDesc>,
    /// Emissive triangles (frame mesh indices), grouped by emitter.
    pub area_tris: Vec<u32>,
    /// Per emissive triangle, the running sum of its group's areas up to and including it.
    pub area_cdf: Vec<f32>,
    /// Per triangle of the frame, the index of the area emitter of its actor (what
    /// MIS's density of hitting it reads), `u32::MAX` for none.
    pub emitter_of_prim: Vec<u32>,
    /// Radiance of escaping rays (black: no environment emitter).
    pub environment: Color,
    /// Some emitter can be hit by a ray (an area light or the environment).
    pub any_hittable: bool,
}

impl EmitterTable {
    /// The table of `frame`.
    pub fn new(frame: &Frame) -> Self {
        let lights = Lights::new(frame);
        let mut area_tris = Vec::new();
        let mut area_cdf = Vec::new();
        let emitters = lights
            .emitters
            .iter()
            .map(|e| match *e {
                Emitter::Area(g) => {
                    let g = &lights.groups[g];
                    let first = area_tris.len() as u32;
                    area_tris.extend_from_slice(&g.tris);
                    area_cdf.extend_from_slice(&g.cdf);
                    EmitterDesc::Area { first, count: g.tris.len() as u32, total: g.area() }
                }
                Emitter::Point { position, intensity, falloff, kind } => {
                    EmitterDesc::Point { position, intensity, falloff, kind }
                }
                Emitter::Directional { towards_light, irradiance } => {
                    EmitterDesc::Directional { towards_light, irradiance }
                }
                Emitter::Environment => EmitterDesc::Environment,
            })
            .collect();
        let mut emitter_of_prim = vec![u32::MAX; frame.mesh.triangle_count()];
        for (a, range) in frame.actor_ranges.iter().enumerate() {
            if let Some(e) = lights.emitter_of_actor[a] {
                for prim in range.clone() {
                    if let Some(slot) = emitter_of_prim.get_mut(prim as usize) {
                        *slot = e;
                    }
                }
            }
        }
        Self {
            emitters,
            area_tris,
            area_cdf,
            emitter_of_prim,
            environment: lights.environment(),
            any_hittable: lights.any_hittable(),
        }
    }
}

/// One lobe of a BSDF, in the path tracer's local shading frame (`bsdf.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LobeDesc {
    /// Lambertian, `ρ / π`.
    Diffuse(Color),
    /// Normalised modified Phong: colour, exponent.
    Phong(Color, f32),
    /// Perfect mirror of constant reflectance.
    Mirror(Color),
    /// A conductor; `rough` the distribution and its (clamped) `αu`, `αv`, `None` smooth.
    Conductor {
        /// Real part of the index of refraction.
        eta: Color,
        /// Imaginary part.
        k: Color,
        /// Factor on the reflected light.
        scale: Color,
        /// The microfacet distribution and roughness, `None` when smooth.
        rough: Option<(Microfacet, f32, f32)>,
    },
    /// A smooth dielectric: `eta` inside over outside, reflected and transmitted factors.
    Dielectric {
        /// Index inside over outside.
        eta: f32,
        /// Factor on reflected light.
        r: Color,
        /// Factor on transmitted light.
        t: Color,
    },
}

/// A material's BSDF as the path tracer builds it (untextured: the texel is white).
#[derive(Clone, Debug, PartialEq)]
pub struct BsdfDesc {
    /// Up to four lobes with the probability of choosing each.
    pub lobes: Vec<(LobeDesc, f32)>,
    /// Reflecting lobes work from both sides.
    pub two_sided: bool,
}

impl BsdfDesc {
    /// The BSDF of `m` (`env_ior`: the medium outside transparent Phong materials).
    pub fn of(m: &Material, env_ior: f32) -> Self {
        let b = Bsdf::of(m, Color::ONE, env_ior);
        let lobes = b
            .lobe_list()
            .map(|(l, p)| {
                let d = match l {
                    Lobe::Diffuse(c) => LobeDesc::Diffuse(c),
                    Lobe::Phong(c, n) => LobeDesc::Phong(c, n),
                    Lobe::Mirror(c) => LobeDesc::Mirror(c),
                    Lobe::Conductor { eta, k, scale, rough } => {
                        LobeDesc::Conductor { eta, k, scale, rough: rough.map(|mf| (mf.kind, mf.ax, mf.ay)) }
                    }
                    Lobe::Dielectric { eta, r, t } => LobeDesc::Dielectric { eta, r, t },
                };
                (d, p)
            })
            .collect();
        Self { lobes, two_sided: b.two_sided() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_geom::TriangleMesh;
    use dynray_scene::{Actor, Bsdf as Desc, BsdfKind, Scene};

    /// The table lists what `Lights` samples, in its order, with each group's running
    /// area sums, and maps every triangle of an emissive actor to its emitter.
    #[test]
    fn emitter_table_mirrors_the_lights() {
        let quad = |y: f32, s: f32| TriangleMesh {
            positions: vec![[-s, y, -s], [s, y, -s], [s, y, s], [-s, y, s]],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            normals: None,
            uvs: None,
        };
        let lamp = Material { emission: Color::new(2.0, 1.0, 0.5), ..Material::default() };
        let mut s = Scene { materials: vec![Material::default(), lamp], ..Default::default() };
        s.environment.background = Color::new(0.1, 0.2, 0.3);
        s.actors.push(Actor::new(None, quad(0.0, 1.0), 0));
        s.actors.push(Actor::new(None, quad(2.0, 0.5), 1));
        s.lights.push(dynray_scene::Light {
            kind: LightKind::Point { position: Vec3::new(1.0, 1.0, 0.0), falloff: 2 },
            color: Color::ONE,
            emitter_stand_in: false,
        });
        let frame = s.frame(0.0);
        let t = EmitterTable::new(&frame);
        assert_eq!(t.emitters.len(), 3, "{:?}", t.emitters);
        assert_eq!(t.emitters[0], EmitterDesc::Area { first: 0, count: 2, total: 1.0 });
        assert!(matches!(t.emitters[1], EmitterDesc::Point { falloff: 2, .. }));
        assert_eq!(t.emitters[2], EmitterDesc::Environment);
        assert_eq!(t.area_tris, vec![2, 3]);
        assert_eq!(t.area_cdf, vec![0.5, 1.0]);
        assert_eq!(t.emitter_of_prim, vec![u32::MAX, u32::MAX, 0, 0]);
        assert_eq!(t.environment, Color::new(0.1, 0.2, 0.3));
        assert!(t.any_hittable);
    }

    /// Physical BSDFs are one lobe; the Phong mapping's lobes carry probabilities that
    /// sum to one and colours scaled down together where they exceed 1.
    #[test]
    fn bsdf_descriptions_are_the_path_tracers() {
        let gold = Material {
            bsdf: Some(Desc {
                kind: BsdfKind::Conductor {
                    eta: Color::splat(0.2),
                    k: Color::splat(3.0),
                    specular_reflectance: Color::ONE,
                    roughness: Some(dynray_scene::Roughness {
                        distribution: Microfacet::Ggx,
                        alpha_u: 0.0,
                        alpha_v: 0.3,
                    }),
                },
                two_sided: false,
            }),
            ..Material::default()
        };
        let b = BsdfDesc::of(&gold, 1.0);
        assert!(!b.two_sided);
        assert_eq!(b.lobes.len(), 1);
        // Roughness clamped as Microfacet::new does.
        assert!(matches!(b.lobes[0], (LobeDesc::Conductor { rough: Some((Microfacet::Ggx, ax, ay)), .. }, p)
            if ax == 1e-4 && ay == 0.3 && p == 1.0));
        let phong = Material {
            diffuse: Color::splat(0.8),
            spot: Color::splat(0.4),
            shine: 20.0,
            transparency: Color::splat(0.4),
            ior: 1.5,
            ..Material::default()
        };
        let b = BsdfDesc::of(&phong, 1.0);
        assert!(b.two_sided);
        assert_eq!(b.lobes.len(), 3);
        let total: f32 = b.lobes.iter().map(|(_, p)| p).sum();
        assert!((total - 1.0).abs() < 1e-6);
        assert!(matches!(b.lobes[0].0, LobeDesc::Diffuse(c) if (c.x - 0.5).abs() < 1e-6));
        assert!(matches!(b.lobes[2].0, LobeDesc::Dielectric { eta, .. } if eta == 1.5));
    }
}
