//! The distance fields a scene places (`.scn` `adf { … }`, [`Frame::distance_fields`]):
//! loaded once per job, then intersected beside the frame's triangles through the
//! engine's one scene-level intersector and render loop.

use anyhow::{Context, Result};
use dynray_accel::Accel;
use dynray_adf::{Adf, AdfGeometry};
use dynray_geom::Aabb;
use dynray_render::{render_with, Aov, AovIntegrator, Film, Geometry, RenderOptions, RenderStats, SceneIntersector};
use dynray_render::{Integrator, TriangleGeometry};
use dynray_scene::{FieldPlacement, Frame};
use std::path::PathBuf;

/// The fields of a scene, each file read once however often it is placed.
#[derive(Default)]
pub struct Fields {
    files: Vec<(PathBuf, Adf)>,
}

impl Fields {
    /// Reads every file of `placements` (a scene's or frame's `distance_fields`); an
    /// unreadable one is an error naming it and the scene (`label`).
    pub fn load(placements: &[FieldPlacement], label: &str) -> Result<Self> {
        let mut files: Vec<(PathBuf, Adf)> = Vec::new();
        for f in placements {
            if files.iter().all(|(p, _)| *p != f.file) {
                let adf = Adf::load(&f.file).with_context(|| format!("{label}: its `adf` block"))?;
                files.push((f.file.clone(), adf));
            }
        }
        Ok(Self { files })
    }

    /// True when the scene places no field.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    /// The frame's geometries: its triangles through `accel` (built on `frame.mesh`),
    /// then each field in placement order.
    pub fn scene<'a>(&'a self, frame: &'a Frame, accel: &'a dyn Accel) -> SceneIntersector<'a> {
        let mut geometries: Vec<Box<dyn Geometry + 'a>> = vec![Box::new(TriangleGeometry::new(frame, accel))];
        geometries.extend(self.geometries(frame).map(|g| Box::new(g) as Box<dyn Geometry + 'a>));
        SceneIntersector::new(geometries)
    }

    /// `" and N distance fields"` for a command's summary line; empty without any.
    pub fn describe(&self, frame: &Frame) -> String {
        match frame.distance_fields.len() {
            0 => String::new(),
            1 => " and 1 distance field".to_string(),
            n => format!(" and {n} distance fields"),
        }
    }

    /// The fields alone (a scene without triangles, which no structure can be built on).
    pub fn fields_only<'a>(&'a self, frame: &'a Frame) -> SceneIntersector<'a> {
        SceneIntersector::new(self.geometries(frame).map(|g| Box::new(g) as Box<dyn Geometry + 'a>).collect())
    }

    /// World bounds of the fields `frame` places (empty when none).
    pub fn bounds(&self, frame: &Frame) -> Aabb {
        self.geometries(frame).fold(Aabb::EMPTY, |b, g| b.union(&g.bounds()))
    }

    /// Each field of `frame`, placed and with its material.
    fn geometries<'a>(&'a self, frame: &'a Frame) -> impl Iterator<Item = AdfGeometry<'a>> + 'a {
        frame.distance_fields.iter().filter_map(|f| {
            // `load` read every file of this frame's scene.
            let (_, adf) = self.files.iter().find(|(p, _)| *p == f.file)?;
            let material = frame.materials.get(f.material as usize).cloned().unwrap_or_default();
            Some(if f.transform.is_identity() {
                AdfGeometry::new(adf, material)
            } else {
                AdfGeometry::placed(adf, material, f.transform.matrix())
            })
        })
    }
}

/// `dynray_render::render` over the frame's triangles and its fields.
pub fn render(frame: &Frame, accel: &dyn Accel, fields: &Fields, options: &RenderOptions<'_>) -> (Film, RenderStats) {
    if fields.is_empty() {
        return dynray_render::render(frame, accel, options);
    }
    let scene = fields.scene(frame, accel);
    let integrator: Box<dyn Integrator + '_> = options.integrator.create(frame, &scene, &options.params);
    render_with(frame, integrator.as_ref(), options)
}

/// `dynray_render::render_aov` over the frame's triangles and its fields.
pub fn render_aov(frame: &Frame, accel: &dyn Accel, fields: &Fields, aov: Aov, options: &RenderOptions<'_>) -> Film {
    if fields.is_empty() {
        return dynray_render::render_aov(frame, accel, aov, options);
    }
    let scene = fields.scene(frame, accel);
    render_with(frame, &AovIntegrator::new(aov, &scene), &RenderOptions { spp: 1, passes: 1, ..*options }).0
}
