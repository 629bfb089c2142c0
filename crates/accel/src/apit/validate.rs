//! Self-checks of both structures: indices in range, every fragment reachable exactly
//! once, tree invariants, every triangle either near or rasterised somewhere.

use super::abuffer::ABuffer;
use super::build::Base;
use super::node::{Fragment, NONE};
use super::tree::Apit;

/// Checks the fragments' contents and that every far triangle has at least one.
fn check_fragments(base: &Base, frags: &[Fragment]) -> Result<(), String> {
    let n = base.tris.len();
    if base.near.windows(2).any(|w| w[0] >= w[1]) || base.near.last().is_some_and(|&k| k as usize >= n) {
        return Err("near list not ascending or out of range".into());
    }
    let mut covered = vec![false; n];
    for &k in &base.near {
        covered[k as usize] = true;
    }
    for (i, f) in frags.iter().enumerate() {
        if f.tri as usize >= n {
            return Err(format!("fragment {i} names triangle {} of {n}", f.tri));
        }
        if !(f.zmin <= f.zmax && f.zmin.is_finite() && f.zmax.is_finite()) {
            return Err(format!("fragment {i}: bad depth interval [{}, {}]", f.zmin, f.zmax));
        }
        covered[f.tri as usize] = true;
    }
    // Every point of space off the near box lies in some frustum, so a far triangle
    // without a fragment would be invisible to every ray.
    match covered.iter().position(|&c| !c) {
        Some(t) => Err(format!("triangle {t} is neither near nor rasterised")),
        None => Ok(()),
    }
}

impl ABuffer {
    /// Checks the structure's invariants; the error names the first broken one.
    pub(crate) fn check_invariants(&self) -> Result<(), String> {
        if self.heads.len() != self.base.cube.pixels() {
            return Err(format!("{} heads for {} pixels", self.heads.len(), self.base.cube.pixels()));
        }
        check_fragments(&self.base, &self.frags)?;
        let mut seen = vec![false; self.frags.len()];
        for (p, &h) in self.heads.iter().enumerate() {
            let mut f = h;
            while f != NONE {
                let fr = self.frags.get(f as usize).ok_or_else(|| format!("pixel {p}: fragment {f} out of range"))?;
                if std::mem::replace(&mut seen[f as usize], true) {
                    return Err(format!("fragment {f} reached twice (pixel {p})"));
                }
                f = fr.next;
            }
        }
        match seen.iter().position(|&s| !s) {
            Some(f) => Err(format!("fragment {f} unreachable")),
            None => Ok(()),
        }
    }
}

impl Apit {
    /// Checks the structure's invariants (every tree's too); the error names the first
    /// broken one.
    pub(crate) fn check_invariants(&self) -> Result<(), String> {
        if self.roots.len() != self.base.cube.pixels() {
            return Err(format!("{} roots for {} pixels", self.roots.len(), self.base.cube.pixels()));
        }
        check_fragments(&self.base, &self.forest.frags)?;
        let mut seen_nodes = vec![false; self.forest.nodes.len()];
        let mut seen_frags = vec![false; self.forest.frags.len()];
        let mut depth = 0;
        for (p, &r) in self.roots.iter().enumerate() {
            let shape = self
                .forest
                .validate_tree(r, &mut seen_nodes, &mut seen_frags)
                .map_err(|e| format!("pixel {p}: {e}"))?;
            depth = depth.max(shape.depth);
        }
        if depth != self.depth_max {
            return Err(format!("deepest node at {depth}, recorded {}", self.depth_max));
        }
        if let Some(n) = seen_nodes.iter().position(|&s| !s) {
            return Err(format!("node {n} unreachable"));
        }
        match seen_frags.iter().position(|&s| !s) {
            Some(f) => Err(format!("fragment {f} unreachable")),
            None => Ok(()),
        }
    }
}
