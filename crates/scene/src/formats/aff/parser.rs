//! The command loop: reads each command of a file (and of the files it includes), keeps
//! the state they change (material in effect, transform stack, view, lights) and hands
//! geometry to `geometry.rs`, keyframes to `anim.rs`, materials to `material.rs`.

use super::anim::{Keyframes, Range};
use super::geometry::{self, Groups, Place};
use super::lexer::Tokens;
use super::material::Materials;
use crate::animation::{Node, NodePose};
use crate::{Camera, Color, Light, LightKind, LoadError, Projection, Scene, Warning};
use glam::{Mat4, Quat, Vec3};
use std::path::{Path, PathBuf};

/// Blocks (`x`/`xs` bodies) may nest this deep; deeper is an error, not a stack overflow.
const MAX_NESTING: usize = 256;
/// Includes may nest this deep (cycles are caught before; this bounds the recursion).
const MAX_INCLUDE_DEPTH: usize = 64;

/// The `v` command's view.
#[derive(Clone, Copy, Debug)]
pub(super) struct View {
    pub from: Vec3,
    pub at: Vec3,
    pub up: Vec3,
    pub angle: f32,
}

/// Everything read so far.
#[derive(Default)]
pub(super) struct Loader {
    pub scene: Scene,
    pub warnings: Vec<Warning>,
    pub materials: Materials,
    pub groups: Groups,
    pub keys: Keyframes,
    pub range: Option<Range>,
    pub view: Option<View>,
    /// Canonical paths of the files being read, outermost first (cycle detection).
    includes: Vec<PathBuf>,
    nesting: usize,
}

impl Loader {
    /// Reads `path` (already known to exist and canonical as `canonical`) with geometry
    /// placed at `place`.
    pub fn read_file(&mut self, path: &Path, canonical: PathBuf, text: &str, place: Place) -> Result<(), LoadError> {
        if self.includes.len() >= MAX_INCLUDE_DEPTH {
            return Err(LoadError::parse(path, None, format!("includes nested deeper than {MAX_INCLUDE_DEPTH}")));
        }
        self.includes.push(canonical);
        let mut t = Tokens::new(path, text);
        let r = self.commands(&mut t, place, None);
        self.includes.pop();
        r
    }

