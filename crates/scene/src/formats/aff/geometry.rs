//! Geometry commands of AFF/NFF and how their triangles are grouped into actors.
//!
//! Every primitive is turned into triangles at once, with the static transforms (`xs`)
//! since the nearest animated transform (`x`) baked into its vertices; what is left, the
//! animated node, places the actor ([`Place`]). Triangles are gathered into one actor per
//! animated node (or the static world) and kind of vertex data (with or without normals,
//! with or without texture coordinates; `tpa` patches by their key times), in the order
//! the file gives them, so the frame has few actors and a stable triangle order. Actors
//! whose vertices have no normals get smooth ones from the shading rule; polygons with
//! normals (`pp`, `ttp`, meshes with `normals`) keep theirs.
//!
//! - `p n v…` polygons and `pp n (v n)…` patches are fan-triangulated (`0 1 2`, `0 2 3`, …).
//! - `s x y z r` spheres become UV spheres of [`SPHERE_STACKS`] × [`SPHERE_SLICES`]
//!   (960 triangles, smooth normals): dynray traces triangles only.
//! - `c base r0 apex r1` cones and cylinders become [`CONE_SLICES`] side quads with smooth
//!   normals and no caps (NFF cones are open).
//! - `tt tex v×3` / `ttp tex (v n)×3`: a textured triangle, each vertex with `u v`.
//! - `tpa n (time (v n)×3)×n`: a triangle whose vertices and normals are keyed
//!   (a [`VertexKeys`] deformation, linear between keys).
//! - `m` blocks: `vertices n`, optional `normals n`, optional `texturecoords n [texture]`,
//!   then `triangles n` with per triangle 3 vertex indices, then 3 normal indices when
//!   there are normals, then 3 texture-coordinate indices when there are uvs.
//!
//! Texture coordinates are stored as `(u, 1 - v)`: BART's `v` runs down the image
//! (its `0` is the top row), dynray's up (see [`crate::texture`]).

use super::lexer::{reserve, Tokens};
use crate::animation::{Deformation, VertexKeys};
use crate::{Actor, LoadError};
use dynray_geom::{TriangleMesh, Vec3};
use glam::{Mat3, Mat4};
use std::collections::HashMap;

/// Latitude bands of a tessellated sphere.
pub(super) const SPHERE_STACKS: u32 = 16;
/// Longitude segments of a tessellated sphere.
pub(super) const SPHERE_SLICES: u32 = 32;
/// Segments around a tessellated cone or cylinder.
pub(super) const CONE_SLICES: u32 = 32;

/// Where geometry read now goes: the animated node placing it (none: the static world)
/// and the static transforms below that node, baked into the vertices.
#[derive(Clone, Copy, Debug)]
pub(super) struct Place {
    pub node: Option<u32>,
    pub local: Mat4,
}

impl Place {
    pub fn point(&self, p: [f32; 3]) -> [f32; 3] {
        if self.local == Mat4::IDENTITY {
            p
        } else {
            self.local.transform_point3(Vec3::from_array(p)).to_array()
        }
    }

    fn normal_matrix(&self) -> Option<Mat3> {
        (self.local != Mat4::IDENTITY).then(|| Mat3::from_mat4(self.local).inverse().transpose())
    }
}

/// One vertex as the file gives it.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Vertex {
    pub p: [f32; 3],
    pub n: Option<[f32; 3]>,
    pub uv: Option<[f32; 2]>,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct GroupKey {
    node: Option<u32>,
    normals: bool,
    uvs: bool,
    /// `tpa` groups: the key times' bits.
    keys: Option<Vec<u32>>,
}

#[derive(Debug, Default)]
struct Group {
    key: Option<GroupKey>,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    indices: Vec<[u32; 3]>,
    materials: Vec<u32>,
    /// `tpa`: key times, then per key the positions and normals.
    key_times: Vec<f32>,
    key_positions: Vec<Vec<[f32; 3]>>,
    key_normals: Vec<Vec<[f32; 3]>>,
}

/// The actors being gathered, in order of first use.
#[derive(Default)]
pub(super) struct Groups {
    groups: Vec<Group>,
    index: HashMap<GroupKey, usize>,
}

impl Groups {
    fn group(&mut self, key: GroupKey) -> &mut Group {
        let i = *self.index.entry(key.clone()).or_insert_with(|| {
            self.groups.push(Group { key: Some(key), ..Default::default() });
            self.groups.len() - 1
        });
        &mut self.groups[i]
    }

