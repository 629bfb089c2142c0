//! A [`Frame`]: the scene at one time `t`, flattened into one world-space mesh for the
//! acceleration structures and integrators, and [`Scene::frame_into`], which fills it.
//!
//! Order is the contract structures rely on to refit instead of rebuilding: triangles
//! come in actor order, then in each actor's own triangle order, for every `t`; vertices
//! likewise. Time enters through [`Scene::animation`] (`animation/`): the rig's node
//! matrices at `t` place actors with a [`crate::Actor::node`], lights and the camera; an
//! actor's [`crate::Actor::deform`] poses its vertices (keys, morphs, skin) — never
//! changing its triangle count or order.

use crate::{Camera, Environment, FieldPlacement, Light, Material, Projection, Scene, Settings, Texture, Transform};
use dynray_geom::{TriangleMesh, Vec3};
use std::ops::Range;
use std::sync::Arc;

/// One time step of a scene, flattened for the acceleration structures and integrators.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// All actors' triangles in world space, concatenated in actor order (triangle order
    /// within each).
    pub mesh: TriangleMesh,
    /// Material index per triangle of `mesh`.
    pub materials_of: Vec<u32>,
    /// Materials.
    pub materials: Vec<Material>,
    /// The scene's textures (shared pointers: filling a frame copies no texels).
    pub textures: Vec<Arc<Texture>>,
    /// Lights.
    pub lights: Vec<Light>,
    /// The camera (resolved: never absent).
    pub camera: Camera,
    /// Render settings.
    pub settings: Settings,
    /// Background, ambient, medium.
    pub environment: Environment,
    /// `actor_ranges[a]` is the range of triangle indices (into `mesh.indices` and
    /// `materials_of`) that actor `a` of [`Scene::actors`] became: the ranges are in
    /// actor order, contiguous, and cover every triangle, so a hit's triangle index
    /// finds its actor by binary search ([`Frame::actor_of`]).
    pub actor_ranges: Vec<Range<u32>>,
    /// `vertex_ranges[a]` is the range of vertex indices (into `mesh.positions` and its
    /// normals and uvs) that actor `a` became, in actor order and contiguous like
    /// `actor_ranges`: where a simulation (`dynray-sim`) writes an actor's deformed
    /// vertices.
    pub vertex_ranges: Vec<Range<u32>>,
    /// `actor_states[a]` says how actor `a` was placed in this frame, for structures that
    /// keep parts of a frame from one frame to the next (`dynray-accel`'s two-level
    /// layouts): static actors are built once, rigid ones become instances of their local
    /// mesh, deforming ones are refit or rebuilt.
    pub actor_states: Vec<ActorState>,
    /// The scene's distance fields ([`Scene::distance_fields`]): not in `mesh`; whoever
    /// renders the frame loads them and intersects them beside it.
    pub distance_fields: Vec<FieldPlacement>,
    /// The time this frame was filled for, in seconds.
    pub time: f32,
}

impl Default for Frame {
    /// An empty frame to fill with [`Scene::frame_into`]. Its camera is a placeholder (at
    /// `+z`, looking at the origin) that filling replaces.
    fn default() -> Self {
        Self {
            mesh: TriangleMesh::default(),
            materials_of: Vec::new(),
            materials: Vec::new(),
            textures: Vec::new(),
            lights: Vec::new(),
            camera: Camera {
                position: Vec3::Z,
                look_at: Vec3::ZERO,
                up: Vec3::Y,
                projection: Projection::Perspective { fov_y_deg: 45.0 },
                clip: crate::Clip::NONE,
            },
            settings: Settings::default(),
            environment: Environment::default(),
            actor_ranges: Vec::new(),
            vertex_ranges: Vec::new(),
            actor_states: Vec::new(),
            distance_fields: Vec::new(),
            time: 0.0,
        }
    }
}

/// How one actor's world geometry came about in a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ActorState {
    /// A [`crate::Motion::Static`] actor: the same world triangles in every frame.
    Static,
    /// A moving actor placed whole by this transform: its world vertices are the
    /// transform applied to its local mesh ([`crate::Actor::mesh`]), bit for bit.
    Rigid(Transform),
    /// An actor whose vertices move on their own (a deformation: keys, morphs, skin; or a
    /// simulated body, whose vertices the simulation writes into the frame).
    Deforming,
}

impl Frame {
    /// The actor (index into [`Scene::actors`]) that triangle `prim` of `mesh` belongs
    /// to; `None` when `prim` is out of range (a miss is `u32::MAX`).
    pub fn actor_of(&self, prim: u32) -> Option<usize> {
        let a = self.actor_ranges.partition_point(|r| r.end <= prim);
        self.actor_ranges.get(a).filter(|r| r.contains(&prim)).map(|_| a)
    }
}

impl Scene {
    /// The scene at time `t`, in a new [`Frame`]. Use [`Scene::frame_into`] to reuse one
    /// frame's buffers from frame to frame.
    pub fn frame(&self, t: f32) -> Frame {
        let mut f = Frame::default();
        self.frame_into(t, &mut f);
        f
    }

