//! The in-memory scene (seed 003 §2.4): actors with meshes and materials, lights, camera,
//! render settings and environment. [`Scene::frame_into`] flattens it into a
//! [`crate::Frame`] (`frame.rs`); actors are in `actor.rs`.

use crate::{Actor, Bsdf, Texture, TextureRef};
use dynray_geom::{Aabb, TriangleMesh, Vec3};
use std::sync::Arc;

/// An RGB colour, linear, components usually in `[0, 1]`.
pub type Color = Vec3;

/// A surface (the seed's `Surface` class): every factor is a colour, as the seed's
/// `color × finish` reading gives it (see docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name, for diagnostics (`""` when anonymous).
    pub name: String,
    /// Reflectance for the scene's ambient light.
    pub ambient: Color,
    /// Lambertian reflectance.
    pub diffuse: Color,
    /// Phong highlight colour (the seed's "spot").
    pub spot: Color,
    /// Phong exponent.
    pub shine: f32,
    /// Mirror reflection coefficient.
    pub specular: Color,
    /// Transmission coefficient.
    pub transparency: Color,
    /// Index of refraction of the material.
    pub ior: f32,
    /// A colour texture that multiplies `diffuse` and `ambient` at each point (glTF
    /// `baseColorTexture`, MTL `map_Kd`, `.scn` `texture`); see
    /// [`Material::diffuse_texel`].
    pub diffuse_texture: Option<TextureRef>,
    /// Radiance the surface emits (W·m⁻²·sr⁻¹ per channel), from the side its geometric
    /// normal points to (the front of a counter-clockwise triangle) only, as Mitsuba's
    /// `area` emitter does. The path tracer samples emissive triangles as area lights;
    /// the Whitted integrator ignores it (it lights with [`Light`]s only, among them a
    /// stand-in for the surface where the loader adds one: [`Light::emitter_stand_in`]).
    pub emission: Color,
    /// A physically based BSDF for the path tracer (`bsdf.rs`); `None` derives one from
    /// the Phong coefficients above (docs/rendering.md, "Path tracer").
    pub bsdf: Option<Bsdf>,
}

impl Material {
    /// The seed's reading of `material { color C finish { … } }`: each factor scales `color`.
    pub fn from_finish(name: impl Into<String>, color: Color, f: &Finish) -> Self {
        Self {
            name: name.into(),
            ambient: color * f.ambient,
            diffuse: color * f.diffuse,
            spot: Color::ONE * f.spot,
            shine: f.shine,
            specular: Color::ONE * f.specular,
            transparency: Color::ONE * f.transparency,
            ior: f.ior,
            diffuse_texture: None,
            emission: Color::ZERO,
            bsdf: None,
        }
    }
}

impl Default for Material {
    /// Matte light grey, as used when a file has no material.
    fn default() -> Self {
        Self::from_finish("default", Color::splat(0.8), &Finish::default())
    }
}

/// The scalar factors of the scene language's `finish { … }`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Finish {
    /// Ambient factor.
    pub ambient: f32,
    /// Diffuse factor.
    pub diffuse: f32,
    /// Highlight factor.
    pub spot: f32,
    /// Highlight exponent.
    pub shine: f32,
    /// Mirror factor.
    pub specular: f32,
    /// Transmission factor.
    pub transparency: f32,
    /// Index of refraction.
    pub ior: f32,
}

impl Default for Finish {
    fn default() -> Self {
        Self { ambient: 0.1, diffuse: 0.9, spot: 0.0, shine: 1.0, specular: 0.0, transparency: 0.0, ior: 1.0 }
    }
}

