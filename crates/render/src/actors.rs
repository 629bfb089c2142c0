//! A frame's actors as `dynray-accel`'s two-level structures see them: which triangles
//! and vertices each became, and whether it stays, moves whole (its local mesh and
//! transform) or deforms ([`dynray_scene::ActorState`]). The renderer, `animate` and the
//! bench build their [`LiveScene`]s from this one description.

use dynray_accel::{AccelSpec, ActorGeometry, ActorMotion, BuildError, LiveScene, SceneLayout, UpdatePolicy};
use dynray_scene::{ActorState, Frame, Scene};
use std::time::Duration;

/// The actors of `frame`, a frame that `scene` filled ([`Scene::frame_into`]). A frame
/// that does not match the scene's actors (filled otherwise) is described as one
/// deforming actor: two-level structures then hold it in world space, exactly.
pub fn actor_geometry<'a>(scene: &'a Scene, frame: &Frame) -> Vec<ActorGeometry<'a>> {
    let matches = frame.actor_states.len() == scene.actors.len()
        && frame.actor_ranges.len() == scene.actors.len()
        && frame.vertex_ranges.len() == scene.actors.len();
    if !matches {
        return vec![ActorGeometry {
            triangles: 0..frame.mesh.triangle_count() as u32,
            vertices: 0..frame.mesh.positions.len() as u32,
            motion: ActorMotion::Deforming,
        }];
    }
    scene
        .actors
        .iter()
        .enumerate()
        .map(|(a, actor)| ActorGeometry {
            triangles: frame.actor_ranges[a].clone(),
            vertices: frame.vertex_ranges[a].clone(),
            motion: match frame.actor_states[a] {
                ActorState::Static => ActorMotion::Static,
                ActorState::Deforming => ActorMotion::Deforming,
                ActorState::Rigid(t) => ActorMotion::Rigid { local: &actor.mesh, to_world: t.matrix() },
            },
        })
        .collect()
}

/// `spec` over `frame` in `layout` (the camera as the eye of view-dependent structures).
pub fn build_live_scene(
    spec: &AccelSpec,
    policy: UpdatePolicy,
    layout: SceneLayout,
    scene: &Scene,
    frame: &Frame,
) -> Result<(LiveScene, Duration), BuildError> {
    LiveScene::build(spec, policy, layout, &actor_geometry(scene, frame), &frame.mesh, Some(frame.camera.position))
}
