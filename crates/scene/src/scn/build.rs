//! The last step: the parsed actors become a [`Scene`]. Spheres are tessellated here,
//! once the final `sphere_detail` (or the image size it is derived from) is known;
//! each actor keeps its object-space mesh and its transform (the frame applies it);
//! materials are shared between actors that use the same one.

use super::animate::Axis;
use super::diag::Diag;
use super::objects::Shape;
use super::parser::{ActorEntry, State};
use crate::animation::Clip;
use crate::shapes::uv_sphere;
use crate::{Actor, Material, Motion, Scene, Settings, Timeline, Transform, Warning};
use dynray_geom::TriangleMesh;
use glam::DMat4;
use std::collections::HashMap;
use std::rc::Rc;

/// Fewest longitude segments `sphere_detail` accepts.
pub const MIN_SPHERE_DETAIL: u32 = 8;

/// Most longitude segments `sphere_detail` accepts (a sphere then has ~8 M triangles).
pub const MAX_SPHERE_DETAIL: u32 = 4096;

/// Largest deviation, in pixels, of a tessellated sphere's silhouette from the true
/// circle when the sphere fills the image (the worst case the automatic detail plans for).
pub const SILHOUETTE_TOLERANCE_PX: f64 = 0.25;

/// Longitude segments for spheres when `settings` gives no `sphere_detail`: a polygon
/// with `n` sides around a circle of radius `r` pixels strays `r (1 - cos(π/n))` from it,
/// so `n` is the smallest count keeping that under [`SILHOUETTE_TOLERANCE_PX`] for a
/// sphere as large as the image (radius = half the larger side). 640×480 gives 80.
pub fn auto_sphere_detail(settings: &Settings) -> u32 {
    let r = (settings.width.max(settings.height) as f64 * 0.5).max(1.0);
    let n = (std::f64::consts::PI / (1.0 - SILHOUETTE_TOLERANCE_PX / r).max(-1.0).acos()).ceil();
    let n = (n as u32).clamp(MIN_SPHERE_DETAIL, MAX_SPHERE_DETAIL);
    n + n % 2
}

/// Memory per generated triangle, structure included: positions and normals of its
/// vertices, its indices, and its share of an acceleration structure's nodes.
const BYTES_PER_TRIANGLE: u64 = 160;

/// Refuses, at the first sphere, spheres whose tessellation would not fit the memory
/// budget ([`dynray_geom::budget`]), before any is generated: `sphere_detail` is bounded
/// per sphere, but a thousand spheres at the bound are not.
fn check_sphere_budget(st: &State, slices: u32) -> Result<(), Diag> {
    let spheres: Vec<&ActorEntry> =
        st.actors.iter().filter(|e| e.object.parts.iter().any(|p| matches!(p.shape, Shape::Sphere { .. }))).collect();
    let Some(first) = spheres.first() else { return Ok(()) };
    let count: u64 =
        st.actors.iter().flat_map(|e| &e.object.parts).filter(|p| matches!(p.shape, Shape::Sphere { .. })).count()
            as u64;
    let each = 2 * (slices as u64 / 2) * slices as u64;
    let what = format!(
        "{count} sphere{} of {each} triangles each (sphere_detail {slices})",
        if count == 1 { "" } else { "s" }
    );
    dynray_geom::budget::check(&what, count.saturating_mul(each).saturating_mul(BYTES_PER_TRIANGLE))
        .map_err(|m| Diag::new(first.file, first.span.clone(), m))
}

