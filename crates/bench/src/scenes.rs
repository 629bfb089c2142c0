//! Bench scenes: the named test models of `shared/scenes`, or any mesh/scene file, loaded
//! into a [`Frame`] with a camera that frames them and at least one light.

use anyhow::{bail, Context, Result};
use dynray_scene::{Frame, Scene};
use std::path::{Path, PathBuf};

/// The models the bench knows by name, and their files under the scenes folder.
pub const KNOWN_SCENES: &[(&str, &str)] = &[
    ("bunny", "bunny/bun_zipper.ply"),
    ("dragon", "dragon/dragon_vrip.ply.gz"),
    ("dragon-res2", "dragon/dragon_vrip_res2.ply.gz"),
    ("dragon-res3", "dragon/dragon_vrip_res3.ply.gz"),
    ("dragon-res4", "dragon/dragon_vrip_res4.ply.gz"),
    ("cornell-box", "cornell-box/mcguire-obj/CornellBox-Original.obj"),
    ("duck", "Duck/glTF-Binary/Duck.glb"),
    ("cesium-man", "CesiumMan/glTF-Binary/CesiumMan.glb"),
    ("morph-cube", "AnimatedMorphCube/glTF/AnimatedMorphCube.gltf"),
    ("bart-kitchen", "bart/kitchen/aff/kitchen.aff"),
    ("bart-robots", "bart/robot/aff/Robot.aff"),
    ("bart-museum", "bart/museum/aff/museum5.aff"),
];

/// The name of the built-in demo scene (mirror and glass spheres on a checkerboard, the
/// scene `dynray render` draws): no file needed.
pub const DEMO: &str = "demo";

/// A loaded bench scene.
pub struct BenchScene {
    /// Name as given (`bunny`) or the file's name.
    pub name: String,
    /// The file it was read from.
    pub path: PathBuf,
    /// The flattened frame at t = 0 (camera resolved, lights present).
    pub frame: Frame,
    /// The scene itself when it is animated (`Scene::is_animated`): the dynamic preset
    /// poses it frame by frame.
    pub animated: Option<Scene>,
    /// The file gives its own camera (a bare mesh gets the default view, which
    /// `--framing tight` may move).
    pub own_camera: bool,
}

/// Where the named models live: `explicit` if given, else `$DYNRAY_SCENES`, else
/// `../shared/scenes` from the current directory, else `../shared/scenes` beside the
/// checkout the running executable was built in (found by walking up from it).
pub fn scenes_dir(explicit: Option<&Path>) -> Option<PathBuf> {
    if let Some(d) = explicit {
        return Some(d.to_path_buf());
    }
    if let Some(d) = std::env::var_os("DYNRAY_SCENES") {
        return Some(PathBuf::from(d));
    }
    let cwd = PathBuf::from("../shared/scenes");
    if cwd.is_dir() {
        return Some(cwd);
    }
    let exe = std::env::current_exe().ok()?;
    exe.ancestors().skip(1).filter_map(|a| a.parent()).map(|p| p.join("shared/scenes")).find(|d| d.is_dir())
}

fn known_names() -> String {
    let mut names: Vec<&str> = KNOWN_SCENES.iter().map(|(n, _)| *n).collect();
    names.push(DEMO);
    names.extend(crate::carousel::NAMES.iter().map(|(n, _)| *n));
    names.join(", ")
}

/// Resolves one `--scenes` entry to a file: an existing path, or a known model name.
pub fn resolve(entry: &str, dir: Option<&Path>) -> Result<(String, PathBuf)> {
    let p = Path::new(entry);
    if p.is_file() {
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| entry.to_string());
        return Ok((name, p.to_path_buf()));
    }
    let Some(rel) = KNOWN_SCENES.iter().find(|(n, _)| *n == entry).map(|(_, f)| f) else {
        if dynray_scene::FileFormat::of(p).is_some() {
            bail!("{entry}: no such file");
        }
        bail!("unknown scene `{entry}`: not a file, and not one of the known models ({})", known_names());
    };
    let Some(dir) = dir else {
        bail!(
            "scene `{entry}` needs the test models folder: none found (give --scenes-dir DIR or set DYNRAY_SCENES; \
             looked for ../shared/scenes from here and beside the executable's checkout)"
        );
    };
    let path = dir.join(rel);
    if !path.is_file() {
        bail!("scene `{entry}`: {} does not exist (scenes folder {})", path.display(), dir.display());
    }
    Ok((entry.to_string(), path))
}

/// The built-in demo scene as a bench scene.
pub fn demo() -> BenchScene {
    let mut scene = dynray_scene::demo::demo_scene();
    scene.add_default_light();
    BenchScene {
        name: DEMO.to_string(),
        path: PathBuf::from("(built-in demo scene)"),
        frame: scene.frame(0.0),
        animated: None,
        own_camera: true,
    }
}

/// Loads a resolved scene; the frame gets the scene's camera or one framing its box,
/// and a default light when the file has none (shadow rays need one).
pub fn load(name: &str, path: &Path) -> Result<BenchScene> {
    let mut scene = dynray_scene::load_file(path).with_context(|| format!("scene `{name}`"))?;
    if scene.triangle_count() == 0 {
        bail!("scene `{name}` ({}) has no triangles", path.display());
    }
    scene.add_default_light();
    // `load_file` gives a file without a camera the default view.
    let own_camera = scene.camera != Some(dynray_scene::Camera::default_view(&scene));
    let frame = scene.frame(scene.animation.timeline.time_of(0));
    let animated = scene.is_animated().then_some(scene);
    Ok(BenchScene { name: name.to_string(), path: path.to_path_buf(), frame, animated, own_camera })
}

/// Loads the scenes named in `names` (model names, files, or `demo`).
pub fn load_scenes(names: &[String], dir: Option<&Path>) -> Result<Vec<BenchScene>> {
    let dir = scenes_dir(dir);
    // Resolve every name before loading any, so a typo fails at once (a carousel names
    // its model's file).
    let carousel = |n: &str| crate::carousel::NAMES.iter().find(|(c, _)| *c == n).map(|(_, model)| *model);
    let resolved: Vec<Option<(String, PathBuf)>> = names
        .iter()
        .map(|n| match (n.as_str(), carousel(n)) {
            (DEMO, _) => Ok(None),
            (_, Some(model)) => resolve(model, dir.as_deref()).map(|(_, p)| Some((n.clone(), p))),
            _ => resolve(n, dir.as_deref()).map(Some),
        })
        .collect::<Result<_>>()?;
    resolved
        .iter()
        .map(|r| match r {
            None => Ok(demo()),
            Some((n, p)) if carousel(n).is_some() => load_carousel(n, p),
            Some((n, p)) => load(n, p),
        })
        .collect()
}

/// The carousel around the model file `model` (`crate::carousel`).
fn load_carousel(name: &str, model: &Path) -> Result<BenchScene> {
    let scene = crate::carousel::scene(model)?;
    let frame = scene.frame(scene.animation.timeline.time_of(0));
    Ok(BenchScene { name: name.to_string(), path: model.to_path_buf(), frame, animated: Some(scene), own_camera: true })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_names_list_the_known_ones() {
        let e = resolve("teapot", None).unwrap_err().to_string();
        assert!(e.contains("teapot") && e.contains("dragon-res4") && e.contains("cesium-man"), "{e}");
        let e = resolve("missing.ply", None).unwrap_err().to_string();
        assert!(e.contains("no such file"), "{e}");
    }
}
