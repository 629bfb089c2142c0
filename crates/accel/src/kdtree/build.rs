//! SAH kd-tree construction in O(N log N) by event sorting (Wald & Havran, "On building
//! fast kd-trees for ray tracing, and on doing that in O(N log N)", RT 2006).
//!
//! Why events and not binning: the seed's baseline is the classic high-quality kd-tree
//! ("SAH and optimal split planes", seed 000 §4.4), and only an exact sweep over every
//! clipped triangle bound finds those planes; binning would evaluate a few dozen planes
//! per axis and lose exactly the tight empty-space cuts a kd-tree is prized for. The
//! sweep is kept O(N log N) overall by sorting the events once at the root and, at each
//! split, splitting the sorted lists in order; only the straddling triangles, re-clipped
//! against each child ("perfect splits", see clip.rs), produce new events that need a
//! sort (a small set, O(√N) on typical scenes), merged back in linear time.
//!
//! Per axis, an event is a triangle's clipped extent start or end, or a "planar" event
//! for a triangle flat in that axis. Planar triangles lying in the split plane go to the
//! side with the lower cost. Splits exactly on a node face are never taken: they would
//! create zero-volume cells for no gain in the SAH.

use super::clip::clipped_bounds;
use super::node::{KdNode, MAX_INDEX};
use super::params::KdTreeParams;
use super::tree::Tree;
use crate::BuildError;
use crate::StructureParams;
use dynray_geom::{Aabb, Triangle, TriangleMesh};
use std::cmp::Ordering;

const END: u8 = 0;
const PLANAR: u8 = 1;
const START: u8 = 2;

/// One event on one axis; lists are sorted by (position, kind, triangle).
#[derive(Clone, Copy, Debug)]
struct Event {
    pos: f32,
    tri: u32,
    kind: u8,
}

fn event_order(a: &Event, b: &Event) -> Ordering {
    a.pos.total_cmp(&b.pos).then(a.kind.cmp(&b.kind)).then(a.tri.cmp(&b.tri))
}

/// Event lists of one node, one per axis, each sorted.
type Events = [Vec<Event>; 3];

/// Where each of a node's triangles goes after a split.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Left,
    Right,
    Both,
}

/// The best plane of a node.
#[derive(Clone, Copy, Debug)]
struct Split {
    axis: usize,
    pos: f32,
    /// Triangles lying in the plane go left (else right).
    planar_left: bool,
    cost: f32,
    /// Triangles that will be referenced from both children.
    straddling: usize,
}

/// Build-wide state: the triangles, parameters, scratch arrays indexed by triangle, and
/// the output arrays.
struct Builder<'a> {
    tris: &'a [Triangle],
    params: &'a KdTreeParams,
    max_depth: u32,
    /// Duplicated references still allowed (see `max_refs_per_triangle`).
    dup_budget: usize,
    side: Vec<Side>,
    boxes: Vec<Aabb>,
    nodes: Vec<KdNode>,
    leaf_starts: Vec<u32>,
    prim_ids: Vec<u32>,
    depth: u32,
}

/// Builds the tree over the mesh's triangles.
pub fn build(mesh: &TriangleMesh, params: &KdTreeParams) -> Result<Tree, BuildError> {
    params.validate()?;
    mesh.validate()?;
    let n = mesh.triangle_count();
    if n > MAX_INDEX as usize {
        return Err(BuildError::Limit(format!("{n} triangles; the kd-tree indexes at most {MAX_INDEX}")));
    }
    let tris: Vec<Triangle> = mesh.triangles().collect();
    let bounds = tris.iter().fold(Aabb::EMPTY, |b, t| b.union(&t.bounds()));
    let mut events: Events = Default::default();
    for (i, t) in tris.iter().enumerate() {
        push_events(&mut events, i as u32, &t.bounds());
    }
    for list in &mut events {
        list.sort_unstable_by(event_order);
    }
    let dup_budget = ((params.max_refs_per_triangle as f64 - 1.0) * n as f64) as usize;
    let mut b = Builder {
        tris: &tris,
        params,
        max_depth: params.depth_limit(n),
        dup_budget,
        side: vec![Side::Both; n],
        boxes: vec![Aabb::EMPTY; n],
        nodes: Vec::new(),
        leaf_starts: vec![0],
        prim_ids: Vec::new(),
        depth: 0,
    };
    b.node(events, n, bounds, 0)?;
    let Builder { nodes, leaf_starts, prim_ids, depth, .. } = b;
    Ok(Tree { nodes, leaf_starts, prim_ids, tris, bounds, depth, params: *params })
}

/// Appends the events of one triangle with clipped box `b`. `+ 0.0` turns −0 into +0 so
/// that the sort's total order agrees with `==` (the sweep groups equal positions).
fn push_events(ev: &mut Events, tri: u32, b: &Aabb) {
    for (axis, list) in ev.iter_mut().enumerate() {
        let (lo, hi) = (b.min[axis] + 0.0, b.max[axis] + 0.0);
        if lo == hi {
            list.push(Event { pos: lo, tri, kind: PLANAR });
        } else {
            list.push(Event { pos: lo, tri, kind: START });
            list.push(Event { pos: hi, tri, kind: END });
        }
    }
}

