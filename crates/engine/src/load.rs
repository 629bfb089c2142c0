//! From a path (or none: the built-in demo) to a scene a job can pose: any scene or mesh
//! file the engine reads, or a distance field (`.adf`) shown in the scene its source
//! mesh would have had. The library does not print: load warnings come back, each
//! distinct one once, for the front end to show.

use anyhow::Result;
use dynray_adf::Adf;
use dynray_scene::{Camera, Material, Scene, Shading};
use std::path::{Path, PathBuf};

/// A loaded scene, unshaded (its vertices as the file gives them): what a job poses.
pub struct Loaded {
    /// The scene; a `.adf` file's is [`field_scene`].
    pub scene: Scene,
    /// How summaries and errors name it: the path, or "built-in demo scene".
    pub label: String,
    /// The file, `None` for the demo.
    pub path: Option<PathBuf>,
    /// The loader's warnings (a missing `.mtl`, …), each distinct one once.
    pub warnings: Vec<String>,
    /// The field, when the file is a distance field.
    pub field: Option<Adf>,
}

impl Loaded {
    /// Loads `path`, or the built-in demo scene when `None`.
    pub fn open(path: Option<&Path>) -> Result<Self> {
        match path {
            None => Ok(Self::demo()),
            Some(p) if is_adf(p) => {
                let adf = Adf::load(p)?;
                let scene = field_scene(&adf);
                Ok(Loaded {
                    scene,
                    label: p.display().to_string(),
                    path: Some(p.into()),
                    warnings: vec![],
                    field: Some(adf),
                })
            }
            Some(p) => {
                let report = dynray_scene::load_file_unshaded(p)?;
                let mut warnings: Vec<String> = Vec::with_capacity(report.warnings.len());
                for w in report.warnings.iter().map(|w| w.to_string()) {
                    if !warnings.contains(&w) {
                        warnings.push(w);
                    }
                }
                Ok(Loaded {
                    scene: report.scene,
                    label: p.display().to_string(),
                    path: Some(p.into()),
                    warnings,
                    field: None,
                })
            }
        }
    }

    /// The built-in demo scene.
    pub fn demo() -> Self {
        Loaded {
            scene: dynray_scene::demo::demo_scene(),
            label: "built-in demo scene".to_string(),
            path: None,
            warnings: vec![],
            field: None,
        }
    }

    /// An in-memory scene (Python's `dynray.Scene`), named `label`.
    pub fn from_scene(scene: Scene, label: impl Into<String>) -> Self {
        Loaded { scene, label: label.into(), path: None, warnings: vec![], field: None }
    }

    /// Applies the shading the scene asks for (flat everywhere when `flat`): generated
    /// normals for smooth meshes that have none. Call once, before posing.
    pub fn shade(&mut self, flat: bool) -> Result<()> {
        // Before applying the shading, so that no normals are generated only to be dropped.
        if flat {
            for actor in &mut self.scene.actors {
                actor.shading = Shading::Flat;
            }
        }
        let label = PathBuf::from(&self.label);
        self.scene.apply_shading().map_err(|source| dynray_scene::LoadError::Mesh { path: label, source }.into())
    }
}

/// True for a path read as a distance field.
pub fn is_adf(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("adf"))
}

/// The scene a field is rendered in: what its source mesh file would have had — the
/// default material, the default light placed for the mesh's box, and the mesh's camera
/// (stored in the file), so `render mesh.ply` and `render mesh.adf` frame the same view.
pub fn field_scene(adf: &Adf) -> Scene {
    let mut scene = Scene { materials: vec![Material::default()], ..Default::default() };
    scene.add_default_light_around(adf.source_bounds());
    scene.camera = Some(match adf.info().view {
        Some(v) => v.camera(),
        None => Camera::framing(&adf.source_bounds()),
    });
    scene
}
