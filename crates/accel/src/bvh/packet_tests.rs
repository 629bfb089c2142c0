//! The packet kernels against the single-ray box test (`Aabb::clip`) and against each
//! other, on adversarial packets: mixed direction signs, zero components, origins on box
//! planes, empty and negative intervals, partial packets.

use super::kernel::Nears;
use super::kernel::Scalar;
use super::node::{Node4, Node8, WideNode};
use super::packet::{lanes, Frustum, Lanes, Packet, PacketKernel, PACKET};
use dynray_geom::{Aabb, PreparedRay, Ray, Vec3};
use rand::{rngs::SmallRng, Rng, SeedableRng};

fn grid(rng: &mut SmallRng) -> Vec3 {
    Vec3::new(rng.gen_range(-3..=3) as f32, rng.gen_range(-3..=3) as f32, rng.gen_range(-3..=3) as f32)
}

/// A node of random boxes on a small integer grid (rays start on their planes and run
/// along them), with `1..=W` children.
fn node<N: WideNode>(rng: &mut SmallRng, i: usize) -> (N, Vec<Aabb>) {
    let mut node = N::empty();
    let mut boxes = Vec::new();
    for _ in 0..(1 + i % N::W) {
        let (a, b) = if i.is_multiple_of(3) {
            let v = |rng: &mut SmallRng| {
                Vec3::new(rng.gen_range(-4.0..4.0), rng.gen_range(-4.0..4.0), rng.gen_range(-4.0..4.0))
            };
            (v(rng), v(rng))
        } else {
            (grid(rng), grid(rng))
        };
        let bx = Aabb::new(a.min(b), a.max(b));
        node.push(boxes.len() as u32, &bx);
        boxes.push(bx);
    }
    (node, boxes)
}

/// 1..=8 rays from one origin: coherent (one direction, perturbed; some components
/// exactly zero or of one sign), grid directions (zero components, mixed signs) or
/// random ones, with intervals that include empty, negative and zero-length ones.
fn packet_rays(rng: &mut SmallRng, i: usize) -> Vec<Ray> {
    let o = if i.is_multiple_of(2) {
        grid(rng)
    } else {
        Vec3::new(rng.gen_range(-5.0..5.0), rng.gen_range(-5.0..5.0), rng.gen_range(-5.0..5.0))
    };
    let n = if i.is_multiple_of(4) { rng.gen_range(1..=PACKET) } else { PACKET };
    let base = Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
    let zero_axis = rng.gen_range(0..6);
    (0..n)
        .map(|_| {
            let mut d = match i % 3 {
                0 => {
                    base + Vec3::new(rng.gen_range(-0.05..0.05), rng.gen_range(-0.05..0.05), rng.gen_range(-0.05..0.05))
                }
                1 => grid(rng),
                _ => Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)),
            };
            if zero_axis < 3 && rng.gen_bool(0.7) {
                d[zero_axis] = if rng.gen_bool(0.5) { 0.0 } else { -0.0 };
            }
            if d == Vec3::ZERO {
                d = Vec3::Y;
            }
            // Every fifth packet starts all lanes at `tmin >= 0`, the case the SIMD tests
            // widen without a sign pick.
            let tmin = if i.is_multiple_of(5) {
                [0.0, 0.5, -0.0][rng.gen_range(0..3)]
            } else {
                [0.0, -1.0, f32::NEG_INFINITY, 0.5, 2.0][rng.gen_range(0..5)]
            };
            let tmax = [f32::INFINITY, 1.0, 3.0, 0.0, 0.25][rng.gen_range(0..5)];
            Ray::with_interval(o, d, tmin, tmax)
        })
        .collect()
}

/// Per-lane limits as traversal holds them: `min(best t, tmax)` for some best `t`.
fn limits(rng: &mut SmallRng, p: &Packet) -> Lanes {
    let mut limit = [f32::NEG_INFINITY; PACKET];
    for l in lanes(p.active) {
        let best = [f32::INFINITY, 2.0, 0.5, 0.0, 4.0][rng.gen_range(0..5)];
        limit[l] = best.min(p.tmax[l]);
    }
    limit
}

type LanesFn<N> = fn(&N, usize, &Packet, &Lanes, u32, &mut Lanes) -> u32;
type FrustumFn<N> = fn(&N, &Frustum, &mut Nears) -> u32;
type OrderedFn<N> = fn(&N, usize, &Packet, &[i32; 3], &Lanes, u32, &mut Lanes) -> u32;