    /// Commands until the end of the file, or until the `}` closing the block opened at
    /// line `open`.
    fn commands(&mut self, t: &mut Tokens<'_>, place: Place, open: Option<usize>) -> Result<(), LoadError> {
        while let Some(w) = t.peek() {
            t.word("a command")?;
            match w.text {
                "}" if open.is_some() => return Ok(()),
                "}" => return Err(t.error(w.line, "`}` without a matching `{`")),
                "v" => self.read_view(t)?,
                "b" => self.scene.environment.background = Color::from_array(t.vec3("`b` background colour")?),
                "am" => self.scene.environment.ambient = Color::from_array(t.vec3("`am` ambient colour")?),
                "l" => self.read_light(t, &place)?,
                "f" => self.materials.read_f(t, &mut self.scene)?,
                "fm" => self.materials.read_fm(t, &mut self.scene)?,
                "p" | "pp" => {
                    let m = self.materials.current(&mut self.scene);
                    geometry::read_polygon(t, w.text == "pp", &mut self.groups, &place, m)?;
                }
                "s" => {
                    let m = self.materials.current(&mut self.scene);
                    geometry::read_sphere(t, &mut self.groups, &place, m)?;
                }
                "c" => {
                    let m = self.materials.current(&mut self.scene);
                    geometry::read_cone(t, &mut self.groups, &place, m)?;
                }
                "tt" | "ttp" => {
                    let name = t.word("a texture file name")?;
                    let m = self.materials.textured(&mut self.scene, &mut self.warnings, t.path, name.line, name.text);
                    geometry::read_textured_triangle(t, w.text == "ttp", &mut self.groups, &place, m)?;
                }
                "tpa" => {
                    let m = self.materials.current(&mut self.scene);
                    geometry::read_tpa(t, &mut self.groups, &place, m)?;
                }
                "m" => {
                    let m = self.materials.current(&mut self.scene);
                    let (mats, scene, warnings, path) =
                        (&mut self.materials, &mut self.scene, &mut self.warnings, t.path);
                    let texture = |line: usize, name: &str| mats.textured(scene, warnings, path, line, name);
                    geometry::read_mesh(t, &mut self.groups, &place, m, texture)?;
                }
                "x" => {
                    let name = t.word("the transform's name after `x`")?;
                    let node = self.animated_node(name.text, &place);
                    self.keys.animated(node, name.text, t.path, name.line);
                    t.expect("{", &format!("after `x {}`", name.text))?;
                    self.block(t, Place { node: Some(node), local: Mat4::IDENTITY }, w.line)?;
                }
                "xs" => {
                    let s = Vec3::from_array(t.vec3("`xs` scale")?);
                    let axis = Vec3::from_array(t.vec3("`xs` rotation axis")?);
                    let deg = t.number("`xs` rotation angle")?;
                    let tr = Vec3::from_array(t.vec3("`xs` translation")?);
                    let r = if axis.length_squared() > 0.0 {
                        Quat::from_axis_angle(axis.normalize(), deg.to_radians())
                    } else if deg == 0.0 {
                        Quat::IDENTITY
                    } else {
                        return Err(t.error(w.line, "`xs`: the rotation axis is zero"));
                    };
                    t.expect("{", "after the `xs` transform")?;
                    let local = place.local * Mat4::from_scale_rotation_translation(s, r, tr);
                    self.block(t, Place { node: place.node, local }, w.line)?;
                }
                "k" => self.keys.read_k(t)?,
                "a" => self.read_range(t, w.line)?,
                "i" => self.include(t, &place, w.line)?,
                other => {
                    const KNOWN: &str = "v b am l f fm p pp s c tt ttp tpa m x xs k a i";
                    return Err(t.error(w.line, format!("unknown command `{other}` (AFF/NFF commands: {KNOWN})")));
                }
            }
        }
        match open {
            Some(line) => {
                Err(t.error(t.line(), format!("end of file inside the block opened at line {line} (missing `}}`)")))
            }
            None => Ok(()),
        }
    }

    fn block(&mut self, t: &mut Tokens<'_>, place: Place, line: usize) -> Result<(), LoadError> {
        if self.nesting >= MAX_NESTING {
            return Err(t.error(line, format!("transform blocks nested deeper than {MAX_NESTING}")));
        }
        self.nesting += 1;
        let r = self.commands(t, place, Some(line));
        self.nesting -= 1;
        r
    }

    /// The node of `x name` under `place`: the static transforms above it become a
    /// matrix node first (they cannot be baked into an animated node's keys).
    fn animated_node(&mut self, name: &str, place: &Place) -> u32 {
        let nodes = &mut self.scene.animation.rig.nodes;
        let mut parent = place.node;
        if place.local != Mat4::IDENTITY {
            nodes.push(Node {
                name: Some(format!("{name} (static parent)")),
                parent,
                rest: NodePose::Matrix(place.local),
                rest_weights: Vec::new(),
            });
            parent = Some(nodes.len() as u32 - 1);
        }
        nodes.push(Node { name: Some(name.to_string()), parent, rest: NodePose::IDENTITY, rest_weights: Vec::new() });
        nodes.len() as u32 - 1
    }

