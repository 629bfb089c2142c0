//! glTF `KHR_lights_punctual`: the point, spot and directional lights of a glTF file,
//! placed by the nodes that reference them.
//!
//! A light sits at its node's world origin and shines along the node's local `−z`.
//! The extension gives intensities in photometric units: candela for point and spot
//! lights, lux for directional ones. dynray's Whitted shading multiplies a light's colour
//! by the diffuse reflectance directly (`ρ · E`, no `1/π`), so a glTF light becomes a
//! light of colour `color × intensity / π` — the radiance `ρ E / π` a Lambertian surface
//! reflects — with inverse-square falloff for point and spot lights, as the extension
//! prescribes. Spot cones keep their inner and outer angles (a smooth step between). The
//! optional `range` (a distance beyond which the light may be cut off) is not applied:
//! the extension allows renderers to ignore it.

use crate::{Color, Light, LightKind};
use glam::{Mat4, Vec3};
use gltf::khr_lights_punctual::Kind;
use std::f32::consts::PI;

/// The dynray light for glTF `light` on a node with world matrix `world`; an error
/// saying why when its colour × intensity or the node's matrix is not finite.
pub(crate) fn convert(light: &gltf::khr_lights_punctual::Light<'_>, world: Mat4) -> Result<Light, String> {
    let color = Color::from_array(light.color()) * light.intensity().max(0.0) / PI;
    let position = world.transform_point3(Vec3::ZERO);
    let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    let kind = match light.kind() {
        Kind::Point => LightKind::Point { position, falloff: 2 },
        Kind::Directional => LightKind::Directional { direction },
        Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            let outer = outer_cone_angle.clamp(0.0, PI / 2.0);
            let inner = inner_cone_angle.clamp(0.0, outer);
            LightKind::Spot { position, direction, cos_inner: inner.cos(), cos_outer: outer.cos(), falloff: 2 }
        }
    };
    let placed = match kind {
        LightKind::Directional { direction } => direction != Vec3::ZERO && direction.is_finite(),
        LightKind::Point { position, .. } => position.is_finite(),
        LightKind::Spot { position, direction, .. } => position.is_finite() && direction != Vec3::ZERO,
    };
    if !color.is_finite() {
        return Err(format!(
            "its colour × intensity is not finite ({:?} × {}); skipped",
            light.color(),
            light.intensity()
        ));
    }
    if !placed {
        return Err("its node's transform is not finite (or flattens its direction); skipped".into());
    }
    Ok(Light { kind, color, emitter_stand_in: false })
}
