//! End-to-end tests of the `dynray` binary: real files in, real files out, and every
//! bad-input path giving one clear message, a non-zero exit and no partial output.

mod support;

use npyz::WriterBuilder;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn dynray(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dynray")).args(args).output().expect("run dynray")
}

fn scenes() -> PathBuf {
    std::env::var("DYNRAY_SCENES")
        .map(PathBuf::from)
        .unwrap_or_else(|_| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes"))
}

fn bunny() -> String {
    scenes().join("bunny/bun_zipper.ply").to_string_lossy().into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Fails with the output shown when the command failed.
fn ok(o: Output) -> Output {
    assert!(o.status.success(), "dynray failed: {}\n{}", o.status, stderr(&o));
    o
}

/// Asserts a clean failure: exit 1, one `dynray:` message mentioning `needle`, no panic.
fn fails_with(o: Output, needle: &str) {
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "expected exit 1, got {:?}: {err}", o.status);
    assert!(err.starts_with("dynray: "), "message should start with `dynray: `: {err}");
    assert!(err.contains(needle), "message should mention {needle:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

fn read_npz<T: npyz::Deserialize>(path: &Path, name: &str) -> Vec<T> {
    let mut npz = npyz::npz::NpzArchive::open(path).unwrap();
    npz.by_name(name).unwrap().unwrap_or_else(|| panic!("no array {name}")).into_vec().unwrap()
}

fn bunny_rays() -> Vec<[f32; 8]> {
    // A fan of rays from in front of the bunny towards its box, plus misses and clipped ones.
    let mut rows = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            let x = -0.1 + 0.2 * i as f32 / 39.0;
            let y = 0.03 + 0.16 * j as f32 / 39.0;
            rows.push([x, y, 1.0, 0.0, 0.0, -1.0, 0.0, f32::INFINITY]);
        }
    }
    rows.push([0.0, 0.1, 1.0, 0.0, 1.0, 0.0, 0.0, f32::INFINITY]); // misses upwards
    rows.push([-0.02, 0.1, 1.0, 0.0, 0.0, -1.0, 0.0, 0.5]); // clipped before the bunny
    rows
}

#[test]
fn trace_rays_matches_between_structures_and_brute_and_writes_npz() {
    let dir = tempfile::tempdir().unwrap();
    let rays = dir.path().join("rays.npy");
    support::write_rays_npy(&rays, &bunny_rays());
    let mut results = Vec::new();
    for accel in ["brute", "bvh", "bih:max_prims=5", "octree:high_quality"] {
        let out = dir.path().join(format!("{}.npz", accel.replace(':', "_")));
        ok(dynray(&[
            "trace-rays",
            &bunny(),
            "--rays",
            rays.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--accel",
            accel,
        ]));
        let t: Vec<f32> = read_npz(&out, "t");
        let prim: Vec<i64> = read_npz(&out, "prim");
        let u: Vec<f32> = read_npz(&out, "u");
        let v: Vec<f32> = read_npz(&out, "v");
        assert_eq!((t.len(), prim.len(), u.len(), v.len()), (1602, 1602, 1602, 1602));
        let hits = prim.iter().filter(|&&p| p >= 0).count();
        assert!(hits > 400, "only {hits} hits");
        assert!(prim[1600] == -1 && t[1600] == f32::INFINITY, "upward ray should miss");
        assert!(prim[1601] == -1, "clipped ray should miss");
        assert!(prim.iter().all(|&p| (-1..69_451).contains(&p)));
        results.push((t.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), prim));
    }
    for (i, name) in ["bvh", "bih:max_prims=5", "octree:high_quality"].iter().enumerate() {
        assert_eq!(results[0], results[i + 1], "{name} and brute disagree");
    }
}

