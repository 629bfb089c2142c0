//! Keeping a structure current over the frames of an animation: the update policy
//! (`--update rebuild|refit|auto`) and [`LiveAccel`], which applies it.
//!
//! - `rebuild`: a fresh build every frame in which the geometry changed (seed 000's BIH
//!   strategy).
//! - `refit`: keep the tree and recompute its bounds ([`Accel::update`]) — structures
//!   without a refit rebuild instead, so the policy is always valid.
//! - `auto`: refit while the refit tree's SAH cost stays within
//!   [`UpdatePolicy::DEFAULT_MAX_COST_RATIO`] of the cost the last fresh build had;
//!   rebuild once it drifts past. SAH costs here are normalised by the root's surface
//!   area ([`crate::AccelStats::sah_cost`]), so a tree that merely moved or scaled keeps
//!   its cost and a tree whose boxes grew to overlap loses it. A structure reporting no
//!   SAH cost would refit under `auto` as under `refit` (both refitting structures, BVH
//!   and BIH, report one). How the bound was chosen:
//!   docs/animate.md ("Update policies").
//!
//! A frame whose triangles are bit-identical to the last one's (a still scene, or the
//! still frames of an animation) keeps the structure as it is under every policy.

use crate::{Accel, AccelSpec, BuildError};
use dynray_geom::{TriangleMesh, Vec3};
use std::fmt;
use std::str::FromStr;
use std::time::{Duration, Instant};

/// How a structure follows moving geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum UpdatePolicy {
    /// Build afresh each frame.
    Rebuild,
    /// Refit where the structure can (else rebuild).
    Refit,
    /// Refit until the SAH cost exceeds `max_cost_ratio` × the last fresh build's.
    Auto {
        /// The bound (> 1).
        max_cost_ratio: f64,
    },
}

impl UpdatePolicy {
    /// The `auto` bound: rebuild when a refit tree's SAH cost exceeds the last fresh
    /// build's by 30 % (docs/animate.md, "Update policies").
    pub const DEFAULT_MAX_COST_RATIO: f64 = 1.3;

    /// Names accepted by [`UpdatePolicy::from_str`].
    pub const NAMES: [&'static str; 3] = ["rebuild", "refit", "auto"];
}

impl Default for UpdatePolicy {
    fn default() -> Self {
        UpdatePolicy::Auto { max_cost_ratio: Self::DEFAULT_MAX_COST_RATIO }
    }
}

impl fmt::Display for UpdatePolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UpdatePolicy::Rebuild => f.write_str("rebuild"),
            UpdatePolicy::Refit => f.write_str("refit"),
            UpdatePolicy::Auto { max_cost_ratio } if *max_cost_ratio == Self::DEFAULT_MAX_COST_RATIO => {
                f.write_str("auto")
            }
            UpdatePolicy::Auto { max_cost_ratio } => write!(f, "auto:{max_cost_ratio}"),
        }
    }
}

impl FromStr for UpdatePolicy {
    type Err = String;

    /// `rebuild`, `refit`, `auto` or `auto:RATIO` (RATIO > 1).
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "rebuild" => Ok(UpdatePolicy::Rebuild),
            "refit" => Ok(UpdatePolicy::Refit),
            "auto" => Ok(UpdatePolicy::default()),
            _ => match s.strip_prefix("auto:").map(str::parse::<f64>) {
                Some(Ok(r)) if r > 1.0 && r.is_finite() => Ok(UpdatePolicy::Auto { max_cost_ratio: r }),
                Some(_) => Err(format!("`{s}`: the auto bound must be a number above 1, as in auto:1.3")),
                None => Err(format!("unknown update policy `{s}` (expected rebuild, refit, auto or auto:RATIO)")),
            },
        }
    }
}

/// What [`LiveAccel::update`] did for one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpdateAction {
    /// Nothing moved: the structure was kept.
    Kept,
    /// Bounds recomputed over the same tree.
    Refit,
    /// Built afresh (by policy, because the structure cannot refit, or because `auto`
    /// found the refit tree too costly).
    Rebuilt,
    /// Only instances moved: their parts were kept and the top level rebuilt
    /// ([`crate::LiveScene`]).
    Moved,
}

impl UpdateAction {
    /// Lower-case name, as `timings.csv` writes it.
    pub fn name(self) -> &'static str {
        match self {
            UpdateAction::Kept => "kept",
            UpdateAction::Refit => "refit",
            UpdateAction::Rebuilt => "rebuilt",
            UpdateAction::Moved => "moved",
        }
    }
}

