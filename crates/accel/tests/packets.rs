//! 8-ray packets through the wide BVH (`Wbvh::intersect_packet`,
//! `Accel::intersect_coherent_into`) against its single rays, bit for bit (triangle, `t`,
//! `u`, `v`), and any-hit packets (`Wbvh::occluded_packet`,
//! `Accel::occluded_coherent_into`) against single-ray `occluded`,
//! at both widths with every kernel: on the bunny and dragon oracle sets (each
//! group of 8 rays given its first ray's origin, so lanes mix every direction and
//! interval of the set), on camera packets checked against brute force as well, and on
//! adversarial packets (mixed signs, zero components, origins on box planes and on
//! vertices, empty, zero-length and NaN intervals, NaN directions, partial packets).
//!
//! Every kernel this CPU runs is named explicitly (`KernelRequest::runnable`).

mod support;

use dynray_accel::bvh::KernelRequest;
use dynray_accel::{Accel, BatchQuery, Coherent, Wbvh, WbvhParams};
use dynray_geom::{Hit, Ray, TriangleMesh, Vec3};
use rand::{rngs::SmallRng, Rng, SeedableRng};
use support::*;

/// Every width and kernel.
fn variants(mesh: &TriangleMesh) -> Vec<(String, Wbvh)> {
    let mut out = Vec::new();
    for width in [4, 8] {
        for kernel in KernelRequest::runnable() {
            let w = Wbvh::build(mesh, &WbvhParams { width, kernel, ..WbvhParams::default() }).unwrap();
            out.push((format!("width {width}, kernel {}", w.kernel()), w));
        }
    }
    out
}

fn same(a: &Hit, b: &Hit) -> bool {
    a.prim == b.prim
        && a.t.to_bits() == b.t.to_bits()
        && a.u.to_bits() == b.u.to_bits()
        && a.v.to_bits() == b.v.to_bits()
}

/// Traces `rays` in packets of 8 consecutive rays and asserts each answer is the single
/// ray's; returns how many of the packets' answers are hits.
fn check_packets(w: &Wbvh, rays: &[Ray], label: &str) -> usize {
    let mut got = vec![Hit::MISS; rays.len()];
    for (rs, hs) in rays.chunks(8).zip(got.chunks_mut(8)) {
        w.intersect_packet(rs, hs);
    }
    let bad: Vec<usize> = (0..rays.len()).filter(|&i| !same(&got[i], &w.intersect(&rays[i]))).collect();
    let show: Vec<String> = bad
        .iter()
        .take(5)
        .map(|&i| format!("  ray {i} {:?}: packet {:?}, single {:?}", rays[i], got[i], w.intersect(&rays[i])))
        .collect();
    assert!(
        bad.is_empty(),
        "{label}: {} of {} packet answers differ from single rays\n{}",
        bad.len(),
        rays.len(),
        show.join("\n")
    );
    got.iter().filter(|h| h.is_hit()).count()
}

/// Traces `rays` as any-hit packets of 8 consecutive rays and asserts each answer is the
/// single ray's `occluded`; returns how many are occluded.
fn check_occluded_packets(w: &Wbvh, rays: &[Ray], label: &str) -> usize {
    let mut got = vec![false; rays.len()];
    for (rs, os) in rays.chunks(8).zip(got.chunks_mut(8)) {
        w.occluded_packet(rs, os);
    }
    let bad: Vec<usize> = (0..rays.len()).filter(|&i| got[i] != w.occluded(&rays[i])).collect();
    let show: Vec<String> = bad
        .iter()
        .take(5)
        .map(|&i| format!("  ray {i} {:?}: packet {}, single {}", rays[i], got[i], !got[i]))
        .collect();
    assert!(
        bad.is_empty(),
        "{label}: {} of {} any-hit packet answers differ from single rays\n{}",
        bad.len(),
        rays.len(),
        show.join("\n")
    );
    got.iter().filter(|&&o| o).count()
}

/// `rays` (unbounded) with their intervals cut around their closest hits `hits`, in turn:
/// ending exactly at the hit (occluded), one float before it (not: nothing is nearer),
/// at half its distance (not), or left whole. With the brute-force answers of the cut rays.
fn cut_at_hits(rays: &[Ray], hits: &[Hit]) -> (Vec<Ray>, Vec<bool>) {
    let mut cut = rays.to_vec();
    let mut want = Vec::with_capacity(rays.len());
    for (i, (r, h)) in cut.iter_mut().zip(hits).enumerate() {
        assert!(r.tmax == f32::INFINITY, "cut_at_hits takes unbounded rays");
        if h.is_hit() {
            r.tmax = match i % 4 {
                0 => h.t,
                1 => h.t.next_down(),
                2 => h.t * 0.5,
                _ => f32::INFINITY,
            };
        }
        want.push(h.is_hit() && h.t <= r.tmax);
    }
    (cut, want)
}