/// Where light comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// A point light attenuated by `1 / d^falloff` (falloff 0 = no attenuation).
    Point {
        /// Position.
        position: Vec3,
        /// Integer attenuation exponent.
        falloff: i32,
    },
    /// Light arriving along `direction` (from the light towards the scene), unattenuated.
    Directional {
        /// Direction of travel of the light.
        direction: Vec3,
    },
    /// A point light that shines into a cone (glTF's `spot`): full intensity within
    /// `cos_inner` of `direction`, none beyond `cos_outer`, a smooth step between, and
    /// attenuated like [`LightKind::Point`].
    Spot {
        /// Position.
        position: Vec3,
        /// Axis of the cone, from the light outwards.
        direction: Vec3,
        /// Cosine of the angle within which the light is at full intensity.
        cos_inner: f32,
        /// Cosine of the angle beyond which no light leaves (`<= cos_inner`).
        cos_outer: f32,
        /// Integer attenuation exponent, as for point lights.
        falloff: i32,
    },
}

impl LightKind {
    /// The light given in a node's space, in world space (`m`: the node's world
    /// matrix): positions transformed as points, directions as vectors, kept unit length.
    pub fn transformed(&self, m: &glam::Mat4) -> LightKind {
        let dir = |d: Vec3| m.transform_vector3(d).normalize_or(d);
        match *self {
            LightKind::Point { position, falloff } => {
                LightKind::Point { position: m.transform_point3(position), falloff }
            }
            LightKind::Directional { direction } => LightKind::Directional { direction: dir(direction) },
            LightKind::Spot { position, direction, cos_inner, cos_outer, falloff } => LightKind::Spot {
                position: m.transform_point3(position),
                direction: dir(direction),
                cos_inner,
                cos_outer,
                falloff,
            },
        }
    }

    /// The share of the light's intensity sent towards `to_point`, a unit direction from
    /// the light: 1 for point and directional lights, the cone's smooth step for spots.
    pub fn cone_factor(&self, to_point: Vec3) -> f32 {
        match *self {
            LightKind::Spot { direction, cos_inner, cos_outer, .. } => {
                let c = direction.normalize_or_zero().dot(to_point);
                if c >= cos_inner {
                    1.0
                } else if c <= cos_outer || cos_inner <= cos_outer {
                    0.0
                } else {
                    let x = (c - cos_outer) / (cos_inner - cos_outer);
                    x * x * (3.0 - 2.0 * x)
                }
            }
            _ => 1.0,
        }
    }
}

/// A light source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Point or directional.
    pub kind: LightKind,
    /// Colour (intensity).
    pub color: Color,
    /// The light only stands in for an emissive surface ([`Material::emission`]) under the
    /// integrators that light with [`Light`]s alone (Whitted and cumulative, on the CPU
    /// and the GPU). The path tracer samples that surface itself as an area light and
    /// skips this light, so the lamp is not counted twice. The OBJ loader's `Ke` lamps
    /// are such lights (formats/obj.rs, "Emitters"); every other light has `false`.
    pub emitter_stand_in: bool,
}

/// Camera projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Perspective with the vertical field of view in degrees.
    Perspective {
        /// Vertical field of view, degrees.
        fov_y_deg: f32,
    },
    /// Parallel (orthographic) with the view height in world units.
    Parallel {
        /// Height of the view window.
        height: f32,
    },
}

/// A camera: position, look-at point, up vector, projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub look_at: Vec3,
    /// Up direction (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// Projection.
    pub projection: Projection,
    /// Where along the view direction the camera starts and stops seeing.
    pub clip: Clip,
}

/// The camera's near and far clipping planes, as distances along the view direction
/// (Mitsuba's `near_clip`/`far_clip`): a camera ray sees what lies between the two
/// planes, so geometry in front of the near plane is invisible. Only camera rays are
/// clipped; shadow and secondary rays see everything.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clip {
    /// Distance of the near plane from the eye (0: no near plane).
    pub near: f32,
    /// Distance of the far plane from the eye (infinity: no far plane).
    pub far: f32,
}

impl Clip {
    /// No clipping: camera rays over `[0, ∞)`, as scene-language and mesh cameras.
    pub const NONE: Clip = Clip { near: 0.0, far: f32::INFINITY };
}

impl Default for Clip {
    fn default() -> Self {
        Clip::NONE
    }
}

