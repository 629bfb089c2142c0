//! [`LiveScene`]: the structures of an animation's frames kept current under an update
//! policy, in one layout — one [`LiveAccel`] over the whole frame ([`SceneLayout::Flat`]),
//! or a [`TwoLevel`] whose parts follow their actors.

use super::build::{check_actors, role};
use super::{transformed_bounds, ActorGeometry, ActorMotion, PartSpace, SceneLayout, TwoLevel};
use crate::{Accel, AccelSpec, BuildError, LiveAccel, UpdateAction, UpdatePolicy, UpdateReport};
use dynray_geom::{TriangleMesh, Vec3};
use std::time::{Duration, Instant};

/// What one two-level update did to the parts.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PartUpdates {
    /// Parts left as they were (static, or instances whose part did not change).
    pub kept: usize,
    /// Parts refitted.
    pub refit: usize,
    /// Parts rebuilt.
    pub rebuilt: usize,
    /// Instances whose transform changed.
    pub moved: usize,
    /// Time of the top-level rebuild.
    pub top: Duration,
}

/// The structure of an animated scene, kept current frame by frame.
pub enum LiveScene {
    /// One structure over the frame's mesh.
    Flat(LiveAccel),
    /// Parts under a top level.
    TwoLevel {
        /// The structure.
        tl: Box<TwoLevel>,
        /// Its policy, for parts.
        policy: UpdatePolicy,
        /// The layout it was built for.
        layout: SceneLayout,
        /// What the last update did.
        last: PartUpdates,
    },
}