/// Builds the scene from everything read.
/// Problems that do not stop it (a texture that cannot be read) go to `warnings`.
pub(crate) fn build(mut st: State, warnings: &mut Vec<Warning>) -> Result<Scene, Diag> {
    let textures = std::mem::take(&mut st.textures);
    let settings = st.settings.as_ref().map(|s| s.0).unwrap_or_default();
    let slices = st.sphere_detail.unwrap_or_else(|| auto_sphere_detail(&settings));
    check_sphere_budget(&st, slices)?;
    let mut scene = Scene {
        settings,
        environment: st.environment.as_ref().map(|e| e.0).unwrap_or_default(),
        camera: st.camera.as_ref().map(|c| c.0),
        lights: st.lights.clone(),
        physics: st.physics.as_ref().map(|p| p.0),
        ..Default::default()
    };
    let axis = Axis { frames: st.frames.unwrap_or(1), frame_rate: st.frame_rate.unwrap_or(24.0) as f64 };
    scene.animation.timeline = Timeline { start: 0.0, frames: axis.frames, frame_rate: axis.frame_rate as f32 };
    let mut channels = Vec::new();
    // Animated actors: (actor, innermost node, statement), placed and checked once the
    // rig is complete.
    let mut animated = Vec::new();
    let mut explicit = Vec::new();
    let mut table = MaterialTable::default();
    for entry in std::mem::take(&mut st.actors) {
        let first_light = scene.lights.len();
        scene.lights.extend_from_slice(&entry.object.lights);
        // Parts of one object share one transform (modifiers apply to the whole object),
        // so the actor keeps its parts in object space and the transform beside them; the
        // frame applies it with the same `f32` matrix the builder once baked with, so
        // world positions keep their bits. Should parts ever differ, each is baked here
        // and the actor has none.
        let first = entry.object.parts.first().map_or(DMat4::IDENTITY, |p| p.transform);
        let shared = entry.object.parts.iter().all(|p| p.transform == first);
        // Only a non-identity matrix is applied: the builder always skipped identities.
        let transform =
            if shared && first != DMat4::IDENTITY { Transform::new(first.as_mat4()) } else { Transform::IDENTITY };
        let mut mesh = TriangleMesh::default();
        let mut materials = Vec::new();
        let mut parts = Vec::with_capacity(entry.object.parts.len());
        for part in &entry.object.parts {
            let mut m = match &part.shape {
                Shape::Mesh(m) => (**m).clone(),
                Shape::Sphere { center, radius } => uv_sphere(*center, *radius, slices / 2, slices),
            };
            if !shared && part.transform != DMat4::IDENTITY {
                m.transform(&part.transform.as_mat4());
            }
            let id = table.index(&mut scene.materials, part.material.as_ref());
            parts.push((m, id));
        }
        // Parts of one object keep their vertex normals only if all have them (a mesh
        // file's parts always agree); otherwise the flat normal is used throughout.
        let all_normals = parts.iter().all(|(m, _)| m.normals.is_some());
        for (mut m, id) in parts {
            if !all_normals {
                m.normals = None;
            }
            materials.extend(std::iter::repeat_n(id, m.triangle_count()));
            mesh.append(&m);
        }
        let node = match &entry.object.anim {
            Some(anim) => {
                let before = if shared { first } else { DMat4::IDENTITY };
                let rig = &mut scene.animation.rig;
                let (moving, leaf) =
                    anim.spec.add_nodes(rig, &mut channels, entry.name.as_deref(), before, anim.after, axis)?;
                // A mesh file's lamps are in the parts' space, i.e. under the animation.
                for light in first_light..scene.lights.len() {
                    scene.animation.light_nodes.push((light, moving));
                }
                Some(leaf)
            }
            None => None,
        };
        match (entry.object.motion.clone(), &entry.object.anim) {
            (Some((Motion::Static, f, s)), Some(anim)) => {
                return Err(Diag::new(f, s, "`motion static` on an animated object")
                    .label("this object moves")
                    .also(anim.spec.file, anim.spec.span.clone(), "animated here")
                    .note("an animated object is dynamic; remove `motion static` or the `animate` block"));
            }
            (Some((m, _, _)), _) => explicit.push((scene.actors.len(), m)),
            (None, _) => {}
        }
        if let Some((_, f, s)) = &entry.object.elastic {
            if let Some(anim) = &entry.object.anim {
                return Err(Diag::new(*f, s.clone(), "an `elastic` body cannot also be keyframe-animated")
                    .label("the simulation moves this object")
                    .also(anim.spec.file, anim.spec.span.clone(), "animated here")
                    .note("remove the `animate` block or the `elastic` one"));
            }
            if let Some((Motion::Static, mf, ms)) = &entry.object.motion {
                return Err(Diag::new(*mf, ms.clone(), "`motion static` on an `elastic` body")
                    .label("the simulation moves this object")
                    .also(*f, s.clone(), "`elastic` given here")
                    .note("a simulated body is dynamic; remove `motion static`"));
            }
            explicit.push((scene.actors.len(), Motion::Dynamic));
        }
        let actor = Actor {
            materials,
            transform,
            motion: Motion::Static,
            node,
            deform: None,
            elastic: entry.object.elastic.as_ref().map(|e| e.0),
            shading: entry.object.shading,
            ..Actor::new(entry.name, mesh, 0)
        };
        if let Some(leaf) = node {
            animated.push((scene.actors.len(), leaf, entry.file, entry.span));
            scene.actors.push(actor);
            continue;
        }
        // Checked in world space, as the frame will hold it: a transform can overflow
        // `f32`. (Indices and attributes are the same in both spaces.)
        let checked = if transform.is_identity() { actor.mesh.validate() } else { actor.world_mesh().validate() };
        if let Err(e) = checked {
            return Err(Diag::new(entry.file, entry.span, format!("this object's geometry is unusable: {e}"))
                .label("placed here")
                .note("a transform may have pushed coordinates beyond single precision"));
        }
        scene.actors.push(actor);
    }
    for field in std::mem::take(&mut st.fields) {
        let material = table.index(&mut scene.materials, field.material.as_ref());
        let m = field.transform;
        // The field is marched in its own space, so the map to it must exist.
        if !m.is_finite() || m.determinant() == 0.0 || !m.as_mat4().inverse().is_finite() {
            return Err(Diag::new(field.at.0, field.at.1, "this distance field's transform cannot be inverted")
                .label("placed here")
                .note(
                    "a scale of zero (or a non-finite value) flattens the field; rays are marched in its own space",
                ));
        }
        let transform = if m == DMat4::IDENTITY { Transform::IDENTITY } else { Transform::new(m.as_mat4()) };
        scene.distance_fields.push(crate::FieldPlacement { file: field.file, transform, material });
    }
    animate_lights_and_camera(&mut scene, &st, &mut channels, axis)?;
    place_animated(&mut scene, channels, &animated)?;
    // Built here, so never expected to fail; a failure is reported rather than trusted.
    scene.validate_animation().map_err(|e| {
        Diag::new(0, 0..0, format!("internal error: the scene's animation is inconsistent: {e}"))
            .note("this is a bug in dynray; please report it with this file")
    })?;
    scene.mark_moving_actors();
    for (a, m) in explicit {
        scene.actors[a].motion = m;
    }
    super::textures::resolve(&mut scene, textures, warnings);
    Ok(scene)
}

