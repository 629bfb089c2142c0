//! Smoke test of `dynray bench --quick`'s library path on the dragon-res4 at a tiny size:
//! the JSON report is complete and consistent and agrees with brute force.

mod support;

use dynray_bench::{run, BenchConfig};
use support::scenes_dir;

#[test]
fn quick_bench_report_is_complete_and_consistent() {
    let out = tempfile::tempdir().unwrap();
    let mut c = BenchConfig::new(true);
    c.scenes = vec!["dragon-res4".into()];
    c.scenes_dir = Some(scenes_dir());
    c.width = 24;
    c.height = 18;
    c.out = out.path().to_path_buf();
    c.progress = false;
    let report = run(&c).unwrap();
    assert!(report.mismatches.is_empty(), "{:?}", report.mismatches);
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.path().join("report.json")).unwrap()).unwrap();
    let scenes = json["scenes"].as_array().unwrap();
    assert_eq!(scenes.len(), 1);
    let accels = c.accels_or_default();
    let structs = scenes[0]["structures"].as_array().unwrap();
    assert_eq!(structs.len(), accels.len());
    for s in structs {
        assert!(s["build_ms"].as_f64().unwrap().is_finite());
        assert!(s["time_to_image_ms"].as_f64().unwrap() > 0.0);
        let kinds = s["kinds"].as_array().unwrap();
        assert_eq!(kinds.len(), 4);
        for k in kinds {
            assert!(k["mrays_per_s"].as_f64().unwrap() > 0.0, "{k}");
            assert!(k["nodes_per_ray"].as_f64().unwrap().is_finite());
            assert!(k["triangles_per_ray"].as_f64().unwrap().is_finite());
        }
        assert!(out.path().join(s["heatmap"].as_str().unwrap()).is_file());
    }
    assert!(out.path().join("report.md").is_file());
    assert!(out.path().join("mrays.svg").is_file());
}
