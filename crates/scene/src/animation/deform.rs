//! How a deforming actor's vertices move: keyed vertex positions (BART's `tpa` patches),
//! morph targets and skinning (glTF), in that order; and its normals, carried along or
//! regenerated from the moved positions.
//!
//! All per-vertex arrays are per vertex of the actor's mesh. Generating smooth normals
//! splits vertices along creases ([`dynray_geom::SmoothNormals`]); [`Deformation::gather`]
//! then copies each array to the split vertices, and [`Deformation::smooth`] keeps the
//! topology so each frame's normals are made from that frame's positions.

use super::rig::Rig;
use dynray_geom::{SmoothNormals, TriangleMesh};
use glam::{Mat3, Mat4, Vec3};
use std::sync::Arc;

/// Keyed vertex positions: the mesh at each key time, linearly interpolated between
/// (held before the first key and after the last).
#[derive(Clone, Debug, PartialEq)]
pub struct VertexKeys {
    /// Key times, strictly increasing.
    pub times: Vec<f32>,
    /// `positions[k][v]`: vertex `v` at key `k` (the actor's local space).
    pub positions: Vec<Vec<[f32; 3]>>,
    /// Normals per key, when the source gives them.
    pub normals: Option<Vec<Vec<[f32; 3]>>>,
}

/// One morph target: displacements added to the base mesh, scaled by its weight.
#[derive(Clone, Debug, PartialEq)]
pub struct MorphTarget {
    /// Position displacement per vertex.
    pub positions: Vec<[f32; 3]>,
    /// Normal displacement per vertex, when the file gives it.
    pub normals: Option<Vec<[f32; 3]>>,
}

/// Morph targets and the node whose weights drive them.
#[derive(Clone, Debug, PartialEq)]
pub struct Morph {
    /// The node ([`Rig::nodes`]) whose weights apply (glTF: the mesh's node).
    pub node: u32,
    /// The targets.
    pub targets: Vec<MorphTarget>,
}

/// A mesh bound to a skin: up to four joint influences per vertex (glTF's `JOINTS_0`
/// and `WEIGHTS_0`).
#[derive(Clone, Debug, PartialEq)]
pub struct SkinBinding {
    /// Index into [`Rig::skins`].
    pub skin: u32,
    /// Per vertex, four indices into that skin's joints.
    pub joints: Vec<[u16; 4]>,
    /// Per vertex, the four weights (glTF asks them to sum to one; they are used as
    /// given, and a vertex whose weights sum to zero stays where it is).
    pub weights: Vec<[f32; 4]>,
}

/// What deforms an actor; `None` fields do nothing.
#[derive(Clone, Debug, Default)]
pub struct Deformation {
    /// Keyed vertex positions, replacing the mesh's own.
    pub keys: Option<VertexKeys>,
    /// Morph targets, added next.
    pub morph: Option<Morph>,
    /// Skinning, last: it takes the vertices to world space (the actor's node and
    /// transform are then not applied, as glTF specifies).
    pub skin: Option<SkinBinding>,
    /// Set by shading when the actor's normals were generated: normals are remade each
    /// frame from the deformed positions with this topology.
    pub smooth: Option<Arc<SmoothNormals>>,
}

impl PartialEq for Deformation {
    /// Equal deformations; regenerated-normal topologies compare by their output
    /// triangles and vertex count (the split they describe).
    fn eq(&self, other: &Self) -> bool {
        let same_smooth = match (&self.smooth, &other.smooth) {
            (None, None) => true,
            (Some(a), Some(b)) => {
                Arc::ptr_eq(a, b)
                    || (a.vertex_count() == b.vertex_count()
                        && a.indices() == b.indices()
                        && a.crease_deg() == b.crease_deg())
            }
            _ => false,
        };
        self.keys == other.keys && self.morph == other.morph && self.skin == other.skin && same_smooth
    }
}

