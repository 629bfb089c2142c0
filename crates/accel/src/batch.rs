//! Many rays at once: the query interface a renderer, the bench, the CLI and other
//! libraries' adapters share (and, later, the GPU backend).

use crate::Accel;
use dynray_geom::{Hit, Ray};
use rayon::prelude::*;

/// Rays per rayon task in the blanket implementation. 1024 rays take 0.1–1 ms on the
/// CPU structures (bunny, one core), long enough that scheduling costs under 1 %, short
/// enough that 2–16 cores stay busy on the bench's 64k-ray sets. The bench's competitor
/// adapters use the same chunks, so their passes and ours are scheduled alike.
pub const BATCH_CHUNK: usize = 1024;

/// Tracing a slice of rays into a slice of answers, in ray order.
///
/// Every [`Accel`] has it through the blanket implementation below (parallel over chunks
/// of [`BATCH_CHUNK`] rays); other implementations (other libraries' adapters in the
/// bench, a GPU backend) trace the batch their own way but keep the same contract.
pub trait BatchQuery: Sync {
    /// Writes the closest hit of `rays[i]` (with `u`, `v`) into `hits[i]`, [`Hit::MISS`]
    /// for a miss. Panics unless `hits.len() == rays.len()`.
    fn intersect_into(&self, rays: &[Ray], hits: &mut [Hit]);

    /// Writes whether anything lies on `rays[i]` within `[tmin, tmax]` into `out[i]`.
    /// Panics unless `out.len() == rays.len()`.
    fn occluded_into(&self, rays: &[Ray], out: &mut [bool]);

    /// [`BatchQuery::intersect_into`] into a new vector.
    fn intersect_batch(&self, rays: &[Ray]) -> Vec<Hit> {
        let mut hits = vec![Hit::MISS; rays.len()];
        self.intersect_into(rays, &mut hits);
        hits
    }

    /// [`BatchQuery::occluded_into`] into a new vector.
    fn occluded_batch(&self, rays: &[Ray]) -> Vec<bool> {
        let mut out = vec![false; rays.len()];
        self.occluded_into(rays, &mut out);
        out
    }
}

/// Asserts the slice contract of [`BatchQuery`], naming both lengths.
#[track_caller]
pub fn check_batch_lengths(rays: usize, answers: usize) {
    assert_eq!(rays, answers, "batch query: {rays} rays but room for {answers} answers");
}

impl<T: Accel + ?Sized> BatchQuery for T {
    fn intersect_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        check_batch_lengths(rays.len(), hits.len());
        rays.par_chunks(BATCH_CHUNK)
            .zip(hits.par_chunks_mut(BATCH_CHUNK))
            .for_each(|(rs, hs)| self.intersect_stream_into(rs, hs));
    }

    fn occluded_into(&self, rays: &[Ray], out: &mut [bool]) {
        check_batch_lengths(rays.len(), out.len());
        rays.par_chunks(BATCH_CHUNK)
            .zip(out.par_chunks_mut(BATCH_CHUNK))
            .for_each(|(rs, os)| self.occluded_stream_into(rs, os));
    }
}

/// [`BatchQuery`] for rays the caller knows to be coherent (camera rays in pixel order,
/// rays leaving one point): closest hits through [`Accel::intersect_coherent_into`] and
/// any-hit queries through [`Accel::occluded_coherent_into`] (packets where the
/// structure has them), parallel over the same chunks of [`BATCH_CHUNK`] rays as the
/// blanket implementation. The answers are the blanket implementation's, bit for bit;
/// only the speed differs.
pub struct Coherent<'a, A: ?Sized>(pub &'a A);

// Packets are groups of consecutive rays: a chunk boundary must not split one.
const _: () = assert!(BATCH_CHUNK.is_multiple_of(crate::bvh::PACKET), "chunks must hold whole packets");

impl<A: Accel + ?Sized> BatchQuery for Coherent<'_, A> {
    fn intersect_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        check_batch_lengths(rays.len(), hits.len());
        rays.par_chunks(BATCH_CHUNK)
            .zip(hits.par_chunks_mut(BATCH_CHUNK))
            .for_each(|(rs, hs)| self.0.intersect_coherent_into(rs, hs));
    }

    fn occluded_into(&self, rays: &[Ray], out: &mut [bool]) {
        check_batch_lengths(rays.len(), out.len());
        rays.par_chunks(BATCH_CHUNK)
            .zip(out.par_chunks_mut(BATCH_CHUNK))
            .for_each(|(rs, os)| self.0.occluded_coherent_into(rs, os));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Brute, Bvh, BvhParams};
    use dynray_geom::{TriangleMesh, Vec3};

    /// A strip of unit quads along x, so rays hit different triangles in a known order.
    fn strip(n: u32) -> TriangleMesh {
        let mut pos = Vec::new();
        let mut idx = Vec::new();
        for i in 0..=n {
            pos.push([i as f32, 0.0, 0.0]);
            pos.push([i as f32, 1.0, 0.0]);
        }
        for i in 0..n {
            let a = 2 * i;
            idx.push([a, a + 2, a + 1]);
            idx.push([a + 1, a + 2, a + 3]);
        }
        TriangleMesh::new(pos, idx)
    }

    #[test]
    fn batches_keep_ray_order_across_chunks() {
        let mesh = strip(64);
        let bvh = Bvh::build(&mesh, &BvhParams::default()).unwrap();
        // More than two chunks, so a chunk-order mistake would show.
        let rays: Vec<Ray> = (0..3 * BATCH_CHUNK + 17)
            .map(|i| {
                let x = (i % 70) as f32 - 2.5;
                Ray::new(Vec3::new(x, 0.3, 1.0), Vec3::new(0.0, 0.0, -1.0))
            })
            .collect();
        let hits = bvh.intersect_batch(&rays);
        let occ = bvh.occluded_batch(&rays);
        for (i, r) in rays.iter().enumerate() {
            assert!(hits[i].same_as(&bvh.intersect(r)), "ray {i}");
            assert_eq!(
                (hits[i].u.to_bits(), hits[i].v.to_bits()),
                (bvh.intersect(r).u.to_bits(), bvh.intersect(r).v.to_bits())
            );
            assert_eq!(occ[i], bvh.occluded(r), "ray {i}");
        }
        assert!(hits.iter().any(|h| h.is_hit()) && hits.iter().any(|h| !h.is_hit()));
        // Through a trait object too (the CLI holds a `Box<dyn Accel>`).
        let boxed: Box<dyn Accel> = Box::new(Brute::build(&mesh).unwrap());
        let bh = boxed.intersect_batch(&rays);
        assert!(bh.iter().zip(&hits).all(|(a, b)| a.same_as(b)));
    }

    #[test]
    #[should_panic(expected = "3 rays but room for 2 answers")]
    fn mismatched_lengths_panic_with_both() {
        let mesh = strip(1);
        let brute = Brute::build(&mesh).unwrap();
        let rays = [Ray::new(Vec3::ZERO, Vec3::X); 3];
        brute.intersect_into(&rays, &mut [Hit::MISS; 2]);
    }
}
