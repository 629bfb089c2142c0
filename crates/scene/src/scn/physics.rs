//! The point-based physics blocks (docs/scene-language.md §9.1, docs/physics.md): the
//! top-level `physics { … }` and an object's `elastic { … }`. Both read through
//! `Parser::block`, so unknown and duplicated keys are errors with the file position.

use super::parser::{Parser, R};
use crate::{ElasticParams, PhysicsSettings};

/// Most phyxels one body may ask for (the neighbour lists grow with it).
pub const MAX_PHYXELS: i64 = 1_000_000;

/// Fewest phyxels: the MLS gradient needs neighbours in three directions.
pub const MIN_PHYXELS: i64 = 8;

/// Largest `substeps` accepted.
pub const MAX_SUBSTEPS: i64 = 100_000;

impl Parser<'_> {
    /// `physics { [gravity V] [ground R] [substeps I] }`; the keyword is consumed.
    pub(crate) fn physics(&mut self) -> R<PhysicsSettings> {
        let mut s = PhysicsSettings::default();
        self.block("physics", &["gravity", "ground", "substeps"], &[], |p, key, span| {
            match key {
                "gravity" => s.gravity = p.vector("physics gravity")?,
                "ground" => s.ground = Some(p.real_f32("physics ground", "it must be a finite height", |_| true)?),
                "substeps" => s.substeps = p.int("physics substeps", 1, MAX_SUBSTEPS)? as u32,
                other => return Err(p.unhandled(span, other, "physics")),
            }
            Ok(())
        })?;
        Ok(s)
    }

    /// `elastic { [young R] [poisson R] [density R] [damping R] [phyxels I] [velocity V]
    /// [volume R] [yield R] [creep R] [max_plastic R] }`; the keyword is consumed.
    pub(crate) fn elastic(&mut self) -> R<ElasticParams> {
        let mut e = ElasticParams::default();
        let keys = [
            "young",
            "poisson",
            "density",
            "damping",
            "phyxels",
            "velocity",
            "volume",
            "yield",
            "creep",
            "max_plastic",
        ];
        self.block("elastic", &keys, &[], |p, key, span| {
            let pos = |x: f64| x > 0.0;
            let nonneg = |x: f64| x >= 0.0;
            match key {
                "young" => e.young = p.real_f32("Young's modulus `young`", "it must be positive (Pa)", pos)?,
                "poisson" => {
                    e.poisson =
                        p.real_f32("Poisson's ratio `poisson`", "it must lie in [0, 0.5)", |x| (0.0..0.5).contains(&x))?
                }
                "density" => e.density = p.real_f32("elastic density", "it must be positive (kg/m³)", pos)?,
                "damping" => {
                    e.damping = p.real_f32("elastic damping", "it must lie in [0, 1]", |x| (0.0..=1.0).contains(&x))?
                }
                "phyxels" => e.phyxels = p.int("the number of phyxels", MIN_PHYXELS, MAX_PHYXELS)? as u32,
                "velocity" => e.velocity = p.vector("elastic velocity")?,
                "volume" => {
                    e.volume = Some(p.real_f32("volume stiffness `volume`", "it must not be negative (Pa)", nonneg)?)
                }
                "yield" => e.plastic_yield = p.real_f32("plastic `yield`", "it must not be negative", nonneg)?,
                "creep" => e.plastic_creep = p.real_f32("plastic `creep`", "it must not be negative (1/s)", nonneg)?,
                "max_plastic" => e.plastic_max = p.real_f32("`max_plastic`", "it must not be negative", nonneg)?,
                other => return Err(p.unhandled(span, other, "elastic")),
            }
            Ok(())
        })?;
        Ok(e)
    }
}
