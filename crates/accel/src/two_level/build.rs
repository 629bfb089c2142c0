//! Spreading a frame's actors over parts and instances, and building each part.

use super::{transformed_bounds, ActorGeometry, ActorMotion, Instance, Part, PartSpace, SceneLayout, TwoLevel};
use crate::{AccelSpec, BuildError, LiveAccel, UpdatePolicy};
use dynray_geom::{Aabb, TriangleMesh, Vec3};
use glam::Mat4;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};

/// An error about the actors given, as a [`BuildError`].
pub(crate) fn bad_actors(spec: &AccelSpec, message: String) -> BuildError {
    BuildError::Spec { spec: format!("{spec} (two-level)"), message }
}

/// How an actor is held, under a layout.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Role {
    /// In the static part.
    Static,
    /// A world-space part of its own.
    World,
    /// An instance of a local-space part.
    Instance,
}

/// The role of `a` under `layout` (an actor without triangles has none).
pub(crate) fn role(a: &ActorGeometry<'_>, layout: SceneLayout) -> Option<Role> {
    if a.triangles.is_empty() {
        return None;
    }
    Some(match (a.motion, layout) {
        (ActorMotion::Static, _) => Role::Static,
        (ActorMotion::Rigid { to_world, .. }, SceneLayout::Instanced) if invertible(&to_world) => Role::Instance,
        _ => Role::World,
    })
}

/// Whether `m` has a usable inverse (a flattening scale has none: such an actor is held
/// in world space instead).
fn invertible(m: &Mat4) -> bool {
    let d = m.determinant();
    d.is_finite() && d.abs() > 1e-30 && m.inverse().is_finite()
}

