//! Structure parameters as text (`--accel NAME[:key=value,…]`): every structure takes its
//! fields and presets, bad input names the structure, the key and the choices, and the
//! parameters reach the built structure. (Moved from the bench, which now uses AccelSpec.)

use dynray_accel::apit::Observer;
use dynray_accel::{
    AccelKind, AccelSpec, ApitParams, BihParams, BuildError, BvhParams, GridParams, KdTreeParams, OctreeParams,
    StructureParams,
};
use dynray_geom::Vec3;

fn kv(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
    pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect()
}

#[test]
fn every_structure_takes_its_fields_and_presets() {
    assert_eq!(BihParams::from_pairs(&[]).unwrap(), BihParams::default());
    let b = BihParams::from_pairs(&kv(&[("max_prims", "5"), ("preset", "wachter_keller"), ("shrink", "on")])).unwrap();
    assert_eq!(b, BihParams { max_prims: 5, shrink: BihParams::default().shrink, ..BihParams::wachter_keller() });
    let b = BihParams::from_pairs(&kv(&[("shrink", "off"), ("empty_cut", "0.5")])).unwrap();
    assert_eq!((b.shrink, b.empty_cut), (None, Some(0.5)));
    let o = OctreeParams::from_pairs(&kv(&[("balance", "off"), ("max_depth", "6")])).unwrap();
    assert_eq!(o, OctreeParams { balance: false, max_depth: 6, ..OctreeParams::default() });
    let b = BvhParams::from_pairs(&kv(&[("preset", "fast"), ("bins", "32")])).unwrap();
    assert_eq!(b, BvhParams { bins: 32, ..BvhParams::fast() });
    let k = KdTreeParams::from_pairs(&kv(&[("max_depth", "auto"), ("min_prims", "4")])).unwrap();
    assert_eq!(k, KdTreeParams { min_prims: 4, ..KdTreeParams::default() });
    let k = KdTreeParams::from_pairs(&kv(&[("max_depth", "20")])).unwrap();
    assert_eq!(k.max_depth, Some(20));
    let g = GridParams::from_pairs(&kv(&[("density", "3"), ("exact_overlap", "no")])).unwrap();
    assert_eq!(g, GridParams { density: 3.0, exact_overlap: false, ..GridParams::default() });
    let a = ApitParams::from_pairs(&kv(&[("resolution", "32")])).unwrap();
    assert_eq!((a.resolution, a.observer), (32, Observer::Eye));
    let a = ApitParams::from_pairs(&kv(&[("observer", "center")])).unwrap();
    assert_eq!(a.observer, Observer::BoundsCenter);
}

#[test]
fn every_key_is_documented_and_settable_and_every_preset_valid() {
    for &kind in AccelKind::ALL {
        let keys = AccelSpec::keys(kind);
        assert_eq!(keys[0].name, "preset", "{kind}");
        for k in &keys {
            assert!(!k.doc.is_empty(), "{kind}: key {} has no doc", k.name);
        }
        for name in AccelSpec::presets(kind) {
            AccelSpec::with_preset(kind, name).check().unwrap_or_else(|e| panic!("{kind}:{name}: {e}"));
        }
        assert!(AccelSpec::presets(kind).contains(&"default"), "{kind}");
    }
    // A key listed but not settable would be a lie in the error messages: try each with
    // a value of its kind and accept only bad-value or range errors, never unknown-key.
    for &kind in AccelKind::ALL {
        for k in AccelSpec::keys(kind).into_iter().skip(1) {
            for v in ["1", "on", "eye"] {
                let spec = AccelSpec { kind, params: kv(&[(k.name, v)]) };
                if let Err(BuildError::UnknownParam { key, .. }) = spec.check() {
                    panic!("{kind}: listed key {key} is not accepted");
                }
            }
        }
    }
}

#[test]
fn specs_parse_print_and_round_trip() {
    for (text, kind, params) in [
        ("bvh", AccelKind::Bvh, vec![]),
        ("bvh2:bins=8", AccelKind::Bvh2, vec![("bins", "8")]),
        ("bih:max_prims=5", AccelKind::Bih, vec![("max_prims", "5")]),
        ("bih:max_prims=5,shrink=off", AccelKind::Bih, vec![("max_prims", "5"), ("shrink", "off")]),
        ("octree:fast", AccelKind::Octree, vec![("preset", "fast")]),
        (
            "kdtree-ropes:high_quality,min_prims=2",
            AccelKind::KdTreeRopes,
            vec![("preset", "high_quality"), ("min_prims", "2")],
        ),
        ("apit:observer=center", AccelKind::Apit, vec![("observer", "center")]),
    ] {
        let s: AccelSpec = text.parse().unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(s, AccelSpec { kind, params: kv(&params) }, "{text}");
        let back: AccelSpec = s.to_string().parse().unwrap();
        assert_eq!(back, s, "{text} -> {s}");
    }
    assert_eq!("octree:fast".parse::<AccelSpec>().unwrap().to_string(), "octree:preset=fast");
}

