//! MTL material libraries (the companions of OBJ files): parsing and the mapping to
//! dynray's [`Material`].
//!
//! dynray parses MTL itself rather than through tobj because tobj's MTL reader panics on
//! a colour with fewer than three numbers and reports no line numbers.
//!
//! The mapping to [`Material`] is documented (as a table) in [`super::obj`].
//!
//! A colour may be given as one number (grey) or three; `spectral` and `xyz` colours are
//! not supported and give a warning. `map_Kd` is read (file name and its `-o`, `-s`,
//! `-clamp` options; other options are skipped with a warning); the other texture maps
//! (`map_Ks`, `bump`, …) are not used, which one warning per library says. `Tf`,
//! `sharpness` and every other statement are ignored.

use crate::report::Warning;
use crate::texture::{ColorSpace, TextureSampler, Wrap};
use crate::{Color, Environment, Finish, LoadError, Material, Scene, Texture, TextureRef};
use glam::{Affine2, Vec2};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A `map_Kd` statement: the image file (as written, relative to the `.mtl`) and the
/// options dynray applies.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TextureMap {
    /// File name as written.
    pub file: String,
    /// 1-based line of the statement.
    pub line: usize,
    /// `-o u v`: added to the uv after scaling.
    pub offset: Vec2,
    /// `-s u v`: multiplies the uv.
    pub scale: Vec2,
    /// `-clamp on`: clamp to the edge instead of repeating.
    pub clamp: bool,
}

/// One `newmtl` block as written in the file.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct MtlMaterial {
    pub name: String,
    pub ka: Option<Color>,
    pub kd: Option<Color>,
    pub ks: Option<Color>,
    pub ke: Option<Color>,
    pub ns: Option<f32>,
    pub ni: Option<f32>,
    pub d: Option<f32>,
    pub tr: Option<f32>,
    pub illum: Option<u32>,
    pub map_kd: Option<TextureMap>,
    /// The `.mtl` file it was read from (texture files are relative to it).
    pub library: PathBuf,
}

impl MtlMaterial {
    /// Emitted radiance, when the material emits.
    pub fn emission(&self) -> Option<Color> {
        self.ke.filter(|e| e.max_element() > 0.0)
    }

    /// The dynray material (mapping in the module docs).
    pub fn to_material(&self) -> Material {
        let base = Material::default();
        let diffuse = self.kd.unwrap_or(base.diffuse);
        let ks = self.ks.unwrap_or(Color::ZERO);
        let mirror = matches!(self.illum, Some(3 | 5 | 7));
        let opacity = match (self.d, self.tr) {
            (Some(d), _) => d,
            (None, Some(tr)) => 1.0 - tr,
            (None, None) => 1.0,
        };
        let ambient = match self.emission() {
            // Under the scene's ambient light the emitter then shows its own radiance.
            Some(ke) => ke / Environment::default().ambient.max(Color::splat(1e-6)),
            None => self.ka.unwrap_or(diffuse * Finish::default().ambient),
        };
        Material {
            name: self.name.clone(),
            ambient,
            diffuse,
            spot: ks,
            shine: self.ns.unwrap_or(Finish::default().shine),
            specular: if mirror { ks } else { Color::ZERO },
            transparency: Color::splat((1.0 - opacity).clamp(0.0, 1.0)),
            ior: self.ni.unwrap_or(1.0),
            diffuse_texture: None,
            // The path tracer's area light (obj.rs, "Emitters").
            emission: self.emission().unwrap_or(Color::ZERO),
            bsdf: None,
        }
    }
}

