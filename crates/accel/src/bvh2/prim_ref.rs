//! What the binned-SAH builder moves around: one triangle's reference (its box and mesh
//! index in 32 bytes) and a box held in SIMD registers.

use dynray_geom::Aabb;
use glam::{Vec3A, Vec4};

/// A box in SIMD registers (`Vec3A` = one SSE register per corner): the builder's
/// unions run once per triangle per axis, so they are worth a vector instruction each.
#[derive(Clone, Copy, Debug)]
pub(super) struct Box3 {
    pub lo: Vec3A,
    pub hi: Vec3A,
}

impl Box3 {
    pub(super) const EMPTY: Box3 = Box3 { lo: Vec3A::INFINITY, hi: Vec3A::NEG_INFINITY };

    #[inline(always)]
    pub(super) fn union(&self, o: &Box3) -> Box3 {
        Box3 { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    #[inline(always)]
    pub(super) fn grow(&mut self, p: Vec3A) {
        self.lo = self.lo.min(p);
        self.hi = self.hi.max(p);
    }

    #[inline(always)]
    pub(super) fn with(mut self, p: Vec3A) -> Box3 {
        self.grow(p);
        self
    }

    pub(super) fn aabb(&self) -> Aabb {
        Aabb::new(self.lo.into(), self.hi.into())
    }
}

impl From<&Aabb> for Box3 {
    fn from(b: &Aabb) -> Self {
        Box3 { lo: b.min.into(), hi: b.max.into() }
    }
}

/// One triangle as the builder sees it, in 32 bytes (Embree's layout): its box, with the
/// mesh index in the 4th lane of the low corner. The centroid is taken as `lo + hi` (twice
/// the box centre: the scale cancels in binning), so it costs no storage; 48-byte refs with
/// a stored vertex-mean centroid made every pass over the refs move 1.5× the bytes.
#[derive(Clone, Copy, Debug)]
pub(super) struct PrimRef {
    /// `xyz`: low corner; `w`: the mesh index's bits.
    lo: Vec4,
    hi: Vec3A,
}

impl PrimRef {
    pub(super) fn new(b: &Aabb, id: u32) -> Self {
        PrimRef { lo: Vec3A::from(b.min).extend(f32::from_bits(id)), hi: b.max.into() }
    }

    #[inline(always)]
    pub(super) fn id(&self) -> u32 {
        self.lo.w.to_bits()
    }

    #[inline(always)]
    pub(super) fn bounds(&self) -> Box3 {
        Box3 { lo: Vec3A::from_vec4(self.lo), hi: self.hi }
    }

    /// Twice the box centre: what binning, partition and the median split order by.
    #[inline(always)]
    pub(super) fn center2(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo) + self.hi
    }
}
