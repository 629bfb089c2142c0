//! Mitsuba 3 scene files (`.xml`): the subset its test scenes use, into a [`Scene`] that
//! the path tracer renders as Mitsuba would (docs/formats.md, "Mitsuba 3 scenes").
//!
//! - `tree.rs`: the XML (roxmltree) as owned elements, `include`s expanded, `default`
//!   parameters substituted for `$name`;
//! - `props.rs`: an object's typed properties, taken by name, leftovers an error;
//! - `transform.rs`: `translate`, `rotate`, `scale`, `matrix`, `lookat`;
//! - `spectrum.rs`: `wavelength:value` spectra to RGB as `scalar_rgb` converts them;
//! - `sensor.rs`: the `perspective` camera, `hdrfilm`, `independent` sampler;
//! - `shapes.rs`: `obj`, `ply`, `rectangle`, `cube`, `sphere`;
//! - `bsdf.rs`: `diffuse`, `conductor`, `roughconductor`, `dielectric`, `twosided`;
//! - here: the scene's top level, `ref`/`id`, emitters (`area` on shapes, `point`,
//!   `constant`) and the `path` integrator's `max_depth`.
//!
//! Anything else — another plugin type, an unknown parameter, a nested object where none
//! belongs — is a [`LoadError::Parse`] naming the file, line and element, never ignored.
//!
//! Conventions carried over:
//! - `max_depth` (path segments, 2 = direct light only, −1 = unbounded) is stored as
//!   [`crate::Settings::max_recursion_level`] `= max_depth − 1`: the Whitted level that
//!   counts the same light paths (a camera ray and its shadow ray are Mitsuba's two
//!   segments); the path tracer reads it back as `max_depth`. Unbounded becomes
//!   [`MAX_DEPTH_UNBOUNDED`].
//! - Area emitters are materials with [`crate::Material::emission`], one-sided (they
//!   emit where the triangle's normal points). A point light's `intensity` `I` (W/sr)
//!   becomes a [`Light`] of colour `I / π` with inverse-square falloff: dynray's light
//!   colour is the radiance a white Lambertian surface facing the light reflects at unit
//!   distance (Whitted's `ρ · E` convention; glTF lights are converted the same way), so
//!   the Whitted image of a diffuse scene equals its direct lighting.
//! - A `constant` emitter's radiance is the [`crate::Environment::background`]; without
//!   one it is black. There is no ambient light.

// `!(x > 0.0)` is deliberate here and in the submodules: it is true for NaN, which must
// take the rejecting branch (hostile files, degenerate geometry).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod bsdf;
mod props;
mod sensor;
mod shapes;
mod spectrum;
mod transform;
mod tree;

pub use shapes::SPHERE_LEVELS;

use crate::Light;
use crate::{
    Actor, Color, Environment, LightKind, LoadError, LoadReport, Material, Scene, Settings, Shading, Transform, Warning,
};
use props::Props;
use std::collections::HashMap;
use std::path::Path;
use tree::Elem;

/// The Mitsuba `max_depth` that stands for −1 (unbounded paths): Russian roulette ends
/// paths long before it.
pub const MAX_DEPTH_UNBOUNDED: u32 = 65;

/// Loads a Mitsuba 3 scene file (module docs).
pub fn load(path: &Path) -> Result<LoadReport, LoadError> {
    let root = tree::read_scene(path)?;
    root.only_attrs(&["version"])?;
    let mut ids: HashMap<&str, &Elem> = HashMap::new();
    collect_ids(&root, &mut ids)?;
    let mut b = Builder { ids, scene: Scene::default(), warnings: Vec::new(), bsdfs: HashMap::new() };
    b.scene.environment = Environment { background: Color::ZERO, ambient: Color::ZERO, ior: 1.0 };
    b.scene.settings = Settings { max_recursion_level: MAX_DEPTH_UNBOUNDED - 1, ..Settings::default() };
    let mut have_sensor = None;
    for e in &root.children {
        match e.tag.as_str() {
            "integrator" => b.integrator(e)?,
            "sensor" => {
                if let Some(line) = have_sensor {
                    return Err(
                        e.error(format!("a second <sensor> (the first is at line {line}): dynray renders one camera"))
                    );
                }
                have_sensor = Some(e.line);
                let s = sensor::read_sensor(e, &mut b.warnings)?;
                b.scene.camera = Some(s.camera);
                let st = &mut b.scene.settings;
                (st.width, st.height, st.spp) = (s.width, s.height, Some(s.spp));
            }
            "shape" => b.shape(e)?,
            "emitter" => b.emitter(e)?,
            // Definitions, instantiated where a `ref` names them.
            "bsdf" if e.attr("id").is_some() => {}
            "bsdf" => return Err(e.error("a top-level <bsdf> without an `id` is never used")),
            other => return Err(e.error(format!("<{other}> is not supported at the top level of a scene"))),
        }
    }
    if b.scene.materials.is_empty() {
        b.scene.materials.push(Material::default());
    }
    Ok(LoadReport { scene: b.scene, warnings: b.warnings })
}