impl Deformation {
    /// Checks the arrays against the actor's `vertices` and the rig, so evaluation never
    /// indexes out of range. The message names the part at fault.
    pub fn validate(&self, vertices: usize, rig: &Rig) -> Result<(), String> {
        let count = |what: &str, n: usize| {
            if n == vertices {
                Ok(())
            } else {
                Err(format!("{what} has {n} vertices, the mesh {vertices}"))
            }
        };
        if let Some(sm) = &self.smooth {
            count("the regenerated normals' topology", sm.vertex_count())?;
        }
        if let Some(k) = &self.keys {
            if k.times.is_empty() || k.times.len() != k.positions.len() {
                return Err(format!("{} key times for {} keyed meshes", k.times.len(), k.positions.len()));
            }
            if k.times.windows(2).any(|w| w[0].partial_cmp(&w[1]) != Some(std::cmp::Ordering::Less))
                || k.times.iter().any(|t| !t.is_finite())
            {
                return Err("vertex key times must be finite and increasing".into());
            }
            for (i, p) in k.positions.iter().enumerate() {
                count(&format!("vertex key {i}"), p.len())?;
            }
            if let Some(ns) = &k.normals {
                if ns.len() != k.times.len() {
                    return Err(format!("{} normal keys for {} key times", ns.len(), k.times.len()));
                }
                for (i, n) in ns.iter().enumerate() {
                    count(&format!("vertex key {i}'s normals"), n.len())?;
                }
            }
        }
        if let Some(m) = &self.morph {
            if m.node as usize >= rig.nodes.len() {
                return Err(format!(
                    "morph weights come from node {}, but there are {} nodes",
                    m.node,
                    rig.nodes.len()
                ));
            }
            for (i, t) in m.targets.iter().enumerate() {
                count(&format!("morph target {i}"), t.positions.len())?;
                if let Some(n) = &t.normals {
                    count(&format!("morph target {i}'s normals"), n.len())?;
                }
            }
        }
        if let Some(s) = &self.skin {
            let Some(skin) = rig.skins.get(s.skin as usize) else {
                return Err(format!("skin {} does not exist ({} skins)", s.skin, rig.skins.len()));
            };
            count("the skin's joints", s.joints.len())?;
            count("the skin's weights", s.weights.len())?;
            for (v, (j, w)) in s.joints.iter().zip(&s.weights).enumerate() {
                if let Some(bad) = j.iter().zip(w).find(|(&j, &w)| w != 0.0 && j as usize >= skin.joints.len()) {
                    return Err(format!("vertex {v} names joint {} of a skin with {}", bad.0, skin.joints.len()));
                }
                if w.iter().any(|w| !w.is_finite()) {
                    return Err(format!("vertex {v} has a non-finite skin weight"));
                }
            }
        }
        Ok(())
    }

    /// Copies every per-vertex array to the vertices `smooth` split off (they deform
    /// with their source vertex) and keeps `smooth` to remake normals each frame.
    pub fn gather(&mut self, smooth: Arc<SmoothNormals>) -> Result<(), dynray_geom::MeshError> {
        let mut scratch = Vec::new();
        let mut regather = |v: &mut Vec<[f32; 3]>| -> Result<(), dynray_geom::MeshError> {
            smooth.gather(v, &mut scratch)?;
            std::mem::swap(v, &mut scratch);
            Ok(())
        };
        if let Some(k) = &mut self.keys {
            k.positions.iter_mut().try_for_each(&mut regather)?;
            // Generated normals replace the keys' own.
            k.normals = None;
        }
        if let Some(m) = &mut self.morph {
            for t in &mut m.targets {
                regather(&mut t.positions)?;
                t.normals = None;
            }
        }
        if let Some(s) = &mut self.skin {
            let mut j = Vec::new();
            smooth.gather(&s.joints, &mut j)?;
            s.joints = j;
            let mut w = Vec::new();
            smooth.gather(&s.weights, &mut w)?;
            s.weights = w;
        }
        self.smooth = Some(smooth);
        Ok(())
    }

    /// Whether the deformation leaves the vertices in world space (skinning does).
    pub fn is_world_space(&self) -> bool {
        self.skin.is_some()
    }