/// The figures of one update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UpdateReport {
    /// What was done.
    pub action: UpdateAction,
    /// Wall time of the update (the refit, the rebuild, or both under `auto` when the
    /// refit was rejected).
    pub time: Duration,
    /// SAH cost of the structure now, where it reports one, relative to the cost of the
    /// last fresh build (1 right after a build).
    pub cost_ratio: Option<f64>,
}

/// A structure the update policy can drive: the CPU's structures ([`LiveAccel`]) and
/// the GPU backend's device tree both implement it, so the policy's arithmetic —
/// [`PolicyState::update`] — is written once.
pub trait PolicyTarget {
    /// What a build or refit can fail with.
    type Error;
    /// Builds afresh over `mesh`.
    fn rebuild(&mut self, mesh: &TriangleMesh, eye: Option<Vec3>) -> Result<(), Self::Error>;
    /// True when the structure can refit its bounds over the same triangles.
    fn refits(&self) -> bool;
    /// Recomputes the bounds over `mesh` (same triangles, moved vertices).
    fn refit(&mut self, mesh: &TriangleMesh, eye: Option<Vec3>) -> Result<(), Self::Error>;
    /// The normalised SAH cost ([`crate::AccelStats::sah_cost`]) of the structure now, where it
    /// has one; asked only under `auto` (it may cost a tree walk or a read-back).
    fn sah_cost(&mut self, mesh: &TriangleMesh) -> Result<Option<f64>, Self::Error>;
    /// True when the structure depends on the eye, so a moved camera is a change.
    fn view_dependent(&self) -> bool {
        false
    }
}

/// What the update policy remembers between frames: the triangles a structure was last
/// built or updated on, and the SAH cost of its last fresh build.
#[derive(Clone, Debug)]
pub struct PolicyState {
    policy: UpdatePolicy,
    /// The triangles (positions and indices) the structure was last built or updated on.
    positions: Vec<[f32; 3]>,
    indices: Vec<[u32; 3]>,
    /// SAH cost of the last fresh build.
    built_cost: Option<f64>,
    /// The cost ratio the last update reported (a kept frame reports it again rather
    /// than walking the unchanged tree).
    last_ratio: Option<f64>,
}

impl PolicyState {
    /// The state right after `target` was built over `mesh`.
    pub fn after_build<T: PolicyTarget>(
        policy: UpdatePolicy,
        target: &mut T,
        mesh: &TriangleMesh,
    ) -> Result<Self, T::Error> {
        let built_cost = cost(target, mesh, policy)?;
        Ok(PolicyState {
            policy,
            positions: mesh.positions.clone(),
            indices: mesh.indices.clone(),
            built_cost,
            last_ratio: built_cost.filter(|&b| b > 0.0).map(|_| 1.0),
        })
    }

    /// The policy.
    pub fn policy(&self) -> UpdatePolicy {
        self.policy
    }

    /// The triangles the structure was last built or updated on.
    pub fn mesh(&self) -> TriangleMesh {
        TriangleMesh::new(self.positions.clone(), self.indices.clone())
    }

    /// How many triangles the structure holds.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Brings `target` to `mesh`, the next frame of the same scene (same triangles, same
    /// order), following the policy. A mesh with other indices or another vertex count
    /// (not the same scene) is rebuilt.
    pub fn update<T: PolicyTarget>(
        &mut self,
        target: &mut T,
        mesh: &TriangleMesh,
        eye: Option<Vec3>,
    ) -> Result<UpdateReport, T::Error> {
        let same_topology = mesh.indices == self.indices && mesh.positions.len() == self.positions.len();
        let view_dependent = eye.is_some() && target.view_dependent();
        if same_topology && mesh.positions == self.positions && !view_dependent {
            return Ok(UpdateReport { action: UpdateAction::Kept, time: Duration::ZERO, cost_ratio: self.last_ratio });
        }
        let t = Instant::now();
        let refits = target.refits() && same_topology;
        let mut action = match (self.policy, refits) {
            (UpdatePolicy::Rebuild, _) | (_, false) => {
                self.rebuild(target, mesh, eye)?;
                UpdateAction::Rebuilt
            }
            (UpdatePolicy::Refit | UpdatePolicy::Auto { .. }, true) => {
                target.refit(mesh, eye)?;
                UpdateAction::Refit
            }
        };
        let mut now = if action == UpdateAction::Rebuilt { self.built_cost } else { cost(target, mesh, self.policy)? };
        if let (UpdatePolicy::Auto { max_cost_ratio }, UpdateAction::Refit) = (self.policy, action) {
            if self.ratio(now).is_some_and(|r| r > max_cost_ratio) {
                self.rebuild(target, mesh, eye)?;
                now = self.built_cost;
                action = UpdateAction::Rebuilt;
            }
        }
        let time = t.elapsed();
        self.positions.clone_from(&mesh.positions);
        self.indices.clone_from(&mesh.indices);
        self.last_ratio = self.ratio(now);
        Ok(UpdateReport { action, time, cost_ratio: self.last_ratio })
    }

