//! Structure variants on the command line: `NAME[:key=value,...]`, and the registry hook
//! that builds a structure with such parameters.
//!
//! Grammar of `--accels`: a comma-separated list; a piece without `=` starts a new
//! structure (optionally `name:key=value`), a piece with `=` adds a parameter to the
//! structure before it. So `bvh,bih:max_prims=5,shrink=off,grid` is three structures, the
//! second with two parameters. Keys are checked by [`crate::params`] as the list is parsed, which rejects any key
//! the structure does not know, naming the keys it does.

use crate::params::{build_with_params, check_params};
use anyhow::{bail, Result};
use dynray_accel::{Accel, AccelKind};
use dynray_geom::TriangleMesh;
use dynray_scene::Frame;

/// One structure to measure: a kind and its non-default parameters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AccelVariant {
    /// The structure.
    pub kind: AccelKind,
    /// `key=value` parameters in the order given (empty: the kind's defaults).
    pub params: Vec<(String, String)>,
}

impl AccelVariant {
    /// A variant with default parameters.
    pub fn new(kind: AccelKind) -> Self {
        Self { kind, params: Vec::new() }
    }

    /// The spelling used in reports: `bih` or `bih:max_prims=5,shrink=off`.
    pub fn label(&self) -> String {
        if self.params.is_empty() {
            return self.kind.name().to_string();
        }
        let p: Vec<String> = self.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
        format!("{}:{}", self.kind.name(), p.join(","))
    }

    /// Builds the structure over `mesh` (see [`build_variant`]).
    pub fn build(&self, mesh: &TriangleMesh) -> Result<Box<dyn Accel>> {
        build_variant(self.kind, &self.params, mesh)
    }

    /// Builds the structure over `frame`'s mesh for views from its camera: the A-PIT and
    /// the A-buffer centre their cube on the eye (seed 004's observer) unless the variant
    /// says `observer=center`; the other structures ignore the camera.
    pub fn build_in(&self, frame: &Frame) -> Result<Box<dyn Accel>> {
        build_with_params(self.kind, &self.params, &frame.mesh, Some(frame.camera.position))
    }
}

/// Parses an `--accels` list (grammar in the module docs).
pub fn parse_accels(list: &str) -> Result<Vec<AccelVariant>> {
    let mut out: Vec<AccelVariant> = Vec::new();
    for piece in list.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (name, param) = match piece.split_once(':') {
            Some((n, p)) => (Some(n), Some(p)),
            None if piece.contains('=') => (None, Some(piece)),
            None => (Some(piece), None),
        };
        if let Some(name) = name {
            let kind: AccelKind = name.parse().map_err(|e: String| anyhow::anyhow!("--accels: {e}"))?;
            out.push(AccelVariant::new(kind));
        }
        if let Some(p) = param.filter(|p| !p.is_empty()) {
            let Some((k, v)) = p.split_once('=') else {
                bail!("--accels: `{p}` is not key=value (in `{list}`)");
            };
            let (k, v) = (k.trim(), v.trim());
            if k.is_empty() {
                bail!("--accels: empty parameter name in `{p}`");
            }
            let Some(last) = out.last_mut() else {
                bail!("--accels: parameter `{p}` comes before any structure name");
            };
            if last.params.iter().any(|(q, _)| q == k) {
                bail!("--accels: parameter `{k}` given twice for {}", last.kind);
            }
            last.params.push((k.to_string(), v.to_string()));
        }
    }
    if out.is_empty() {
        bail!("--accels: no structure named in `{list}`");
    }
    for v in &out {
        check_params(v.kind, &v.params).map_err(|e| anyhow::anyhow!("--accels: {e}"))?;
    }
    Ok(out)
}

/// Builds `kind` over `mesh` with `params` applied on top of its defaults, rejecting
/// unknown keys and bad values with a message that names them (see [`crate::params`]).
/// The A-PIT and the A-buffer are centred on the mesh's box here; [`AccelVariant::build_in`]
/// centres them on the camera.
pub fn build_variant(kind: AccelKind, params: &[(String, String)], mesh: &TriangleMesh) -> Result<Box<dyn Accel>> {
    build_with_params(kind, params, mesh, None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_split_into_structures_and_parameters() {
        let v = parse_accels("bih:max_prims=5,shrink=off,bvh").unwrap();
        assert_eq!(v.len(), 2);
        assert_eq!(v[0].params, vec![("max_prims".into(), "5".into()), ("shrink".into(), "off".into())]);
        assert_eq!(v[0].label(), "bih:max_prims=5,shrink=off");
        assert_eq!(v[1].label(), "bvh");
    }

    #[test]
    fn bad_lists_are_rejected_with_the_culprit() {
        for (list, needle) in [
            ("nope", "nope"),
            ("x=1", "before any structure"),
            ("bih:max_prims=1,max_prims=2", "twice"),
            ("bih:leaf=3", "unknown parameter `leaf`"),
            ("brute:oops", "key=value"),
            ("", "no structure"),
        ] {
            let e = parse_accels(list).unwrap_err().to_string();
            assert!(e.contains(needle), "{list}: {e}");
        }
    }

    #[test]
    fn unknown_keys_are_rejected_by_the_hook() {
        let mesh = TriangleMesh::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]);
        let e = build_variant(AccelKind::Brute, &[("leaf".into(), "4".into())], &mesh).err().unwrap();
        assert!(e.to_string().contains("unknown parameter `leaf`"), "{e}");
        assert!(build_variant(AccelKind::Brute, &[], &mesh).is_ok());
    }
}