    /// Adds triangles over `vertices` (all with normals or none, all with uvs or none).
    pub fn add(&mut self, place: &Place, vertices: &[Vertex], triangles: &[[u32; 3]], material: u32) {
        let Some(first) = vertices.first() else { return };
        let key = GroupKey { node: place.node, normals: first.n.is_some(), uvs: first.uv.is_some(), keys: None };
        let nm = place.normal_matrix();
        let g = self.group(key);
        let base = g.positions.len() as u32;
        for v in vertices {
            g.positions.push(place.point(v.p));
            if let Some(n) = v.n {
                g.normals.push(transform_normal(nm, n));
            }
            if let Some([u, w]) = v.uv {
                g.uvs.push([u, 1.0 - w]);
            }
        }
        g.indices.extend(triangles.iter().map(|t| t.map(|i| i + base)));
        g.materials.extend(std::iter::repeat_n(material, triangles.len()));
    }

    /// Adds a `tpa` triangle: `keys[k]` holds key `k`'s time and three vertices.
    fn add_keyed(&mut self, place: &Place, keys: &[(f32, [Vertex; 3])], material: u32) {
        let bits = keys.iter().map(|(t, _)| t.to_bits()).collect();
        let key = GroupKey { node: place.node, normals: true, uvs: false, keys: Some(bits) };
        let nm = place.normal_matrix();
        let g = self.group(key);
        if g.key_times.is_empty() {
            g.key_times = keys.iter().map(|k| k.0).collect();
            g.key_positions = vec![Vec::new(); keys.len()];
            g.key_normals = vec![Vec::new(); keys.len()];
        }
        let base = g.key_positions[0].len() as u32;
        for (k, (_, vs)) in keys.iter().enumerate() {
            for v in vs {
                g.key_positions[k].push(place.point(v.p));
                g.key_normals[k].push(transform_normal(nm, v.n.unwrap_or_default()));
            }
        }
        g.indices.push([base, base + 1, base + 2]);
        g.materials.push(material);
    }

    /// The actors, with their node (placement is set by the caller once the rig is known).
    pub fn into_actors(self, name_of: impl Fn(Option<u32>) -> String) -> Vec<Actor> {
        let mut actors = Vec::with_capacity(self.groups.len());
        for g in self.groups {
            let key = g.key.expect("groups are made with a key");
            let keyed = key.keys.is_some();
            let (positions, normals) = if keyed {
                (g.key_positions[0].clone(), Some(g.key_normals[0].clone()))
            } else {
                (g.positions, key.normals.then_some(g.normals))
            };
            let mesh = TriangleMesh { positions, indices: g.indices, normals, uvs: key.uvs.then_some(g.uvs) };
            let mut actor = Actor::new(Some(name_of(key.node)), mesh, 0);
            actor.materials = g.materials;
            actor.node = key.node;
            if keyed {
                actor.deform = Some(Deformation {
                    keys: Some(VertexKeys {
                        times: g.key_times,
                        positions: g.key_positions,
                        normals: Some(g.key_normals),
                    }),
                    ..Default::default()
                });
            }
            actors.push(actor);
        }
        actors
    }
}

fn transform_normal(nm: Option<Mat3>, n: [f32; 3]) -> [f32; 3] {
    match nm {
        Some(m) => (m * Vec3::from_array(n)).normalize_or_zero().to_array(),
        None => n,
    }
}

/// Fan triangles over `n` polygon vertices.
fn fan(n: usize) -> Vec<[u32; 3]> {
    (1..n.saturating_sub(1) as u32).map(|i| [0, i, i + 1]).collect()
}

/// `p n` (`with_normals`: `pp n`): the polygon's vertices.
pub(super) fn read_polygon(
    t: &mut Tokens<'_>,
    with_normals: bool,
    groups: &mut Groups,
    place: &Place,
    material: u32,
) -> Result<(), LoadError> {
    let cmd = if with_normals { "pp" } else { "p" };
    let line = t.line();
    let n = t.count(&format!("`{cmd}` vertex count"))?;
    if n < 3 {
        return Err(t.error(line, format!("`{cmd}`: a polygon needs at least 3 vertices, found {n}")));
    }
    let mut vs = Vec::with_capacity(reserve(t, n, if with_normals { 6 } else { 3 }));
    for i in 0..n {
        let what = format!("`{cmd}` vertex {} of {n}", i + 1);
        let p = t.vec3(&what)?;
        let nrm = if with_normals { Some(t.vec3(&what)?) } else { None };
        vs.push(Vertex { p, n: nrm, uv: None });
    }
    groups.add(place, &vs, &fan(n), material);
    Ok(())
}