/// Each lane's mask bit and entry distance are `Aabb::clip`'s for that lane's ray (by
/// both lane tests, the ordered one where the frustum is bounded on every axis), and the
/// frustum accepts every child some lane enters.
fn check<N: WideNode>(lane_test: LanesFn<N>, ordered: OrderedFn<N>, frustum: FrustumFn<N>) {
    let mut rng = SmallRng::seed_from_u64(11);
    let (mut entered, mut culled, mut ordered_checks) = (0, 0, 0);
    for i in 0..30_000 {
        let (node, boxes) = node::<N>(&mut rng, i);
        let rays = packet_rays(&mut rng, i);
        let p = Packet::new(&rays);
        assert_eq!(p.active, (1 << rays.len()) - 1, "one origin: every lane travels");
        let limit = limits(&mut rng, &p);
        let f = Frustum::new(&p, &limit);
        let mut fnear = [0.0; 8];
        let fmask = frustum(&node, &f, &mut fnear);
        assert_eq!(fmask >> boxes.len(), 0, "unused children must never be entered");
        for (k, bx) in boxes.iter().enumerate() {
            let mut near = [0.0; PACKET];
            let mask = lane_test(&node, k, &p, &limit, p.active, &mut near);
            let bounded = f.sign.iter().all(|&s| s != 0);
            let (mut near_o, mut mask_o) = ([0.0; PACKET], mask);
            if bounded {
                mask_o = ordered(&node, k, &p, &f.sign, &limit, p.active, &mut near_o);
                ordered_checks += 1;
            }
            for (l, r) in rays.iter().enumerate() {
                let want = bx.clip(&PreparedRay::new(r), r.tmin, limit[l]);
                assert_eq!(mask >> l & 1 == 1, want.is_some(), "box {bx:?} lane {l} ray {r:?} limit {}", limit[l]);
                assert_eq!(mask_o >> l & 1 == 1, want.is_some(), "ordered: box {bx:?} lane {l} ray {r:?}");
                if let Some((n, _)) = want {
                    // Equal as numbers (-0 and +0 may differ; entry distances are only compared).
                    assert_eq!(near[l], n, "box {bx:?} lane {l} ray {r:?}");
                    if bounded {
                        assert_eq!(near_o[l], n, "ordered: box {bx:?} lane {l} ray {r:?}");
                    }
                }
            }
            assert_eq!(mask & !p.active, 0);
            if mask != 0 {
                entered += 1;
                assert!(
                    fmask >> k & 1 == 1,
                    "the frustum rejects box {bx:?} that lanes {mask:#b} enter: {f:?} {rays:?}"
                );
            } else if fmask >> k & 1 == 0 {
                culled += 1;
            }
        }
    }
    // Both outcomes must be common, or the superset check proves little.
    assert!(entered > 10_000 && culled > 10_000, "entered {entered}, culled by the frustum {culled}");
    assert!(ordered_checks > 10_000, "{ordered_checks} boxes through the ordered lane test");
}

#[test]
fn scalar_packet_tests_are_the_single_ray_box_test_and_the_frustum_a_superset() {
    check::<Node4>(Scalar::lanes, Scalar::lanes_ordered, Scalar::frustum);
    check::<Node8>(Scalar::lanes, Scalar::lanes_ordered, Scalar::frustum);
}

#[cfg(target_arch = "x86_64")]
#[test]
fn avx2_packet_tests_are_the_single_ray_box_test_and_the_frustum_a_superset() {
    use super::kernel_avx2::Avx2;
    if !std::arch::is_x86_feature_detected!("avx2") {
        eprintln!("skipped: this CPU has no AVX2");
        return;
    }
    check::<Node4>(Avx2::lanes_checked, Avx2::lanes_ordered_checked, Avx2::frustum_checked);
    check::<Node8>(Avx2::lanes_checked, Avx2::lanes_ordered_checked, Avx2::frustum_checked);
}

/// The same packet, bit for bit (`inv`, intervals, origin; `active`, `nonneg`).
#[cfg(target_arch = "x86_64")]
fn same_packet(a: &Packet, b: &Packet) -> bool {
    let bits = |l: &Lanes| l.map(f32::to_bits);
    a.inv.map(|r| bits(&r)) == b.inv.map(|r| bits(&r))
        && bits(&a.tmin) == bits(&b.tmin)
        && bits(&a.tmax) == bits(&b.tmax)
        && a.org.map(f32::to_bits) == b.org.map(f32::to_bits)
        && (a.active, a.nonneg) == (b.active, b.nonneg)
}

/// The AVX2 packet set-up (an in-register transpose) is `Packet::new`'s, also on lanes
/// that leave the packet (another origin, a NaN anywhere, a non-finite origin).
#[cfg(target_arch = "x86_64")]
#[test]
fn avx2_packet_set_up_is_the_scalar_one() {
    use super::kernel_avx2::Avx2;
    if !std::arch::is_x86_feature_detected!("avx2") {
        eprintln!("skipped: this CPU has no AVX2");
        return;
    }
    let mut rng = SmallRng::seed_from_u64(13);
    let mut partial = 0;
    for i in 0..20_000 {
        let mut rays = packet_rays(&mut rng, i);
        for r in rays.iter_mut().skip(1) {
            match rng.gen_range(0..40) {
                0 => r.origin.y = f32::from_bits(r.origin.y.to_bits() ^ 1),
                1 => r.dir.z = f32::NAN,
                2 => r.tmin = f32::NAN,
                3 => r.tmax = f32::NAN,
                4 => r.origin.x = -r.origin.x,
                5 => r.tmin = -1.0,
                _ => {}
            }
        }
        if i % 97 == 0 {
            rays[0].origin.z = [f32::INFINITY, f32::NAN][i % 2];
        }
        if i % 89 == 0 {
            rays[0].dir.x = f32::NAN;
        }
        let (want, got) = (Packet::new(&rays), Avx2::packet_checked(&rays));
        partial += (want.active != (1 << rays.len()) - 1) as u32;
        assert!(same_packet(&want, &got), "packet {i}: {want:?} against {got:?} for {rays:?}");
        let limit = limits(&mut rng, &want);
        let (f, g) = (Frustum::new(&want, &limit), Avx2::frustum_with_checked(&want, &limit));
        assert_eq!(format!("{f:?}"), format!("{g:?}"), "frustum of packet {i}");
    }
    assert!(partial > 1000, "too few packets with lanes left out: {partial}");
}