    /// Fills `frame` with the scene at time `t` (seconds from the start of the scene's
    /// animation; static scenes look the same at every `t`).
    ///
    /// Every buffer of `frame` is cleared and refilled in place, so a frame of the same
    /// scene is filled again without allocating. Triangle and vertex order is the same
    /// for every `t` (module docs). Actors without vertex normals get zero normals when
    /// another actor has some: shading reads a zero normal as "use the triangle's
    /// geometric normal" (seed 003 §3.1), so one mesh can mix both. Likewise actors
    /// without texture coordinates get `(0, 0)` uvs when another actor has some (the
    /// frame once dropped every actor's uvs then, and with them a textured mesh's
    /// texture); loaders give such actors untextured materials, so nothing samples them.
    pub fn frame_into(&self, t: f32, frame: &mut Frame) {
        let Frame { mesh, materials_of, actor_ranges, vertex_ranges, actor_states, .. } = frame;
        mesh.positions.clear();
        mesh.indices.clear();
        materials_of.clear();
        actor_ranges.clear();
        vertex_ranges.clear();
        actor_states.clear();
        let any_normals = self.actors.iter().any(|a| a.mesh.normals.is_some());
        let any_uvs = self.actors.iter().any(|a| a.mesh.uvs.is_some());
        let mut normals = mesh.normals.take().unwrap_or_default();
        normals.clear();
        let mut uvs = mesh.uvs.take().unwrap_or_default();
        uvs.clear();
        let rig = &self.animation.rig;
        let mut world = Vec::new();
        if !rig.nodes.is_empty() {
            rig.world_matrices(t, &mut world);
        }
        let mut scratch = Vec::new();
        for a in &self.actors {
            let base = mesh.positions.len() as u32;
            let first = mesh.indices.len() as u32;
            // A node's world matrix at `t` places the actor; else its own transform.
            let placement = match a.node.and_then(|n| world.get(n as usize)) {
                Some(m) => Transform::new(*m),
                None => a.transform,
            };
            match &a.deform {
                None => {
                    if placement.is_identity() {
                        mesh.positions.extend_from_slice(&a.mesh.positions);
                    } else {
                        mesh.positions.extend(a.mesh.positions.iter().map(|&p| placement.point(p)));
                    }
                    if any_normals {
                        match &a.mesh.normals {
                            Some(n) if placement.is_identity() => normals.extend_from_slice(n),
                            Some(n) => {
                                let to_world = placement.normal_fn();
                                normals.extend(n.iter().map(|&v| to_world(v)));
                            }
                            None => normals.resize(normals.len() + a.mesh.vertex_count(), [0.0; 3]),
                        }
                    }
                }
                Some(d) => {
                    let (vstart, nstart) = (mesh.positions.len(), normals.len());
                    // Normals carried through the deformation: the file's own. Generated
                    // ones are remade below from the posed positions.
                    let carry = any_normals && a.mesh.normals.is_some() && d.smooth.is_none();
                    d.pose(&a.mesh, rig, t, &world, &mut mesh.positions, carry.then_some(&mut normals));
                    if !d.is_world_space() && !placement.is_identity() {
                        for p in &mut mesh.positions[vstart..] {
                            *p = placement.point(*p);
                        }
                        if carry {
                            let to_world = placement.normal_fn();
                            for n in &mut normals[nstart..] {
                                *n = to_world(*n);
                            }
                        }
                    }
                    if any_normals && !carry {
                        let posed = &mesh.positions[vstart..];
                        match &d.smooth {
                            Some(sm)
                                if sm.compute(&posed[..sm.vertex_count() - sm.split_count()], &mut scratch).is_ok() =>
                            {
                                normals.extend_from_slice(&scratch)
                            }
                            _ => normals.resize(nstart + a.mesh.vertex_count(), [0.0; 3]),
                        }
                    }
                }
            }
            mesh.indices.extend(a.mesh.indices.iter().map(|t| t.map(|i| i + base)));
            materials_of.extend_from_slice(&a.materials);
            if any_uvs {
                match &a.mesh.uvs {
                    Some(t) => uvs.extend_from_slice(t),
                    None => uvs.resize(uvs.len() + a.mesh.vertex_count(), [0.0; 2]),
                }
            }
            actor_ranges.push(first..mesh.indices.len() as u32);
            vertex_ranges.push(base..mesh.positions.len() as u32);
            actor_states.push(if a.deform.is_some() || a.elastic.is_some() {
                ActorState::Deforming
            } else if a.motion == crate::Motion::Static {
                ActorState::Static
            } else {
                ActorState::Rigid(placement)
            });
        }
        mesh.normals = any_normals.then_some(normals);
        mesh.uvs = any_uvs.then_some(uvs);
        frame.materials.clone_from(&self.materials);
        if frame.materials.is_empty() {
            frame.materials.push(Material::default());
        }
        frame.textures.clone_from(&self.textures);
        frame.lights.clone_from(&self.lights);
        for &(light, node) in &self.animation.light_nodes {
            if let (Some(l), Some(m)) = (frame.lights.get_mut(light), world.get(node as usize)) {
                l.kind = l.kind.transformed(m);
            }
        }
        frame.camera = self.camera.unwrap_or_else(|| Camera::framing(&frame.mesh.bounds()));
        if let Some(m) = self.animation.camera_node.and_then(|n| world.get(n as usize)) {
            frame.camera = frame.camera.transformed(m);
        }
        frame.settings = self.settings;
        frame.environment = self.environment;
        frame.distance_fields.clone_from(&self.distance_fields);
        frame.time = t;
    }
}
