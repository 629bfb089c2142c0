//! A body (the seed's "body"): its phyxels, their neighbourhoods (found through the
//! spatial hash), masses, volumes and MLS weights, and its state. Built once from the
//! rest shape; [`Body::step`] advances it by one time step.
//!
//! Every per-phyxel quantity is computed by a parallel map that writes element `i` from
//! inputs alone, and every sum runs over a list in a fixed order (a phyxel's neighbours;
//! the pairs naming it, sorted by owner), so results are bit-identical whatever the
//! thread count.

use crate::contact::Contact;
use crate::elastic::{phyxel_stress, PhyxelStress};
use crate::hash::SpatialHash;
use crate::kernel::poly6;
use crate::material::Material;
use crate::mls::{gradient, inverse_moments};
use crate::sampling::{mesh_volume, sample_inside};
use crate::surface::Surface;
use crate::SimError;
use dynray_geom::TriangleMesh;
use dynray_scene::ElasticParams;
use glam::{DMat3, DVec3};
use rayon::prelude::*;

/// Nearest neighbours whose mean distance `r̄` sets a phyxel's support radius.
pub const SUPPORT_NEIGHBOURS: usize = 10;

/// Support radius over `r̄`: on a regular grid of spacing `s` this gives `h ≈ 2.1 s`,
/// about 30 neighbours, enough for a well-conditioned moment matrix while keeping the
/// neighbour lists short. (Müller et al. use `3 r̄`; that triples the work here.)
pub const SUPPORT_SCALE: f64 = 1.8;

/// A simulated body.
#[derive(Clone, Debug)]
pub struct Body {
    /// Index of the actor in the scene.
    pub actor: usize,
    /// Its material.
    pub material: Material,
    /// Rest positions of the phyxels (world space at time 0).
    pub rest: Vec<DVec3>,
    /// Current positions.
    pub pos: Vec<DVec3>,
    /// Current velocities.
    pub vel: Vec<DVec3>,
    /// Masses, kg (they sum to density × mesh volume).
    pub mass: Vec<f64>,
    /// Volumes `v_i`, m³ (kernel-weighted estimate, scaled to the mesh volume).
    pub volume: Vec<f64>,
    /// Support radii `h_i`.
    pub support: Vec<f64>,
    /// Plastic strain per phyxel.
    pub plastic: Vec<DMat3>,
    /// Grid spacing of the sampling, m.
    pub spacing: f64,
    /// The mesh vertices that follow the phyxels.
    pub surface: Surface,
    initial_velocity: DVec3,
    /// Neighbour lists (CSR): pairs `nbr_start[i]..nbr_start[i+1]` belong to phyxel `i`.
    nbr_start: Vec<u32>,
    /// Neighbour `j` of each pair.
    nbr: Vec<u32>,
    /// `d_ij` of each pair (`mls.rs`).
    d: Vec<DVec3>,
    /// Damping coefficient of each pair, kg/s.
    damp: Vec<f64>,
    /// Pairs naming each phyxel as neighbour (CSR over pair indices, sorted by owner).
    rev_start: Vec<u32>,
    rev: Vec<u32>,
    /// Owner `i` of each pair.
    owner: Vec<u32>,
}

