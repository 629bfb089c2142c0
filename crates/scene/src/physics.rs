//! Parameters of point-based physics (docs/physics.md) as the scene file gives them: the
//! scene's `physics { … }` block and an actor's `elastic { … }` block. They are plain
//! values; `dynray-sim` reads them and runs the simulation (the scene crate knows nothing
//! of it, so that the dependency points one way).

use glam::Vec3;

/// The scene-wide `physics { gravity V ground R substeps I }` block. Lengths are scene
/// units (taken as metres), time seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicsSettings {
    /// Acceleration of gravity (default `<0, -9.81, 0>`).
    pub gravity: Vec3,
    /// Height `y` of a horizontal floor plane; `None`: no floor.
    pub ground: Option<f32>,
    /// Fewest integration steps per frame; the integrator takes more where its stability
    /// bound needs them (default 1).
    pub substeps: u32,
}

impl Default for PhysicsSettings {
    fn default() -> Self {
        Self { gravity: Vec3::new(0.0, -9.81, 0.0), ground: None, substeps: 1 }
    }
}

/// An actor's `elastic { … }` block: a meshless elastic (optionally plastic) body after
/// Müller et al. 2004. SI units: Pa, kg/m³, m/s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElasticParams {
    /// Young's modulus `E` in Pa (`young`, default 5e4).
    pub young: f32,
    /// Poisson's ratio `ν`, in `[0, 0.5)` (`poisson`, default 0.3).
    pub poisson: f32,
    /// Density in kg/m³ (`density`, default 1000).
    pub density: f32,
    /// Damping of internal (relative) motion as a fraction of the critical damping of
    /// one phyxel pair, in `[0, 1]` (`damping`, default 0.02).
    pub damping: f32,
    /// Number of phyxels to sample through the volume (`phyxels`, default 1000; the
    /// sampler gets close to it, not exactly).
    pub phyxels: u32,
    /// Initial velocity of the whole body (`velocity`, default zero).
    pub velocity: Vec3,
    /// Stiffness `k_v` of the volume-conserving term in Pa (`volume`; `None`: `E`).
    pub volume: Option<f32>,
    /// Plastic yield: the elastic strain norm past which strain creeps into plastic
    /// strain (`yield`, default 0: no plasticity unless `creep` > 0).
    pub plastic_yield: f32,
    /// Creep rate in 1/s (`creep`, default 0: purely elastic).
    pub plastic_creep: f32,
    /// Largest norm of the plastic strain (`max_plastic`, default 1).
    pub plastic_max: f32,
}

impl Default for ElasticParams {
    fn default() -> Self {
        Self {
            young: 5e4,
            poisson: 0.3,
            density: 1000.0,
            damping: 0.02,
            phyxels: 1000,
            velocity: Vec3::ZERO,
            volume: None,
            plastic_yield: 0.0,
            plastic_creep: 0.0,
            plastic_max: 1.0,
        }
    }
}
