//! Choosing a structure by name (`--accel NAME`) and building it with default parameters.

use crate::{ABuffer, Accel, Apit, ApitParams, Brute, BuildError};
use dynray_geom::TriangleMesh;

/// Every structure the engine offers, by the name `--accel` accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AccelKind {
    /// [`Brute`]: every triangle for every ray (the oracle).
    Brute,
    /// [`Apit`]: A-buffers on a cube around the mesh centre with pseudo-interval trees.
    Apit,
    /// [`ABuffer`]: the same A-buffers with plain per-pixel lists (seed 004's baseline).
    ABuffer,
}

impl AccelKind {
    /// All kinds, in the order listings show them.
    pub const ALL: &'static [AccelKind] = &[AccelKind::Brute, AccelKind::Apit, AccelKind::ABuffer];

    /// The `--accel` spelling.
    pub fn name(self) -> &'static str {
        match self {
            AccelKind::Brute => "brute",
            AccelKind::Apit => "apit",
            AccelKind::ABuffer => "abuffer",
        }
    }

    /// Builds the structure over `mesh` with its default parameters.
    pub fn build(self, mesh: &TriangleMesh) -> Result<Box<dyn Accel>, BuildError> {
        Ok(match self {
            AccelKind::Brute => Box::new(Brute::build(mesh)?),
            AccelKind::Apit => Box::new(Apit::build(mesh, &ApitParams::default())?),
            AccelKind::ABuffer => Box::new(ABuffer::build(mesh, &ApitParams::default())?),
        })
    }
}

impl std::str::FromStr for AccelKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        AccelKind::ALL.iter().copied().find(|k| k.name() == s).ok_or_else(|| {
            let names: Vec<_> = AccelKind::ALL.iter().map(|k| k.name()).collect();
            format!("unknown structure `{s}` (expected one of: {})", names.join(", "))
        })
    }
}

impl std::fmt::Display for AccelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