/// Each group of 8 rays with its first ray's origin: packets whose lanes point anywhere.
fn shared_origins(rays: &[Ray]) -> Vec<Ray> {
    let mut out = rays.to_vec();
    for g in out.chunks_mut(8) {
        let o = g[0].origin;
        g.iter_mut().for_each(|r| r.origin = o);
    }
    out
}

/// Pinhole-camera packets: from eyes around the mesh, 2 × 4 pixel blocks of rays
/// aimed around random points of its box (coherent, one origin per packet).
fn camera_packets(mesh: &TriangleMesh, packets: usize, seed: u64) -> Vec<Ray> {
    let mut rng = SmallRng::seed_from_u64(seed);
    let b = mesh.bounds();
    let diag = b.extent().length();
    let mut rays = Vec::new();
    for _ in 0..packets {
        let dir =
            Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)).normalize_or_zero();
        let eye = b.center() + dir * diag * rng.gen_range(0.3..1.5);
        let target = b.min + (b.max - b.min) * Vec3::new(rng.gen(), rng.gen(), rng.gen());
        let fwd = target - eye;
        let right = fwd.cross(Vec3::Y).normalize_or_zero() * fwd.length() * 1e-3;
        let up = right.cross(fwd).normalize_or_zero() * fwd.length() * 1e-3;
        for k in 0..8 {
            rays.push(Ray::new(eye, fwd + right * (k % 4) as f32 + up * (k / 4) as f32));
        }
    }
    rays
}

fn check_model(mesh: &TriangleMesh, set: &[Ray], cameras: usize, name: &str) {
    let incoherent = shared_origins(set);
    let cams = camera_packets(mesh, cameras, 7);
    // The camera packets against brute force too (cached on disk like the oracle sets).
    let want = brute_hits(mesh, &cams);
    assert!(want.iter().filter(|h| h.is_hit()).count() > cams.len() / 4, "{name}: the camera packets must hit");
    for (label, w) in variants(mesh) {
        let hits = check_packets(&w, &incoherent, &format!("{name} oracle set, shared origins ({label})"));
        assert!(hits > incoherent.len() / 10, "{name}: {hits} hits");
        check_packets(&w, &cams, &format!("{name} camera packets ({label})"));
        let got = Coherent(&w as &dyn Accel).intersect_batch(&cams);
        let bad = (0..cams.len()).filter(|&i| !same(&got[i], &want[i])).count();
        assert_eq!(bad, 0, "{name} camera packets ({label}): {bad} differ from brute force");
        // The oracle set as it is: mostly one origin per ray, so mostly single rays.
        let got = Coherent(&w as &dyn Accel).intersect_batch(set);
        let single = w.intersect_batch(set);
        assert!((0..set.len()).all(|i| same(&got[i], &single[i])), "{name} oracle set, coherent path ({label})");
        // Any-hit packets: the shared-origin set, and the camera packets cut at their
        // hits against brute force through the trait's coherent path.
        let occluded = check_occluded_packets(&w, &incoherent, &format!("{name} oracle set, any hit ({label})"));
        assert!(occluded > incoherent.len() / 10, "{name}: {occluded} occluded");
        let (cut, want_occ) = cut_at_hits(&cams, &want);
        let occluded = check_occluded_packets(&w, &cut, &format!("{name} camera packets cut at hits ({label})"));
        assert!(
            occluded > cut.len() / 8 && occluded < cut.len() * 7 / 8,
            "{name}: {occluded} of {} occluded",
            cut.len()
        );
        let got = Coherent(&w as &dyn Accel).occluded_batch(&cut);
        let bad = (0..cut.len()).filter(|&i| got[i] != want_occ[i]).count();
        assert_eq!(
            bad, 0,
            "{name} camera packets cut at hits ({label}): {bad} any-hit answers differ from brute force"
        );
    }
}

#[test]
fn packets_are_single_rays_on_the_bunny() {
    let mesh = bunny();
    check_model(&mesh, &bunny_rays(&mesh), 4000, "bunny");
}

#[test]
fn packets_are_single_rays_on_the_dragon() {
    let mesh = dragon_res2();
    check_model(&mesh, &dragon_rays(&mesh), 1500, "dragon_res2");
}