/// The scene's materials as parts and fields name them: each parsed material once
/// (shared `Rc`s are one material), and one default material for whatever names none.
#[derive(Default)]
struct MaterialTable {
    index_of: HashMap<*const Material, u32>,
    default_index: Option<u32>,
}

impl MaterialTable {
    /// The index in `materials` of `m` (`None`: the default), added on first use.
    fn index(&mut self, materials: &mut Vec<Material>, m: Option<&Rc<Material>>) -> u32 {
        let mut push = |m: Material| {
            materials.push(m);
            materials.len() as u32 - 1
        };
        match m {
            Some(mat) => *self.index_of.entry(Rc::as_ptr(mat)).or_insert_with(|| push((**mat).clone())),
            None => *self.default_index.get_or_insert_with(|| push(Material::default())),
        }
    }
}

/// Nodes for the animated lights (`animation.light_nodes`) and the animated camera
/// (`animation.camera_node`), each given in its node's space.
fn animate_lights_and_camera(
    scene: &mut Scene,
    st: &State,
    channels: &mut Vec<crate::animation::Channel>,
    axis: Axis,
) -> Result<(), Diag> {
    let rig = &mut scene.animation.rig;
    for (light, spec) in &st.light_anims {
        let (node, _) = spec.add_nodes(rig, channels, None, DMat4::IDENTITY, DMat4::IDENTITY, axis)?;
        scene.animation.light_nodes.push((*light, node));
    }
    if let Some(spec) = &st.camera_anim {
        let (node, _) = spec.add_nodes(rig, channels, Some("camera"), DMat4::IDENTITY, DMat4::IDENTITY, axis)?;
        scene.animation.camera_node = Some(node);
    }
    Ok(())
}

/// Gives the rig its one clip ("scene") and each animated actor its placement at time 0
/// as [`Actor::transform`], checking the geometry there as static actors are checked.
fn place_animated(
    scene: &mut Scene,
    channels: Vec<crate::animation::Channel>,
    animated: &[(usize, u32, super::diag::FileId, std::ops::Range<usize>)],
) -> Result<(), Diag> {
    let rig = &mut scene.animation.rig;
    if !channels.is_empty() {
        rig.clips.push(Clip { name: Some("scene".into()), channels });
    }
    if rig.nodes.is_empty() {
        return Ok(());
    }
    let mut world = Vec::new();
    rig.world_matrices(0.0, &mut world);
    for (a, leaf, file, span) in animated {
        let actor = &mut scene.actors[*a];
        actor.transform = Transform::new(world[*leaf as usize]);
        if let Err(e) = actor.world_mesh().validate() {
            return Err(Diag::new(*file, span.clone(), format!("this object's geometry is unusable: {e}"))
                .label("placed here")
                .note("a transform may have pushed coordinates beyond single precision"));
        }
    }
    Ok(())
}
