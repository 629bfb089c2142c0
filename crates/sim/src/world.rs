//! The world: every simulated body of a scene, gravity, the contacts, and the clock.
//! Time advances in fixed steps of `1 / (frame_rate × steps_per_frame)` from time 0, so
//! the state at a time is the same however it was reached (frame by frame, a shard's
//! frames only, or a single `--time`): [`World::advance_to`] steps forward from where it
//! is, or starts again from time 0 when asked for an earlier time.

use crate::body::Body;
use crate::contact::Contact;
use crate::integrator::steps_per_frame;
use crate::SimError;
use dynray_geom::TriangleMesh;
use dynray_scene::{Frame, Motion, PhysicsSettings, Scene};
use glam::DVec3;

/// The simulated bodies of a scene and their clock.
pub struct World {
    bodies: Vec<Body>,
    /// Which bodies write normals (their actor has vertex normals).
    smooth: Vec<bool>,
    gravity: DVec3,
    contact: Contact,
    dt: f64,
    steps_per_frame: u32,
    steps: u64,
}

impl World {
    /// The world of `scene`'s actors with an `elastic` block (`None` when it has none),
    /// colliding with the floor and with the static actors' triangles. Frames come at
    /// the scene's frame rate.
    pub fn from_scene(scene: &Scene) -> Result<Option<Self>, SimError> {
        // Most scenes have no bodies: return before copying any geometry.
        if scene.actors.iter().all(|a| a.elastic.is_none()) {
            return Ok(None);
        }
        let settings = scene.physics.unwrap_or_default();
        let mut bodies = Vec::new();
        let mut smooth = Vec::new();
        let mut statics = TriangleMesh::default();
        for (a, actor) in scene.actors.iter().enumerate() {
            match &actor.elastic {
                Some(p) => {
                    bodies.push(Body::new(a, &actor.world_mesh(), p)?);
                    smooth.push(actor.mesh.normals.is_some());
                }
                None if actor.motion == Motion::Static => {
                    let mut m = actor.world_mesh();
                    m.normals = None;
                    m.uvs = None;
                    statics.append(&m);
                }
                None => {}
            }
        }
        if bodies.is_empty() {
            return Ok(None);
        }
        let rate = scene.animation.timeline.frame_rate as f64;
        let mut w = Self::new(&settings, bodies, Some(statics), rate)?;
        w.smooth = smooth;
        Ok(Some(w))
    }

    /// A world of `bodies` under `settings`, colliding with `statics` (world space),
    /// stepped so that `frame_rate` frames per second fall on step boundaries.
    pub fn new(
        settings: &PhysicsSettings,
        bodies: Vec<Body>,
        statics: Option<TriangleMesh>,
        frame_rate: f64,
    ) -> Result<Self, SimError> {
        let contact = Contact::new(settings.ground.map(f64::from), statics)?;
        let n = steps_per_frame(1.0 / frame_rate, settings.substeps, &bodies)?;
        let smooth = vec![true; bodies.len()];
        Ok(Self {
            bodies,
            smooth,
            gravity: settings.gravity.as_dvec3(),
            contact,
            dt: 1.0 / (frame_rate * n as f64),
            steps_per_frame: n,
            steps: 0,
        })
    }

    /// The bodies.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The time step, s.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Steps per frame (the scene's `substeps`, or more where stability needs them).
    pub fn steps_per_frame(&self) -> u32 {
        self.steps_per_frame
    }

    /// Gravity, m/s².
    pub fn gravity(&self) -> DVec3 {
        self.gravity
    }

    /// Sets the step count and each body's positions, velocities and plastic strains
    /// (checked by the caller, `checkpoint.rs`, to be this world's).
    pub(crate) fn set_state(&mut self, steps: u64, states: Vec<(Vec<DVec3>, Vec<DVec3>, Vec<glam::DMat3>)>) {
        for (b, (pos, vel, plastic)) in self.bodies.iter_mut().zip(states) {
            b.pos = pos;
            b.vel = vel;
            b.plastic = plastic;
        }
        self.steps = steps;
    }

    /// Steps taken since time 0.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The simulated time, s.
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.dt
    }

    /// One line for logs: bodies, phyxels, neighbour pairs, the step.
    pub fn describe(&self) -> String {
        let phyxels: usize = self.bodies.iter().map(Body::len).sum();
        let pairs: usize = self.bodies.iter().map(Body::pair_count).sum();
        format!(
            "elastic bodies {}, phyxels {phyxels}, pairs {pairs}, {} steps/frame of {:.3} ms",
            self.bodies.len(),
            self.steps_per_frame,
            self.dt * 1e3
        )
    }

    /// Back to time 0.
    pub fn reset(&mut self) {
        self.bodies.iter_mut().for_each(Body::reset);
        self.steps = 0;
    }

    /// One step of every body; fails if a body's state stopped being finite.
    pub fn step(&mut self) -> Result<(), SimError> {
        for b in &mut self.bodies {
            b.step(self.dt, self.gravity, &self.contact);
        }
        self.steps += 1;
        // A cheap divergence check (one phyxel would do; the centre of mass sees all).
        if self.steps.is_multiple_of(64) {
            self.check()?;
        }
        Ok(())
    }

    fn check(&self) -> Result<(), SimError> {
        match self.bodies.iter().find(|b| !b.centre_of_mass().is_finite()) {
            Some(b) => Err(SimError::Diverged { actor: b.actor, step: self.steps }),
            None => Ok(()),
        }
    }

    /// Steps to the step nearest time `t` (s from time 0; negative is time 0), starting
    /// again from time 0 if `t` is earlier than now.
    pub fn advance_to(&mut self, t: f64) -> Result<(), SimError> {
        let target = if t > 0.0 { (t / self.dt).round() as u64 } else { 0 };
        if target < self.steps {
            self.reset();
        }
        while self.steps < target {
            self.step()?;
        }
        self.check()
    }

    /// Writes each body's deformed vertices (and, where its actor has them, recomputed
    /// normals) over its actor's vertices in `frame` (a frame of the scene the world was
    /// made from).
    pub fn write_into(&self, frame: &mut Frame) -> Result<(), SimError> {
        for (b, smooth) in self.bodies.iter().zip(&self.smooth) {
            let n = b.surface.vertex_count();
            let range = frame
                .vertex_ranges
                .get(b.actor)
                .filter(|r| (r.end - r.start) as usize == n && r.end as usize <= frame.mesh.positions.len())
                .ok_or(SimError::FrameMismatch { actor: b.actor, vertices: n })?;
            let range = range.start as usize..range.end as usize;
            let grads = b.gradients();
            b.surface.deform(&b.rest, &b.pos, &grads, &mut frame.mesh.positions[range.clone()]);
            if *smooth {
                if let Some(normals) = frame.mesh.normals.as_mut().filter(|v| v.len() >= range.end) {
                    b.surface.normals(&frame.mesh.positions[range.clone()], &mut normals[range]);
                }
            }
        }
        Ok(())
    }

    /// The deformed vertices of body `b` now (world space), as [`World::write_into`]
    /// writes them.
    pub fn surface_positions(&self, b: usize) -> Vec<[f32; 3]> {
        let body = &self.bodies[b];
        let mut out = vec![[0.0; 3]; body.surface.vertex_count()];
        body.surface.deform(&body.rest, &body.pos, &body.gradients(), &mut out);
        out
    }
}