#[test]
fn trace_rays_occluded_agrees_with_hits() {
    let dir = tempfile::tempdir().unwrap();
    let rays = dir.path().join("rays.npy");
    support::write_rays_npy(&rays, &bunny_rays());
    let hits = dir.path().join("h.npz");
    let occ = dir.path().join("o.npz");
    let r = rays.to_str().unwrap();
    ok(dynray(&["trace-rays", &bunny(), "--rays", r, "-o", hits.to_str().unwrap()]));
    ok(dynray(&["trace-rays", &bunny(), "--rays", r, "-o", occ.to_str().unwrap(), "--occluded"]));
    let prim: Vec<i64> = read_npz(&hits, "prim");
    let o: Vec<bool> = read_npz(&occ, "occluded");
    assert_eq!(prim.iter().map(|&p| p >= 0).collect::<Vec<_>>(), o);
}

#[test]
fn info_reports_counts_and_structure() {
    let o = ok(dynray(&["info", &bunny()]));
    let out = String::from_utf8_lossy(&o.stdout);
    for needle in ["triangles   69,451", "vertices    35,947", "structure   bvh", "memory", "max depth", "SAH cost"] {
        assert!(out.contains(needle), "missing {needle:?} in:\n{out}");
    }
}

/// A mesh read from a scene file warns through the scene, once, and the command still
/// succeeds (it renders with the default material).
#[test]
fn scene_mesh_warnings_are_printed_once() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tri.obj"), "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let scn = dir.path().join("a.scn");
    std::fs::write(&scn, "mesh { file \"tri.obj\" }\nmesh { file \"tri.obj\" }\n").unwrap();
    let o = ok(dynray(&["info", scn.to_str().unwrap()]));
    let err = stderr(&o);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("gone.mtl")).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].starts_with("dynray: warning: ") && lines[0].contains("tri.obj:1:"), "{err}");
}

#[test]
fn missing_file_is_a_clean_error() {
    fails_with(dynray(&["info", "/nonexistent/model.ply"]), "/nonexistent/model.ply");
}

#[test]
fn unknown_extension_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("model.xyz");
    std::fs::write(&p, "1 2 3\n").unwrap();
    fails_with(dynray(&["info", p.to_str().unwrap()]), "model.xyz");
}

#[test]
fn truncated_ply_names_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cut.ply");
    std::fs::write(&p, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n").unwrap();
    fails_with(dynray(&["info", p.to_str().unwrap()]), "cut.ply");
}

#[test]
fn malformed_npy_is_a_clean_error_and_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let rays = dir.path().join("bad.npy");
    std::fs::write(&rays, b"\x93NUMPY garbage").unwrap();
    let out = dir.path().join("hits.npz");
    fails_with(
        dynray(&["trace-rays", &bunny(), "--rays", rays.to_str().unwrap(), "-o", out.to_str().unwrap()]),
        "bad.npy",
    );
    assert!(!out.exists());
}

#[test]
fn wrong_ray_shape_is_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let rays = dir.path().join("six.npy");
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[2, 6])
        .writer(std::fs::File::create(&rays).unwrap())
        .begin_nd()
        .unwrap();
    w.extend([0.0f32; 12]).unwrap();
    w.finish().unwrap();
    let out = dir.path().join("hits.npz");
    fails_with(
        dynray(&["trace-rays", &bunny(), "--rays", rays.to_str().unwrap(), "-o", out.to_str().unwrap()]),
        "(N, 8)",
    );
}

/// A `.npy` whose header claims `shape` (any numbers) over a few bytes of data.
fn lying_npy(shape: &str, fortran: bool) -> Vec<u8> {
    let order = if fortran { "True" } else { "False" };
    let mut dict = format!("{{'descr': '<f4', 'fortran_order': {order}, 'shape': {shape}, }}");
    while (10 + dict.len() + 1) % 64 != 0 {
        dict.push(' ');
    }
    dict.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((dict.len() as u16).to_le_bytes());
    bytes.extend(dict.as_bytes());
    bytes.extend([0u8; 64]);
    bytes
}