impl TwoLevel {
    /// Builds the parts of `actors` (one frame of a scene whose triangles are `mesh`) and
    /// the top level over them. `eye` is the camera, for view-dependent structures (an
    /// instance's part is given the eye in its local space).
    pub fn build(
        spec: &AccelSpec,
        policy: UpdatePolicy,
        layout: SceneLayout,
        actors: &[ActorGeometry<'_>],
        mesh: &TriangleMesh,
        eye: Option<Vec3>,
    ) -> Result<TwoLevel, BuildError> {
        check_actors(spec, actors, mesh, true)?;
        let mut tl = TwoLevel {
            spec: spec.clone(),
            parts: Vec::new(),
            instances: Vec::new(),
            top: Vec::new(),
            order: Vec::new(),
            triangles: mesh.triangle_count() as u32,
        };
        let statics: Vec<usize> =
            (0..actors.len()).filter(|&i| role(&actors[i], layout) == Some(Role::Static)).collect();
        if !statics.is_empty() {
            tl.add_world_part(spec, policy, actors, statics, mesh, eye, u32::MAX)?;
        }
        // Local parts by content, so actors sharing a mesh share one structure (not for
        // view-dependent structures: each instance sees the eye in its own space).
        let shareable = !spec.kind.is_view_dependent();
        let mut by_content: HashMap<u64, Vec<u32>> = HashMap::new();
        for (i, a) in actors.iter().enumerate() {
            match role(a, layout) {
                None | Some(Role::Static) => {}
                Some(Role::World) => tl.add_world_part(spec, policy, actors, vec![i], mesh, eye, i as u32)?,
                Some(Role::Instance) => {
                    let ActorMotion::Rigid { local, to_world } = a.motion else { unreachable!("role") };
                    let to_local = to_world.inverse();
                    let key = content_key(local);
                    let same = |p: &u32| match &tl.parts[*p as usize].space {
                        PartSpace::Local { actors: owners } => {
                            let ActorMotion::Rigid { local: other, .. } = actors[owners[0]].motion else {
                                return false;
                            };
                            other.positions == local.positions && other.indices == local.indices
                        }
                        PartSpace::World { .. } => false,
                    };
                    let found =
                        if shareable { by_content.get(&key).and_then(|v| v.iter().copied().find(same)) } else { None };
                    let part = match found {
                        Some(p) => p,
                        None => {
                            let local_eye = eye.map(|e| to_local.transform_point3(e));
                            let (live, _) = LiveAccel::build(spec, policy, local, local_eye)?;
                            tl.parts.push(Part {
                                live,
                                space: PartSpace::Local { actors: Vec::new() },
                                bounds: local.bounds(),
                                sub: TriangleMesh::default(),
                            });
                            let p = tl.parts.len() as u32 - 1;
                            by_content.entry(key).or_default().push(p);
                            p
                        }
                    };
                    let PartSpace::Local { actors: owners } = &mut tl.parts[part as usize].space else {
                        unreachable!("local part")
                    };
                    owners.push(i);
                    let bounds = transformed_bounds(&tl.parts[part as usize].bounds, &to_world);
                    tl.instances.push(Instance {
                        part,
                        actor: i as u32,
                        first_prim: a.triangles.start,
                        to_local: Some(to_local),
                        to_world: Some(to_world),
                        bounds,
                    });
                }
            }
        }
        tl.rebuild_top();
        Ok(tl)
    }

    /// A world-space part over `members` (actor indices) and its instance.
    #[allow(clippy::too_many_arguments)]
    fn add_world_part(
        &mut self,
        spec: &AccelSpec,
        policy: UpdatePolicy,
        actors: &[ActorGeometry<'_>],
        members: Vec<usize>,
        mesh: &TriangleMesh,
        eye: Option<Vec3>,
        actor: u32,
    ) -> Result<(), BuildError> {
        let mut sub = TriangleMesh::default();
        let mut prims = Vec::new();
        for &m in &members {
            let a = &actors[m];
            let base = sub.positions.len() as u32;
            sub.positions.extend_from_slice(&mesh.positions[a.vertices.start as usize..a.vertices.end as usize]);
            sub.indices.extend(
                mesh.indices[a.triangles.start as usize..a.triangles.end as usize]
                    .iter()
                    .map(|t| t.map(|v| v - a.vertices.start + base)),
            );
            prims.extend(a.triangles.clone());
        }
        let (live, _) = LiveAccel::build(spec, policy, &sub, eye)?;
        let bounds = sub.bounds();
        self.parts.push(Part { live, space: PartSpace::World { actors: members, prims }, bounds, sub });
        self.instances.push(Instance {
            part: self.parts.len() as u32 - 1,
            actor,
            first_prim: 0,
            to_local: None,
            to_world: None,
            bounds,
        });
        Ok(())
    }

    /// The top level over the instances' current boxes.
    pub(crate) fn rebuild_top(&mut self) {
        let boxes: Vec<Aabb> = self.instances.iter().map(|i| i.bounds).collect();
        (self.top, self.order) = super::top::build(&boxes);
    }
}

/// Actors must tile the frame: contiguous triangle and vertex ranges in order, each
/// actor's indices inside its own vertex range (checked when `indices` is set: at a
/// build; the frames of one scene keep their triangles, and an update checks the ranges
/// alone), a rigid actor's local mesh of the same size as its frame triangles.
pub(crate) fn check_actors(
    spec: &AccelSpec,
    actors: &[ActorGeometry<'_>],
    mesh: &TriangleMesh,
    indices: bool,
) -> Result<(), BuildError> {
    let (mut tri, mut vert) = (0u32, 0u32);
    for (i, a) in actors.iter().enumerate() {
        if a.triangles.start != tri || a.vertices.start != vert || a.triangles.end < tri || a.vertices.end < vert {
            return Err(bad_actors(
                spec,
                format!("actor {i}: ranges {:?}/{:?} do not follow the previous actor's", a.triangles, a.vertices),
            ));
        }
        (tri, vert) = (a.triangles.end, a.vertices.end);
        if tri as usize > mesh.triangle_count() || vert as usize > mesh.positions.len() {
            return Err(bad_actors(
                spec,
                format!("actor {i}: ranges beyond the frame's {} triangles", mesh.triangle_count()),
            ));
        }
        let inside = |t: &[u32; 3]| t.iter().all(|v| a.vertices.contains(v));
        let own = &mesh.indices[a.triangles.start as usize..tri as usize];
        if let Some(t) = if indices { own.iter().position(|t| !inside(t)) } else { None } {
            return Err(bad_actors(
                spec,
                format!("actor {i}: triangle {} uses a vertex of another actor", a.triangles.start as usize + t),
            ));
        }
        if let ActorMotion::Rigid { local, .. } = a.motion {
            if local.triangle_count() != a.triangles.len() || local.positions.len() != a.vertices.len() {
                return Err(bad_actors(
                    spec,
                    format!(
                        "actor {i}: local mesh of {} triangles for {} frame triangles",
                        local.triangle_count(),
                        a.triangles.len()
                    ),
                ));
            }
        }
    }
    if tri as usize != mesh.triangle_count() {
        return Err(bad_actors(
            spec,
            format!("the actors cover {tri} of the frame's {} triangles", mesh.triangle_count()),
        ));
    }
    Ok(())
}

/// A hash of a mesh's positions (bits) and indices: equal meshes share a part.
fn content_key(m: &TriangleMesh) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    m.indices.hash(&mut h);
    for p in &m.positions {
        p.map(f32::to_bits).hash(&mut h);
    }
    h.finish()
}
