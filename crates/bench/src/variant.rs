//! The `--accels` list: structures with their parameters, each an [`AccelSpec`] of
//! dynray-accel (which owns the keys, presets and checks; see docs/bench.md, "Structure
//! parameters").
//!
//! Grammar: a comma-separated list; a piece without `=` starts a new structure (`name`,
//! `name:key=value` or `name:preset`), a piece with `=` adds a parameter to the structure
//! before it. So `bvh,bih:max_prims=5,shrink=off,grid` is three structures, the second
//! with two parameters. Each structure is checked as the list is parsed.

use anyhow::{bail, Result};
use dynray_accel::AccelSpec;

/// Parses an `--accels` list (grammar in the module docs).
pub fn parse_accels(list: &str) -> Result<Vec<AccelSpec>> {
    // Group the pieces into one `NAME[:k=v,k=v]` text per structure, then let
    // `AccelSpec` parse each (same grammar, messages and checks as `--accel`).
    let mut groups: Vec<String> = Vec::new();
    for piece in list.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        if piece.contains(':') || !piece.contains('=') {
            groups.push(piece.to_string());
            continue;
        }
        let Some(last) = groups.last_mut() else {
            bail!("--accels: parameter `{piece}` comes before any structure name");
        };
        last.push(if last.contains(':') { ',' } else { ':' });
        last.push_str(piece);
    }
    if groups.is_empty() {
        bail!("--accels: no structure named in `{list}`");
    }
    groups.iter().map(|g| g.parse::<AccelSpec>().map_err(|e| anyhow::anyhow!("--accels: {e}"))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_accel::AccelKind;

    #[test]
    fn lists_split_into_structures_and_parameters() {
        let v = parse_accels("bih:max_prims=5,shrink=off,bvh,octree:fast,grid").unwrap();
        assert_eq!(v.len(), 4);
        assert_eq!(v[0].params, vec![("max_prims".into(), "5".into()), ("shrink".into(), "off".into())]);
        assert_eq!(v[0].to_string(), "bih:max_prims=5,shrink=off");
        assert_eq!(v[1].to_string(), "bvh");
        assert_eq!(v[2], AccelSpec::with_preset(AccelKind::Octree, "fast"));
        assert_eq!(v[3], AccelSpec::new(AccelKind::Grid));
    }

    #[test]
    fn bad_lists_are_rejected_with_the_culprit() {
        for (list, needle) in [
            ("nope", "nope"),
            ("x=1", "before any structure"),
            ("bih:max_prims=1,max_prims=2", "twice"),
            ("bih:leaf=3", "unknown parameter `leaf`"),
            ("brute:oops", "unknown preset `oops`"),
            ("bih:max_prims=5,oops", "unknown structure `oops`"),
            ("", "no structure"),
        ] {
            let e = parse_accels(list).unwrap_err().to_string();
            assert!(e.contains(needle), "{list}: {e}");
        }
    }
}