/// `tt tex` / `ttp tex`: one textured triangle (the texture name was read by the caller).
pub(super) fn read_textured_triangle(
    t: &mut Tokens<'_>,
    with_normals: bool,
    groups: &mut Groups,
    place: &Place,
    material: u32,
) -> Result<(), LoadError> {
    let cmd = if with_normals { "ttp" } else { "tt" };
    let mut vs = [Vertex::default(); 3];
    for (i, v) in vs.iter_mut().enumerate() {
        let what = format!("`{cmd}` vertex {}", i + 1);
        v.p = t.vec3(&what)?;
        if with_normals {
            v.n = Some(t.vec3(&what)?);
        }
        v.uv = Some([t.number(&what)?, t.number(&what)?]);
    }
    groups.add(place, &vs, &[[0, 1, 2]], material);
    Ok(())
}

/// `s x y z r`.
pub(super) fn read_sphere(
    t: &mut Tokens<'_>,
    groups: &mut Groups,
    place: &Place,
    material: u32,
) -> Result<(), LoadError> {
    let line = t.line();
    let c = t.vec3("`s` centre")?;
    let r = t.number("`s` radius")?;
    if r <= 0.0 {
        return Err(t.error(line, format!("`s`: the radius must be positive, found {r}")));
    }
    let m = crate::shapes::uv_sphere(Vec3::from_array(c), r, SPHERE_STACKS, SPHERE_SLICES);
    add_mesh(groups, place, &m, material);
    Ok(())
}

/// `c bx by bz r0 ax ay az r1`.
pub(super) fn read_cone(
    t: &mut Tokens<'_>,
    groups: &mut Groups,
    place: &Place,
    material: u32,
) -> Result<(), LoadError> {
    let line = t.line();
    let base = Vec3::from_array(t.vec3("`c` base centre")?);
    let r0 = t.number("`c` base radius")?;
    let apex = Vec3::from_array(t.vec3("`c` apex centre")?);
    let r1 = t.number("`c` apex radius")?;
    let axis = apex - base;
    let h = axis.length();
    if h == 0.0 || r0 < 0.0 || r1 < 0.0 || r0 + r1 == 0.0 {
        return Err(t.error(line, "`c`: a cone needs distinct end centres and non-negative radii, not both zero"));
    }
    let w = axis / h;
    let u = w.any_orthonormal_vector();
    let v = w.cross(u);
    let mut vs = Vec::with_capacity(2 * CONE_SLICES as usize);
    for j in 0..CONE_SLICES {
        let a = std::f32::consts::TAU * j as f32 / CONE_SLICES as f32;
        let radial = u * a.cos() + v * a.sin();
        // The side's normal leans towards the narrow end by the slope (r0 - r1) / h.
        let n = (radial * h + w * (r0 - r1)).normalize();
        vs.push(Vertex { p: (base + radial * r0).to_array(), n: Some(n.to_array()), uv: None });
        vs.push(Vertex { p: (apex + radial * r1).to_array(), n: Some(n.to_array()), uv: None });
    }
    let mut tris = Vec::with_capacity(2 * CONE_SLICES as usize);
    for j in 0..CONE_SLICES {
        let (b0, a0) = (2 * j, 2 * j + 1);
        let (b1, a1) = (2 * ((j + 1) % CONE_SLICES), 2 * ((j + 1) % CONE_SLICES) + 1);
        tris.push([b0, b1, a1]);
        tris.push([b0, a1, a0]);
    }
    groups.add(place, &vs, &tris, material);
    Ok(())
}

fn add_mesh(groups: &mut Groups, place: &Place, m: &TriangleMesh, material: u32) {
    let normals = m.normals.as_deref();
    let vs: Vec<Vertex> =
        (0..m.positions.len()).map(|i| Vertex { p: m.positions[i], n: normals.map(|n| n[i]), uv: None }).collect();
    groups.add(place, &vs, &m.indices, material);
}

/// `tpa n`, then `n` keys of a time and three vertices with normals.
pub(super) fn read_tpa(t: &mut Tokens<'_>, groups: &mut Groups, place: &Place, material: u32) -> Result<(), LoadError> {
    let line = t.line();
    let n = t.count("`tpa` key count")?;
    if n == 0 {
        return Err(t.error(line, "`tpa`: an animated triangle needs at least one key"));
    }
    let mut keys: Vec<(f32, [Vertex; 3])> = Vec::with_capacity(reserve(t, n, 19));
    for k in 0..n {
        let what = format!("`tpa` key {} of {n}", k + 1);
        let key_line = t.line();
        let time = t.number(&format!("{what}: time"))?;
        if let Some(&(prev, _)) = keys.last() {
            if time <= prev {
                return Err(t.error(key_line, format!("{what}: time {time} is not after the previous key's {prev}")));
            }
        }
        let mut vs = [Vertex::default(); 3];
        for v in &mut vs {
            v.p = t.vec3(&what)?;
            v.n = Some(t.vec3(&what)?);
        }
        keys.push((time, vs));
    }
    groups.add_keyed(place, &keys, material);
    Ok(())
}

