//! Seed 003 Algorithm 2.2: dividing a node's primitive references between its two sides,
//! on one thread (Hoare) or, for the large nodes at the top, on all of them.

use super::prim_ref::{Box3, PrimRef};
use glam::Vec3A;
use rayon::prelude::*;

/// Refs per chunk of the parallel partition: fixed, so the chunking and not the thread
/// count decides the result.
pub(super) const CHUNK: usize = 1 << 14;

/// A node's two sides after its split: counts, boxes and centroid boxes.
pub(super) struct Sides {
    pub nl: usize,
    pub lb: Box3,
    pub rb: Box3,
    pub lc: Box3,
    pub rc: Box3,
}

/// Seed 003 Algorithm 2.2: Hoare-style in-place partition by the centroid predicate
/// `is_left`. Returns the number of left refs (they end up first) and the centroid boxes
/// of both sides, gathered on the way (a separate pass per node cost a read of every ref).
pub(super) fn partition(refs: &mut [PrimRef], is_left: impl Fn(Vec3A) -> bool) -> (usize, Box3, Box3) {
    let (mut l, mut r) = (0, refs.len());
    let (mut lc, mut rc) = (Box3::EMPTY, Box3::EMPTY);
    loop {
        while l < r {
            let c = refs[l].center2();
            if !is_left(c) {
                break;
            }
            lc.grow(c);
            l += 1;
        }
        while l < r {
            let c = refs[r - 1].center2();
            if is_left(c) {
                break;
            }
            rc.grow(c);
            r -= 1;
        }
        if l >= r {
            return (l, lc, rc);
        }
        // refs[l] is right and refs[r - 1] left: swapped, each joins its side.
        refs.swap(l, r - 1);
        lc.grow(refs[l].center2());
        rc.grow(refs[r - 1].center2());
        l += 1;
        r -= 1;
    }
}

/// [`partition`] of a large node on all threads (issue 11: the root's 871k dragon refs were
/// partitioned by one thread while the other waited). Each fixed `CHUNK` chunk is
/// partitioned in place in parallel, then the rights that lie below the final split point
/// are swapped, in parallel pieces, with the lefts above it (Embree's parallel in-place
/// partition). The chunking, not the thread count, fixes the result, so builds stay
/// deterministic; each side holds the same refs as after [`partition`], in another order.
pub(super) fn par_partition(refs: &mut [PrimRef], is_left: impl Fn(Vec3A) -> bool + Sync) -> (usize, Box3, Box3) {
    let parts: Vec<(usize, Box3, Box3)> = refs.par_chunks_mut(CHUNK).map(|c| partition(c, &is_left)).collect();
    let n = refs.len();
    let nl: usize = parts.iter().map(|p| p.0).sum();
    let (lc, rc) = parts.iter().fold((Box3::EMPTY, Box3::EMPTY), |(l, r), p| (l.union(&p.1), r.union(&p.2)));
    // Misplaced ranges, ascending: rights inside [0, nl), lefts inside [nl, n). They hold
    // equally many refs (the rights below nl are nl minus the lefts below it).
    let (mut rights_low, mut lefts_high) = (Vec::new(), Vec::new());
    for (i, p) in parts.iter().enumerate() {
        let start = i * CHUNK;
        let (mid, end) = (start + p.0, (start + CHUNK).min(n));
        if mid > nl.max(start) {
            lefts_high.push(nl.max(start)..mid);
        }
        if nl.min(end) > mid {
            rights_low.push(mid..nl.min(end));
        }
    }
    // Pair them into equal pieces of at most CHUNK refs, cut off the two halves in
    // ascending order (disjoint `&mut` slices without unsafe).
    let (mut low, mut high) = refs.split_at_mut(nl);
    let (mut low_at, mut high_at) = (0, nl);
    let mut pieces = Vec::new();
    let (mut ra, mut rb) = (rights_low.into_iter(), lefts_high.into_iter());
    let (mut a, mut b) = (ra.next(), rb.next());
    while let (Some(x), Some(y)) = (a.clone(), b.clone()) {
        let len = x.len().min(y.len()).min(CHUNK);
        let (_, rest) = std::mem::take(&mut low).split_at_mut(x.start - low_at);
        let (pa, rest) = rest.split_at_mut(len);
        (low, low_at) = (rest, x.start + len);
        let (_, rest) = std::mem::take(&mut high).split_at_mut(y.start - high_at);
        let (pb, rest) = rest.split_at_mut(len);
        (high, high_at) = (rest, y.start + len);
        pieces.push((pa, pb));
        a = if len == x.len() { ra.next() } else { Some(x.start + len..x.end) };
        b = if len == y.len() { rb.next() } else { Some(y.start + len..y.end) };
    }
    debug_assert!(a.is_none() && b.is_none(), "misplaced counts differ");
    pieces.into_par_iter().for_each(|(pa, pb)| pa.swap_with_slice(pb));
    (nl, lc, rc)
}

