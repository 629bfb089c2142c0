//! The side-by-side competitors (feature `compare`) trace the bunny's four ray sets and
//! agree with brute force on at least 99.9 % of the checked rays, per competitor and kind.
#![cfg(feature = "compare")]

use dynray_accel::{AccelKind, BatchQuery, Brute};
use dynray_bench::compare;
use dynray_bench::measure::oracle;
use dynray_bench::{rays, scenes, AccelSpec, RayKind};

/// Rays per kind checked against brute force: enough that 99.9 % allows a handful of
/// disagreements (edge and tie cases of their triangle tests), few enough for a test.
const CHECKED: usize = 4000;

#[test]
fn every_competitor_agrees_with_brute_force_on_the_bunny() {
    let dir = scenes::scenes_dir(None);
    let (name, path) = scenes::resolve("bunny", dir.as_deref()).expect("the bunny (set DYNRAY_SCENES)");
    let sc = scenes::load(&name, &path).expect("bunny loads");
    let mesh = &sc.frame.mesh;
    let bvh = AccelSpec::new(AccelKind::Bvh).build(mesh, None).expect("bvh builds");
    let sets = rays::generate(&sc.frame, 160, 120, &RayKind::ALL, bvh.as_ref());
    let brute = Brute::build(mesh).expect("brute builds");
    let expected = oracle(&brute, &sets, Some(CHECKED));

    let mut notes = Vec::new();
    let results = compare::measure_scene(&name, mesh, &sets, &expected, 1, &[], &mut notes, &|_| {})
        .expect("every competitor builds");
    assert!(notes.is_empty(), "competitors left out: {notes:?}");
    let names: Vec<String> = results.iter().map(|c| format!("{} {}", c.name, c.variant)).collect();
    for want in ["embree single-ray", "obvhs cwbvh", "obvhs bvh2"] {
        assert!(names.iter().any(|n| n == want), "{want} missing from {names:?}");
    }
    for c in &results {
        assert!(c.build_ms > 0.0 && c.memory_bytes.is_some_and(|b| b > 0), "{} {}: {c:?}", c.name, c.variant);
        let want_kinds = if c.variant == "packet8" { 1 } else { 4 };
        assert_eq!(c.kinds.len(), want_kinds, "{} {}", c.name, c.variant);
        for k in &c.kinds {
            let (set_kind, rays) = sets.sets.iter().find(|(kk, _)| kk.name() == k.kind).unwrap();
            assert_eq!(k.rays, rays.len());
            eprintln!(
                "{} {} {}: {} / {} same, {} same hit/miss, max rel dt {:e}",
                c.name, c.variant, k.kind, k.same_answer, k.checked, k.same_hit_or_miss, k.max_rel_t_diff
            );
            assert_eq!(k.checked, CHECKED.min(rays.len()), "{} {} {}", c.name, c.variant, k.kind);
            assert!(
                k.agreement >= 0.999,
                "{} {} {}: {} of {} agree with brute force",
                c.name,
                c.variant,
                k.kind,
                k.same_answer,
                k.checked
            );
            // Same triangle means nearly the same distance, whatever their triangle test.
            assert!(k.max_rel_t_diff < 1e-3, "{} {} {}: max rel Δt {}", c.name, c.variant, k.kind, k.max_rel_t_diff);
            // The timed pass counts hits on every ray: it must match brute force's rate
            // on the sample within the sample's disagreements and sampling noise.
            let e = expected.iter().find(|e| e.kind == *set_kind).unwrap();
            let want_rate = if set_kind.is_shadow() {
                e.occluded.iter().filter(|o| **o).count() as f64 / e.indices.len() as f64
            } else {
                e.hits.iter().filter(|h| h.is_hit()).count() as f64 / e.indices.len() as f64
            };
            let got_rate = k.hits as f64 / k.rays as f64;
            assert!(
                (got_rate - want_rate).abs() < 0.05,
                "{} {} {}: hit rate {got_rate} vs {want_rate}",
                c.name,
                c.variant,
                k.kind
            );
        }
    }
}