#[test]
fn bad_parameters_name_the_structure_key_and_choices() {
    for (text, needle) in [
        ("bih:max_prims=x", "bih: parameter `max_prims=x`: expected a whole number"),
        ("bih:max_prims=0", "bih: invalid parameter max_prims"),
        ("bih:leaf=4", "bih: unknown parameter `leaf` (known: preset, max_prims, max_depth, shrink, empty_cut)"),
        ("bih:preset=turbo", "bih: unknown preset `turbo` (known: default, fast"),
        ("bih:turbo", "bih: unknown preset `turbo`"),
        ("octree:balance=maybe", "expected on or off"),
        ("octree-descent:max_depth=20", "octree-descent: invalid parameter max_depth"),
        ("bvh:bins=1", "bvh: invalid parameter bins"),
        ("grid:density=-1", "grid: invalid parameter density"),
        ("kdtree-ropes:empty_bonus=2", "kdtree-ropes: invalid parameter empty_bonus"),
        ("kdtree:max_depth=deep", "expected a whole number or auto"),
        ("apit:observer=left", "eye or center"),
        ("abuffer:resolution=0", "abuffer: invalid parameter resolution: 0 is outside"),
        ("abuffer:leaf=1", "abuffer: unknown parameter `leaf` (known: preset, resolution"),
        ("brute:x=1", "brute: unknown parameter `x` (known: preset)"),
        ("nope", "unknown structure `nope` (expected one of: brute, bvh"),
        ("bih:max_prims=1,max_prims=2", "given twice"),
        ("bih:max_prims=1,fast", "`fast` is not key=value"),
        ("bih:=3", "empty parameter name"),
    ] {
        let e = text.parse::<AccelSpec>().unwrap_err().to_string();
        assert!(e.contains(needle), "{text}: {e}");
    }
    // Typed variants, for callers that react to them.
    assert!(matches!("bih:leaf=4".parse::<AccelSpec>(), Err(BuildError::UnknownParam { structure: "bih", .. })));
    assert!(matches!("bih:x".parse::<AccelSpec>(), Err(BuildError::UnknownPreset { structure: "bih", .. })));
    assert!(matches!("bih:max_prims=x".parse::<AccelSpec>(), Err(BuildError::BadValue { structure: "bih", .. })));
}

#[test]
fn parameters_reach_the_built_structure() {
    let mesh = dynray_scene::shapes::icosphere(Vec3::ZERO, 1.0, 2);
    let build = |s: &str| s.parse::<AccelSpec>().unwrap().build(&mesh, None).unwrap();
    assert!(build("bih:max_prims=1").stats().leaves > build("bih:max_prims=30").stats().leaves);
    assert!(build("octree").stats().leaves >= build("octree:balance=off").stats().leaves);
    assert!(build("grid:density=4").stats().nodes > build("grid:density=1").stats().nodes);
    // A spec built without parsing is still checked.
    let raw = AccelSpec { kind: AccelKind::Bvh2, params: kv(&[("leaf", "2")]) };
    assert!(matches!(raw.build(&mesh, None), Err(BuildError::UnknownParam { .. })));
}

#[test]
fn the_apit_cube_follows_the_eye_unless_told_center() {
    let mesh = dynray_scene::shapes::icosphere(Vec3::ZERO, 1.0, 2);
    let eye = Vec3::new(0.25, 3.0, -4.0);
    let observer = |s: &str, eye: Option<Vec3>| {
        let a = s.parse::<AccelSpec>().unwrap().build(&mesh, eye).unwrap();
        a.stats().extra.into_iter().find(|(k, _)| k == "observer").map(|(_, v)| v).unwrap()
    };
    assert_eq!(observer("apit", Some(eye)), "(0.25, 3, -4)");
    assert_eq!(observer("abuffer", Some(eye)), "(0.25, 3, -4)");
    let centre = observer("apit", None);
    assert_ne!(centre, "(0.25, 3, -4)");
    assert_eq!(observer("apit:observer=center", Some(eye)), centre);
}
