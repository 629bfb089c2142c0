//! glTF skins ([`Skin`]: joints as rig nodes, inverse bind matrices) and what deforms a
//! mesh actor ([`MeshDeform`]): the skin binding from `JOINTS_0`/`WEIGHTS_0` and the
//! morph targets' `POSITION`/`NORMAL` displacements, gathered primitive by primitive in
//! the order the actor's mesh concatenates them.
//!
//! Only the first set of four influences is read (`JOINTS_1`/`WEIGHTS_1` are ignored
//! with a warning). A primitive without an attribute its neighbours have gets zeros: no
//! displacement, no influence (an unskinned vertex of a skinned mesh stays at its bind
//! position, in the skin's space).

use super::accessor::{check_accessor_with, read_components};
use super::animation::skin_label;
use crate::animation::{Deformation, Morph, MorphTarget, Skin, SkinBinding};
use crate::report::Warning;
use glam::Mat4;
use gltf::accessor::{DataType, Dimensions};
use std::path::Path;

/// The skin `skin` of the file with its joints mapped to rig nodes (`rig_of`); every
/// joint must be a node of the walked scene.
pub(super) fn read_skin(skin: &gltf::Skin, buffers: &[Vec<u8>], rig_of: &[Option<u32>]) -> Result<Skin, String> {
    let label = skin_label(skin.index(), skin.name());
    let mut joints = Vec::new();
    for (j, node) in skin.joints().enumerate() {
        match rig_of.get(node.index()).copied().flatten() {
            Some(r) => joints.push(r),
            None => {
                return Err(format!("{label}: joint {j} is node {}, which is not in the scene shown", node.index()))
            }
        }
    }
    let inverse_bind = match skin.inverse_bind_matrices() {
        None => vec![Mat4::IDENTITY; joints.len()],
        Some(acc) => {
            let what = |m: String| format!("{label}: inverseBindMatrices: {m}");
            check_accessor_with(&acc, Dimensions::Mat4, &[DataType::F32], false, buffers).map_err(what)?;
            if acc.count() < joints.len() {
                return Err(what(format!(
                    "accessor {} has {} matrices for {} joints",
                    acc.index(),
                    acc.count(),
                    joints.len()
                )));
            }
            let m = read_components(&acc, buffers).map_err(what)?;
            let mats: Vec<Mat4> = m.chunks_exact(16).take(joints.len()).map(Mat4::from_cols_slice).collect();
            if let Some(j) = mats.iter().position(|m| !m.is_finite()) {
                return Err(what(format!("matrix {j} is not finite")));
            }
            mats
        }
    };
    Ok(Skin { name: skin.name().map(str::to_string), joints, inverse_bind })
}

/// A mesh actor's deformation, built one primitive at a time.
pub(super) struct MeshDeform {
    /// `(index into the rig's skins, joint count)` when the actor's node has a skin.
    skin: Option<(u32, usize)>,
    joints: Vec<[u16; 4]>,
    weights: Vec<[f32; 4]>,
    any_skinned: bool,
    /// Per morph target, displacements of every vertex read so far.
    positions: Vec<Vec<[f32; 3]>>,
    normals: Vec<Vec<[f32; 3]>>,
    any_target_normals: bool,
    warned_second_set: bool,
    /// A target accessor is sparse (not read): the mesh's morph targets are dropped, and
    /// it keeps its base shape, as before animation was read.
    sparse_targets: bool,
}

/// The number of morph targets of `mesh` (the most any primitive has; glTF asks them
/// all to have the same).
pub(super) fn target_count(mesh: &gltf::Mesh) -> usize {
    mesh.primitives().map(|p| p.morph_targets().len()).max().unwrap_or(0)
}

impl MeshDeform {
    /// For a mesh with `targets` morph targets, skinned by `skin` when given.
    pub(super) fn new(skin: Option<(u32, usize)>, targets: usize) -> Self {
        MeshDeform {
            skin,
            joints: Vec::new(),
            weights: Vec::new(),
            any_skinned: false,
            positions: vec![Vec::new(); targets],
            normals: vec![Vec::new(); targets],
            any_target_normals: false,
            warned_second_set: false,
            sparse_targets: false,
        }
    }

