//! `<shape>` geometry: `obj` and `ply` files, and Mitsuba's `rectangle`, `cube` and
//! `sphere`, each as a mesh in its local space and the `to_world` matrix that places it.
//!
//! - `rectangle`: `[-1, 1]²` in the plane z = 0, normal +z (two triangles).
//! - `cube`: `[-1, 1]³`, normals outwards (12 triangles).
//! - `sphere`: `center` and `radius` (defaults 0 and 1), tessellated as an icosphere of
//!   [`SPHERE_LEVELS`] subdivisions (81,920 triangles) with the analytic normals at its
//!   vertices. The triangles lie inside the true sphere by at most 7.2·10⁻⁵ of the radius
//!   (a unit test measures it): on the reference scene's unit sphere seen from 6 units
//!   through 256 pixels over 40°, 0.005 of a pixel, far below the noise of any render.
//!   dynray's scene intersector could take an analytic sphere (a `Geometry`), but the
//!   scene model and every structure are triangle meshes; the tessellation keeps one path.
//! - `obj`: read by dynray's OBJ loader (its polygons fan-triangulated, its materials
//!   and `Ke` lamps dropped: the XML gives the BSDF and emitter); `ply` likewise.
//!
//! `face_normals="true"` drops vertex normals (flat shading); `flip_normals="true"`
//! turns the surface around (winding and normals), which flips a one-sided BSDF or
//! emitter too.

use super::props::Props;
use super::tree::Elem;
use crate::{shapes, LoadError, Warning};
use dynray_geom::{TriangleMesh, Vec3};
use glam::{DMat4, DVec3};

/// Subdivisions of the icosphere that stands for Mitsuba's analytic `sphere`.
pub const SPHERE_LEVELS: u32 = 6;

/// A shape's geometry in local space.
pub(super) struct ShapeGeometry {
    pub mesh: TriangleMesh,
    pub to_world: DMat4,
    /// `face_normals`: shade with the triangles' own normals.
    pub flat: bool,
}

/// Reads the geometry of `<shape>` `e` from `p` (its properties), leaving the BSDF and
/// emitter children to the caller.
pub(super) fn read_geometry(
    e: &Elem,
    p: &mut Props<'_>,
    warnings: &mut Vec<Warning>,
) -> Result<ShapeGeometry, LoadError> {
    let ty = e.required("type")?;
    let mut to_world = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
    let flip = p.boolean("flip_normals", false)?;
    let mut flat = false;
    let mut mesh = match ty {
        "obj" | "ply" => {
            let (file, _) =
                p.string("filename")?.ok_or_else(|| e.error(format!("<shape type=\"{ty}\"> needs a `filename`")))?;
            flat = p.boolean("face_normals", false)?;
            // Texture coordinates are not used by any supported BSDF.
            p.boolean("flip_tex_coords", true)?;
            let path = e.resolve(&file)?;
            let wrap = |err: LoadError| e.error(format!("{err}"));
            if ty == "obj" {
                let report = crate::formats::obj::load(&path).map_err(wrap)?;
                warnings.extend(report.warnings);
                concat(report.scene.actors.into_iter().map(|a| a.world_mesh()))
            } else {
                crate::formats::ply::load(&path).map_err(wrap)?
            }
        }
        "rectangle" => TriangleMesh {
            positions: vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            normals: Some(vec![[0.0, 0.0, 1.0]; 4]),
            uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
        },
        "cube" => shapes::cuboid(Vec3::ZERO, Vec3::splat(2.0), Vec3::ZERO),
        "sphere" => {
            let center = p.point("center")?.unwrap_or(DVec3::ZERO);
            let radius = p.float("radius", 1.0)?;
            if !(radius > 0.0) {
                return Err(e.error(format!("sphere radius {radius}: must be positive")));
            }
            to_world = to_world * DMat4::from_translation(center) * DMat4::from_scale(DVec3::splat(radius));
            shapes::icosphere(Vec3::ZERO, 1.0, SPHERE_LEVELS)
        }
        other => {
            return Err(e.error(format!(
                "<shape type=\"{other}\"> is not supported (dynray reads obj, ply, rectangle, cube, sphere)"
            )))
        }
    };
    if mesh.indices.is_empty() {
        return Err(e.error(format!("<shape type=\"{ty}\"> has no triangles")));
    }
    if flip {
        for t in &mut mesh.indices {
            t.swap(1, 2);
        }
        if let Some(ns) = &mut mesh.normals {
            for n in ns {
                *n = n.map(|c| -c);
            }
        }
    }
    Ok(ShapeGeometry { mesh, to_world, flat })
}

/// The meshes one after the other; normals and uvs kept only when every part has them.
fn concat(parts: impl Iterator<Item = TriangleMesh>) -> TriangleMesh {
    let parts: Vec<TriangleMesh> = parts.collect();
    let all_normals = parts.iter().all(|m| m.normals.is_some());
    let all_uvs = parts.iter().all(|m| m.uvs.is_some());
    let mut out =
        TriangleMesh { normals: all_normals.then(Vec::new), uvs: all_uvs.then(Vec::new), ..Default::default() };
    for m in parts {
        let base = out.positions.len() as u32;
        out.indices.extend(m.indices.iter().map(|t| t.map(|i| i + base)));
        out.positions.extend_from_slice(&m.positions);
        if let (Some(o), Some(n)) = (&mut out.normals, &m.normals) {
            o.extend_from_slice(n);
        }
        if let (Some(o), Some(u)) = (&mut out.uvs, &m.uvs) {
            o.extend_from_slice(u);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound the module docs state: every triangle of the sphere's tessellation lies
    /// within 7.2e-5 of the unit sphere (its centroids are the farthest points inside).
    #[test]
    fn tessellated_sphere_is_within_its_stated_error() {
        let m = shapes::icosphere(Vec3::ZERO, 1.0, SPHERE_LEVELS);
        assert_eq!(m.indices.len(), 81_920);
        let worst = m
            .indices
            .iter()
            .map(|t| {
                let c = t.iter().map(|&i| Vec3::from_array(m.positions[i as usize])).sum::<Vec3>() / 3.0;
                1.0 - c.length()
            })
            .fold(0.0f32, f32::max);
        assert!(worst > 1e-5 && worst < 7.2e-5, "largest distance inside the sphere: {worst}");
    }
}
