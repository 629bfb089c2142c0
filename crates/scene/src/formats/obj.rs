//! Wavefront OBJ (+ MTL) loader: tobj builds the meshes, dynray checks the text first so
//! that every error names the line, and maps MTL materials and emitters to the scene.
//!
//! # Geometry
//! - Each tobj model (a run of faces under one `o`/`g` name and one `usemtl`) becomes one
//!   [`Actor`], named after the group in effect when its faces were read. Actors are in
//!   file order and polygons are fan-triangulated (`a b c`, `a c d`, …) in file order, so
//!   frame triangle `i` is the `i`-th triangle of the file's faces.
//! - Vertex normals are kept for an actor when every vertex of its faces has one; uvs
//!   likewise. Vertices are de-duplicated per actor (tobj's `single_index`).
//! - `l` and `p` statements, and `f` with fewer than three vertices (a warning), give no
//!   triangles. Free-form geometry is ignored. `#` starts a comment anywhere on a line.
//!
//! # Checks (before tobj runs)
//! Numbers must parse and be finite; `v` has 3 coordinates plus an optional non-zero `w`
//! (applied here) or an RGB triple (dropped); `vt` has 1–3 numbers; `vn` has 3; every
//! face index (absolute or negative/relative, for `v`, `vt` and `vn`) must name an
//! element already defined (forward references, which the format does not allow, are
//! errors).
//! Each failure is a [`LoadError::Parse`] naming the file and the line. The checks make
//! tobj's own error paths (which carry no line) unreachable in practice, and also keep
//! out the face indices on which tobj 4.0 would overflow.
//!
//! # Materials
//! MTL libraries are parsed by dynray (tobj's MTL reader panics on a short colour and
//! gives no line numbers). Mapping to [`Material`]:
//!
//! | MTL | dynray | when absent |
//! |---|---|---|
//! | `Kd` | `diffuse` | 0.72 grey (the default material's diffuse) |
//! | `Ka` | `ambient` | `Kd × 0.1` (the default finish's ambient fraction) |
//! | `Ks` | `spot` (Phong highlight) | black |
//! | `Ns` | `shine` | 1 |
//! | `illum` 3, 5, 7 | `specular` (mirror) = `Ks` | black for every other `illum` |
//! | `d` / `Tr` | `transparency` = `1 - d`, or `Tr` when there is no `d` | 0 |
//! | `Ni` | `ior` | 1 |
//! | `Ke` | `emission` = `Ke` (an area light for the path tracer), `ambient` = `Ke / environment ambient` and a stand-in point light for Whitted (see Emitters) | no emission |
//! | `map_Kd` | `diffuse_texture`: multiplies `diffuse` and `ambient` (see Textures) | untextured |
//!
//! A colour may be one number (grey) or three; `spectral`/`xyz` colours are ignored with a
//! warning. The other texture maps (`map_Ks`, `map_Bump`, `bump`, …) are not used, which
//! one warning per library says; `Tf` and `sharpness` are ignored silently. A malformed
//! MTL is an error naming the `.mtl` file and line. A missing library, or a `usemtl`
//! naming no known material, is a [`Warning`]; those faces get [`Material::default`].
//!
//! # Textures
//! `map_Kd file` names an image (PNG, JPEG, PPM/PNM, BMP) relative to the `.mtl` file
//! (a name with `\` separators that does not exist is retried with `/`), decoded as sRGB
//! and only for materials some face uses, each file once. Options: `-o u v` and
//! `-s u v` give the uv transform `uv × s + o`, `-clamp on` clamps instead of
//! repeating; every other option is skipped with a warning. OBJ's `vt` convention,
//! `(0, 0)` at the image's bottom-left and `v` up, is dynray's, so uvs are kept as
//! written. A texture that cannot be read or decoded is a [`Warning`] naming the image,
//! the `.mtl` and its line, and the material renders untextured. A textured material on
//! faces without `vt` is rendered untextured there, with a warning.
//!
//! # Emitters
//! A material with a non-black `Ke` is an area light: its [`Material::emission`] is `Ke`,
//! the radiance it emits from the side its faces' winding normal points to (one-sided,
//! like glTF's and Mitsuba's emitters). The path tracer samples those triangles as area
//! lights, by next-event estimation with MIS (crates/render/src/path/lights.rs), so an
//! `.obj` lamp casts soft shadows and the image converges to what Mitsuba 3 renders from
//! the same file with `area` emitters (`tools/reference/cornell_obj.py`,
//! crates/render/tests/mitsuba_reference.rs). A lamp wound facing away from the scene
//! therefore lights the ceiling behind it, as in Mitsuba.
//!
//! The Whitted and cumulative integrators have no area lights, so each actor using such a
//! material also gets a point light standing in for it, marked
//! [`Light::emitter_stand_in`]: those integrators light with it, the path tracer skips it
//! (it already has the surface; counting both would light the scene twice). The stand-in
//! sits at the actor's area-weighted centroid, nudged off the surface along its mean
//! normal (flipped to face the scene's centre) by 0.1 % of the scene's diagonal (so
//! shadow rays towards it do not stop on the emitter itself), with colour `Ke × area` and
//! inverse-square falloff: the radiant intensity of a small Lambertian emitter of
//! radiance `Ke` seen along its normal. (The Cornell box's `Ke 17 12 4` over its
//! 0.47 × 0.38 lamp gives about 3.0, 2.1, 0.7.) The emitter's material gets
//! `ambient = Ke / environment ambient`, so the lamp itself looks as bright as it emits
//! under Whitted's ambient term (the path tracer shows its emission instead).
//! Files without emitters get the default light when loaded on their own
//! ([`crate::load_file_report`]); through a scene file's `mesh { file }` they bring none.
//! There, a `material` modifier that replaces the file's materials takes the emission
//! away, and the stand-in becomes an ordinary point light for every integrator
//! (scn/objects.rs).

