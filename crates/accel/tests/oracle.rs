//! The oracle test every structure shares: each kind × each of its presets, built through
//! `AccelSpec` on the bunny (and with its default parameters on the 202k-triangle
//! dragon_res2), validated, then identical closest hits (same triangle, same `t`, `u`, `v`
//! bits) and identical any-hit answers to brute force on the standard random and
//! adversarial ray sets. Structure-specific checks (leaf-size sweeps, refit, ropes,
//! degenerate scenes, thread-count independence) stay in the `oracle_<structure>.rs` files.
//!
//! One `#[test]` per kind, so the harness runs them in parallel and a failure names the
//! structure.

mod support;

use dynray_accel::{Accel, AccelKind, AccelSpec, BuildError};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use support::*;

fn build(spec: &AccelSpec, mesh: &TriangleMesh, label: &str) -> Box<dyn Accel> {
    let a = spec.build(mesh, None).unwrap_or_else(|e| panic!("{spec} on {label}: {e}"));
    let s = a.validate(mesh).unwrap_or_else(|e| panic!("{spec} on {label}: {e}"));
    assert!(s.primitive_refs >= mesh.triangle_count(), "{spec} on {label}: {s:?}");
    a
}

fn check_kind(kind: AccelKind) {
    let mesh = bunny();
    // Brute force is the oracle: tracing the full sets with it again would only repeat
    // the cache's computation (minutes); a sample checks its batch path and any-hit.
    let rays: Vec<Ray> = if kind == AccelKind::Brute { bunny_rays(&mesh)[..4_000].to_vec() } else { bunny_rays(&mesh) };
    let presets = AccelSpec::presets(kind);
    assert!(presets.contains(&"default"), "{kind}: {presets:?}");
    for preset in presets {
        let spec = AccelSpec::with_preset(kind, preset);
        let a = build(&spec, &mesh, "bunny");
        assert_eq!(a.name(), kind.name());
        assert_matches_oracle(a.as_ref(), &mesh, &rays, &format!("bunny ({spec})"));
    }
    if kind != AccelKind::Brute {
        let dragon = dragon_res2();
        let a = build(&AccelSpec::new(kind), &dragon, "dragon_res2");
        assert_matches_oracle(a.as_ref(), &dragon, &dragon_rays(&dragon), "dragon_res2 (default)");
    }
}

macro_rules! oracle_tests {
    ($($test:ident: $kind:ident),* $(,)?) => {
        $(#[test]
        fn $test() {
            check_kind(AccelKind::$kind);
        })*

        /// A kind added to `AccelKind::ALL` without a test here fails this one.
        #[test]
        fn every_kind_has_an_oracle_test() {
            let tested = [$(AccelKind::$kind),*];
            for k in AccelKind::ALL {
                assert!(tested.contains(k), "{k} has no oracle test in oracle.rs");
            }
        }
    };
}

oracle_tests!(
    brute: Brute,
    bvh: Bvh,
    bvh2: Bvh2,
    bih: Bih,
    kdtree: KdTree,
    kdtree_ropes: KdTreeRopes,
    octree: Octree,
    octree_descent: OctreeDescent,
    grid: Grid,
    apit: Apit,
    abuffer: ABuffer,
);

/// Every structure's `update` (a refit where it has one, else a rebuild) follows a mesh
/// whose vertices move, staying exact on the moved mesh, and refuses a mesh with other
/// triangles.
#[test]
fn update_follows_moved_vertices_for_every_kind_and_rejects_new_topology() {
    let mesh = bunny();
    let mut all: Vec<(AccelKind, Box<dyn Accel>)> =
        AccelKind::ALL.iter().map(|&k| (k, build(&AccelSpec::new(k), &mesh, "bunny"))).collect();
    for (step, amp) in [(0u64, 0.01f32), (1, 0.2)] {
        let moved = wave(&mesh, amp, step as f32);
        let mut rays = random_rays(&moved, 4_000, 500 + step);
        rays.extend(adversarial_rays(&moved, 1_000, 600 + step));
        for (kind, a) in &mut all {
            a.update(&moved).unwrap_or_else(|e| panic!("{kind} update: {e}"));
            a.validate(&moved).unwrap_or_else(|e| panic!("{kind} after update: {e}"));
            assert_matches_oracle(a.as_ref(), &moved, &rays, &format!("bunny wave {amp} ({kind} update)"));
        }
    }
    let mut other = mesh.clone();
    other.indices.pop();
    for (kind, a) in &mut all {
        let e = a.update(&other).err();
        assert!(matches!(e, Some(BuildError::TopologyChanged { .. })), "{kind}: {e:?}");
    }
}

/// `update_for_eye` moves the A-PIT's and the A-buffer's cube to the new eye (seed 004
/// centres it on the observer every frame) and stays exact, `observer=center` keeps the
/// cube where it was, and the other structures simply update.
#[test]
fn update_for_eye_recentres_view_dependent_structures_and_stays_exact() {
    let mesh = bunny();
    let b = mesh.bounds();
    let eye0 = b.center() + Vec3::new(0.0, 0.0, 2.0 * b.extent().z);
    let eye1 = b.center() + Vec3::new(1.5 * b.extent().x, 0.3 * b.extent().y, 0.0);
    let observer = |a: &dyn Accel| a.stats().extra.into_iter().find(|(k, _)| k == "observer").map(|(_, v)| v);
    let shown = |p: Vec3| Some(format!("({}, {}, {})", p.x, p.y, p.z));
    let rays = random_rays(&mesh, 6_000, 77);
    for kind in [AccelKind::Apit, AccelKind::ABuffer] {
        let mut a = AccelSpec::with_preset(kind, "fast").build(&mesh, Some(eye0)).unwrap();
        assert_eq!(observer(a.as_ref()), shown(eye0), "{kind}");
        a.update_for_eye(&mesh, eye1).unwrap();
        assert_eq!(observer(a.as_ref()), shown(eye1), "{kind}");
        a.validate(&mesh).unwrap();
        assert_matches_oracle(a.as_ref(), &mesh, &rays, &format!("{kind} after update_for_eye"));
        // A plain update keeps the last eye.
        a.update(&mesh).unwrap();
        assert_eq!(observer(a.as_ref()), shown(eye1), "{kind}");

        let spec: AccelSpec = format!("{kind}:fast,observer=center").parse().unwrap();
        let mut c = spec.build(&mesh, Some(eye0)).unwrap();
        let centre = observer(c.as_ref());
        assert_eq!(centre, shown(b.center()), "{kind}");
        c.update_for_eye(&mesh, eye1).unwrap();
        assert_eq!(observer(c.as_ref()), centre, "{kind}: observer=center must not follow the eye");
    }
    // View-independent structures: the default is a plain update.
    let mut bvh = AccelSpec::new(AccelKind::Bvh).build(&mesh, Some(eye0)).unwrap();
    let before = bvh.stats();
    bvh.update_for_eye(&mesh, eye1).unwrap();
    assert_eq!(bvh.stats().nodes, before.nodes);
    assert_matches_oracle(bvh.as_ref(), &mesh, &rays, "bvh after update_for_eye");
}