/// Every element with an `id` (a `<ref id>` names one, it has none), at any depth; a
/// repeated id is an error.
fn collect_ids<'a>(e: &'a Elem, ids: &mut HashMap<&'a str, &'a Elem>) -> Result<(), LoadError> {
    for c in &e.children {
        if let Some(id) = c.attr("id").filter(|_| c.tag != "ref") {
            if let Some(first) = ids.insert(id, c) {
                return Err(c.error(format!(
                    "id `{id}` is used twice (first at {}:{})",
                    first.file.display(),
                    first.line
                )));
            }
        }
        collect_ids(c, ids)?;
    }
    Ok(())
}

struct Builder<'a> {
    ids: HashMap<&'a str, &'a Elem>,
    scene: Scene,
    warnings: Vec<Warning>,
    /// Material index of each BSDF element already read (by address: one per element).
    bsdfs: HashMap<*const Elem, u32>,
}

impl<'a> Builder<'a> {
    fn integrator(&mut self, e: &Elem) -> Result<(), LoadError> {
        let ty = e.required("type")?;
        if ty != "path" {
            return Err(
                e.error(format!("<integrator type=\"{ty}\"> is not supported (dynray's path tracer is `path`)"))
            );
        }
        let mut p = Props::new(e)?;
        let depth = p.integer("max_depth", -1)?;
        let rr = p.integer("rr_depth", 5)?;
        let hide = p.boolean("hide_emitters", false)?;
        p.finish()?;
        if rr != 5 {
            return Err(e.error(format!("rr_depth {rr}: dynray's path tracer starts Russian roulette at depth 5 only")));
        }
        if hide {
            return Err(e.error("hide_emitters=\"true\" is not supported"));
        }
        let depth = match depth {
            -1 => MAX_DEPTH_UNBOUNDED,
            d if (1..=MAX_DEPTH_UNBOUNDED as i64).contains(&d) => d as u32,
            d => return Err(e.error(format!("max_depth {d}: expected -1 or 1..={MAX_DEPTH_UNBOUNDED}"))),
        };
        self.scene.settings.max_recursion_level = depth - 1;
        Ok(())
    }