use super::mtl::{self, MtlMaterial};
use crate::report::{LoadReport, Warning};
use crate::texture::untexture_where_no_uvs;
use crate::{Actor, Color, Light, LightKind, LoadError, Material, Scene};
use dynray_geom::{MeshError, TriangleMesh, Vec3};
use std::path::Path;

/// Loads an `.obj` file, its material libraries, and builds the scene (see module docs).
pub fn load(path: &Path) -> Result<LoadReport, LoadError> {
    let bytes = dynray_geom::file::read(path).map_err(|e| LoadError::io(path, e))?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
        LoadError::parse(path, Some(line), "not UTF-8 text")
    })?;
    let mut warnings = Vec::new();
    let checked = check(path, text, &mut warnings)?;

    // Material libraries, in statement order: tobj asks for them in the same order and
    // numbers materials by concatenation, so `material_id` indexes `libraries.concat()`.
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut libraries: Vec<Vec<MtlMaterial>> = Vec::new();
    for (line, names) in &checked.mtllibs {
        let mut lib = Vec::new();
        for name in names {
            lib.extend(load_library(path, *line, &dir.join(name), &mut warnings)?);
        }
        libraries.push(lib);
    }
    let next_library = std::cell::Cell::new(0usize);
    // `..Default::default()` stays: tobj's `merging`/`reordering` features add fields.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut checked.text.as_bytes(), &options, |_| {
        let k = next_library.get();
        next_library.set(k + 1);
        let lib = libraries.get(k).map(Vec::as_slice).unwrap_or(&[]);
        let stubs: Vec<tobj::Material> =
            lib.iter().map(|m| tobj::Material { name: m.name.clone(), ..Default::default() }).collect();
        let map = lib.iter().enumerate().map(|(i, m)| (m.name.clone(), i)).collect();
        Ok((stubs, map))
    })
    .map_err(|e| LoadError::parse(path, None, format!("OBJ: {e}")))?;
    let all: Vec<MtlMaterial> = libraries.concat();

    for (line, name) in &checked.usemtl {
        if !all.iter().any(|m| &m.name == name) {
            warnings.push(Warning::new(
                path,
                Some(*line),
                format!("material `{name}` is not defined in any material library; using the default material"),
            ));
        }
    }

    let mut scene = Scene { materials: all.iter().map(MtlMaterial::to_material).collect(), ..Default::default() };
    let mut default_material = None;
    let mut emitters = Vec::new();
    for model in models {
        let m = model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let material = match m.material_id.filter(|&i| i < all.len()) {
            Some(i) => i as u32,
            None => *default_material.get_or_insert_with(|| {
                scene.materials.push(Material::default());
                scene.materials.len() as u32 - 1
            }),
        };
        let positions: Vec<[f32; 3]> = m.positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let n = positions.len();
        let normals =
            (m.normals.len() == 3 * n).then(|| m.normals.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect());
        let uvs = (m.texcoords.len() == 2 * n).then(|| m.texcoords.chunks_exact(2).map(|c| [c[0], c[1]]).collect());
        let indices = m.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let mesh = TriangleMesh { positions, indices, normals, uvs };
        mesh.validate().map_err(|source| LoadError::Mesh { path: path.to_path_buf(), source })?;
        if let Some(ke) = all.get(material as usize).and_then(MtlMaterial::emission) {
            emitters.push((scene.actors.len(), ke));
        }
        let name = (!model.name.is_empty()).then_some(model.name);
        scene.actors.push(Actor::new(name, mesh, material));
    }
    if scene.actors.is_empty() {
        return Err(LoadError::Mesh { path: path.to_path_buf(), source: MeshError::Empty });
    }
    mtl::attach_textures(&mut scene, &all, &mut warnings);
    untexture_where_no_uvs(&mut scene, path, &mut warnings);
    let bounds = scene.bounds();
    let nudge = bounds.extent().length() * 1e-3;
    for (actor, ke) in emitters {
        scene.lights.push(emitter_light(&scene.actors[actor].mesh, ke, nudge, bounds.center()));
    }
    Ok(LoadReport { scene, warnings })
}