/// Halves `refs`: by centroid order along `axis` (object median), or by index.
pub(super) fn median_split(refs: &mut [PrimRef], axis: Option<usize>) -> Sides {
    let mid = refs.len() / 2;
    if let Some(a) = axis {
        // `select_nth_unstable` is deterministic for a given input order.
        refs.select_nth_unstable_by(mid, |x, y| x.center2()[a].total_cmp(&y.center2()[a]).then(x.id().cmp(&y.id())));
    }
    let boxes = |s: &[PrimRef]| {
        s.iter().fold((Box3::EMPTY, Box3::EMPTY), |(b, c), r| (b.union(&r.bounds()), c.with(r.center2())))
    };
    let ((lb, lc), (rb, rc)) = (boxes(&refs[..mid]), boxes(&refs[mid..]));
    Sides { nl: mid, lb, rb, lc, rc }
}

#[cfg(test)]
mod tests {
    use super::super::build::tests::r;
    use super::*;

    #[test]
    fn partition_keeps_every_ref_and_splits_at_the_predicate() {
        let mut v: Vec<PrimRef> =
            [5.0, 1.0, 7.0, 2.0, 9.0, 0.0, 3.0].iter().enumerate().map(|(i, &x)| r(x, i as u32)).collect();
        // Centres are doubled: 2x < 8 is x < 4.
        let (nl, lc, rc) = partition(&mut v, |c| c.x < 8.0);
        assert_eq!(nl, 4);
        assert!(v[..nl].iter().all(|p| p.center2().x < 8.0) && v[nl..].iter().all(|p| p.center2().x >= 8.0));
        assert_eq!((lc.lo.x, lc.hi.x, rc.lo.x, rc.hi.x), (0.0, 6.0, 10.0, 18.0));
        let mut ids: Vec<u32> = v.iter().map(|p| p.id()).collect();
        ids.sort();
        assert_eq!(ids, (0..7).collect::<Vec<_>>());
    }

    /// The parallel partition puts the same refs on each side as the serial one, with the
    /// same centroid boxes, whatever the chunks' mix (all left, all right, mixed).
    #[test]
    fn par_partition_matches_partition() {
        let n = 3 * CHUNK + 1234;
        let v: Vec<PrimRef> = (0..n as u32).map(|i| r((i.wrapping_mul(2_654_435_761) % 1000) as f32, i)).collect();
        for cut in [-1.0, 300.0, 1001.0, 1999.0, 2500.0] {
            // The first chunk is all at 0: all left or all right of the other chunks' mix.
            let pred = |c: Vec3A| c.x < cut;
            let mut a = v.clone();
            a[..CHUNK].iter_mut().for_each(|p| *p = r(0.0, p.id()));
            let mut b = a.clone();
            let (sa, sb) = (partition(&mut a, pred), par_partition(&mut b, pred));
            assert_eq!(sa.0, sb.0, "cut {cut}");
            assert_eq!((sa.1.lo, sa.1.hi, sa.2.lo, sa.2.hi), (sb.1.lo, sb.1.hi, sb.2.lo, sb.2.hi));
            let side = |s: &[PrimRef]| {
                let mut ids: Vec<u32> = s.iter().map(|p| p.id()).collect();
                ids.sort_unstable();
                ids
            };
            assert_eq!(side(&a[..sa.0]), side(&b[..sb.0]), "cut {cut}");
            assert_eq!(side(&a[sa.0..]), side(&b[sb.0..]), "cut {cut}");
        }
    }

    #[test]
    fn partition_handles_all_left_and_all_right() {
        let mut v: Vec<PrimRef> = (0..5).map(|i| r(i as f32, i)).collect();
        assert_eq!(partition(&mut v, |_| true).0, 5);
        assert_eq!(partition(&mut v, |_| false).0, 0);
        assert_eq!(partition(&mut [], |_| true).0, 0);
    }
}