/// Packets built to break the packet path: origins on vertices and on the planes of
/// boxes (a grid of unit cubes whose faces line up with the origins), directions of
/// mixed signs and with zero components (±0), lanes with empty (`tmin > tmax`),
/// zero-length and NaN intervals, NaN directions, other origins, partial packets.
#[test]
fn adversarial_packets_are_single_rays() {
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for i in 0..12u32 {
        for j in 0..12u32 {
            for k in 0..3u32 {
                let (x, y, z) = (i as f32, j as f32, k as f32 * 2.0);
                let b = pos.len() as u32;
                pos.extend([[x, y, z], [x + 1.0, y, z], [x, y + 1.0, z], [x + 1.0, y + 1.0, z + (i % 2) as f32]]);
                idx.extend([[b, b + 1, b + 2], [b + 1, b + 3, b + 2]]);
            }
        }
    }
    let mesh = TriangleMesh::new(pos, idx);
    let mut rng = SmallRng::seed_from_u64(9);
    let mut rays = Vec::new();
    let mut sizes = Vec::new();
    for p in 0..6000 {
        let o = match p % 3 {
            0 => Vec3::new(rng.gen_range(0..=12) as f32, rng.gen_range(0..=12) as f32, rng.gen_range(-1..=5) as f32),
            1 => Vec3::from_array(mesh.positions[rng.gen_range(0..mesh.positions.len())]),
            _ => Vec3::new(rng.gen_range(-2.0..14.0), rng.gen_range(-2.0..14.0), rng.gen_range(-3.0..7.0)),
        };
        let base = Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
        let n = if p % 5 == 0 { rng.gen_range(1..8) } else { 8 };
        let packet: Vec<Ray> = (0..n)
            .map(|_| {
                let mut d = match rng.gen_range(0..4) {
                    0 => base + Vec3::new(rng.gen_range(-0.1..0.1), rng.gen_range(-0.1..0.1), rng.gen_range(-0.1..0.1)),
                    1 => Vec3::new(
                        rng.gen_range(-1..=1) as f32,
                        rng.gen_range(-1..=1) as f32,
                        rng.gen_range(-1..=1) as f32,
                    ),
                    2 => Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)),
                    _ => base * if rng.gen() { 1e-18 } else { 1e18 },
                };
                if rng.gen_bool(0.2) {
                    d[rng.gen_range(0..3)] = if rng.gen() { 0.0 } else { -0.0 };
                }
                let (mut tmin, mut tmax) = match rng.gen_range(0..8) {
                    0 => (0.0, 0.0),
                    1 => (2.0, 1.0),
                    2 => (f32::NEG_INFINITY, f32::INFINITY),
                    3 => (0.5, 3.0),
                    4 => (f32::NAN, f32::INFINITY),
                    _ => (0.0, f32::INFINITY),
                };
                if rng.gen_bool(0.02) {
                    tmax = f32::NAN;
                    tmin = 0.0;
                }
                let mut r = Ray::with_interval(o, d, tmin, tmax);
                match rng.gen_range(0..50) {
                    0 => r.dir.y = f32::NAN,
                    1 => r.origin.x += 0.25,
                    _ => {}
                }
                r
            })
            .collect();
        sizes.push(n);
        rays.extend(packet);
    }
    for (label, w) in variants(&mesh) {
        let mut got = vec![Hit::MISS; rays.len()];
        let mut at = 0;
        for &n in &sizes {
            w.intersect_packet(&rays[at..at + n], &mut got[at..at + n]);
            at += n;
        }
        let mut hits = 0;
        for (i, (r, g)) in rays.iter().zip(&got).enumerate() {
            let want = w.intersect(r);
            assert!(same(g, &want), "adversarial ({label}): ray {i} {r:?}: packet {g:?}, single {want:?}");
            hits += g.is_hit() as usize;
        }
        assert!(hits > rays.len() / 5, "{label}: only {hits} of {} hit", rays.len());
        let mut occ = vec![false; rays.len()];
        let mut at = 0;
        for &n in &sizes {
            w.occluded_packet(&rays[at..at + n], &mut occ[at..at + n]);
            at += n;
        }
        for (i, (r, o)) in rays.iter().zip(&occ).enumerate() {
            assert_eq!(*o, w.occluded(r), "adversarial any hit ({label}): ray {i} {r:?}");
        }
    }
    // And against brute force, through the coherent path of the trait (sizes aside).
    let want = brute_hits(&mesh, &rays);
    let w = Wbvh::build(&mesh, &WbvhParams::default()).unwrap();
    let mut got = vec![Hit::MISS; rays.len()];
    w.intersect_coherent_into(&rays, &mut got);
    assert!((0..rays.len()).all(|i| same(&got[i], &want[i])), "coherent path vs brute force");
    let mut occ = vec![false; rays.len()];
    w.occluded_coherent_into(&rays, &mut occ);
    assert!((0..rays.len()).all(|i| occ[i] == w.occluded(&rays[i])), "coherent any-hit path vs single rays");
}

#[test]
fn structures_without_packets_answer_coherent_queries_one_ray_at_a_time() {
    let mesh = bunny();
    let rays = camera_packets(&mesh, 200, 3);
    let bvh = dynray_accel::AccelKind::Bvh2.build(&mesh).unwrap();
    assert!(!bvh.traces_packets());
    let mut got = vec![Hit::MISS; rays.len()];
    bvh.intersect_coherent_into(&rays, &mut got);
    assert!((0..rays.len()).all(|i| same(&got[i], &bvh.intersect(&rays[i]))));
    let mut occ = vec![false; rays.len()];
    bvh.occluded_coherent_into(&rays, &mut occ);
    assert!((0..rays.len()).all(|i| occ[i] == bvh.occluded(&rays[i])));
    assert!(Wbvh::build(&mesh, &WbvhParams::default()).unwrap().traces_packets());
}