/// The point light standing in for an emissive actor under the integrators without area
/// lights; the path tracer skips it (module docs, "Emitters").
fn emitter_light(mesh: &TriangleMesh, ke: Color, nudge: f32, scene_center: Vec3) -> Light {
    let (mut area, mut centroid, mut normal) = (0.0f32, Vec3::ZERO, Vec3::ZERO);
    for t in mesh.triangles() {
        let n = (t.p1 - t.p0).cross(t.p2 - t.p0);
        let a = 0.5 * n.length();
        area += a;
        centroid += t.centroid() * a;
        normal += n;
    }
    let (position, color) = if area > 0.0 {
        let centroid = centroid / area;
        // Off the side that faces the scene, whatever the emitter's winding: a lamp
        // wound outwards would otherwise put its light between itself and the ceiling.
        let mut n = normal.normalize_or_zero();
        if n.dot(scene_center - centroid) < 0.0 {
            n = -n;
        }
        (centroid + n * nudge, ke * area)
    } else {
        // Degenerate emitter: no area to weigh by, so the vertex mean and the bare colour.
        let mean = mesh.positions.iter().map(|p| Vec3::from_array(*p)).sum::<Vec3>() / mesh.vertex_count() as f32;
        (mean, ke)
    };
    Light { kind: LightKind::Point { position, falloff: 2 }, color, emitter_stand_in: true }
}

/// Reads and parses one MTL file; a missing file is a warning, a malformed one an error.
fn load_library(
    obj: &Path,
    line: usize,
    lib: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<MtlMaterial>, LoadError> {
    let bytes = match dynray_geom::file::read(lib) {
        Ok(b) => b,
        Err(e) => {
            warnings.push(Warning::new(
                obj,
                Some(line),
                format!("material library {} cannot be read ({e}); using the default material", lib.display()),
            ));
            return Ok(Vec::new());
        }
    };
    let text = String::from_utf8_lossy(&bytes);
    mtl::parse(lib, &text, warnings)
}

/// The OBJ text as tobj will see it, and the statements dynray handles itself.
struct Checked {
    /// The file with comments, `l`/`p` statements and short faces blanked (line numbers
    /// unchanged) and one-number `vt` padded to two.
    text: String,
    /// `mtllib` statements: line and file names.
    mtllibs: Vec<(usize, Vec<String>)>,
    /// `usemtl` statements: line and material name.
    usemtl: Vec<(usize, String)>,
}

/// Checks every statement tobj will read (module docs, "Checks").
fn check(path: &Path, text: &str, warnings: &mut Vec<Warning>) -> Result<Checked, LoadError> {
    let mut out = Checked { text: String::with_capacity(text.len()), mtllibs: Vec::new(), usemtl: Vec::new() };
    let (mut nv, mut nvt, mut nvn) = (0usize, 0usize, 0usize);
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        let key = words.next().unwrap_or("");
        let args: Vec<&str> = words.collect();
        let err = |m: String| LoadError::parse(path, Some(line_no), m);
        let numbers = |what: &str| -> Result<Vec<f32>, LoadError> {
            args.iter()
                .map(|w| match w.parse::<f32>() {
                    Ok(v) if v.is_finite() => Ok(v),
                    Ok(v) => Err(err(format!("`{key}`: {what} must be finite, found {v}"))),
                    Err(_) => Err(err(format!("`{key}`: expected a number for {what}, found `{w}`"))),
                })
                .collect()
        };
        let mut keep = line.to_string();
        match key {
            "v" => {
                let v = numbers("a coordinate")?;
                // Written back as `v x y z` (divided by w): tobj would reject a file
                // whose vertices are only partly coloured, and dynray has no use for colour.
                let w = match v.len() {
                    3 | 6 => 1.0,
                    4 if v[3] != 0.0 => v[3],
                    4 => return Err(err("`v`: the weight w must not be 0".into())),
                    n => return Err(err(format!("`v`: expected x y z [w] or x y z r g b, found {n} numbers"))),
                };
                let p = [v[0] / w, v[1] / w, v[2] / w];
                if !p.iter().all(|c| c.is_finite()) {
                    return Err(err(format!("`v`: x y z / w is not finite (w = {w})")));
                }
                keep = format!("v {} {} {}", p[0], p[1], p[2]);
                nv += 1;
            }
            "vt" => {
                let v = numbers("a texture coordinate")?;
                match v.len() {
                    1 => keep = format!("vt {} 0", v[0]),
                    2 | 3 => {}
                    n => return Err(err(format!("`vt`: expected u [v [w]], found {n} numbers"))),
                }
                nvt += 1;
            }
            "vn" => {
                if numbers("a normal component")?.len() != 3 {
                    return Err(err(format!("`vn`: expected 3 numbers, found {}", args.len())));
                }
                nvn += 1;
            }
            "f" => {
                for a in &args {
                    check_face_vertex(a, [nv, nvt, nvn]).map_err(|m| err(format!("`f`: vertex `{a}`: {m}")))?;
                }
                if args.len() < 3 {
                    warnings.push(Warning::new(
                        path,
                        Some(line_no),
                        format!("face with {} vertices has no area; skipped", args.len()),
                    ));
                    keep.clear();
                }
            }
            // Lines and points are not surfaces; tobj would turn 3+-vertex lines into faces.
            "l" | "p" => keep.clear(),
            "usemtl" => {
                let name = line[key.len()..].trim();
                if name.is_empty() {
                    return Err(err("`usemtl` without a material name".into()));
                }
                out.usemtl.push((line_no, name.to_string()));
                // tobj splits the name off at a space, not at a tab.
                keep = format!("usemtl {name}");
            }
            "mtllib" => {
                if args.is_empty() {
                    return Err(err("`mtllib` without a file name".into()));
                }
                // One name with spaces, if such a file exists; else one file per word.
                let whole = line[key.len()..].trim();
                let dir = path.parent().unwrap_or(Path::new(""));
                let names = if args.len() > 1 && dir.join(whole).is_file() {
                    vec![whole.to_string()]
                } else {
                    args.iter().map(|s| s.to_string()).collect()
                };
                out.mtllibs.push((line_no, names));
            }
            _ => {}
        }
        out.text.push_str(&keep);
        out.text.push('\n');
    }
    Ok(out)
}