/// Parses an MTL file's text. `path` labels errors and warnings.
pub(crate) fn parse(path: &Path, text: &str, warnings: &mut Vec<Warning>) -> Result<Vec<MtlMaterial>, LoadError> {
    let mut out: Vec<MtlMaterial> = Vec::new();
    // Texture statements dynray does not use, for one warning at the end.
    let mut unused_maps: Vec<String> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else { continue };
        let err = |m: String| LoadError::parse(path, Some(line_no), m);
        if key == "newmtl" {
            let name = line[key.len()..].trim();
            if name.is_empty() {
                return Err(err("`newmtl` without a name".into()));
            }
            out.push(MtlMaterial { name: name.to_string(), library: path.to_path_buf(), ..Default::default() });
            continue;
        }
        if key == "map_Kd" {
            let Some(m) = out.last_mut() else {
                return Err(err("`map_Kd` before any `newmtl`".into()));
            };
            // The file name may contain spaces: take it from the raw line, not the words.
            m.map_kd = texture_map(path, line_no, line[key.len()..].trim(), warnings);
            continue;
        }
        let is_map = key.starts_with("map_") || ["bump", "disp", "decal", "refl", "norm"].contains(&key);
        if is_map {
            if !unused_maps.iter().any(|k| k == key) {
                unused_maps.push(key.to_string());
            }
            continue;
        }
        let known = ["Ka", "Kd", "Ks", "Ke", "Ns", "Ni", "d", "Tr", "illum"];
        if !known.contains(&key) {
            continue; // Tf, sharpness, …: not used by dynray
        }
        let Some(m) = out.last_mut() else {
            return Err(err(format!("`{key}` before any `newmtl`")));
        };
        let args: Vec<&str> = words.collect();
        let number = |w: &str| -> Result<f32, LoadError> {
            match w.parse::<f32>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(err(format!("`{key}`: expected a finite number, found `{w}`"))),
            }
        };
        match key {
            "Ka" | "Kd" | "Ks" | "Ke" => {
                let c = match args.as_slice() {
                    ["spectral" | "xyz", ..] => {
                        warnings.push(Warning::new(
                            path,
                            Some(line_no),
                            format!("`{key} {}` colours are not supported; ignored", args[0]),
                        ));
                        continue;
                    }
                    [g] => Color::splat(number(g)?),
                    [r, g, b] => Color::new(number(r)?, number(g)?, number(b)?),
                    _ => return Err(err(format!("`{key}`: expected 1 or 3 numbers, found {}", args.len()))),
                };
                let slot = match key {
                    "Ka" => &mut m.ka,
                    "Kd" => &mut m.kd,
                    "Ks" => &mut m.ks,
                    _ => &mut m.ke,
                };
                *slot = Some(c);
            }
            _ => {
                let [w] = args.as_slice() else {
                    return Err(err(format!("`{key}`: expected one number, found {}", args.len())));
                };
                match key {
                    "Ns" => m.ns = Some(number(w)?),
                    "Ni" => {
                        let v = number(w)?;
                        if v <= 0.0 {
                            return Err(err(format!("`Ni`: index of refraction must be positive, found {v}")));
                        }
                        m.ni = Some(v);
                    }
                    "d" => m.d = Some(number(w)?),
                    "Tr" => m.tr = Some(number(w)?),
                    _ => {
                        let v = w
                            .parse::<u32>()
                            .map_err(|_| err(format!("`illum`: expected an integer 0..10, found `{w}`")))?;
                        m.illum = Some(v);
                    }
                }
            }
        }
    }
    if !unused_maps.is_empty() {
        let list: Vec<String> = unused_maps.iter().map(|k| format!("`{k}`")).collect();
        warnings.push(Warning::new(
            path,
            None,
            format!("{} not used (dynray reads only `map_Kd` textures); ignored", list.join(", ")),
        ));
    }
    Ok(out)
}

/// Reads `map_Kd`'s arguments: options, then the file name (the rest of the line,
/// spaces included). Options dynray does not apply are skipped with a warning; a
/// statement without a file name is a warning and gives no texture.
fn texture_map(path: &Path, line: usize, rest: &str, warnings: &mut Vec<Warning>) -> Option<TextureMap> {
    let mut map = TextureMap { file: String::new(), line, offset: Vec2::ZERO, scale: Vec2::ONE, clamp: false };
    let mut warn = |m: String| warnings.push(Warning::new(path, Some(line), format!("`map_Kd`: {m}")));
    // Each word with its byte offset in `rest`, so the file name can be cut out whole.
    let words: Vec<(usize, &str)> =
        rest.split_whitespace().map(|w| (w.as_ptr() as usize - rest.as_ptr() as usize, w)).collect();
    let number = |i: usize| words.get(i).and_then(|(_, w)| w.parse::<f32>().ok()).filter(|v| v.is_finite());
    let mut i = 0;
    while let Some(&(_, opt)) = words.get(i).filter(|(_, w)| w.len() > 1 && w.starts_with('-')) {
        i += 1;
        match opt {
            // Up to three numbers: u [v [w]] (w is for 3-D textures).
            "-o" | "-s" | "-t" => {
                let mut n = Vec::new();
                while n.len() < 3 {
                    let Some(v) = number(i) else { break };
                    n.push(v);
                    i += 1;
                }
                match (opt, n.as_slice()) {
                    (_, []) => warn(format!("`{opt}` without numbers; skipped")),
                    ("-o", [u, rest @ ..]) => map.offset = Vec2::new(*u, rest.first().copied().unwrap_or(0.0)),
                    ("-s", [u, rest @ ..]) => map.scale = Vec2::new(*u, rest.first().copied().unwrap_or(1.0)),
                    _ => warn(format!("option `{opt}` (turbulence) is not supported; ignored")),
                }
            }
            "-clamp" => {
                map.clamp = words.get(i).is_some_and(|(_, w)| *w == "on");
                i += 1;
            }
            "-mm" | "-blendu" | "-blendv" | "-bm" | "-boost" | "-cc" | "-imfchan" | "-texres" | "-type" => {
                i += if opt == "-mm" { 2 } else { 1 };
                warn(format!("option `{opt}` is not supported; ignored"));
            }
            _ => warn(format!("option `{opt}` is unknown; skipped")),
        }
    }
    match words.get(i) {
        Some(&(start, _)) => {
            map.file = rest[start..].trim_end().to_string();
            Some(map)
        }
        None => {
            warn("no file name; no texture".into());
            None
        }
    }
}