impl Body {
    /// Samples about `params.phyxels` phyxels inside `mesh` (world space, closed) and
    /// builds their neighbourhoods. `actor` names the body in errors.
    pub fn new(actor: usize, mesh: &TriangleMesh, params: &ElasticParams) -> Result<Self, SimError> {
        let material = Material::new(params);
        let total = mesh_volume(mesh);
        if !(total > 0.0 && total.is_finite()) {
            return Err(SimError::NoVolume { actor, volume: total });
        }
        let (rest, s) = sample_inside(mesh, total, params.phyxels)?;
        let n = rest.len();
        if n < 8 {
            return Err(SimError::TooFewPhyxels { actor, found: n });
        }
        let hash = SpatialHash::new(&rest, 2.0 * s);
        let support: Vec<f64> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut found = Vec::new();
                let mut r = 2.5 * s;
                loop {
                    hash.within(&rest, rest[i], r, &mut found);
                    if found.len() > SUPPORT_NEIGHBOURS || found.len() == n {
                        break;
                    }
                    r *= 2.0;
                }
                let mut dist: Vec<f64> =
                    found.iter().filter(|&&j| j as usize != i).map(|&j| rest[j as usize].distance(rest[i])).collect();
                dist.sort_by(f64::total_cmp);
                let k = dist.len().clamp(1, SUPPORT_NEIGHBOURS);
                SUPPORT_SCALE * dist.iter().take(k).sum::<f64>() / k as f64
            })
            .collect();
        let lists: Vec<Vec<u32>> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut v = Vec::new();
                hash.within(&rest, rest[i], support[i], &mut v);
                v.retain(|&j| j as usize != i);
                v
            })
            .collect();
        // Masses: m_i = ρ v_i, with v_i ∝ 1 / (kernel density) (Müller §3.1) scaled so
        // that the volumes add up to the mesh's.
        let m0 = material.density * s * s * s;
        let inv_density: Vec<f64> = (0..n)
            .into_par_iter()
            .map(|i| {
                let h = support[i];
                let rho = m0 * poly6(0.0, h)
                    + lists[i].iter().map(|&j| m0 * poly6(rest[j as usize].distance_squared(rest[i]), h)).sum::<f64>();
                m0 / rho
            })
            .collect();
        let scale = total / inv_density.iter().sum::<f64>();
        let volume: Vec<f64> = inv_density.iter().map(|v| v * scale).collect();
        let mass: Vec<f64> = volume.iter().map(|v| v * material.density).collect();
        let mut nbr_start = Vec::with_capacity(n + 1);
        nbr_start.push(0u32);
        for l in &lists {
            nbr_start.push(nbr_start.last().copied().unwrap_or(0) + l.len() as u32);
        }
        let nbr: Vec<u32> = lists.concat();
        let owner: Vec<u32> = (0..n as u32).flat_map(|i| std::iter::repeat_n(i, lists[i as usize].len())).collect();
        let per_phyxel: Vec<Option<Vec<(DVec3, f64)>>> = (0..n)
            .into_par_iter()
            .map(|i| {
                let h = support[i];
                let w0 = poly6(0.0, h);
                let pairs: Vec<(DVec3, f64, f64)> = lists[i]
                    .iter()
                    .map(|&j| {
                        let x = rest[j as usize] - rest[i];
                        (x, mass[j as usize] * poly6(x.length_squared(), h), poly6(x.length_squared(), h) / w0)
                    })
                    .collect();
                let ainv = inverse_moments(pairs.iter().map(|p| (p.0, p.1)))?;
                Some(
                    pairs
                        .iter()
                        .zip(&lists[i])
                        .map(|(&(x, mw, wn), &j)| {
                            // Critical damping of a pair: 2 √(k m), spring k ≈ E s, reduced mass.
                            let (mi, mj) = (mass[i], mass[j as usize]);
                            let c = material.damping * 2.0 * (material.young * s * mi * mj / (mi + mj)).sqrt() * wn;
                            (ainv * (x * mw), c)
                        })
                        .collect(),
                )
            })
            .collect();
        let mut d = Vec::with_capacity(nbr.len());
        let mut damp = Vec::with_capacity(nbr.len());
        for (i, p) in per_phyxel.into_iter().enumerate() {
            let p = p.ok_or(SimError::SingularMoments { actor, phyxel: i })?;
            d.extend(p.iter().map(|q| q.0));
            damp.extend(p.iter().map(|q| q.1));
        }
        // Reverse lists: pair indices grouped by neighbour, in pair (so owner) order.
        let mut rev_start = vec![0u32; n + 1];
        for &j in &nbr {
            rev_start[j as usize + 1] += 1;
        }
        for i in 0..n {
            rev_start[i + 1] += rev_start[i];
        }
        let mut fill = rev_start.clone();
        let mut rev = vec![0u32; nbr.len()];
        for (k, &j) in nbr.iter().enumerate() {
            rev[fill[j as usize] as usize] = k as u32;
            fill[j as usize] += 1;
        }
        let surface = Surface::new(mesh, &rest, &support, &hash);
        let v0 = params.velocity.as_dvec3();
        Ok(Self {
            actor,
            material,
            pos: rest.clone(),
            vel: vec![v0; n],
            rest,
            mass,
            volume,
            support,
            plastic: vec![DMat3::ZERO; n],
            spacing: s,
            surface,
            initial_velocity: v0,
            nbr_start,
            nbr,
            d,
            damp,
            rev_start,
            rev,
            owner,
        })
    }

    /// Number of phyxels.
    pub fn len(&self) -> usize {
        self.rest.len()
    }

    /// Whether the body has no phyxels (never, once built).
    pub fn is_empty(&self) -> bool {
        self.rest.is_empty()
    }

    /// Number of neighbour pairs.
    pub fn pair_count(&self) -> usize {
        self.nbr.len()
    }

    /// Back to the state at time 0.
    pub fn reset(&mut self) {
        self.pos.clone_from(&self.rest);
        self.vel.fill(self.initial_velocity);
        self.plastic.fill(DMat3::ZERO);
    }

    /// Contact radius of a phyxel: half the spacing, where the surface lies beyond the
    /// outermost phyxels of a grid-sampled body.
    pub fn contact_radius(&self) -> f64 {
        0.5 * self.spacing
    }

    fn pairs(&self, i: usize) -> std::ops::Range<usize> {
        self.nbr_start[i] as usize..self.nbr_start[i + 1] as usize
    }

    /// MLS displacement gradients `∇u_i` of the current state.
    pub fn gradients(&self) -> Vec<DMat3> {
        (0..self.len())
            .into_par_iter()
            .map(|i| {
                let u_i = self.pos[i] - self.rest[i];
                gradient(
                    u_i,
                    self.pairs(i).map(|k| {
                        let j = self.nbr[k] as usize;
                        (self.pos[j] - self.rest[j], self.d[k])
                    }),
                )
            })
            .collect()
    }

    fn stresses(&self) -> Vec<PhyxelStress> {
        let grads = self.gradients();
        (0..self.len())
            .into_par_iter()
            .map(|i| phyxel_stress(grads[i], self.plastic[i], self.volume[i], &self.material))
            .collect()
    }

    /// Internal (elastic, volume, damping) forces of the current state, and the
    /// stresses they came from.
    pub fn internal_forces(&self) -> (Vec<DVec3>, Vec<PhyxelStress>) {
        let st = self.stresses();
        let f = (0..self.len())
            .into_par_iter()
            .map(|j| {
                let (vj, mut f) = (self.vel[j], DVec3::ZERO);
                // Own term: f_j = −M_j d_jj = M_j Σ_k d_jk; damping of its own pairs.
                for k in self.pairs(j) {
                    f += st[j].m * self.d[k];
                    f += (self.vel[self.nbr[k] as usize] - vj) * self.damp[k];
                }
                // As a neighbour of i: f_j = −M_i d_ij; the other end of i's dampers.
                for &k in &self.rev[self.rev_start[j] as usize..self.rev_start[j + 1] as usize] {
                    let i = self.owner[k as usize] as usize;
                    f -= st[i].m * self.d[k as usize];
                    f += (self.vel[i] - vj) * self.damp[k as usize];
                }
                f
            })
            .collect();
        (f, st)
    }

    /// Strain energy of the current state, J.
    pub fn strain_energy(&self) -> f64 {
        self.stresses().iter().map(|s| s.energy).sum()
    }

    /// Kinetic energy, J.
    pub fn kinetic_energy(&self) -> f64 {
        self.vel.iter().zip(&self.mass).map(|(v, m)| 0.5 * m * v.length_squared()).sum()
    }

    /// Total linear momentum, kg m/s.
    pub fn momentum(&self) -> DVec3 {
        self.vel.iter().zip(&self.mass).map(|(v, m)| *v * *m).sum()
    }

    /// Centre of mass.
    pub fn centre_of_mass(&self) -> DVec3 {
        let m: f64 = self.mass.iter().sum();
        self.pos.iter().zip(&self.mass).map(|(p, w)| *p * *w).sum::<DVec3>() / m
    }

    /// Largest damping rate `Σ_pairs c / m` of any phyxel, 1/s (bounds the step).
    pub fn max_damping_rate(&self) -> f64 {
        let mut sum = vec![0.0; self.len()];
        for (k, &c) in self.damp.iter().enumerate() {
            sum[self.owner[k] as usize] += c;
            sum[self.nbr[k] as usize] += c;
        }
        sum.iter().zip(&self.mass).map(|(c, m)| c / m).fold(0.0, f64::max)
    }

    /// One semi-implicit (symplectic) Euler step of `dt`: forces at the current state,
    /// velocities updated first, positions from the new velocities; then contact and the
    /// plastic strain.
    pub fn step(&mut self, dt: f64, gravity: DVec3, contact: &Contact) {
        let (f, st) = self.internal_forces();
        let old = self.pos.clone();
        let mass = &self.mass;
        self.vel.par_iter_mut().enumerate().for_each(|(i, v)| *v += (f[i] / mass[i] + gravity) * dt);
        self.pos.par_iter_mut().zip(&self.vel).for_each(|(p, v)| *p += *v * dt);
        let r = self.contact_radius();
        contact.resolve(&old, &mut self.pos, &mut self.vel, r);
        if self.material.is_plastic() {
            let mat = self.material;
            self.plastic.par_iter_mut().zip(&st).for_each(|(p, s)| *p = crate::plastic::update(*p, s.strain, dt, &mat));
        }
    }
}