    /// Reads `prim`'s influences and displacements (`vertices` of them, its POSITION
    /// count); `label` names it in messages.
    pub(super) fn add_primitive(
        &mut self,
        prim: &gltf::Primitive,
        vertices: usize,
        buffers: &[Vec<u8>],
        label: &str,
        path: &Path,
        warnings: &mut Vec<Warning>,
    ) -> Result<(), String> {
        if let Some((skin, joint_count)) = self.skin {
            let joints = prim.get(&gltf::Semantic::Joints(0));
            let weights = prim.get(&gltf::Semantic::Weights(0));
            let second =
                prim.get(&gltf::Semantic::Joints(1)).is_some() || prim.get(&gltf::Semantic::Weights(1)).is_some();
            if second && !std::mem::replace(&mut self.warned_second_set, true) {
                warnings.push(Warning::new(
                    path,
                    None,
                    format!("{label}: JOINTS_1/WEIGHTS_1 ignored (only the first four influences are read)"),
                ));
            }
            match (joints, weights) {
                (Some(j), Some(w)) => {
                    let jw = read_influences(&j, &w, vertices, buffers).map_err(|m| format!("{label}: {m}"))?;
                    for (v, (js, ws)) in jw.0.iter().zip(&jw.1).enumerate() {
                        if let Some((&bad, _)) =
                            js.iter().zip(ws).find(|(&j, &w)| w != 0.0 && j as usize >= joint_count)
                        {
                            return Err(format!(
                                "{label}: JOINTS_0 of vertex {v} names joint {bad}, but skin {skin} has {joint_count} joints"
                            ));
                        }
                    }
                    self.joints.extend(jw.0);
                    self.weights.extend(jw.1);
                    self.any_skinned = true;
                }
                (j, w) => {
                    if j.is_some() != w.is_some() {
                        return Err(format!("{label}: JOINTS_0 and WEIGHTS_0 must come together"));
                    }
                    self.joints.resize(self.joints.len() + vertices, [0; 4]);
                    self.weights.resize(self.weights.len() + vertices, [0.0; 4]);
                }
            }
        }
        let targets: Vec<_> = prim.morph_targets().collect();
        let sparse = targets.iter().flat_map(|t| [t.positions(), t.normals()]).flatten().any(|a| a.sparse().is_some());
        if sparse && !std::mem::replace(&mut self.sparse_targets, true) {
            warnings.push(Warning::new(
                path,
                None,
                format!("{label}: a morph target accessor is sparse, which dynray does not read; the mesh keeps its base shape"),
            ));
        }
        if self.sparse_targets {
            return Ok(());
        }
        for (t, (pos, nrm)) in self.positions.iter_mut().zip(self.normals.iter_mut()).enumerate() {
            let target = targets.get(t);
            for (what, acc, out) in [
                ("POSITION", target.and_then(|t| t.positions()), &mut *pos),
                ("NORMAL", target.and_then(|t| t.normals()), &mut *nrm),
            ] {
                match acc {
                    Some(acc) => {
                        let here = |m: String| format!("{label}: morph target {t} {what}: {m}");
                        check_accessor_with(&acc, Dimensions::Vec3, &[DataType::F32], false, buffers).map_err(here)?;
                        if acc.count() != vertices {
                            return Err(here(format!("{} entries for {vertices} positions", acc.count())));
                        }
                        let d = read_components(&acc, buffers).map_err(here)?;
                        if d.iter().any(|x| !x.is_finite()) {
                            return Err(here("a displacement is not finite".into()));
                        }
                        out.extend(d.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
                        self.any_target_normals |= what == "NORMAL";
                    }
                    None => out.resize(out.len() + vertices, [0.0; 3]),
                }
            }
        }
        Ok(())
    }

    /// The deformation, if anything deforms the actor: morph weights come from `node`;
    /// target normals are kept only when the actor's mesh has normals to displace.
    pub(super) fn finish(self, node: u32, mesh_has_normals: bool) -> Option<Deformation> {
        let keep_normals = mesh_has_normals && self.any_target_normals;
        let morph = (!self.positions.is_empty() && !self.sparse_targets).then(|| Morph {
            node,
            targets: self
                .positions
                .into_iter()
                .zip(self.normals)
                .map(|(positions, normals)| MorphTarget { positions, normals: keep_normals.then_some(normals) })
                .collect(),
        });
        let skin = match self.skin {
            Some((skin, _)) if self.any_skinned => {
                Some(SkinBinding { skin, joints: self.joints, weights: self.weights })
            }
            _ => None,
        };
        (morph.is_some() || skin.is_some()).then(|| Deformation { morph, skin, ..Default::default() })
    }
}

/// `JOINTS_0` (u8/u16 `VEC4`) and `WEIGHTS_0` (float, or normalised u8/u16, `VEC4`) of
/// one primitive with `vertices` positions.
#[allow(clippy::type_complexity)]
fn read_influences(
    joints: &gltf::Accessor,
    weights: &gltf::Accessor,
    vertices: usize,
    buffers: &[Vec<u8>],
) -> Result<(Vec<[u16; 4]>, Vec<[f32; 4]>), String> {
    check_accessor_with(joints, Dimensions::Vec4, &[DataType::U8, DataType::U16], false, buffers)
        .map_err(|m| format!("JOINTS_0: {m}"))?;
    check_accessor_with(weights, Dimensions::Vec4, &[DataType::F32, DataType::U8, DataType::U16], true, buffers)
        .map_err(|m| format!("WEIGHTS_0: {m}"))?;
    if weights.data_type() != DataType::F32 && !weights.normalized() {
        return Err(format!("WEIGHTS_0: accessor {} is an integer type but not normalized", weights.index()));
    }
    for (what, acc) in [("JOINTS_0", joints), ("WEIGHTS_0", weights)] {
        if acc.count() != vertices {
            return Err(format!("{what} has {} entries for {vertices} positions", acc.count()));
        }
    }
    let j = read_components(joints, buffers).map_err(|m| format!("JOINTS_0: {m}"))?;
    let w = read_components(weights, buffers).map_err(|m| format!("WEIGHTS_0: {m}"))?;
    if let Some(v) = w.chunks_exact(4).position(|w| w.iter().any(|x| !x.is_finite())) {
        return Err(format!("WEIGHTS_0 of vertex {v} is not finite"));
    }
    // Joint components are u8/u16 values read exactly into f32.
    let j = j.chunks_exact(4).map(|c| [c[0] as u16, c[1] as u16, c[2] as u16, c[3] as u16]).collect();
    let w = w.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect();
    Ok((j, w))
}