/// Loads the `map_Kd` textures of the materials (`all`, numbered as the scene's first
/// materials) that some actor of `scene` uses, each file once, as sRGB colour textures
/// with the statement's `-o`/`-s` as the uv transform (`uv × s + o`, in the OBJ uv
/// convention, which is dynray's) and `-clamp on` as clamp-to-edge. A texture that
/// cannot be read or decoded is a warning naming it, the `.mtl` and the line; the
/// material stays untextured.
pub(crate) fn attach_textures(scene: &mut Scene, all: &[MtlMaterial], warnings: &mut Vec<Warning>) {
    let mut used = vec![false; all.len()];
    for id in scene.actors.iter().flat_map(|a| a.materials.iter()) {
        if let Some(u) = used.get_mut(*id as usize) {
            *u = true;
        }
    }
    let mut loaded: HashMap<PathBuf, Option<u32>> = HashMap::new();
    for (i, m) in all.iter().enumerate().filter(|(i, _)| used[*i]) {
        let Some(map) = &m.map_kd else { continue };
        let file = texture_path(m.library.parent().unwrap_or(Path::new("")), &map.file);
        let texture = *loaded.entry(file.clone()).or_insert_with(|| match Texture::load(&file, ColorSpace::Srgb) {
            Ok(t) => {
                scene.textures.push(Arc::new(t));
                Some(scene.textures.len() as u32 - 1)
            }
            Err(e) => {
                warnings.push(Warning::new(
                    &m.library,
                    Some(map.line),
                    format!("material `{}`: `map_Kd` texture: {e}; the material is untextured", m.name),
                ));
                None
            }
        });
        let Some(texture) = texture else { continue };
        let wrap = if map.clamp { Wrap::ClampToEdge } else { Wrap::Repeat };
        scene.materials[i].diffuse_texture = Some(TextureRef {
            texture,
            sampler: TextureSampler { wrap_u: wrap, wrap_v: wrap, ..Default::default() },
            transform: Affine2::from_scale_angle_translation(map.scale, 0.0, map.offset),
        });
    }
}