    /// The deformed vertices at `t`, appended to `positions` (and, when `normals` is
    /// given, the normals likewise): in the actor's local space, or in world space when
    /// [`Deformation::is_world_space`]. `world` holds the rig's node matrices at `t`.
    /// Regenerated normals ([`Deformation::smooth`]) are not made here: the caller makes
    /// them once the positions are in world space.
    pub fn pose(
        &self,
        mesh: &TriangleMesh,
        rig: &Rig,
        t: f32,
        world: &[Mat4],
        positions: &mut Vec<[f32; 3]>,
        normals: Option<&mut Vec<[f32; 3]>>,
    ) {
        let start = positions.len();
        let n = mesh.positions.len();
        let base_normals = mesh.normals.as_deref();
        let mut normals = normals;
        let nstart = normals.as_ref().map_or(0, |v| v.len());
        // 1. Keyed positions (or the mesh's).
        match &self.keys {
            Some(k) => {
                let next = k.times.partition_point(|&x| x <= t);
                let (a, b, s) = if next == 0 {
                    (0, 0, 0.0)
                } else if next == k.times.len() {
                    (next - 1, next - 1, 0.0)
                } else {
                    let (t0, t1) = (k.times[next - 1], k.times[next]);
                    (next - 1, next, ((t - t0) / (t1 - t0)).clamp(0.0, 1.0))
                };
                positions.extend(k.positions[a].iter().zip(&k.positions[b]).map(|(p, q)| lerp3(*p, *q, s)));
                if let Some(out) = normals.as_deref_mut() {
                    match &k.normals {
                        Some(ns) => out.extend(ns[a].iter().zip(&ns[b]).map(|(p, q)| lerp3(*p, *q, s))),
                        None => extend_normals(out, base_normals, n),
                    }
                }
            }
            None => {
                positions.extend_from_slice(&mesh.positions);
                if let Some(out) = normals.as_deref_mut() {
                    extend_normals(out, base_normals, n);
                }
            }
        }
        let ps = &mut positions[start..];
        // 2. Morph targets.
        if let Some(m) = &self.morph {
            let mut w = Vec::new();
            rig.weights(m.node, t, &mut w);
            for (target, &weight) in m.targets.iter().zip(&w) {
                if weight == 0.0 {
                    continue;
                }
                for (p, d) in ps.iter_mut().zip(&target.positions) {
                    *p = add_scaled(*p, *d, weight);
                }
                if let (Some(out), Some(dn)) = (normals.as_deref_mut(), &target.normals) {
                    for (nv, d) in out[nstart..].iter_mut().zip(dn) {
                        *nv = add_scaled(*nv, *d, weight);
                    }
                }
            }
        }
        // 3. Skinning into world space.
        if let Some(s) = &self.skin {
            let skin = &rig.skins[s.skin as usize];
            let joint_mats: Vec<Mat4> =
                skin.joints.iter().zip(&skin.inverse_bind).map(|(&j, ib)| world[j as usize] * *ib).collect();
            let mut out_normals = normals.map(|v| &mut v[nstart..]);
            for (v, p) in ps.iter_mut().enumerate() {
                let (jv, wv) = (s.joints[v], s.weights[v]);
                let mut m = Mat4::ZERO;
                for k in 0..4 {
                    if wv[k] != 0.0 {
                        m += joint_mats[jv[k] as usize] * wv[k];
                    }
                }
                if m == Mat4::ZERO {
                    continue;
                }
                *p = m.transform_point3(Vec3::from_array(*p)).to_array();
                if let Some(out) = out_normals.as_deref_mut() {
                    let nm = Mat3::from_mat4(m).inverse().transpose();
                    out[v] = (nm * Vec3::from_array(out[v])).normalize_or_zero().to_array();
                }
            }
        }
    }
}

fn extend_normals(out: &mut Vec<[f32; 3]>, base: Option<&[[f32; 3]]>, n: usize) {
    match base {
        Some(b) => out.extend_from_slice(b),
        None => out.resize(out.len() + n, [0.0; 3]),
    }
}

fn lerp3(p: [f32; 3], q: [f32; 3], s: f32) -> [f32; 3] {
    [p[0] + (q[0] - p[0]) * s, p[1] + (q[1] - p[1]) * s, p[2] + (q[2] - p[2]) * s]
}

fn add_scaled(p: [f32; 3], d: [f32; 3], w: f32) -> [f32; 3] {
    [p[0] + d[0] * w, p[1] + d[1] * w, p[2] + d[2] * w]
}