impl Camera {
    /// The camera given in a node's space, in world space (`m`: the node's world matrix):
    /// eye and target as points, up as a vector.
    pub fn transformed(&self, m: &glam::Mat4) -> Camera {
        Camera {
            position: m.transform_point3(self.position),
            look_at: m.transform_point3(self.look_at),
            up: m.transform_vector3(self.up).normalize_or(self.up),
            projection: self.projection,
            clip: self.clip,
        }
    }
}

/// Render settings (the seed's `RayTracerSettings`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum ray level; 1 = primary rays only (seed 003 §3.7).
    pub max_recursion_level: u32,
    /// Secondary rays whose weight falls to this or below are not traced.
    pub min_weight: f32,
    /// Samples per pixel the file asks for (Mitsuba's `sample_count`); `None` leaves it
    /// to the renderer's default. `render --spp` overrides it.
    pub spp: Option<u32>,
}

impl Default for Settings {
    fn default() -> Self {
        Self { width: 640, height: 480, max_recursion_level: 10, min_weight: 0.01, spp: None }
    }
}

/// Background, ambient light, and the refractive index of the medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Environment {
    /// Colour of rays that hit nothing.
    pub background: Color,
    /// Ambient light.
    pub ambient: Color,
    /// Refractive index of the medium the camera is in.
    pub ior: f32,
}

impl Default for Environment {
    fn default() -> Self {
        Self { background: Color::new(0.05, 0.05, 0.08), ambient: Color::splat(0.2), ior: 1.0 }
    }
}

/// A whole scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// Geometry.
    pub actors: Vec<Actor>,
    /// Materials referenced by actors.
    pub materials: Vec<Material>,
    /// Decoded image textures, named by index from [`Material::diffuse_texture`];
    /// shared (not copied) by every frame.
    pub textures: Vec<Arc<Texture>>,
    /// Lights.
    pub lights: Vec<Light>,
    /// Camera; `None` frames the scene's bounding box.
    pub camera: Option<Camera>,
    /// Render settings.
    pub settings: Settings,
    /// Background, ambient, medium.
    pub environment: Environment,
    /// Nodes, clips, skins and the timeline (`animation/`); empty for a still scene.
    pub animation: crate::Animation,
    /// The `physics { … }` block, if the file has one; actors with
    /// [`crate::Actor::elastic`] use the defaults without it (docs/physics.md).
    pub physics: Option<crate::PhysicsSettings>,
    /// Distance fields placed beside the actors (`.scn` `adf { … }`); static: every
    /// frame has them where the scene puts them.
    pub distance_fields: Vec<crate::FieldPlacement>,
}

impl Scene {
    /// A scene of one mesh with one material, given default camera and light: what a
    /// bare mesh file becomes.
    pub fn from_mesh(name: Option<String>, mesh: TriangleMesh, material: Material) -> Self {
        let mut s = Scene { materials: vec![material], ..Default::default() };
        s.actors.push(Actor::new(name, mesh, 0));
        s.add_default_light();
        s
    }

    /// Adds a white point light above and in front of the scene when it has none.
    pub fn add_default_light(&mut self) {
        self.add_default_light_around(self.bounds());
    }

    /// [`Scene::add_default_light`] placed for geometry within `b` rather than the
    /// actors' bounds: for geometry that is no actor (a distance field), so it is lit as
    /// its source mesh was. Does nothing when the scene has lights.
    pub fn add_default_light_around(&mut self, b: Aabb) {
        if !self.lights.is_empty() {
            return;
        }
        let (c, r) = if b.is_empty() { (Vec3::ZERO, 1.0) } else { (b.center(), b.extent().length().max(1e-3)) };
        self.lights.push(Light {
            kind: LightKind::Point { position: c + Vec3::new(0.6, 1.2, 1.0) * r, falloff: 0 },
            color: Color::ONE,
            emitter_stand_in: false,
        });
    }

    /// Bounding box of all actors, in world space.
    pub fn bounds(&self) -> Aabb {
        self.actors.iter().fold(Aabb::EMPTY, |b, a| b.union(&a.bounds()))
    }

    /// Number of triangles over all actors.
    pub fn triangle_count(&self) -> usize {
        self.actors.iter().map(|a| a.mesh.triangle_count()).sum()
    }
}
