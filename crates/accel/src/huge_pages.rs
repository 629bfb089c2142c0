//! Transparent huge pages for a tree's large arrays (Linux).
//!
//! A walk over a tree larger than the TLB's reach (Zen 4's L2 TLB: 3,072 entries of 4 KiB,
//! 12 MiB) pays a page walk on many of its node and block loads; 2 MiB pages cover the
//! 47 MiB dragon with 24 entries. Linux backs anonymous memory with them where it was
//! advised with `MADV_HUGEPAGE` (the usual THP mode, `madvise`) before it is first
//! touched, so an array is advised right after its allocation and then filled. Embree does
//! the same for its BVH memory (`os_malloc`: `mmap`, then `madvise(MADV_HUGEPAGE)`).
//!
//! A hint only: where the kernel gives no huge pages (THP off, another OS) nothing changes,
//! and the contents never do.

/// Advises `v`'s whole allocation (its capacity) for huge pages. Call it before the
/// elements are written: pages already touched keep their size.
pub(crate) fn advise<T>(v: &Vec<T>) {
    #[cfg(target_os = "linux")]
    linux::advise(v.as_ptr() as usize, v.capacity() * std::mem::size_of::<T>());
    #[cfg(not(target_os = "linux"))]
    let _ = v;
}

/// `src` in a new allocation advised for huge pages ([`advise`]).
pub(crate) fn copy<T: Copy>(src: &[T]) -> Vec<T> {
    let mut v = Vec::with_capacity(src.len());
    advise(&v);
    v.extend_from_slice(src);
    v
}

#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
mod linux {
    /// `madvise(MADV_HUGEPAGE)` over the pages holding `[start, start + bytes)`.
    pub(super) fn advise(start: usize, bytes: usize) {
        if bytes == 0 {
            return;
        }
        // SAFETY: `sysconf` only reads a system constant.
        let page = match unsafe { libc::sysconf(libc::_SC_PAGESIZE) } {
            p if p > 0 => p as usize,
            _ => return,
        };
        // Whole pages: the partial pages at the ends may hold other allocations too, for
        // which the hint is as harmless.
        let lo = start / page * page;
        let hi = (start + bytes).div_ceil(page) * page;
        // SAFETY: `MADV_HUGEPAGE` changes neither contents nor access rights of the range
        // (the pages of a live allocation, so mapped); the result is ignored, since the
        // advice is a hint (EINVAL where the kernel has no THP).
        unsafe {
            libc::madvise(lo as *mut libc::c_void, hi - lo, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advised_arrays_keep_their_contents() {
        let empty: Vec<u64> = Vec::new();
        advise(&empty);
        assert!(copy::<u64>(&[]).is_empty());
        // Larger than a huge page, and a type whose size is not a power of two.
        let src: Vec<[f32; 5]> = (0..300_000).map(|i| [i as f32, 1.0, 2.0, 3.0, -(i as f32)]).collect();
        let v = copy(&src);
        assert_eq!(v, src);
        let mut w: Vec<u32> = Vec::with_capacity(1 << 20);
        advise(&w);
        w.extend(0..1 << 20);
        assert!(w.iter().enumerate().all(|(i, &x)| x == i as u32));
    }
}