/// A texture file named in an `.mtl` in `dir`. Files written on Windows often use `\`;
/// when the name as written does not exist, `/` is tried.
fn texture_path(dir: &Path, name: &str) -> PathBuf {
    let file = dir.join(name);
    if !file.exists() && name.contains('\\') {
        let slashed = dir.join(name.replace('\\', "/"));
        if slashed.exists() {
            return slashed;
        }
    }
    file
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one(text: &str) -> MtlMaterial {
        let mut w = Vec::new();
        let mut v = parse(Path::new("t.mtl"), text, &mut w).unwrap();
        assert_eq!(v.len(), 1);
        v.pop().unwrap()
    }

    #[test]
    fn maps_every_documented_statement() {
        let m = one("newmtl glass\nKa 0.1 0.2 0.3\nKd 0.5\nKs 1 1 1 # white\nNs 50\nNi 1.5\nd 0.25\nillum 7\n");
        let mat = m.to_material();
        assert_eq!(mat.name, "glass");
        assert_eq!(mat.ambient, Color::new(0.1, 0.2, 0.3));
        assert_eq!(mat.diffuse, Color::splat(0.5));
        assert_eq!(mat.spot, Color::ONE);
        assert_eq!(mat.specular, Color::ONE);
        assert_eq!(mat.shine, 50.0);
        assert_eq!(mat.ior, 1.5);
        assert_eq!(mat.transparency, Color::splat(0.75));
    }

    #[test]
    fn defaults_when_statements_are_absent() {
        let mat = one("newmtl plain\nKd 0.4 0.6 0.8\nKs 0.5 0.5 0.5\nillum 2\nTr 0.3\n").to_material();
        assert_eq!(mat.ambient, Color::new(0.4, 0.6, 0.8) * 0.1);
        assert_eq!(mat.specular, Color::ZERO, "illum 2 has no mirror term");
        assert!((mat.transparency.x - 0.3).abs() < 1e-6);
        assert_eq!(mat.ior, 1.0);
    }

    #[test]
    fn emitter_is_ambient_bright() {
        let m = one("newmtl light\nKd 0.78 0.78 0.78\nKe 17 12 4\n");
        assert_eq!(m.emission(), Some(Color::new(17.0, 12.0, 4.0)));
        let amb = Environment::default().ambient;
        assert_eq!(m.to_material().ambient * amb, Color::new(17.0, 12.0, 4.0));
        assert_eq!(one("newmtl x\nKe 0 0 0\n").emission(), None);
    }

    #[test]
    fn errors_name_file_and_line() {
        let mut w = Vec::new();
        for (text, line, what) in [
            ("newmtl a\nKd 0.5 0.5\n", 2, "expected 1 or 3 numbers"),
            ("newmtl a\n\nNs abc\n", 3, "found `abc`"),
            ("Kd 1 1 1\n", 1, "before any `newmtl`"),
            ("newmtl\n", 1, "without a name"),
            ("newmtl a\nillum x\n", 2, "illum"),
            ("newmtl a\nNi 0\n", 2, "must be positive"),
            ("newmtl a\nKd nan 0 0\n", 2, "finite"),
        ] {
            let e = parse(Path::new("lib.mtl"), text, &mut w).unwrap_err().to_string();
            assert!(e.starts_with(&format!("lib.mtl:{line}: ")), "{e}");
            assert!(e.contains(what), "{e}");
        }
    }

    #[test]
    fn spectral_colours_warn() {
        let mut w = Vec::new();
        let v = parse(Path::new("s.mtl"), "newmtl a\nKd spectral r.rfl\n", &mut w).unwrap();
        assert_eq!(v[0].kd, None);
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].line, Some(2));
    }

    #[test]
    fn map_kd_options_and_file_names() {
        let mut w = Vec::new();
        let text = "newmtl a\nmap_Kd -o 0.5 0.25 -s 2 -clamp on my wood.png\n\
                    newmtl b\nmap_Kd -bm 0.3 -t 1 1 -zz b.jpg\nmap_Bump n.png\nbump n.png\nmap_Ks s.png\n\
                    newmtl c\nmap_Kd -o 1\n";
        let v = parse(Path::new("m.mtl"), text, &mut w).unwrap();
        let a = v[0].map_kd.as_ref().unwrap();
        assert_eq!(a.file, "my wood.png", "names keep their spaces");
        assert_eq!((a.offset, a.scale, a.clamp, a.line), (Vec2::new(0.5, 0.25), Vec2::new(2.0, 1.0), true, 2));
        let b = v[1].map_kd.as_ref().unwrap();
        assert_eq!((b.file.as_str(), b.clamp, b.scale), ("b.jpg", false, Vec2::ONE));
        assert_eq!(v[2].map_kd, None, "`-o 1` then nothing: no file name");
        assert_eq!(v[0].library, Path::new("m.mtl"));
        let msgs: Vec<String> = w.iter().map(|w| w.to_string()).collect();
        assert!(msgs.iter().any(|m| m.starts_with("m.mtl:4: `map_Kd`: option `-bm`")), "{msgs:?}");
        assert!(msgs.iter().any(|m| m.starts_with("m.mtl:4: `map_Kd`: option `-t`")), "{msgs:?}");
        assert!(msgs.iter().any(|m| m.contains("`-zz` is unknown")), "{msgs:?}");
        assert!(msgs.iter().any(|m| m.starts_with("m.mtl:9: `map_Kd`: no file name")), "{msgs:?}");
        let unused = msgs.iter().find(|m| m.contains("not used")).expect("one warning for the other maps");
        assert!(unused.contains("`map_Bump`, `bump`, `map_Ks`"), "{unused}");
        assert_eq!(msgs.len(), 5, "{msgs:?}");
    }
}
