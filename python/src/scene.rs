//! `dynray.load` and `dynray.Scene`: any file the engine reads, with its mesh as the file
//! has it (unshaded, so triangle numbers are the file's faces, as `trace-rays` numbers
//! them), and what the file says about materials, lights and the camera.

use crate::errors::load_error;
use crate::mesh::Mesh;
use dynray_scene::{LightKind, Projection};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

/// A loaded file: `mesh` (every actor placed and concatenated in file order, the file's
/// own vertices), `materials`, `lights`, `camera`, `size` and the loader's `warnings`.
/// `dynray.render` renders it (smooth shading applied then, as the CLI does).
#[pyclass(module = "dynray", frozen)]
pub struct Scene {
    pub(crate) scene: dynray_scene::Scene,
    pub(crate) path: PathBuf,
    mesh: Py<Mesh>,
    warnings: Vec<String>,
}

/// Loads a mesh or scene file (`.obj` with its `.mtl`, `.ply`, `.ply.gz`, `.gltf`,
/// `.glb`, `.npz` with `vertices` and `faces`, `.scn`). Raises `OSError` (e.g.
/// `FileNotFoundError`, `filename` set) when it cannot be read and `ValueError` naming
/// the file (and line) when its content is wrong or its type unknown. `time` (seconds)
/// or `frame` pose `mesh` at that instant of an animated file, its physics simulated to
/// it: the triangles `trace_rays(..., time=, frame=)` and `dynray trace-rays --time/--frame`
/// trace (the engine's own posing, `dynray_engine::jobs::trace::posed_mesh`).
#[pyfunction]
#[pyo3(signature = (path, *, time = None, frame = None))]
pub fn load(py: Python<'_>, path: PathBuf, time: Option<f32>, frame: Option<u32>) -> PyResult<Scene> {
    let report = py.detach(|| dynray_scene::load_file_unshaded(&path)).map_err(load_error)?;
    let mesh = if time.is_none() && frame.is_none() {
        // Frame 0 is the timeline's start, as every front end counts it (engine's timeline.rs).
        let t0 = dynray_engine::timeline::frame_zero(&report.scene);
        report.scene.frame(t0).mesh
    } else {
        let when = dynray_engine::TimeChoice { time, frame, ..Default::default() };
        let loaded = dynray_engine::Loaded::from_scene(report.scene.clone(), path.display().to_string());
        py.detach(|| when.check().and_then(|()| dynray_engine::jobs::trace::posed_mesh(loaded, &when)))
            .map_err(crate::errors::file_error)?
    };
    let mesh = Py::new(py, Mesh::from_mesh(mesh))?;
    let mut warnings: Vec<String> = Vec::new();
    for w in report.warnings.iter().map(|w| w.to_string()) {
        if !warnings.contains(&w) {
            warnings.push(w);
        }
    }
    Ok(Scene { scene: report.scene, path, mesh, warnings })
}

fn vec3(v: dynray_geom::Vec3) -> [f32; 3] {
    v.to_array()
}

#[pymethods]
impl Scene {
    /// The file this scene was read from.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// Every triangle of the file in one `Mesh`, in file order.
    #[getter]
    fn mesh(&self, py: Python<'_>) -> Py<Mesh> {
        self.mesh.clone_ref(py)
    }

    /// Materials as dicts: name, ambient, diffuse, spot, shine, specular, transparency,
    /// ior, and texture (whether a diffuse image texture is used).
    #[getter]
    fn materials<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for m in &self.scene.materials {
            let d = PyDict::new(py);
            d.set_item("name", &m.name)?;
            d.set_item("ambient", vec3(m.ambient))?;
            d.set_item("diffuse", vec3(m.diffuse))?;
            d.set_item("spot", vec3(m.spot))?;
            d.set_item("shine", m.shine)?;
            d.set_item("specular", vec3(m.specular))?;
            d.set_item("transparency", vec3(m.transparency))?;
            d.set_item("ior", m.ior)?;
            d.set_item("texture", m.diffuse_texture.is_some())?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// Lights as dicts: kind (`point`, `directional`, `spot`), color, and position,
    /// direction, falloff, cos_inner, cos_outer as the kind has them. A mesh file without
    /// lights has the engine's one default point light.
    #[getter]
    fn lights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for l in &self.scene.lights {
            let d = PyDict::new(py);
            d.set_item("color", vec3(l.color))?;
            match l.kind {
                LightKind::Point { position, falloff } => {
                    d.set_item("kind", "point")?;
                    d.set_item("position", vec3(position))?;
                    d.set_item("falloff", falloff)?;
                }
                LightKind::Directional { direction } => {
                    d.set_item("kind", "directional")?;
                    d.set_item("direction", vec3(direction))?;
                }
                LightKind::Spot { position, direction, cos_inner, cos_outer, falloff } => {
                    d.set_item("kind", "spot")?;
                    d.set_item("position", vec3(position))?;
                    d.set_item("direction", vec3(direction))?;
                    d.set_item("cos_inner", cos_inner)?;
                    d.set_item("cos_outer", cos_outer)?;
                    d.set_item("falloff", falloff)?;
                }
            }
            list.append(d)?;
        }
        Ok(list)
    }

    /// The camera as a dict (position, look_at, up, and fov_y_deg for a perspective or
    /// parallel_height for a parallel view); a file without one has the default view.
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(c) = &self.scene.camera else { return Ok(None) };
        let d = PyDict::new(py);
        d.set_item("position", vec3(c.position))?;
        d.set_item("look_at", vec3(c.look_at))?;
        d.set_item("up", vec3(c.up))?;
        match c.projection {
            Projection::Perspective { fov_y_deg } => d.set_item("fov_y_deg", fov_y_deg)?,
            Projection::Parallel { height } => d.set_item("parallel_height", height)?,
        }
        Ok(Some(d))
    }

    /// The image size the file asks for, `(width, height)`.
    #[getter]
    fn size(&self) -> (u32, u32) {
        (self.scene.settings.width, self.scene.settings.height)
    }

    /// What the loader warned about (a missing `.mtl`, a texture it could not read, …),
    /// each once.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let m = self.mesh.bind(py).get();
        format!(
            "Scene({:?}, {} triangles, {} materials, {} lights)",
            self.path.display().to_string(),
            m.inner.triangle_count(),
            self.scene.materials.len(),
            self.scene.lights.len()
        )
    }
}
