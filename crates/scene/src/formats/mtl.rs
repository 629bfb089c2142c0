//! MTL material libraries (the companions of OBJ files): parsing and the mapping to
//! dynray's [`Material`].
//!
//! dynray parses MTL itself rather than through tobj because tobj's MTL reader panics on
//! a colour with fewer than three numbers and reports no line numbers.
//!
//! The mapping to [`Material`] is documented (as a table) in [`super::obj`].
//!
//! A colour may be given as one number (grey) or three; `spectral` and `xyz` colours are
//! not supported and give a warning. Texture maps, `Tf`, `sharpness` and every other
//! statement are ignored.

use crate::report::Warning;
use crate::{Color, Environment, Finish, LoadError, Material};
use std::path::Path;

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
        }
    }
}

/// Parses an MTL file's text. `path` labels errors and warnings.
pub(crate) fn parse(path: &Path, text: &str, warnings: &mut Vec<Warning>) -> Result<Vec<MtlMaterial>, LoadError> {
    let mut out: Vec<MtlMaterial> = Vec::new();
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
            out.push(MtlMaterial { name: name.to_string(), ..Default::default() });
            continue;
        }
        let known = ["Ka", "Kd", "Ks", "Ke", "Ns", "Ni", "d", "Tr", "illum"];
        if !known.contains(&key) {
            continue; // texture maps, Tf, sharpness, …: not used by dynray
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
    Ok(out)
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
}
