//! A structure and its parameters as one value: what `--accel NAME[:key=value,…]` means
//! on every command, and what the bench's `--accels` list is made of.
//!
//! Grammar: `NAME`, `NAME:key=value,key=value` or `NAME:PRESET`; a bare word after the
//! colon is a preset name, the same as `preset=PRESET`. Keys belong to the structure's
//! params struct ([`StructureParams`]); the A-PIT and the A-buffer centre their cube on
//! the `eye` given to [`AccelSpec::build`] unless told `observer=center`.

use crate::structure_params::PRESET_KEY;
use crate::{Accel, AccelKind, BuildError, BvhParams, StructureParams};
use dynray_geom::{TriangleMesh, Vec3};
use std::fmt;

/// The brute-force oracle's parameters: none, and one preset (`default`), so that loops
/// over every kind and preset need no special case.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BruteParams;

impl StructureParams for BruteParams {
    const STRUCTURE: &'static str = "brute";
    const KEYS: &'static [crate::ParamKey] = &[];

    fn presets() -> Vec<(&'static str, Self)> {
        vec![("default", BruteParams)]
    }

    fn set(&mut self, key: &str, _: &str) -> Result<(), BuildError> {
        Err(crate::structure_params::unknown_key::<Self>(key))
    }

    fn validate(&self) -> Result<(), BuildError> {
        Ok(())
    }
}

/// A structure kind with `key=value` parameters on top of its defaults.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct AccelSpec {
    /// The structure.
    pub kind: AccelKind,
    /// Parameters in the order given (a bare preset is stored as `("preset", NAME)`).
    pub params: Vec<(String, String)>,
}

impl AccelSpec {
    /// `kind` with its default parameters.
    pub fn new(kind: AccelKind) -> Self {
        Self { kind, params: Vec::new() }
    }

    /// `kind` with the preset `name` (checked when built or by [`AccelSpec::check`]).
    pub fn with_preset(kind: AccelKind, name: &str) -> Self {
        Self { kind, params: vec![(PRESET_KEY.name.to_string(), name.to_string())] }
    }

    /// The preset names of `kind`, `default` among them.
    pub fn presets(kind: AccelKind) -> Vec<&'static str> {
        (kind.descriptor().presets)()
    }

    /// The keys `kind` accepts, `preset` first, each with its one-line doc.
    pub fn keys(kind: AccelKind) -> Vec<crate::ParamKey> {
        std::iter::once(PRESET_KEY).chain(kind.descriptor().keys.iter().copied()).collect()
    }

    /// The params struct of this spec's kind (`WbvhParams` for `bvh`, `BvhParams` for `bvh2`, …), read from its
    /// pairs and validated: what a caller that needs the concrete structure (the GPU
    /// backend uploads a [`Bvh`](crate::Bvh)) builds with.
    pub fn read<P: StructureParams>(&self) -> Result<P, BuildError> {
        P::from_pairs(&self.params).map_err(|e| e.in_structure(self.kind.name()))
    }

    /// The binary tree ([`Bvh`](crate::Bvh), `bvh2`) this spec stands for, for a caller that needs
    /// that tree itself (the GPU backend uploads and traverses a binary BVH): `bvh2` as
    /// given; plain `bvh` means `bvh2` with its defaults (the wide tree's nodes are the
    /// CPU's). `bvh` with parameters (they describe the wide tree) and every other
    /// structure are a [`BuildError::Spec`] that says what to give instead.
    pub fn binary_bvh(&self) -> Result<AccelSpec, BuildError> {
        let refuse = |message: &str| Err(BuildError::Spec { spec: self.to_string(), message: message.into() });
        match self.kind {
            AccelKind::Bvh2 => Ok(self.clone()),
            AccelKind::Bvh if self.params.is_empty() => Ok(AccelSpec::new(AccelKind::Bvh2)),
            AccelKind::Bvh => refuse(
                "the GPU backend traverses the binary tree `bvh2`, and these parameters describe the CPU's \
                 wide tree: give the binary tree's as `bvh2:…`, or use --backend cpu",
            ),
            _ => refuse("the GPU backend traverses a BVH only: use --accel bvh (or bvh2:…), or --backend cpu"),
        }
    }

    /// The parameters of [`AccelSpec::binary_bvh`]'s tree, read and validated.
    pub fn binary_bvh_params(&self) -> Result<BvhParams, BuildError> {
        self.binary_bvh()?.read()
    }

    /// Checks every key, value and preset without building anything (for a command line
    /// about to start a long run).
    pub fn check(&self) -> Result<(), BuildError> {
        (self.kind.descriptor().check)(self)
    }

    /// Builds the structure over `mesh`. `eye` is the camera position: the A-PIT and the
    /// A-buffer centre their cube there (seed 004's observer) unless `observer=center`;
    /// without an eye they centre it on the mesh's box. Other structures ignore it.
    pub fn build(&self, mesh: &TriangleMesh, eye: Option<Vec3>) -> Result<Box<dyn Accel>, BuildError> {
        (self.kind.descriptor().build)(self, mesh, eye)
    }
}

impl From<AccelKind> for AccelSpec {
    fn from(kind: AccelKind) -> Self {
        Self::new(kind)
    }
}

impl std::str::FromStr for AccelSpec {
    type Err = BuildError;

    /// Parses `NAME`, `NAME:key=value,…` or `NAME:PRESET` and checks the parameters.
    fn from_str(s: &str) -> Result<Self, BuildError> {
        let syntax = |message: String| BuildError::Spec { spec: s.to_string(), message };
        let (name, rest) = match s.split_once(':') {
            Some((n, r)) => (n.trim(), Some(r)),
            None => (s.trim(), None),
        };
        let kind: AccelKind = name.parse().map_err(|_| BuildError::UnknownStructure {
            name: name.to_string(),
            known: AccelKind::ALL.iter().map(|k| k.name()).collect(),
        })?;
        let mut spec = AccelSpec::new(kind);
        let pieces: Vec<&str> = rest.map(|r| r.split(',').map(str::trim).collect()).unwrap_or_default();
        for (i, piece) in pieces.iter().enumerate() {
            let (k, v) = match piece.split_once('=') {
                Some((k, v)) => (k.trim(), v.trim()),
                // A bare word right after the colon names a preset.
                None if i == 0 && !piece.is_empty() => (PRESET_KEY.name, *piece),
                None => return Err(syntax(format!("`{piece}` is not key=value"))),
            };
            if k.is_empty() {
                return Err(syntax(format!("empty parameter name in `{piece}`")));
            }
            if spec.params.iter().any(|(q, _)| q == k) {
                return Err(syntax(format!("parameter `{k}` given twice")));
            }
            spec.params.push((k.to_string(), v.to_string()));
        }
        spec.check()?;
        Ok(spec)
    }
}

impl fmt::Display for AccelSpec {
    /// `bih`, or `bih:max_prims=5,shrink=off` (parses back to the same spec).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.kind.name())?;
        for (i, (k, v)) in self.params.iter().enumerate() {
            write!(f, "{}{k}={v}", if i == 0 { ':' } else { ',' })?;
        }
        Ok(())
    }
}