/// The AVX2 frustum, `entered` and `max_limit` give the scalar answers.
#[cfg(target_arch = "x86_64")]
#[test]
fn avx2_frustum_and_entered_are_the_scalar_ones() {
    use super::kernel_avx2::Avx2;
    if !std::arch::is_x86_feature_detected!("avx2") {
        eprintln!("skipped: this CPU has no AVX2");
        return;
    }
    fn go<N: WideNode>() {
        let mut rng = SmallRng::seed_from_u64(12);
        for i in 0..20_000 {
            let (node, _) = node::<N>(&mut rng, i);
            let p = Packet::new(&packet_rays(&mut rng, i));
            let limit = limits(&mut rng, &p);
            let f = Frustum::new(&p, &limit);
            let (mut a, mut b) = ([0.0; 8], [0.0; 8]);
            let (ma, mb) = (Scalar::frustum(&node, &f, &mut a), Avx2::frustum_checked(&node, &f, &mut b));
            assert_eq!(ma, mb, "{f:?} {node:?}");
            for k in lanes(ma) {
                assert_eq!(a[k], b[k], "child {k}: {f:?} {node:?}");
            }
            let near: Lanes = std::array::from_fn(|_| [0.0, 1.0, 0.5, f32::INFINITY, -1.0][rng.gen_range(0..5)]);
            let mask = rng.gen_range(0..256u32);
            assert_eq!(Scalar::entered(&near, &limit, mask), Avx2::entered_checked(&near, &limit, mask));
            assert_eq!(Scalar::max_limit(&limit, mask), Avx2::max_limit_checked(&limit, mask), "{limit:?} {mask:#b}");
            let best: [dynray_geom::Hit; PACKET] = std::array::from_fn(|_| dynray_geom::Hit {
                t: [0.5, 1.0, 3.0, f32::INFINITY][rng.gen_range(0..4)],
                ..dynray_geom::Hit::MISS
            });
            let (mut a, mut b) = (limit, limit);
            Scalar::update_limits(&mut a, &best, &p.tmax, mask & p.active);
            Avx2::update_limits_checked(&mut b, &best, &p.tmax, mask & p.active);
            assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "{best:?} {:?} {mask:#b}", p.tmax);
        }
    }
    go::<Node4>();
    go::<Node8>();
}

#[test]
fn only_rays_from_the_first_origin_without_nan_join_the_packet() {
    let o = Vec3::new(1.0, 2.0, 3.0);
    let mut rays = vec![Ray::new(o, Vec3::X); 8];
    rays[2].origin = Vec3::new(1.0, 2.0, 3.0000002);
    rays[3].dir = Vec3::new(f32::NAN, 0.0, 1.0);
    rays[4].tmin = f32::NAN;
    rays[5].tmax = f32::NAN;
    rays[6].origin = Vec3::new(-0.0, 0.0, 0.0);
    assert_eq!(Packet::new(&rays).active, 0b1000_0011);
    // -0 and +0 are different bits: the box test's `lo - org` could differ in sign.
    rays[0].origin = Vec3::ZERO;
    assert_eq!(Packet::new(&rays[..7]).active, 0b0000_0001);
    // A non-finite origin travels alone.
    rays[0].origin = Vec3::new(f32::INFINITY, 0.0, 0.0);
    assert_eq!(Packet::new(&rays).active, 0);
    assert_eq!(Packet::new(&[]).active, 0);
}

/// The frustum of lanes with mixed signs or zero components bounds nothing on that
/// axis, and of coherent lanes the range of their reciprocal directions.
#[test]
fn frustum_bounds_only_axes_of_one_sign() {
    let o = Vec3::ZERO;
    let rays = [
        Ray::new(o, Vec3::new(1.0, 0.0, -1.0)),
        Ray::new(o, Vec3::new(2.0, 1.0, -4.0)),
        Ray::new(o, Vec3::new(4.0, -1.0, -2.0)),
    ];
    let p = Packet::new(&rays);
    let f = Frustum::new(&p, &[1.0, 2.0, 0.5, 9.0, 9.0, 9.0, 9.0, 9.0]);
    assert_eq!(f.sign, [1, 0, -1]);
    assert_eq!((f.inv_min[0], f.inv_max[0]), (0.25, 1.0));
    assert_eq!((f.inv_min[2], f.inv_max[2]), (-1.0, -0.25));
    // Inactive lanes' limits are ignored.
    assert_eq!((f.tmin, f.limit), (0.0, 2.0));
}
