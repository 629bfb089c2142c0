//! Actors: a mesh in its own (object) space, a material per triangle, and where the
//! actor is placed. The frame ([`crate::Frame`]) is where local geometry becomes world
//! geometry, so that animation can change placement or shape per frame without
//! re-reading or re-baking the source.

use crate::animation::Deformation;
use crate::{NormalSource, Shading, Transform};
use dynray_geom::{Aabb, TriangleMesh, Vec3};

/// Whether an actor's world geometry may change from one frame to the next.
///
/// Acceleration structures can keep what they built for [`Motion::Static`] actors and
/// refit or rebuild only the parts of the frame that belong to [`Motion::Dynamic`] ones
/// (the frame's [`crate::Frame::actor_ranges`] say which triangles those are). Loaders set
/// [`Motion::Dynamic`] on the actors animation moves (a moving [`Actor::node`], a
/// [`Actor::deform`]) and, in the scene language, where the file says so.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Motion {
    /// The same world geometry at every time `t`.
    #[default]
    Static,
    /// World geometry that may differ between times (transform, deformation, or both);
    /// triangle count and order stay the same, so structures can refit.
    Dynamic,
}

/// A mesh placed in the scene with a material per triangle.
#[derive(Clone, Debug, PartialEq)]
pub struct Actor {
    /// Name, if the source gave one.
    pub name: Option<String>,
    /// Geometry in the actor's local (object) space; [`Actor::transform`] places it.
    pub mesh: TriangleMesh,
    /// Index into [`crate::Scene::materials`] for each triangle of `mesh`.
    pub materials: Vec<u32>,
    /// Object-to-world placement, applied when a frame is filled.
    pub transform: Transform,
    /// Whether the world geometry can change with time.
    pub motion: Motion,
    /// How the source asked the actor to be shaded; [`Actor::apply_shading`] makes
    /// `mesh.normals` follow it (`shading.rs`).
    pub shading: Shading,
    /// What `mesh.normals` holds: the source's normals, generated ones, or none.
    pub normal_source: NormalSource,
    /// The node of [`crate::Scene::animation`]'s rig that places the actor: its world
    /// matrix at `t` replaces [`Actor::transform`] (which holds the rest placement).
    pub node: Option<u32>,
    /// What moves the actor's vertices, if anything (`animation/deform.rs`).
    pub deform: Option<Deformation>,
    /// The actor's `elastic { … }` block: a simulated body (`dynray-sim`) whose vertices
    /// the simulation writes into each frame; such an actor is [`Motion::Dynamic`].
    pub elastic: Option<crate::ElasticParams>,
}

impl Actor {
    /// A static actor at the origin ([`Transform::IDENTITY`]) whose triangles all use
    /// `material`, with [`Shading::Auto`] and the normals `mesh` has.
    pub fn new(name: Option<String>, mesh: TriangleMesh, material: u32) -> Self {
        let materials = vec![material; mesh.triangle_count()];
        let normal_source = NormalSource::of(&mesh);
        Self {
            name,
            mesh,
            materials,
            transform: Transform::IDENTITY,
            motion: Motion::Static,
            shading: Shading::Auto,
            normal_source,
            node: None,
            deform: None,
            elastic: None,
        }
    }

    /// The same actor placed by `transform`.
    pub fn with_transform(mut self, transform: Transform) -> Self {
        self.transform = transform;
        self
    }

    /// The actor's geometry in world space (a copy), as a static frame holds it.
    pub fn world_mesh(&self) -> TriangleMesh {
        let mut m = self.mesh.clone();
        self.transform.apply(&mut m);
        m
    }

    /// Bounding box in world space, of exactly the points the frame holds.
    pub fn bounds(&self) -> Aabb {
        if self.transform.is_identity() {
            return self.mesh.bounds();
        }
        Aabb::from_points(self.mesh.positions.iter().map(|&p| Vec3::from_array(self.transform.point(p))))
    }
}
