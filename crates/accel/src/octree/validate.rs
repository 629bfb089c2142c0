//! Self-check of a built octree: record encoding, neighbour links against geometry
//! (including the 2:1 balance and the neighbour order of Eq. 9), the internal nodes
//! against the leaves, triangle coverage, and the cube map.

use super::node::{link_words, nibble, LEAF_BIT, LOCATE, REC_LINKS};
use super::params::MAX_DEPTH_LIMIT;
use super::tables::{in_face_axes, neighbor_slot, FACE_AXIS, FACE_POSITIVE};
use super::Octree;

/// A broken invariant, with the leaf (or node) where it was found.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("invalid octree at leaf {leaf}: {what}")]
pub struct InvalidOctree {
    /// Leaf index (or internal node index, where the message says so).
    pub leaf: usize,
    /// What is wrong, with the values.
    pub what: String,
}

impl Octree {
    /// Checks every invariant the traversals rely on: records are consecutive, each names
    /// its own leaf, a valid triangle run and valid neighbour addresses; every link joins
    /// face-adjacent leaves (one same-size-or-larger neighbour, or four half-size ones in
    /// Eq. 9's order), faces without links are on the root boundary (or, in unbalanced
    /// trees only, have more than four neighbours); in a balanced tree every face has 0, 1
    /// or 4 neighbours and adjacent leaves differ by at most one level; the internal nodes
    /// reach every leaf exactly once, at its own cell, within [`MAX_DEPTH_LIMIT`]; every
    /// mesh triangle is referenced; every cube-map texel names the boundary leaf under it.
    pub(crate) fn check_invariants(&self) -> Result<(), InvalidOctree> {
        let err = |leaf: usize, what: String| Err(InvalidOctree { leaf, what });
        // Record starts, in leaf order.
        let mut addr_of = Vec::with_capacity(self.boxes.len());
        let mut a = 0usize;
        while a < self.records.len() {
            if a + REC_LINKS > self.records.len() {
                return err(addr_of.len(), format!("record at word {a} is truncated"));
            }
            let nc = self.records[a + 3];
            if nc >> 24 != 0 {
                return err(addr_of.len(), format!("nCount {nc:#x} uses bits above 24"));
            }
            addr_of.push(a);
            a += REC_LINKS + (0..6).map(|f| link_words(nibble(nc, f))).sum::<usize>();
        }
        if a != self.records.len() || addr_of.len() != self.boxes.len() {
            return err(
                0,
                format!("{} records in {} words for {} boxes", addr_of.len(), self.records.len(), self.boxes.len()),
            );
        }
        let leaf_at = |addr: u32| addr_of.binary_search(&(addr as usize)).ok();
        let mut referenced = vec![false; self.mesh_triangles];
        for (i, &a) in addr_of.iter().enumerate() {
            let rec = &self.records[a..];
            let (count, first, li, nc) = (rec[0] as usize, rec[1] as usize, rec[2] as usize, rec[3]);
            if li != i {
                return err(i, format!("record names leaf {li}"));
            }
            if first + count > self.tris.len() {
                return err(i, format!("triangle run {first}+{count} exceeds {}", self.tris.len()));
            }
            for &p in &self.prim_ids[first..first + count] {
                match referenced.get_mut(p as usize) {
                    Some(r) => *r = true,
                    None => return err(i, format!("triangle id {p} out of range")),
                }
            }
            let b = &self.boxes[i];
            let (k, cell) = (b.depth(), [b.cell[0] as u32, b.cell[1] as u32, b.cell[2] as u32]);
            if k > self.fine_depth || cell.iter().any(|&c| c >> k != 0) {
                return err(i, format!("cell {cell:?} at depth {k} is invalid"));
            }
            if self.frame.cell_box(cell, k) != b.aabb() {
                return err(i, format!("box {:?} is not cell {cell:?} at depth {k}", b.aabb()));
            }
            let mut link = a + REC_LINKS;
            for f in 0..6 {
                let n = nibble(nc, f);
                let ax = FACE_AXIS[f];
                let across =
                    if FACE_POSITIVE[f] { Some(cell[ax] + 1).filter(|&c| c < 1 << k) } else { cell[ax].checked_sub(1) };
                let nc_cell = across.map(|c| {
                    let mut x = cell;
                    x[ax] = c;
                    x
                });
                match (n, nc_cell) {
                    (0, None) => {}
                    (0, Some(_)) => return err(i, format!("face {f} has no neighbour but is inside the root")),
                    (_, None) => return err(i, format!("face {f} is on the root boundary but has nibble {n}")),
                    (1, Some(x)) => {
                        let j = self.link_leaf(link, &leaf_at, i)?;
                        let nb = &self.boxes[j];
                        let kj = nb.depth();
                        let ok = kj <= k && (0..3).all(|q| x[q] >> (k - kj) == nb.cell[q] as u32);
                        if !ok {
                            return err(
                                i,
                                format!(
                                    "face {f}: leaf {j} (cell {:?}) does not cover cell {x:?} at depth {k}",
                                    nb.cell
                                ),
                            );
                        }
                        if self.params.balance && kj + 1 < k {
                            return err(
                                i,
                                format!("face {f}: neighbour {j} at depth {kj} breaks 2:1 balance (depth {k})"),
                            );
                        }
                    }
                    (4, Some(x)) => {
                        let (u, w) = in_face_axes(f);
                        for s in 0..4 {
                            let j = self.link_leaf(link + s, &leaf_at, i)?;
                            let nb = &self.boxes[j];
                            let c = [nb.cell[0] as u32, nb.cell[1] as u32, nb.cell[2] as u32];
                            let near = if FACE_POSITIVE[f] { 0 } else { 1 };
                            let ok = nb.depth() == k + 1
                                && (0..3).all(|q| c[q] >> 1 == x[q])
                                && c[ax] & 1 == near
                                && neighbor_slot(c[u] & 1 == 1, c[w] & 1 == 1) == s;
                            if !ok {
                                return err(
                                    i,
                                    format!(
                                        "face {f} slot {s}: leaf {j} (cell {c:?}) is not the right half-size neighbour"
                                    ),
                                );
                            }
                        }
                    }
                    (LOCATE, Some(_)) if !self.params.balance => {}
                    _ => return err(i, format!("face {f} has nibble {n}, expected 0, 1 or 4")),
                }
                link += link_words(n);
            }
        }
        if let Some(t) = referenced.iter().position(|r| !r) {
            return err(0, format!("triangle {t} is in no leaf"));
        }
        self.check_inner(&leaf_at)?;
        self.check_cube_map(&leaf_at)
    }