impl LiveScene {
    /// Builds `spec` over the frame (`actors` tile `mesh`), in `layout`. A frame with no
    /// moving actor (nothing for two levels to save) and the flat layout give one
    /// structure over the whole frame.
    pub fn build(
        spec: &AccelSpec,
        policy: UpdatePolicy,
        layout: SceneLayout,
        actors: &[ActorGeometry<'_>],
        mesh: &TriangleMesh,
        eye: Option<Vec3>,
    ) -> Result<(Self, Duration), BuildError> {
        let moving = actors.iter().any(|a| !matches!(a.motion, ActorMotion::Static));
        let t = Instant::now();
        if layout == SceneLayout::Flat || !moving {
            let (live, time) = LiveAccel::build(spec, policy, mesh, eye)?;
            return Ok((LiveScene::Flat(live), time));
        }
        let tl = TwoLevel::build(spec, policy, layout, actors, mesh, eye)?;
        Ok((LiveScene::TwoLevel { tl: Box::new(tl), policy, layout, last: PartUpdates::default() }, t.elapsed()))
    }

    /// The structure, for queries.
    pub fn accel(&self) -> &dyn Accel {
        match self {
            LiveScene::Flat(l) => l.accel(),
            LiveScene::TwoLevel { tl, .. } => tl.as_ref(),
        }
    }

    /// The two-level structure, when that is the layout.
    pub fn two_level(&self) -> Option<&TwoLevel> {
        match self {
            LiveScene::Flat(_) => None,
            LiveScene::TwoLevel { tl, .. } => Some(tl),
        }
    }

    /// The layout in use ([`SceneLayout::Flat`] also where a two-level one was asked for
    /// a frame without moving actors).
    pub fn layout(&self) -> SceneLayout {
        match self {
            LiveScene::Flat(_) => SceneLayout::Flat,
            LiveScene::TwoLevel { layout, .. } => *layout,
        }
    }

    /// What the last update did to the parts (`None` for the flat layout).
    pub fn last_parts(&self) -> Option<PartUpdates> {
        match self {
            LiveScene::Flat(_) => None,
            LiveScene::TwoLevel { last, .. } => Some(*last),
        }
    }

    /// A line for summaries: `2 parts, 17 instances` or `flat`.
    pub fn describe(&self) -> String {
        match self {
            LiveScene::Flat(_) => "flat".into(),
            LiveScene::TwoLevel { tl, layout, .. } => {
                let (p, i) = tl.counts();
                format!("{layout}: {p} parts, {i} instances")
            }
        }
    }

    /// Brings the structure to the next frame of the same scene (`actors` as the frame
    /// gives them now). Static parts are kept; deforming actors' parts follow the
    /// policy; instances take their new transforms; the top level is rebuilt when any box
    /// moved. A frame whose actors no longer match the build (another scene) is built
    /// afresh.
    pub fn update(
        &mut self,
        actors: &[ActorGeometry<'_>],
        mesh: &TriangleMesh,
        eye: Option<Vec3>,
    ) -> Result<UpdateReport, BuildError> {
        let LiveScene::TwoLevel { tl, policy, layout, last } = self else {
            let LiveScene::Flat(l) = self else { unreachable!() };
            return l.update(mesh, eye);
        };
        let t = Instant::now();
        if !same_shape(tl, actors, mesh, *layout) {
            let spec = tl.spec().clone();
            **tl = TwoLevel::build(&spec, *policy, *layout, actors, mesh, eye)?;
            *last = PartUpdates::default();
            return Ok(UpdateReport { action: UpdateAction::Rebuilt, time: t.elapsed(), cost_ratio: None });
        }
        let view_dependent = tl.spec().kind.is_view_dependent();
        let mut parts = PartUpdates::default();
        let mut worst: Option<f64> = None;
        let mut any_bounds = false;
        for p in 0..tl.parts.len() {
            let part = &mut tl.parts[p];
            let report = match &part.space {
                PartSpace::World { actors: members, .. } => {
                    let moves = members.iter().any(|&m| !matches!(actors[m].motion, ActorMotion::Static));
                    if !moves && !view_dependent {
                        None
                    } else {
                        let mut at = 0;
                        for &m in members {
                            let v = &actors[m].vertices;
                            let src = &mesh.positions[v.start as usize..v.end as usize];
                            part.sub.positions[at..at + src.len()].copy_from_slice(src);
                            at += src.len();
                        }
                        let r = part.live.update(&part.sub, eye)?;
                        if r.action != UpdateAction::Kept {
                            part.bounds = part.sub.bounds();
                            any_bounds = true;
                        }
                        Some(r)
                    }
                }
                PartSpace::Local { actors: owners } if view_dependent => {
                    // Not shared (see `build`): its one instance's eye, in local space.
                    let ActorMotion::Rigid { local, to_world } = actors[owners[0]].motion else {
                        unreachable!("same_shape checked the roles")
                    };
                    Some(part.live.update(local, eye.map(|e| to_world.inverse().transform_point3(e)))?)
                }
                PartSpace::Local { .. } => None,
            };
            match report.map(|r| (r.action, r.cost_ratio)) {
                None | Some((UpdateAction::Kept, _)) => parts.kept += 1,
                Some((UpdateAction::Refit, c)) => {
                    parts.refit += 1;
                    worst = max_ratio(worst, c);
                }
                Some((_, c)) => {
                    parts.rebuilt += 1;
                    worst = max_ratio(worst, c);
                }
            }
        }
        for inst in &mut tl.instances {
            match inst.to_world {
                Some(old) => {
                    let ActorMotion::Rigid { to_world, .. } = actors[inst.actor as usize].motion else {
                        unreachable!("same_shape checked the roles")
                    };
                    if to_world != old {
                        inst.to_local = Some(to_world.inverse());
                        inst.to_world = Some(to_world);
                        inst.bounds = transformed_bounds(&tl.parts[inst.part as usize].bounds, &to_world);
                        parts.moved += 1;
                        any_bounds = true;
                    }
                }
                None => inst.bounds = tl.parts[inst.part as usize].bounds,
            }
        }
        if any_bounds {
            let t = Instant::now();
            tl.rebuild_top();
            parts.top = t.elapsed();
        }
        let action = if parts.rebuilt > 0 {
            UpdateAction::Rebuilt
        } else if parts.refit > 0 {
            UpdateAction::Refit
        } else if parts.moved > 0 {
            UpdateAction::Moved
        } else {
            UpdateAction::Kept
        };
        *last = parts;
        Ok(UpdateReport { action, time: t.elapsed(), cost_ratio: worst })
    }
}

/// Whether `actors` hold the same roles, ranges and local meshes as when `tl` was built.
fn same_shape(tl: &TwoLevel, actors: &[ActorGeometry<'_>], mesh: &TriangleMesh, layout: SceneLayout) -> bool {
    if mesh.triangle_count() as u32 != tl.triangles || check_actors(tl.spec(), actors, mesh, false).is_err() {
        return false;
    }
    tl.parts.iter().all(|p| match &p.space {
        PartSpace::World { actors: members, .. } => {
            let verts: usize = members.iter().map(|&m| actors.get(m).map_or(0, |a| a.vertices.len())).sum();
            verts == p.sub.positions.len()
                && members.iter().all(|&m| {
                    actors.get(m).is_some_and(|a| {
                        matches!(role(a, layout), Some(super::build::Role::Static | super::build::Role::World))
                    })
                })
        }
        PartSpace::Local { actors: owners } => {
            owners.iter().all(|&m| actors.get(m).is_some_and(|a| role(a, layout) == Some(super::build::Role::Instance)))
        }
    }) && tl.instances.iter().all(|i| {
        i.to_local.is_none() || actors.get(i.actor as usize).is_some_and(|a| i.first_prim == a.triangles.start)
    }) && mesh.indices.len() == tl.parts.iter().map(|p| p.live.triangle_count()).sum::<usize>() + instanced_extra(tl)
}

/// Frame triangles held by instances beyond their part's first user (shared parts).
fn instanced_extra(tl: &TwoLevel) -> usize {
    tl.parts
        .iter()
        .map(|p| match &p.space {
            PartSpace::Local { actors } => p.live.triangle_count() * actors.len().saturating_sub(1),
            PartSpace::World { .. } => 0,
        })
        .sum()
}

/// The larger of two optional cost ratios (the worst drift of the frame's parts).
fn max_ratio(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.max(y)),
        (x, None) => x,
        (None, y) => y,
    }
}
