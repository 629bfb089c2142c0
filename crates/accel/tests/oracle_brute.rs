//! The oracle checks itself: any-hit and closest-hit agree, and the ray sets really
//! exercise hits and misses.

mod support;

use dynray_accel::{occluded_batch, Brute};
use support::*;

#[test]
fn brute_occluded_agrees_with_closest_hit_on_bunny() {
    let mesh = bunny();
    let rays = random_rays(&mesh, 4_000, 7);
    let hits = brute_hits(&mesh, &rays);
    let brute = Brute::build(&mesh).unwrap();
    let occ = occluded_batch(&brute, &rays);
    for (i, (h, o)) in hits.iter().zip(&occ).enumerate() {
        assert_eq!(h.is_hit(), *o, "ray {i}: {:?}", rays[i]);
    }
    let n_hit = hits.iter().filter(|h| h.is_hit()).count();
    // The mix must contain plenty of both, or the oracle tests would prove little.
    assert!(n_hit > rays.len() / 5 && n_hit < rays.len() * 4 / 5, "{n_hit} hits of {}", rays.len());
}