/// Regression (issue 43): a ray file whose header promises more rows than the file
/// holds — 2^60 rows, whose byte count passes 2^64, in C and Fortran order, or a billion
/// rows over 64 bytes — is a clean error naming the file before anything is allocated
/// for it (not a wrapped size, an index out of bounds or an 8 GiB allocation).
#[test]
fn ray_files_promising_more_rows_than_they_hold_are_clean_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("hits.npz");
    for (i, (shape, fortran)) in
        [("(1152921504606846976, 8)", true), ("(1152921504606846976, 8)", false), ("(1000000000, 8)", false)]
            .into_iter()
            .enumerate()
    {
        let rays = dir.path().join(format!("lying{i}.npy"));
        std::fs::write(&rays, lying_npy(shape, fortran)).unwrap();
        let o = dynray(&["trace-rays", &bunny(), "--rays", rays.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert!(stderr(&o).contains("promises"), "{}", stderr(&o));
        fails_with(o, &format!("lying{i}.npy"));
        assert!(!out.exists());
    }
}

/// Regression (issue 43): a header whose shape's element count passes 2^64 (npyz
/// multiplies it out while parsing the header) is the same clean error, not an overflow
/// panic in a debug build.
#[test]
fn ray_files_whose_shape_product_overflows_are_clean_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("hits.npz");
    for (i, (shape, want)) in [
        ("(4294967296, 4294967296, 8)", "(N, 8)"),
        ("(4294967296, 4294967296)", "(N, 8)"),
        ("(18446744073709551615, 8)", "promises"),
    ]
    .into_iter()
    .enumerate()
    {
        let rays = dir.path().join(format!("huge{i}.npy"));
        std::fs::write(&rays, lying_npy(shape, false)).unwrap();
        let o = dynray(&["trace-rays", &bunny(), "--rays", rays.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert!(!stderr(&o).contains("panicked"), "{shape}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{shape}: {}", stderr(&o));
        fails_with(o, &format!("huge{i}.npy"));
        assert!(!out.exists());
    }
}

#[test]
fn nan_ray_is_rejected_with_its_row() {
    let dir = tempfile::tempdir().unwrap();
    let rays = dir.path().join("nan.npy");
    support::write_rays_npy(&rays, &[[0.0; 8], [f32::NAN, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]]);
    let out = dir.path().join("hits.npz");
    fails_with(
        dynray(&["trace-rays", &bunny(), "--rays", rays.to_str().unwrap(), "-o", out.to_str().unwrap()]),
        "ray 1",
    );
}

#[test]
fn unwritable_output_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let rays = dir.path().join("rays.npy");
    support::write_rays_npy(&rays, &bunny_rays());
    fails_with(
        dynray(&["trace-rays", &bunny(), "--rays", rays.to_str().unwrap(), "-o", "/nonexistent-dir/hits.npz"]),
        "/nonexistent-dir/hits.npz",
    );
}

#[test]
fn unknown_structure_is_a_usage_error() {
    let o = dynray(&["info", &bunny(), "--accel", "nope"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("unknown structure"), "{}", stderr(&o));
}

#[test]
fn info_lists_every_structure_from_the_descriptor_table() {
    let o = dynray(&["info", "--structures"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    let names: Vec<&str> = text.lines().skip(1).filter_map(|l| l.split_whitespace().next()).collect();
    let want: Vec<&str> = dynray_accel::AccelKind::ALL.iter().map(|k| k.name()).collect();
    assert_eq!(names, want, "{text}");
    // The columns say what the structures do: the BVHs refit and run on the GPU, the kd-tree neither.
    let row = |name: &str| text.lines().find(|l| l.split_whitespace().next() == Some(name)).unwrap().to_string();
    assert!(row("bvh2").contains("refit") && row("bvh2").split_whitespace().nth(2) == Some("yes"), "{text}");
    assert!(row("kdtree").contains("rebuild") && row("kdtree").split_whitespace().nth(2) == Some("no"), "{text}");
}

/// Regression (issue 43): `--min-weight=-1` (or 2, or NaN) was accepted.
#[test]
fn min_weight_outside_zero_to_one_is_refused() {
    for w in ["-1", "2", "NaN"] {
        let out = std::env::temp_dir().join("dynray-min-weight-never-written.png");
        let o = dynray(&["render", &format!("--min-weight={w}"), "-o", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "a usage error: {}", stderr(&o));
        assert!(stderr(&o).contains("--min-weight must be a weight in 0..=1"), "{}", stderr(&o));
        assert!(!out.exists());
    }
}

#[test]
fn closed_stdout_pipe_exits_quietly() {
    // `dynray info bunny | head -1`: the reader goes away before dynray writes.
    let mut child = Command::new(env!("CARGO_BIN_EXE_dynray"))
        .args(["info", &bunny()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run dynray");
    drop(child.stdout.take());
    let o = child.wait_with_output().expect("wait for dynray");
    let err = stderr(&o);
    assert!(o.status.success(), "exit {:?}: {err}", o.status);
    assert!(err.is_empty(), "a closed pipe should print nothing: {err}");
}

#[test]
fn errors_print_each_cause_once() {
    let dir = tempfile::tempdir().unwrap();
    let fake = dir.path().join("dir.ply");
    std::fs::create_dir(&fake).unwrap();
    let o = dynray(&["info", fake.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("dir.ply"), "{err}");
    // Refused as a directory before any read (crates/geom/src/file.rs), said once.
    let cause = "not a regular file (a directory)";
    assert_eq!(err.matches(cause).count(), 1, "the cause is missing or repeated: {err}");
}

#[test]
fn accel_parameters_reach_the_structure_and_bad_keys_are_usage_errors() {
    let o = dynray(&["info", &bunny(), "--accel", "bih:max_prims=5"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.lines().any(|l| l.split_whitespace().collect::<Vec<_>>() == ["max_prims", "5"]), "{out}");
    let o = dynray(&["info", &bunny(), "--accel", "bih:leaf=4"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("--accel") && e.contains("bih: unknown parameter `leaf` (known: preset, max_prims"), "{e}");
}

#[test]
fn bad_flag_values_are_usage_errors_and_help_shows_the_real_defaults() {
    for args in [
        &["bench", "--accels", "foo"][..],
        &["bench", "--repeat", "0"],
        &["bench", "--width", "0"],
        &["render", "--width", "0"],
        &["render", "--height", "16385"],
    ] {
        let o = dynray(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
    }
    let help = String::from_utf8_lossy(&dynray(&["bench", "--help"]).stdout).into_owned();
    let config = dynray_bench::BenchConfig::new(false);
    assert!(help.contains(&format!("(default {}; --quick 1)", config.repeat)), "{help}");
    for name in dynray_bench::scenes::KNOWN_SCENES.iter().map(|(n, _)| *n).chain(["demo"]) {
        assert!(help.contains(name), "--scenes help omits {name}: {help}");
    }
}

/// Writes `rows` as an (N, 8) .npy of f64, in C or Fortran order.
fn write_npy_f64(path: &Path, rows: &[[f32; 8]], fortran: bool) {
    let n = rows.len();
    let order = if fortran { npyz::Order::Fortran } else { npyz::Order::C };
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[n as u64, 8])
        .order(order)
        .writer(std::fs::File::create(path).unwrap())
        .begin_nd()
        .unwrap();
    // Fortran order stores column after column.
    let values: Vec<f64> = if fortran {
        (0..8).flat_map(|j| rows.iter().map(move |r| r[j] as f64)).collect()
    } else {
        rows.iter().flat_map(|r| r.map(|x| x as f64)).collect()
    };
    w.extend(values).unwrap();
    w.finish().unwrap();
}

#[test]
fn float64_and_fortran_order_rays_are_converted_and_give_the_same_hits() {
    let dir = tempfile::tempdir().unwrap();
    let rows = bunny_rays();
    let run = |rays: &Path, name: &str| {
        let out = dir.path().join(format!("{name}.npz"));
        let o = ok(dynray(&["trace-rays", &bunny(), "--rays", rays.to_str().unwrap(), "-o", out.to_str().unwrap()]));
        let t: Vec<u32> = read_npz::<f32>(&out, "t").iter().map(|x| x.to_bits()).collect();
        (t, read_npz::<i64>(&out, "prim"), stderr(&o))
    };
    let plain = dir.path().join("f32.npy");
    support::write_rays_npy(&plain, &rows);
    let (t, prim, note) = run(&plain, "f32");
    assert!(!note.contains("note"), "{note}");
    for (fortran, what) in [(false, "float64"), (true, "float64 in Fortran order")] {
        let wide = dir.path().join(format!("f64-{fortran}.npy"));
        write_npy_f64(&wide, &rows, fortran);
        let (t2, prim2, note) = run(&wide, &format!("f64-{fortran}"));
        assert!(note.contains(&format!("rays given as {what}, converted")), "{note}");
        assert_eq!((&t2, &prim2), (&t, &prim), "{what} rays give other hits");
    }
}

#[test]
fn trace_rays_output_must_be_an_npz_file() {
    let dir = tempfile::tempdir().unwrap();
    let rays = dir.path().join("rays.npy");
    support::write_rays_npy(&rays, &bunny_rays());
    for (out, needle) in [("-", "not a stream"), ("hits.npy", "name the output *.npz")] {
        let o = dynray(&["trace-rays", &bunny(), "--rays", rays.to_str().unwrap(), "-o", out]);
        fails_with(o, needle);
        assert!(!Path::new(out).exists() || out == "-", "{out} was written");
    }
}

#[test]
fn fields_add_normals_and_points_of_the_hits() {
    let dir = tempfile::tempdir().unwrap();
    let rays_path = dir.path().join("rays.npy");
    let rows = bunny_rays();
    support::write_rays_npy(&rays_path, &rows);
    let out = dir.path().join("hits.npz");
    let args = ["trace-rays", &bunny(), "--rays", rays_path.to_str().unwrap(), "-o", out.to_str().unwrap()];
    ok(dynray(&[&args[..], &["--fields", "prim,u,v,normal,point"]].concat()));
    let mut npz = npyz::npz::NpzArchive::open(&out).unwrap();
    let mut names: Vec<String> = npz.array_names().map(String::from).collect();
    names.sort();
    assert_eq!(names, ["normal", "point", "prim", "u", "v"], "only the asked arrays");
    let shape = npz.by_name("point").unwrap().unwrap().shape().to_vec();
    assert_eq!(shape, [rows.len() as u64, 3]);
    let (prim, u, v): (Vec<i64>, Vec<f32>, Vec<f32>) =
        (read_npz(&out, "prim"), read_npz(&out, "u"), read_npz(&out, "v"));
    let (normal, point): (Vec<f32>, Vec<f32>) = (read_npz(&out, "normal"), read_npz(&out, "point"));
    let mesh = dynray_scene::load_file(Path::new(&bunny())).unwrap().frame(0.0).mesh;
    let mut hits = 0;
    for (i, r) in rows.iter().enumerate() {
        let (n, p) = (&normal[i * 3..i * 3 + 3], &point[i * 3..i * 3 + 3]);
        if prim[i] < 0 {
            assert!(n.iter().chain(p).all(|x| x.is_nan()), "ray {i}: a miss has NaN normal and point");
            continue;
        }
        hits += 1;
        let tri = mesh.triangle(prim[i] as usize);
        let want = tri.p0 * (1.0 - u[i] - v[i]) + tri.p1 * u[i] + tri.p2 * v[i];
        assert_eq!(p, want.to_array(), "ray {i}: point is the barycentric hit point");
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-5, "ray {i}: |normal| = {len}");
        // The point lies on the ray, up to f32 rounding.
        let o = dynray_geom::Vec3::new(r[0], r[1], r[2]);
        let d = dynray_geom::Vec3::new(r[3], r[4], r[5]);
        let on_ray = (0..3).map(|k| o[k] + d[k] * ((want - o).dot(d) / d.dot(d))).collect::<Vec<f32>>();
        let off = (0..3).map(|k| (on_ray[k] - p[k]).abs()).fold(0.0f32, f32::max);
        assert!(off < 1e-4, "ray {i}: point {p:?} is {off} off the ray");
    }
    assert!(hits > 400, "{hits}");
    let o = dynray(&[&args[..], &["--fields", "t", "--occluded"]].concat());
    assert_eq!(o.status.code(), Some(2), "--fields with --occluded: {}", stderr(&o));
}

/// `--backend gpu` writes the same archive as the CPU, bit for bit (where the adapter has
/// 64-bit floats and passes its self-check; docs/gpu.md), refuses structures other than
/// bvh, and `info --gpu` reports the self-check. Skips without an adapter unless
/// `DYNRAY_REQUIRE_GPU=1` (CI).
#[test]
fn trace_rays_on_the_gpu_writes_the_cpus_hits() {
    if !support::gpu_present() {
        return;
    }
    let info = dynray(&["info", "--gpu"]);
    let out = String::from_utf8_lossy(&info.stdout).to_string();
    assert!(out.contains("self-check"), "{out}");
    let dir = tempfile::tempdir().unwrap();
    let rays = dir.path().join("rays.npy");
    support::write_rays_npy(&rays, &bunny_rays());
    let r = rays.to_str().unwrap();
    let (cpu, gpu) = (dir.path().join("cpu.npz"), dir.path().join("gpu.npz"));
    ok(dynray(&["trace-rays", &bunny(), "--rays", r, "-o", cpu.to_str().unwrap()]));
    // The tree built on the CPU and uploaded, then by each device builder.
    for build in ["cpu", "sah", "lbvh"] {
        let o = dynray(&[
            "trace-rays",
            &bunny(),
            "--rays",
            r,
            "-o",
            gpu.to_str().unwrap(),
            "--backend",
            "gpu",
            "--gpu-build",
            build,
        ]);
        ok(o.clone());
        if build != "cpu" {
            assert!(stderr(&o).contains(&format!("{build} build")), "{build}: {}", stderr(&o));
        }
        if out.contains("f64 kernels") && out.contains("every hit equals") {
            for f in ["t", "u", "v"] {
                let (a, b): (Vec<f32>, Vec<f32>) = (read_npz(&cpu, f), read_npz(&gpu, f));
                assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()), "{build}: {f} differs");
            }
            assert_eq!(read_npz::<i64>(&cpu, "prim"), read_npz::<i64>(&gpu, "prim"), "{build}");
        }
    }
    let o = dynray(&["trace-rays", &bunny(), "--rays", r, "-o", gpu.to_str().unwrap(), "--gpu-build", "lbvh"]);
    assert_eq!(o.status.code(), Some(1), "--gpu-build without --backend gpu");
    assert!(stderr(&o).contains("add --backend gpu"), "{}", stderr(&o));
    fails_with(
        dynray(&[
            "trace-rays",
            &bunny(),
            "--rays",
            r,
            "-o",
            gpu.to_str().unwrap(),
            "--backend",
            "gpu",
            "--accel",
            "bih",
        ]),
        "the GPU backend traverses a BVH only",
    );
}

/// Regression (issue 43): inputs that are not regular files — a device behind a mesh's
/// name, a named pipe, an include that is a device — are refused at once with what they
/// are, instead of hanging on the pipe or reading /dev/zero without end.
#[cfg(unix)]
#[test]
fn devices_and_pipes_are_refused_not_read() {
    let dir = tempfile::tempdir().unwrap();
    let zero = dir.path().join("zero.ply");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let npz = dir.path().join("zero.npz");
    std::os::unix::fs::symlink("/dev/zero", &npz).unwrap();
    let fifo = dir.path().join("pipe.obj");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let scene = dir.path().join("inc.scn");
    std::fs::write(&scene, "include \"zero.ply.scn\"\n").unwrap();
    std::os::unix::fs::symlink("/dev/zero", dir.path().join("zero.ply.scn")).unwrap();
    for (path, what) in [(&zero, "a device"), (&npz, "a device"), (&fifo, "a named pipe"), (&scene, "a device")] {
        let o = dynray(&["info", path.to_str().unwrap()]);
        assert!(stderr(&o).contains(what), "{}: {}", path.display(), stderr(&o));
        fails_with(o, "not a regular file");
    }
}

/// Issue 48: `--threads 0` is a usage error (exit 2, clap's message), not a run-time one.
#[test]
fn zero_threads_is_a_usage_error() {
    let o = dynray(&["--threads", "0", "info", &bunny()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--threads"), "{}", stderr(&o));
    let o = dynray(&["--threads", "1", "info", &bunny()]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Issue 43: a model's references stay inside its folder tree — a glTF buffer, a Mitsuba
/// include, an AFF include naming `../secret` are refused with the rule, and the secret
/// is never quoted; `--allow-outside-references` lifts the rule.
#[test]
fn model_references_stay_in_the_model_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    std::fs::create_dir(d.join("model")).unwrap();
    std::fs::write(d.join("secret.txt"), "TOP-SECRET-LINE\n").unwrap();
    let gltf = d.join("model/m.gltf");
    std::fs::write(&gltf, r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"../secret.txt","byteLength":4}]}"#).unwrap();
    let xml = d.join("model/m.xml");
    std::fs::write(&xml, r#"<scene version="3.0.0"><include filename="../secret.txt"/></scene>"#).unwrap();
    let aff = d.join("model/m.aff");
    std::fs::write(&aff, "i 0 ../secret.txt\n").unwrap();
    for model in [&gltf, &xml, &aff] {
        let o = dynray(&["info", model.to_str().unwrap()]);
        let err = stderr(&o);
        assert!(!err.contains("TOP-SECRET"), "{}: quoted the secret: {err}", model.display());
        fails_with(o, "the folder of the model that names it");
        // Allowed: the file is read (and is no glTF buffer, XML or AFF worth loading).
        let o = dynray(&["--allow-outside-references", "info", model.to_str().unwrap()]);
        assert!(!stderr(&o).contains("the folder of the model"), "{}: {}", model.display(), stderr(&o));
    }
}

/// Issue 43: a `.scn` may include any file (it is the user's own composition), but an
/// error inside an included file that is not a `.scn` gives its place only, never its
/// lines or words.
#[test]
fn an_included_file_that_is_not_a_scene_is_not_quoted() {
    let tmp = tempfile::tempdir().unwrap();
    let secret = tmp.path().join("passwd");
    std::fs::write(&secret, "root:TOP-SECRET:0:0:root:/root:/bin/bash\n").unwrap();
    let scene = tmp.path().join("s.scn");
    std::fs::write(&scene, format!("include \"{}\"\n", secret.display())).unwrap();
    let o = dynray(&["info", scene.to_str().unwrap()]);
    assert!(!stderr(&o).contains("TOP-SECRET") && !stderr(&o).contains("root:"), "{}", stderr(&o));
    fails_with(o, "is not quoted");
    // A `.scn` include keeps its full diagnostic.
    let inc = tmp.path().join("bad.scn");
    std::fs::write(&inc, "sphere { center <0, 0, 0> radius oops }\n").unwrap();
    std::fs::write(&scene, "include \"bad.scn\"\n").unwrap();
    let o = dynray(&["info", scene.to_str().unwrap()]);
    assert!(stderr(&o).contains("radius oops"), "the source line is shown: {}", stderr(&o));
}
