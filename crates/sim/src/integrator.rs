//! The time step. Bodies advance by semi-implicit (symplectic) Euler (`Body::step`),
//! which is stable for an undamped oscillator of angular frequency `ω` while `ω dt < 2`.
//! The stiffest mode of a discretised elastic solid is a pressure wave across one phyxel
//! spacing `s`, `ω ≈ 2 c / s` with `c = √((λ + 2μ + k_v) / ρ)`, which gives the
//! Courant–Friedrichs–Lewy-like bound
//!
//! `dt ≤ C s / c`
//!
//! with a safety factor [`CFL`] below 1 (the MLS stencil couples about 30 neighbours, so
//! its stiffest mode is stiffer than a chain's; [`CFL`] was set from measurement, see
//! its docs). Explicit damping adds `dt ≤ 1 / max_i (Σ_pairs c / m_i)` (Gershgorin's
//! bound on the damping matrix). A frame of `1 / frame_rate` seconds is split into the
//! larger of the scene's `substeps` and the count these bounds need.

use crate::body::Body;
use crate::SimError;

/// Safety factor `C` of the bound `dt ≤ C s / c`. Measured on a cube of 343 phyxels
/// (E = 5e4, ν = 0.3, ρ = 1000, no damping, dropped at 5 m/s onto the floor, 1,000
/// steps; tests/physics.rs): 0.5, 0.6 and 0.7 stay bounded, 0.8 diverges within 128
/// steps; 0.4 leaves a factor of 2.
pub const CFL: f64 = 0.4;

/// Largest stable step of `body`, s.
pub fn stable_dt(body: &Body) -> f64 {
    let elastic = CFL * body.spacing / body.material.wave_speed();
    let rate = body.max_damping_rate();
    if rate > 0.0 {
        elastic.min(1.0 / rate)
    } else {
        elastic
    }
}

/// Most steps one frame may take: past it a frame would take minutes, so the world
/// refuses the material instead of appearing to hang.
pub const MAX_STEPS_PER_FRAME: u32 = 100_000;

/// Steps per frame of `frame_dt` seconds: at least `min`, and enough for every body's
/// stable step; an error past [`MAX_STEPS_PER_FRAME`].
pub fn steps_per_frame(frame_dt: f64, min: u32, bodies: &[Body]) -> Result<u32, SimError> {
    let dt = bodies.iter().map(stable_dt).fold(f64::INFINITY, f64::min);
    let need = if dt > 0.0 { (frame_dt / dt).ceil() } else { f64::INFINITY };
    if need.is_nan() || need > MAX_STEPS_PER_FRAME as f64 {
        let needed = if need.is_finite() { need as u64 } else { u64::MAX };
        return Err(SimError::TooStiff { needed, max: MAX_STEPS_PER_FRAME });
    }
    Ok((need as u32).max(min).max(1))
}
