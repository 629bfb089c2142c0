//! The memory budget (crates/geom/src/budget.rs; issue 43): an excessive request is
//! refused up front, saying what was asked and what the limit is, and a request within
//! the budget runs. `DYNRAY_MEMORY_LIMIT` stands in for a small machine.

mod support;

use std::process::{Command, Output};
use support::{fails_with, ok};

fn dynray_with_limit(limit: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dynray")).env("DYNRAY_MEMORY_LIMIT", limit).args(args).output().unwrap()
}

#[test]
fn an_image_over_the_budget_is_refused_before_rendering() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("big.png");
    let o = out.to_str().unwrap();
    // 4096² pixels × 48 bytes = 768 MiB, over a 64 MiB budget.
    let refused = dynray_with_limit("64M", &["render", "-o", o, "--width", "4096", "--height", "4096", "--spp", "1"]);
    fails_with(refused, "a 4096 × 4096 image needs about 768.0 MiB, more than the memory budget of 64.0 MiB");
    assert!(!out.exists());
    ok(dynray_with_limit("64M", &["render", "-o", o, "--width", "64", "--height", "48", "--spp", "1"]));
}

#[test]
fn spheres_over_the_budget_are_refused_before_tessellation() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("spheres.scn");
    let spheres: String = (0..50).map(|i| format!("sphere {{ center <{i}, 0, 0> radius 0.4 }}\n")).collect();
    let light = "light { position <0, 10, 10> }";
    std::fs::write(&scene, format!("settings {{ sphere_detail 1024 }}\n{light}\n{spheres}")).unwrap();
    let out = tmp.path().join("x.png");
    let args = ["info", scene.to_str().unwrap()];
    // 50 spheres × 1,048,576 triangles × 160 bytes ≈ 7.8 GiB.
    fails_with(dynray_with_limit("1G", &args), "50 spheres of 1048576 triangles each (sphere_detail 1024)");
    assert!(!out.exists());
    let few = tmp.path().join("few.scn");
    std::fs::write(&few, format!("settings {{ sphere_detail 64 }}\n{light}\nsphere {{ center <0, 0, 0> radius 1 }}\n"))
        .unwrap();
    ok(dynray_with_limit("1G", &["info", few.to_str().unwrap()]));
}