    fn link_leaf(&self, word: usize, leaf_at: &dyn Fn(u32) -> Option<usize>, i: usize) -> Result<usize, InvalidOctree> {
        let a = self.records[word];
        leaf_at(a).ok_or_else(|| InvalidOctree { leaf: i, what: format!("link {a} is not a record address") })
    }

    fn check_inner(&self, leaf_at: &dyn Fn(u32) -> Option<usize>) -> Result<(), InvalidOctree> {
        let err = |leaf: usize, what: String| Err(InvalidOctree { leaf, what });
        if self.fine_depth > MAX_DEPTH_LIMIT {
            return err(0, format!("depth {} exceeds the traversal stack ({MAX_DEPTH_LIMIT})", self.fine_depth));
        }
        let mut seen = vec![false; self.boxes.len()];
        let mut inner_seen = vec![false; self.inner.len()];
        let mut stack = vec![(self.root, [0u32; 3], 0u32)];
        while let Some((node, cell, depth)) = stack.pop() {
            if node & LEAF_BIT != 0 {
                let Some(j) = leaf_at(node & !LEAF_BIT) else {
                    return err(0, format!("internal reference {:#x} is not a record", node));
                };
                let b = &self.boxes[j];
                if seen[j] || b.depth() != depth || (0..3).any(|q| b.cell[q] as u32 != cell[q]) {
                    return err(j, format!("reached twice or at the wrong cell {cell:?} depth {depth}"));
                }
                seen[j] = true;
                continue;
            }
            match inner_seen.get_mut(node as usize) {
                Some(s) if !*s => *s = true,
                _ => return err(node as usize, format!("internal node {node} missing or reached twice")),
            }
            if depth >= self.fine_depth {
                return err(node as usize, format!("internal node {node} at depth {depth} >= leaf depth bound"));
            }
            for (o, &c) in self.inner[node as usize].child.iter().enumerate() {
                let o = o as u32;
                stack.push((
                    c,
                    [cell[0] * 2 + (o & 1), cell[1] * 2 + (o >> 1 & 1), cell[2] * 2 + (o >> 2 & 1)],
                    depth + 1,
                ));
            }
        }
        if let Some(j) = seen.iter().position(|s| !s) {
            return err(j, "not reachable from the root".into());
        }
        if let Some(n) = inner_seen.iter().position(|s| !s) {
            return err(n, format!("internal node {n} is unreachable"));
        }
        Ok(())
    }

    fn check_cube_map(&self, leaf_at: &dyn Fn(u32) -> Option<usize>) -> Result<(), InvalidOctree> {
        let r = 1usize << self.cube_depth;
        if self.cube_map.len() != 6 * r * r {
            return Err(InvalidOctree {
                leaf: 0,
                what: format!("cube map has {} texels for R = {r}", self.cube_map.len()),
            });
        }
        for (t, &a) in self.cube_map.iter().enumerate() {
            let (f, tw, tu) = (t / (r * r), t / r % r, t % r);
            let ok = leaf_at(a).filter(|&j| {
                let b = &self.boxes[j];
                let s = self.cube_depth.checked_sub(b.depth());
                let (ax, (u, w)) = (FACE_AXIS[f], in_face_axes(f));
                let side = if FACE_POSITIVE[f] { (1u32 << b.depth()) - 1 } else { 0 };
                s.is_some_and(|s| {
                    b.cell[ax] as u32 == side
                        && b.cell[u] as u32 == (tu >> s) as u32
                        && b.cell[w] as u32 == (tw >> s) as u32
                })
            });
            if ok.is_none() {
                return Err(InvalidOctree {
                    leaf: 0,
                    what: format!("cube map texel {t} (face {f}) names address {a}"),
                });
            }
        }
        Ok(())
    }
}