#[test]
fn a_broken_answer_is_seen_as_disagreement() {
    // The agreement measure itself: a "library" that always misses must not pass.
    struct AlwaysMiss;
    impl BatchQuery for AlwaysMiss {
        fn intersect_into(&self, _rays: &[dynray_geom::Ray], hits: &mut [dynray_geom::Hit]) {
            hits.fill(dynray_geom::Hit::MISS);
        }
        fn occluded_into(&self, _rays: &[dynray_geom::Ray], out: &mut [bool]) {
            out.fill(false);
        }
    }
    let dir = scenes::scenes_dir(None);
    let (name, path) = scenes::resolve("bunny", dir.as_deref()).expect("the bunny (set DYNRAY_SCENES)");
    let sc = scenes::load(&name, &path).expect("bunny loads");
    let bvh = AccelSpec::new(AccelKind::Bvh).build(&sc.frame.mesh, None).expect("bvh builds");
    let sets = rays::generate(&sc.frame, 64, 48, &[RayKind::Primary], bvh.as_ref());
    let expected = oracle(bvh.as_ref(), &sets, None);
    for (e, (_, rays)) in expected.iter().zip(&sets.sets) {
        let a = compare::agreement(&AlwaysMiss, rays, e);
        let hits = e.hits.iter().filter(|h| h.is_hit()).count();
        assert!(hits > 0, "{:?}: the bunny must be hit", e.kind);
        assert_eq!(a.checked, rays.len());
        assert_eq!(a.same_answer, rays.len() - hits, "{:?}", e.kind);
        assert!(a.fraction() < 0.999);
    }
}

/// `embree packet8`'s speed ratio compares with our packet path, `embree single-ray`'s
/// primary ratio with our single rays: each names the entry it used.
#[test]
fn packet8_is_compared_with_our_packets_and_single_rays_with_our_single_rays() {
    use dynray_bench::measure::{measure, MeasureInput};
    let dir = scenes::scenes_dir(None);
    let (name, path) = scenes::resolve("bunny", dir.as_deref()).expect("the bunny (set DYNRAY_SCENES)");
    let sc = scenes::load(&name, &path).expect("bunny loads");
    let mesh = &sc.frame.mesh;
    let wide = AccelSpec::new(AccelKind::Bvh);
    let reference = wide.build(mesh, None).expect("bvh builds");
    let sets = rays::generate(&sc.frame, 160, 120, &[RayKind::Primary], reference.as_ref());
    let brute = Brute::build(mesh).expect("brute builds");
    let expected = oracle(&brute, &sets, Some(CHECKED));
    let input = MeasureInput {
        scene: &name,
        frame: &sc.frame,
        sets: &sets,
        expected: &expected,
        repeat: 1,
        width: 160,
        height: 120,
        time_to_image: false,
    };
    let mut mismatches = Vec::new();
    let (mut ours, _) = measure(&wide, &input, &mut mismatches, &|_| {}).expect("bvh measures");
    assert!(mismatches.is_empty(), "{mismatches:?}");
    let packets = ours.primary_packets.clone().expect("the wide BVH is measured in packets");
    // The ratios are taken against the structure named `compare::OURS`.
    ours.accel = compare::OURS.to_string();
    let mut notes = Vec::new();
    let results = compare::measure_scene(&name, mesh, &sets, &expected, 1, &[ours.clone()], &mut notes, &|_| {})
        .expect("every competitor builds");
    let row = |variant: &str| {
        let c = results.iter().find(|c| c.name == "embree" && c.variant == variant).expect(variant);
        c.kinds.iter().find(|k| k.kind == "primary").expect("primary").clone()
    };
    let (p8, single) = (row("packet8"), row("single-ray"));
    assert_eq!(p8.ours_kind.as_deref(), Some("primary-packet"));
    assert_eq!(p8.ours_over_theirs_speed, Some(packets.mrays_per_s / p8.mrays_per_s));
    assert_eq!(single.ours_kind.as_deref(), Some("primary"));
    assert_eq!(single.ours_over_theirs_speed, Some(ours.kinds[0].mrays_per_s / single.mrays_per_s));
}