/// An `m` block (after the `m`); `texture` resolves a `texturecoords` texture name to
/// the material to use.
pub(super) fn read_mesh(
    t: &mut Tokens<'_>,
    groups: &mut Groups,
    place: &Place,
    material: u32,
    mut texture: impl FnMut(usize, &str) -> u32,
) -> Result<(), LoadError> {
    let mut material = material;
    let start = t.line();
    let header = t.expect("vertices", "after `m`")?;
    let nv = t.count("`vertices` count")?;
    let mut positions = Vec::with_capacity(reserve(t, nv, 3));
    for i in 0..nv {
        positions.push(t.vec3(&format!("mesh vertex {} of {nv} (block at line {})", i + 1, header.line))?);
    }
    let mut normals: Option<Vec<[f32; 3]>> = None;
    let mut uvs: Option<Vec<[f32; 2]>> = None;
    loop {
        let w = t.word("`normals`, `texturecoords` or `triangles` in the `m` block")?;
        match w.text {
            "normals" if normals.is_none() => {
                let n = t.count("`normals` count")?;
                let mut v = Vec::with_capacity(reserve(t, n, 3));
                for i in 0..n {
                    v.push(t.vec3(&format!("mesh normal {} of {n} (line {})", i + 1, w.line))?);
                }
                normals = Some(v);
            }
            "texturecoords" if uvs.is_none() => {
                let n = t.count("`texturecoords` count")?;
                let named = t.peek().is_some_and(|w| !matches!(w.text, "normals" | "triangles"));
                if named && !t.next_is_number() {
                    let name = t.word("a texture file name")?;
                    material = texture(name.line, name.text);
                }
                let mut v = Vec::with_capacity(reserve(t, n, 2));
                for i in 0..n {
                    let what = format!("mesh texture coordinate {} of {n} (line {})", i + 1, w.line);
                    v.push([t.number(&what)?, t.number(&what)?]);
                }
                uvs = Some(v);
            }
            "triangles" => break,
            other => {
                return Err(t.error(
                    w.line,
                    format!("in the `m` block of line {start}: expected `normals`, `texturecoords` or `triangles`, found `{other}`"),
                ))
            }
        }
    }
    let nt = t.count("`triangles` count")?;
    let per = 3 * (1 + normals.is_some() as usize + uvs.is_some() as usize);
    let mut remap: HashMap<[u32; 3], u32> = HashMap::new();
    let mut vs: Vec<Vertex> = Vec::new();
    let mut tris = Vec::with_capacity(reserve(t, nt, per));
    let (nn, nuv) = (normals.as_ref().map_or(0, Vec::len), uvs.as_ref().map_or(0, Vec::len));
    for k in 0..nt {
        let line = t.line();
        let what = format!("mesh triangle {} of {nt}", k + 1);
        let mut read = |limit: usize, kind: &str| -> Result<[u32; 3], LoadError> {
            let mut idx = [0u32; 3];
            for i in &mut idx {
                let v = t.count(&what)?;
                if v >= limit {
                    return Err(t.error(line, format!("{what}: {kind} index {v} out of range (the mesh has {limit})")));
                }
                *i = v as u32;
            }
            Ok(idx)
        };
        let vi = read(nv, "vertex")?;
        let ni = if normals.is_some() { Some(read(nn, "normal")?) } else { None };
        let ti = if uvs.is_some() { Some(read(nuv, "texture coordinate")?) } else { None };
        let mut tri = [0u32; 3];
        for c in 0..3 {
            let key = [vi[c], ni.map_or(u32::MAX, |n| n[c]), ti.map_or(u32::MAX, |n| n[c])];
            tri[c] = *remap.entry(key).or_insert_with(|| {
                vs.push(Vertex {
                    p: positions[vi[c] as usize],
                    n: normals.as_ref().zip(ni).map(|(n, i)| n[i[c] as usize]),
                    uv: uvs.as_ref().zip(ti).map(|(u, i)| u[i[c] as usize]),
                });
                vs.len() as u32 - 1
            });
        }
        tris.push(tri);
    }
    groups.add(place, &vs, &tris, material);
    Ok(())
}