    fn rebuild<T: PolicyTarget>(
        &mut self,
        target: &mut T,
        mesh: &TriangleMesh,
        eye: Option<Vec3>,
    ) -> Result<(), T::Error> {
        target.rebuild(mesh, eye)?;
        self.built_cost = cost(target, mesh, self.policy)?;
        Ok(())
    }

    fn ratio(&self, now: Option<f64>) -> Option<f64> {
        match (now, self.built_cost) {
            (Some(n), Some(b)) if b > 0.0 => Some(n / b),
            _ => None,
        }
    }
}

/// A CPU structure as the policy drives it.
struct CpuTarget<'a> {
    spec: &'a AccelSpec,
    accel: &'a mut Box<dyn Accel>,
}

impl PolicyTarget for CpuTarget<'_> {
    type Error = BuildError;

    fn rebuild(&mut self, mesh: &TriangleMesh, eye: Option<Vec3>) -> Result<(), BuildError> {
        *self.accel = self.spec.build(mesh, eye)?;
        Ok(())
    }

    fn refits(&self) -> bool {
        self.accel.update_refits()
    }

    fn refit(&mut self, mesh: &TriangleMesh, eye: Option<Vec3>) -> Result<(), BuildError> {
        match eye {
            Some(e) => self.accel.update_for_eye(mesh, e),
            None => self.accel.update(mesh),
        }
    }

    fn sah_cost(&mut self, _mesh: &TriangleMesh) -> Result<Option<f64>, BuildError> {
        Ok(self.accel.sah_cost())
    }

    fn view_dependent(&self) -> bool {
        self.spec.kind.is_view_dependent()
    }
}

/// A structure over the triangles of an animated scene, updated frame by frame.
pub struct LiveAccel {
    spec: AccelSpec,
    accel: Box<dyn Accel>,
    state: PolicyState,
}

impl LiveAccel {
    /// Builds `spec` over `mesh` (`eye`: the camera, for the view-dependent structures).
    pub fn build(
        spec: &AccelSpec,
        policy: UpdatePolicy,
        mesh: &TriangleMesh,
        eye: Option<Vec3>,
    ) -> Result<(Self, Duration), BuildError> {
        let t = Instant::now();
        let mut accel = spec.build(mesh, eye)?;
        let time = t.elapsed();
        let state = PolicyState::after_build(policy, &mut CpuTarget { spec, accel: &mut accel }, mesh)?;
        Ok((LiveAccel { spec: spec.clone(), accel, state }, time))
    }

    /// The structure, for queries.
    pub fn accel(&self) -> &dyn Accel {
        self.accel.as_ref()
    }

    /// The policy.
    pub fn policy(&self) -> UpdatePolicy {
        self.state.policy()
    }

    /// The triangles the structure was last built or updated on.
    pub fn mesh(&self) -> TriangleMesh {
        self.state.mesh()
    }

    /// How many triangles it holds.
    pub fn triangle_count(&self) -> usize {
        self.state.triangle_count()
    }

    /// Brings the structure to `mesh` under the policy ([`PolicyState::update`]).
    pub fn update(&mut self, mesh: &TriangleMesh, eye: Option<Vec3>) -> Result<UpdateReport, BuildError> {
        self.state.update(&mut CpuTarget { spec: &self.spec, accel: &mut self.accel }, mesh, eye)
    }
}

/// The structure's normalised SAH cost, computed only where a policy reads it (`auto`)
/// — for the others it would be a tree walk per frame for a figure nobody asked for.
fn cost<T: PolicyTarget>(target: &mut T, mesh: &TriangleMesh, policy: UpdatePolicy) -> Result<Option<f64>, T::Error> {
    match policy {
        UpdatePolicy::Auto { .. } => target.sah_cost(mesh),
        _ => Ok(None),
    }
}