/// Box `b` cut at `pos` on `axis`: (below, above).
fn split_box(b: &Aabb, axis: usize, pos: f32) -> (Aabb, Aabb) {
    let (mut l, mut r) = (*b, *b);
    l.max[axis] = pos;
    r.min[axis] = pos;
    (l, r)
}

/// Merges sorted `b` into sorted `a`, in place from the back (no second buffer).
fn merge(mut a: Vec<Event>, b: Vec<Event>) -> Vec<Event> {
    let Some(&fill) = b.first() else { return a };
    let (mut i, mut j) = (a.len(), b.len());
    a.resize(i + j, fill);
    for k in (0..a.len()).rev() {
        if j == 0 {
            break;
        }
        if i > 0 && event_order(&a[i - 1], &b[j - 1]) == Ordering::Greater {
            a[k] = a[i - 1];
            i -= 1;
        } else {
            a[k] = b[j - 1];
            j -= 1;
        }
    }
    a
}

impl Builder<'_> {
    /// SAH cost of a split with `nl` and `nr` triangles and child area ratios `pl`, `pr`.
    fn cost(&self, pl: f32, pr: f32, nl: usize, nr: usize) -> f32 {
        let p = self.params;
        let bonus = if nl == 0 || nr == 0 { p.empty_bonus } else { 1.0 };
        bonus * (p.traversal_cost + p.intersection_cost * (pl * nl as f32 + pr * nr as f32))
    }

    /// The sweep: every event position strictly inside the node is a candidate plane;
    /// counts left/right/planar are updated in one pass per axis (Wald & Havran, Alg. 4).
    fn find_split(&self, ev: &Events, n: usize, bx: &Aabb) -> Option<Split> {
        let sa = bx.surface_area();
        if sa.is_nan() || sa <= 0.0 {
            return None;
        }
        let inv_sa = 1.0 / sa;
        let e = bx.extent();
        let mut best: Option<Split> = None;
        for (axis, list) in ev.iter().enumerate() {
            if bx.max[axis] <= bx.min[axis] {
                continue;
            }
            // A child's area is linear in the plane position: 2·(cross + length·perimeter).
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let (cross, perim) = (e[u] * e[v], e[u] + e[v]);
            let area = |len: f32| 2.0 * (cross + len * perim) * inv_sa;
            let (mut nl, mut nr) = (0usize, n);
            let mut i = 0;
            while i < list.len() {
                let pos = list[i].pos;
                let mut count = [0usize; 3];
                for kind in [END, PLANAR, START] {
                    while i < list.len() && list[i].pos == pos && list[i].kind == kind {
                        count[kind as usize] += 1;
                        i += 1;
                    }
                }
                let (pe, pp, ps) = (count[END as usize], count[PLANAR as usize], count[START as usize]);
                if pe + pp + ps == 0 {
                    // Only a NaN position groups with nothing; clip.rs never yields one, but a
                    // sweep must not spin on it.
                    debug_assert!(false, "unsortable event position {pos}");
                    i += 1;
                    continue;
                }
                nr -= pe + pp;
                if pos > bx.min[axis] && pos < bx.max[axis] {
                    let (pl, pr) = (area(pos - bx.min[axis]), area(bx.max[axis] - pos));
                    let cost_left = self.cost(pl, pr, nl + pp, nr);
                    let cost_right = self.cost(pl, pr, nl, nr + pp);
                    let (cost, planar_left) =
                        if cost_left <= cost_right { (cost_left, true) } else { (cost_right, false) };
                    if best.is_none_or(|b| cost < b.cost) {
                        // `nl` and `nr` both count the straddlers (started before the plane,
                        // ending after it); everything else is counted once or is planar.
                        let straddling = nl + nr + pp - n;
                        best = Some(Split { axis, pos, planar_left, cost, straddling });
                    }
                }
                nl += ps + pp;
            }
        }
        best
    }

    /// Builds the subtree of one node and returns its index.
    fn node(&mut self, ev: Events, n: usize, bx: Aabb, depth: u32) -> Result<u32, BuildError> {
        let index = self.nodes.len() as u32;
        if index > MAX_INDEX {
            return Err(BuildError::Limit(format!("more than {MAX_INDEX} kd-tree nodes")));
        }
        self.depth = self.depth.max(depth);
        let leaf_cost = self.params.intersection_cost * n as f32;
        let split = if n as u32 <= self.params.min_prims || depth >= self.max_depth {
            None
        } else {
            self.find_split(&ev, n, &bx).filter(|s| s.cost < leaf_cost && s.straddling <= self.dup_budget)
        };
        let Some(split) = split else {
            return self.leaf(&ev);
        };
        self.dup_budget -= split.straddling;
        self.nodes.push(KdNode::interior(split.axis, split.pos, 0));
        let (lbox, rbox) = split_box(&bx, split.axis, split.pos);
        let (left, right, nl, nr) = self.partition(ev, &split, &lbox, &rbox);
        self.node(left, nl, lbox, depth + 1)?;
        let r = self.node(right, nr, rbox, depth + 1)?;
        self.nodes[index as usize] = KdNode::interior(split.axis, split.pos, r);
        Ok(index)
    }

    /// Emits a leaf holding the node's triangles (each once, ascending).
    fn leaf(&mut self, ev: &Events) -> Result<u32, BuildError> {
        let index = self.nodes.len() as u32;
        let leaf = (self.leaf_starts.len() - 1) as u32;
        let start = self.prim_ids.len();
        // Every triangle has exactly one START or PLANAR event per axis.
        self.prim_ids.extend(ev[0].iter().filter(|e| e.kind != END).map(|e| e.tri));
        self.prim_ids[start..].sort_unstable();
        if self.prim_ids.len() > MAX_INDEX as usize {
            return Err(BuildError::Limit(format!("more than {MAX_INDEX} kd-tree triangle references")));
        }
        self.leaf_starts.push(self.prim_ids.len() as u32);
        self.nodes.push(KdNode::leaf(leaf));
        Ok(index)
    }

    /// Splits the node's sorted events into the children's sorted events.
    fn partition(&mut self, ev: Events, s: &Split, lbox: &Aabb, rbox: &Aabb) -> (Events, Events, usize, usize) {
        // Classify by the events on the split axis (Wald & Havran, Alg. 5).
        for e in &ev[s.axis] {
            self.side[e.tri as usize] = Side::Both;
        }
        let (mut nl, mut nr) = (0, 0);
        for e in &ev[s.axis] {
            let side = &mut self.side[e.tri as usize];
            match e.kind {
                END if e.pos <= s.pos => *side = Side::Left,
                START if e.pos >= s.pos => *side = Side::Right,
                PLANAR if e.pos < s.pos || (e.pos == s.pos && s.planar_left) => *side = Side::Left,
                PLANAR => *side = Side::Right,
                _ => continue,
            }
            if *side == Side::Left {
                nl += 1
            } else {
                nr += 1
            }
        }
        // Keep the one-sided events in order; collect the straddlers' current boxes.
        // At most two events per triangle and axis, plus room for the straddlers' new ones.
        let straddling = s.straddling;
        let mut left: Events = std::array::from_fn(|_| Vec::with_capacity(2 * (nl + straddling)));
        let mut right: Events = std::array::from_fn(|_| Vec::with_capacity(2 * (nr + straddling)));
        let mut straddlers = Vec::new();
        for (axis, list) in ev.into_iter().enumerate() {
            for e in list {
                match self.side[e.tri as usize] {
                    Side::Left => left[axis].push(e),
                    Side::Right => right[axis].push(e),
                    Side::Both => {
                        let b = &mut self.boxes[e.tri as usize];
                        if axis == 0 && e.kind != END {
                            straddlers.push(e.tri);
                            *b = Aabb::EMPTY;
                        }
                        if e.kind != END {
                            b.min[axis] = e.pos;
                        }
                        if e.kind != START {
                            b.max[axis] = e.pos;
                        }
                    }
                }
            }
        }
        debug_assert_eq!(straddlers.len(), s.straddling, "sweep and classification disagree");
        // Re-clip the straddlers to each child; sort the new events and merge them in.
        let mut new_left: Events = Default::default();
        let mut new_right: Events = Default::default();
        for &t in &straddlers {
            let tri = &self.tris[t as usize];
            let cur = self.boxes[t as usize];
            for (cbox, out) in [(lbox, &mut new_left), (rbox, &mut new_right)] {
                // A straddler truly reaches into both children; if rounding made the clip
                // come out empty, fall back to its current box cut to the child.
                let b = clipped_bounds(tri, cbox).unwrap_or_else(|| cur.intersection(cbox));
                push_events(out, t, &b);
            }
        }
        let nl = nl + straddlers.len();
        let nr = nr + straddlers.len();
        let merge_all = |old: Events, mut new: Events| -> Events {
            let mut out: Events = Default::default();
            for (axis, list) in old.into_iter().enumerate() {
                let mut add = std::mem::take(&mut new[axis]);
                add.sort_unstable_by(event_order);
                out[axis] = merge(list, add);
            }
            out
        };
        (merge_all(left, new_left), merge_all(right, new_right), nl, nr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn in_place_merge_equals_sorting_the_concatenation() {
        let ev = |pos: f32, kind: u8, tri: u32| Event { pos, tri, kind };
        let mut a = vec![ev(0.0, START, 3), ev(1.0, END, 1), ev(1.0, START, 0), ev(5.0, END, 2)];
        let mut b = vec![ev(-1.0, PLANAR, 9), ev(1.0, PLANAR, 4), ev(1.0, START, 7), ev(9.0, END, 8)];
        a.sort_unstable_by(event_order);
        b.sort_unstable_by(event_order);
        let mut want = [a.clone(), b.clone()].concat();
        want.sort_unstable_by(event_order);
        let got = merge(a, b);
        let key = |v: &[Event]| v.iter().map(|e| (e.pos.to_bits(), e.kind, e.tri)).collect::<Vec<_>>();
        assert_eq!(key(&got), key(&want));
        assert_eq!(key(&merge(Vec::new(), want.clone())), key(&want));
    }
}