    /// `v` and its `from`, `at`, `up`, `angle`, `hither`, `resolution` lines.
    fn read_view(&mut self, t: &mut Tokens<'_>) -> Result<(), LoadError> {
        let mut view = self.view.unwrap_or(View { from: Vec3::Z, at: Vec3::ZERO, up: Vec3::Y, angle: 45.0 });
        let line = t.line();
        while let Some(w) = t.peek() {
            match w.text {
                "from" | "at" | "up" | "angle" | "hither" | "resolution" => t.word("a view parameter")?,
                _ => break,
            };
            let what = format!("`v` {}", w.text);
            match w.text {
                "from" => view.from = Vec3::from_array(t.vec3(&what)?),
                "at" => view.at = Vec3::from_array(t.vec3(&what)?),
                "up" => view.up = Vec3::from_array(t.vec3(&what)?),
                "angle" => {
                    view.angle = t.number(&what)?;
                    if !(view.angle > 0.0 && view.angle < 180.0) {
                        return Err(
                            t.error(w.line, format!("`v` angle must be in (0, 180) degrees, found {}", view.angle))
                        );
                    }
                }
                // dynray's cameras have no near plane.
                "hither" => {
                    t.number(&what)?;
                }
                _ => {
                    let (wd, ht) = (t.count(&what)?, t.count(&what)?);
                    if wd == 0 || ht == 0 {
                        return Err(t.error(w.line, format!("`v` resolution {wd} × {ht} is empty")));
                    }
                    (self.scene.settings.width, self.scene.settings.height) = (wd as u32, ht as u32);
                }
            }
        }
        // A camera that looks nowhere, or rolls about an undefined axis, renders nothing
        // meaningful: say so rather than draw an empty image.
        if view.from == view.at {
            return Err(t.error(
                line,
                format!("`v`: `from` and `at` are the same point {:?}: the camera looks nowhere", view.from),
            ));
        }
        if (view.at - view.from).cross(view.up).length_squared() == 0.0 {
            return Err(t.error(line, format!("`v`: `up` {:?} is parallel to the view direction", view.up)));
        }
        self.view = Some(view);
        self.scene.camera = Some(Camera {
            position: view.from,
            look_at: view.at,
            up: view.up,
            projection: Projection::Perspective { fov_y_deg: view.angle },
            clip: crate::Clip::NONE,
        });
        Ok(())
    }

    /// `l x y z [r g b]`: a point light, placed like geometry.
    fn read_light(&mut self, t: &mut Tokens<'_>, place: &Place) -> Result<(), LoadError> {
        let p = t.vec3("`l` position")?;
        let color = if t.next_is_number() { Color::from_array(t.vec3("`l` colour")?) } else { Color::ONE };
        let position = Vec3::from_array(place.point(p));
        self.scene.lights.push(Light {
            kind: LightKind::Point { position, falloff: 0 },
            color,
            emitter_stand_in: false,
        });
        if let Some(node) = place.node {
            self.scene.animation.light_nodes.push((self.scene.lights.len() - 1, node));
        }
        Ok(())
    }

    /// `a start end frames`.
    fn read_range(&mut self, t: &mut Tokens<'_>, line: usize) -> Result<(), LoadError> {
        let start = t.number("`a` start time")?;
        let end = t.number("`a` end time")?;
        let frames = t.count("`a` frame count")?;
        if end <= start || frames == 0 {
            return Err(t.error(line, format!("`a {start} {end} {frames}`: needs start < end and at least one frame")));
        }
        if let Some(r) = &self.range {
            return Err(t.error(line, format!("a second `a` line (the first at {}:{})", r.path.display(), r.line)));
        }
        self.range = Some(Range { start, end, frames: frames as u32, path: t.path.to_path_buf(), line });
        Ok(())
    }

    /// `i level file`: reads `file`, relative to the including file, in place.
    fn include(&mut self, t: &mut Tokens<'_>, place: &Place, line: usize) -> Result<(), LoadError> {
        // BART's detail level; every level's geometry is read.
        t.number("`i` detail level")?;
        let name = t.word("the file name after `i`")?;
        let dir = t.path.parent().unwrap_or(Path::new(""));
        let file = self.materials.root().check(&dir.join(name.text)).map_err(|m| t.error(line, m))?;
        let canonical = std::fs::canonicalize(&file)
            .map_err(|e| t.error(line, format!("include `{}`: cannot read {}: {e}", name.text, file.display())))?;
        if let Some(at) = self.includes.iter().position(|p| *p == canonical) {
            let chain: Vec<String> = self.includes[at..]
                .iter()
                .chain(std::iter::once(&canonical))
                .map(|p| p.file_name().map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into_owned()))
                .collect();
            return Err(t.error(line, format!("include cycle: {}", chain.join(" → "))));
        }
        let bytes = dynray_geom::file::read(&file)
            .map_err(|e| t.error(line, format!("include `{}`: cannot read {}: {e}", name.text, file.display())))?;
        let text = String::from_utf8_lossy(&bytes);
        self.read_file(&file, canonical, &text, *place)
    }
}
