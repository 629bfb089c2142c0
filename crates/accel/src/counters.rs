//! Traversal counters, compiled away when not asked for.
//!
//! Traversal loops are generic over [`Counter`]: with [`NoCount`] every call is an empty
//! inline function, so the normal path pays nothing; with [`TraversalCounts`] the bench
//! and the heat-map renderer get per-ray work figures from the very same code.

/// Receives traversal events.
pub trait Counter {
    /// A node (or grid cell, or leaf) was visited.
    fn node(&mut self);
    /// `n` triangles were tested.
    fn triangles(&mut self, n: u32);
    /// `n` nodes were visited (a nested structure's count, passed up at once).
    fn nodes(&mut self, n: u64) {
        (0..n).for_each(|_| self.node());
    }
}

/// The counter that counts nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoCount;

impl Counter for NoCount {
    #[inline(always)]
    fn node(&mut self) {}
    #[inline(always)]
    fn triangles(&mut self, _: u32) {}
    #[inline(always)]
    fn nodes(&mut self, _: u64) {}
}

/// Accumulated traversal work.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalCounts {
    /// Nodes or cells visited.
    pub nodes: u64,
    /// Ray–triangle tests.
    pub triangles: u64,
}

impl Counter for TraversalCounts {
    #[inline(always)]
    fn node(&mut self) {
        self.nodes += 1;
    }
    #[inline(always)]
    fn triangles(&mut self, n: u32) {
        self.triangles += n as u64;
    }
    #[inline(always)]
    fn nodes(&mut self, n: u64) {
        self.nodes += n;
    }
}

impl std::ops::AddAssign for TraversalCounts {
    fn add_assign(&mut self, o: Self) {
        self.nodes += o.nodes;
        self.triangles += o.triangles;
    }
}