    /// `e`, or the element its `<ref id>` names (checked to be a `tag`).
    fn deref(&self, e: &'a Elem, tag: &str) -> Result<&'a Elem, LoadError> {
        if e.tag != "ref" {
            return Ok(e);
        }
        e.only_attrs(&["id", "name"])?;
        let id = e.required("id")?;
        let target = self.ids.get(id).ok_or_else(|| e.error(format!("<ref id=\"{id}\">: no element has this id")))?;
        if target.tag != tag {
            return Err(e.error(format!("<ref id=\"{id}\"> names a <{}>, expected a <{tag}>", target.tag)));
        }
        Ok(target)
    }

    fn material_of(&mut self, bsdf: &'a Elem) -> Result<u32, LoadError> {
        if let Some(&m) = self.bsdfs.get(&(bsdf as *const Elem)) {
            return Ok(m);
        }
        let m = bsdf::read_bsdf(bsdf)?;
        self.scene.materials.push(m);
        let i = self.scene.materials.len() as u32 - 1;
        self.bsdfs.insert(bsdf as *const Elem, i);
        Ok(i)
    }

    fn shape(&mut self, e: &'a Elem) -> Result<(), LoadError> {
        let mut p = Props::new(e)?;
        let geometry = shapes::read_geometry(e, &mut p, &mut self.warnings)?;
        // The BSDF and the emitter: nested, or named by a `ref`.
        let mut bsdf = None;
        let mut emitter = None;
        let mut nested = p.objects("bsdf");
        nested.extend(p.objects("emitter"));
        nested.extend(p.objects("ref"));
        for c in nested {
            let tag = match c.tag.as_str() {
                "ref" => c.attr("id").and_then(|id| self.ids.get(id)).map_or("bsdf", |t| t.tag.as_str()),
                t => t,
            };
            let slot = match tag {
                "bsdf" => &mut bsdf,
                "emitter" => &mut emitter,
                other => return Err(c.error(format!("a shape takes a <bsdf> and an <emitter>, not a <{other}>"))),
            };
            if slot.is_some() {
                return Err(c.error(format!("the shape has a second <{tag}>")));
            }
            *slot = Some(self.deref(c, tag)?);
        }
        p.finish()?;
        let mut material = match bsdf {
            Some(b) => self.material_of(b)?,
            None => {
                // Mitsuba's default: a diffuse BSDF of reflectance 0.5, black on an
                // emitter (its shape.cpp), so a lamp reflects none of the light that
                // reaches it (0.5 made the glass-and-metal scene's lamp bounce light back
                // onto the floor: +0.5 % at max_depth >= 4).
                let reflectance = if emitter.is_some() { 0.0 } else { 0.5 };
                let m = Material {
                    name: if emitter.is_some() { "default emitter (black)" } else { "default diffuse" }.into(),
                    diffuse: Color::splat(reflectance),
                    ambient: Color::ZERO,
                    bsdf: Some(crate::Bsdf::diffuse(Color::splat(reflectance))),
                    ..Material::default()
                };
                self.scene.materials.push(m);
                self.scene.materials.len() as u32 - 1
            }
        };
        if let Some(em) = emitter {
            let radiance = area_radiance(em)?;
            let mut m = self.scene.materials[material as usize].clone();
            m.emission = radiance;
            // Whitted shows the lamp at its radiance through its ambient term... there is
            // no ambient light in a Mitsuba scene, so it is left as it is: only the path
            // tracer sees emission.
            self.scene.materials.push(m);
            material = self.scene.materials.len() as u32 - 1;
        }
        let name =
            e.attr("id").map(str::to_string).or_else(|| Some(format!("{}@{}", e.attr("type").unwrap_or(""), e.line)));
        let mut actor = Actor::new(name, geometry.mesh, material);
        actor.transform = Transform::new(geometry.to_world.as_mat4());
        if geometry.flat {
            actor.shading = Shading::Flat;
        }
        self.scene.actors.push(actor);
        Ok(())
    }

    fn emitter(&mut self, e: &Elem) -> Result<(), LoadError> {
        let ty = e.required("type")?;
        let mut p = Props::new(e)?;
        match ty {
            "point" => {
                let position = p.point("position")?;
                let to_world = p.transform("to_world")?;
                let intensity = p.color("intensity", true)?.unwrap_or(glam::DVec3::ONE);
                p.finish()?;
                let position = match (position, to_world) {
                    (Some(_), Some(_)) => return Err(e.error("give a point light `position` or `to_world`, not both")),
                    (Some(pos), None) => pos,
                    (None, Some(m)) => m.transform_point3(glam::DVec3::ZERO),
                    (None, None) => glam::DVec3::ZERO,
                };
                self.scene.lights.push(Light {
                    kind: LightKind::Point { position: position.as_vec3(), falloff: 2 },
                    color: (intensity / std::f64::consts::PI).as_vec3(),
                    emitter_stand_in: false,
                });
            }
            "constant" => {
                let radiance = p.color("radiance", true)?.unwrap_or(glam::DVec3::ONE);
                p.finish()?;
                self.scene.environment.background = radiance.as_vec3();
            }
            "area" if e.attr("id").is_some() => {
                // A definition for shapes to `ref`; read (and checked) where it is used.
            }
            "area" => return Err(e.error("an area emitter belongs inside a <shape> (or has an id a shape refers to)")),
            other => {
                return Err(e.error(format!(
                    "<emitter type=\"{other}\"> is not supported (dynray reads area, point, constant)"
                )))
            }
        }
        Ok(())
    }
}

/// The radiance of an `<emitter type="area">`.
fn area_radiance(e: &Elem) -> Result<Color, LoadError> {
    let ty = e.required("type")?;
    if ty != "area" {
        return Err(e.error(format!("a shape's emitter must be `area`, not `{ty}`")));
    }
    let mut p = Props::new(e)?;
    let radiance = p.color("radiance", true)?.unwrap_or(glam::DVec3::ONE);
    p.finish()?;
    if !(radiance.min_element() >= 0.0) {
        return Err(e.error(format!("area radiance {radiance}: negative")));
    }
    Ok(radiance.as_vec3())
}
