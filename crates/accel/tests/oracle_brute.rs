//! The oracle checks itself: any-hit and closest-hit agree, and the ray sets really
//! exercise hits and misses.

mod support;

use dynray_accel::{BatchQuery, Brute};
use support::*;

#[test]
fn brute_occluded_agrees_with_closest_hit_on_bunny() {
    let mesh = bunny();
    let rays = random_rays(&mesh, 4_000, 7);
    let hits = brute_hits(&mesh, &rays);
    let brute = Brute::build(&mesh).unwrap();
    let occ = brute.occluded_batch(&rays);
    for (i, (h, o)) in hits.iter().zip(&occ).enumerate() {
        assert_eq!(h.is_hit(), *o, "ray {i}: {:?}", rays[i]);
    }
    let n_hit = hits.iter().filter(|h| h.is_hit()).count();
    // The mix must contain plenty of both, or the oracle tests would prove little.
    assert!(n_hit > rays.len() / 5 && n_hit < rays.len() * 4 / 5, "{n_hit} hits of {}", rays.len());
}

/// Computes (or loads) the shared oracle answers of a standard set and checks that brute
/// force's any-hit agrees with them; other structures' tests then reuse the cache.
fn check_standard_set(label: &str, mesh: &dynray_geom::TriangleMesh, rays: &[dynray_geom::Ray]) {
    let hits = brute_hits(mesh, rays);
    let n_hit = hits.iter().filter(|h| h.is_hit()).count();
    assert!(n_hit > rays.len() / 5, "{label}: only {n_hit} hits");
    // Spot-check any-hit on a slice (all rays would double the oracle's cost).
    let brute = Brute::build(mesh).unwrap();
    let occ = brute.occluded_batch(&rays[..2_000]);
    for i in 0..2_000 {
        assert_eq!(hits[i].is_hit(), occ[i], "{label} ray {i}");
    }
}

#[test]
fn standard_bunny_set_is_consistent() {
    let mesh = bunny();
    check_standard_set("bunny", &mesh, &bunny_rays(&mesh));
}

#[test]
fn standard_dragon_set_is_consistent() {
    let mesh = dragon_res2();
    check_standard_set("dragon_res2", &mesh, &dragon_rays(&mesh));
}
