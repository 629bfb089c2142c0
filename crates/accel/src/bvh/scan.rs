//! Every block of a list in order, through the wide BVH's block kernels: brute force's
//! loop ([`crate::Brute`] keeps the mesh's triangles as 4-triangle blocks in index
//! order). The scalar kernel is `Triangle::intersect` lane by lane and the AVX2 and AVX-512
//! ones are held to its bits (kernel.rs's tests), so brute force stays the specification while
//! testing four triangles per step.

use super::kernel::{Kernel, KernelChoice, Scalar};
use super::TriBlock;
use dynray_geom::{Hit, PreparedRay};

/// The closest hit over `blocks`: on equal `t` the lower id wins, as in a scan in index
/// order with a strict `<`.
#[inline]
#[allow(unsafe_code)]
pub fn closest(blocks: &[TriBlock], r: &PreparedRay, kernel: KernelChoice) -> Hit {
    #[cfg(target_arch = "x86_64")]
    match kernel {
        // SAFETY: `KernelChoice::Avx512` is only chosen when AVX2, AVX-512 F and VL were
        // detected, `Avx2` when AVX2 was.
        KernelChoice::Avx512 => return unsafe { closest_avx512(blocks, r) },
        KernelChoice::Avx2 => return unsafe { closest_avx2(blocks, r) },
        KernelChoice::Scalar => {}
    }
    let _ = kernel;
    closest_with::<Scalar>(blocks, r)
}

/// Whether any triangle of `blocks` is hit within the ray's interval.
#[inline]
#[allow(unsafe_code)]
pub fn any(blocks: &[TriBlock], r: &PreparedRay, kernel: KernelChoice) -> bool {
    #[cfg(target_arch = "x86_64")]
    match kernel {
        // SAFETY: as in `closest`.
        KernelChoice::Avx512 => return unsafe { any_avx512(blocks, r) },
        KernelChoice::Avx2 => return unsafe { any_avx2(blocks, r) },
        KernelChoice::Scalar => {}
    }
    let _ = kernel;
    Scalar::any_leaf(blocks, r)
}

#[inline(always)]
fn closest_with<K: Kernel>(blocks: &[TriBlock], r: &PreparedRay) -> Hit {
    let mut best = Hit::MISS;
    K::closest_leaf(blocks, r, &mut best);
    best
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(unsafe_code)]
unsafe fn closest_avx2(blocks: &[TriBlock], r: &PreparedRay) -> Hit {
    closest_with::<super::kernel_avx2::Avx2>(blocks, r)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(unsafe_code)]
unsafe fn any_avx2(blocks: &[TriBlock], r: &PreparedRay) -> bool {
    use super::kernel_avx2::Avx2;
    Avx2::any_leaf(blocks, r)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f,avx512vl")]
#[allow(unsafe_code)]
unsafe fn closest_avx512(blocks: &[TriBlock], r: &PreparedRay) -> Hit {
    closest_with::<super::kernel_avx512::Avx512>(blocks, r)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f,avx512vl")]
#[allow(unsafe_code)]
unsafe fn any_avx512(blocks: &[TriBlock], r: &PreparedRay) -> bool {
    use super::kernel_avx512::Avx512;
    Avx512::any_leaf(blocks, r)
}