/// Checks one `v[/vt[/vn]]` reference against the counts defined so far.
fn check_face_vertex(word: &str, counts: [usize; 3]) -> Result<(), String> {
    let parts: Vec<&str> = word.split('/').collect();
    if parts.len() > 3 {
        return Err("expected v, v/vt, v//vn or v/vt/vn".into());
    }
    for (k, part) in parts.iter().enumerate() {
        let what = ["vertex", "texture coordinate", "normal"][k];
        if part.is_empty() {
            if k == 0 {
                return Err("missing vertex index".into());
            }
            continue;
        }
        let i: i64 = part.parse().map_err(|_| format!("`{part}` is not an integer index"))?;
        let n = counts[k] as i64;
        let ok = if i > 0 { i <= n } else { i < 0 && -i <= n };
        if !ok {
            return Err(if i == 0 {
                format!("{what} index 0 (OBJ indices start at 1)")
            } else {
                format!("{what} index {i} is out of range: {n} defined so far")
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_references_are_checked() {
        assert!(check_face_vertex("1/1/1", [1, 1, 1]).is_ok());
        assert!(check_face_vertex("-1//-1", [3, 0, 1]).is_ok());
        assert!(check_face_vertex("4", [3, 0, 0]).unwrap_err().contains("out of range"));
        assert!(check_face_vertex("-4", [3, 0, 0]).unwrap_err().contains("out of range"));
        assert!(check_face_vertex("0", [3, 0, 0]).unwrap_err().contains("start at 1"));
        assert!(check_face_vertex("1/-5", [3, 1, 0]).unwrap_err().contains("texture coordinate"));
        assert!(check_face_vertex("1/1/1/1", [3, 3, 3]).is_err());
        assert!(check_face_vertex("/1", [3, 3, 3]).is_err());
        assert!(check_face_vertex("x", [3, 3, 3]).unwrap_err().contains("not an integer"));
        assert!(check_face_vertex("99999999999999999999", [3, 3, 3]).is_err());
    }

    #[test]
    fn check_keeps_line_numbers() {
        let mut w = Vec::new();
        let c = check(Path::new("a.obj"), "v 0 0 0 # c\nl 1 1\nvt 0.5\nf 1\n", &mut w).unwrap();
        assert_eq!(c.text, "v 0 0 0\n\nvt 0.5 0\n\n");
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].line, Some(4));
    }
}
