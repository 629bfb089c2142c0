//! What can go wrong building or running a simulation.

use thiserror::Error;

/// Errors of `dynray-sim`.
#[derive(Debug, Error)]
pub enum SimError {
    /// The body's mesh encloses no volume (open, inside out, or flat).
    #[error(
        "actor {actor}: the mesh encloses no volume (signed volume {volume}); an elastic body needs a closed mesh"
    )]
    NoVolume {
        /// Index of the actor in the scene.
        actor: usize,
        /// The signed volume found.
        volume: f64,
    },
    /// Too few sample points fell inside the mesh.
    #[error("actor {actor}: only {found} phyxels fell inside the mesh (at least 8 are needed); raise `phyxels`")]
    TooFewPhyxels {
        /// Index of the actor.
        actor: usize,
        /// How many were found.
        found: usize,
    },
    /// A phyxel's neighbours do not span three dimensions, so its MLS moment matrix
    /// cannot be inverted.
    #[error("actor {actor}: phyxel {phyxel} has neighbours in fewer than three directions (singular moment matrix)")]
    SingularMoments {
        /// Index of the actor.
        actor: usize,
        /// Index of the phyxel.
        phyxel: usize,
    },
    /// The structure for inside tests or contact could not be built.
    #[error("building the ray-query structure: {0}")]
    Accel(#[from] dynray_accel::BuildError),
    /// The frame does not hold the actor the body belongs to (another scene's frame).
    #[error("the frame has no vertices for actor {actor} ({vertices} expected)")]
    FrameMismatch {
        /// Index of the actor.
        actor: usize,
        /// Vertices the body has.
        vertices: usize,
    },
    /// The stability bound needs more steps per frame than are allowed: the material is
    /// too stiff (or the phyxels too fine) for an explicit step at this frame rate.
    #[error("the stability bound needs {needed} steps per frame (at most {max} are taken): lower `young` or `phyxels`, or raise `frame_rate`")]
    TooStiff {
        /// Steps per frame the bound asks for.
        needed: u64,
        /// The cap, [`crate::integrator::MAX_STEPS_PER_FRAME`].
        max: u32,
    },
    /// The state stopped being finite: the step was unstable.
    #[error("actor {actor}: the simulation diverged at step {step} (a non-finite position)")]
    Diverged {
        /// Index of the actor.
        actor: usize,
        /// Step count when found.
        step: u64,
    },
    /// A physics checkpoint that cannot be used (docs/animate.md, "Physics checkpoints").
    #[error("physics checkpoint: {0}")]
    Checkpoint(String),
}
