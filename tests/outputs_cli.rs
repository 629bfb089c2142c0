//! Outputs never destroy inputs and never leave temporaries (issue 43): an output path
//! that names a file the command read is refused, whatever its spelling, and SIGTERM or
//! SIGINT in the middle of writing an output removes the temporary
//! (crates/geom/src/file/atomic.rs, src/interrupt.rs).

mod support;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use support::{dynray, fails_with, ok, write_rays_npy};

/// A one-triangle OBJ whose material's diffuse map is `tex.png`, in `dir`.
fn textured_triangle(dir: &Path) {
    std::fs::write(dir.join("tri.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd tex.png\n").unwrap();
    let obj = "mtllib tri.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0.5 1\nusemtl m\nf 1/1 2/2 3/3\n";
    std::fs::write(dir.join("tri.obj"), obj).unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb([200, 30, 30])).save(dir.join("tex.png")).unwrap();
}

fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

#[test]
fn an_output_naming_an_input_is_refused_and_the_input_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    textured_triangle(d);
    let texture = std::fs::read(d.join("tex.png")).unwrap();
    // The scene's own texture, spelled through a detour.
    std::fs::create_dir(d.join("sub")).unwrap();
    let detour = d.join("sub/../tex.png");
    let size = ["--width", "16", "--height", "12", "--spp", "1"];
    let o =
        dynray(&[&["render", d.join("tri.obj").to_str().unwrap(), "-o", detour.to_str().unwrap()][..], &size].concat());
    fails_with(o, "one of the inputs");
    assert_eq!(std::fs::read(d.join("tex.png")).unwrap(), texture, "the texture was replaced");
    // Another output of the same render is fine.
    ok(dynray(
        &[&["render", d.join("tri.obj").to_str().unwrap(), "-o", d.join("out.png").to_str().unwrap()][..], &size]
            .concat(),
    ));

    // trace-rays over an .npz mesh, told to write its hits over that mesh.
    let mesh = d.join("mesh.npz");
    let verts: Vec<f32> = vec![-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 0.0, 1.0, 0.0];
    write_npz_mesh(&mesh, &verts, &[0, 1, 2]);
    let before = std::fs::read(&mesh).unwrap();
    let rays = d.join("rays.npy");
    write_rays_npy(&rays, &[[0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, f32::INFINITY]]);
    let o =
        dynray(&["trace-rays", mesh.to_str().unwrap(), "--rays", rays.to_str().unwrap(), "-o", mesh.to_str().unwrap()]);
    fails_with(o, "one of the inputs");
    assert_eq!(std::fs::read(&mesh).unwrap(), before, "the mesh was replaced");

    // animate --export-meshes into the folder of an input named as its first mesh.
    let anim = d.join("anim");
    std::fs::create_dir(&anim).unwrap();
    let input = anim.join("mesh_0000.obj");
    std::fs::copy(d.join("tri.obj"), &input).unwrap();
    let before = std::fs::read(&input).unwrap();
    let o = dynray(&[
        "animate",
        input.to_str().unwrap(),
        "--out",
        anim.to_str().unwrap(),
        "--export-meshes",
        "--width",
        "16",
        "--height",
        "12",
        "--spp",
        "1",
    ]);
    fails_with(o, "one of the inputs");
    assert_eq!(std::fs::read(&input).unwrap(), before, "the input mesh was replaced");
    for dir in [d, anim.as_path()] {
        assert_eq!(temporaries(dir), Vec::<String>::new());
    }
}

fn write_npz_mesh(path: &Path, vertices: &[f32], faces: &[i64]) {
    let mut npz = npyz::npz::NpzWriter::create(path).unwrap();
    write_rows3(&mut npz, "vertices", vertices);
    write_rows3(&mut npz, "faces", faces);
}

/// `values` as an (N, 3) array `name` of `npz`.
fn write_rows3<T: npyz::AutoSerialize + Copy, W: std::io::Write + std::io::Seek>(
    npz: &mut npyz::npz::NpzWriter<W>,
    name: &str,
    values: &[T],
) {
    use npyz::WriterBuilder;
    let mut w = npz
        .array::<T>(name, Default::default())
        .unwrap()
        .default_dtype()
        .shape(&[values.len() as u64 / 3, 3])
        .begin_nd()
        .unwrap();
    w.extend(values.iter().copied()).unwrap();
    w.finish().unwrap();
}

/// SIGTERM and SIGINT while trace-rays writes a large archive: the process exits with
/// 128 + the signal, and neither the temporary nor a partial archive is left.
#[cfg(unix)]
#[test]
fn a_signal_during_a_write_leaves_no_temporary() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    textured_triangle(d);
    // Four million rays that cannot hit (tmin > tmax): reading them is quick, tracing
    // instant, and writing 64 MB of hits takes long enough to be caught in the act.
    let rays = d.join("rays.npy");
    write_rays_npy(&rays, &vec![[0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 1.0, 0.0]; 4_000_000]);
    for (signal, code) in [("TERM", 143), ("INT", 130)] {
        let out = d.join(format!("hits-{signal}.npz"));
        let mut caught = false;
        for _attempt in 0..3 {
            let mut child = Command::new(env!("CARGO_BIN_EXE_dynray"))
                .args(["trace-rays", d.join("tri.obj").to_str().unwrap(), "--rays", rays.to_str().unwrap()])
                .args(["-o", out.to_str().unwrap()])
                .stderr(Stdio::null())
                .spawn()
                .unwrap();
            let start = Instant::now();
            // Wait for the temporary to appear, then signal.
            while start.elapsed() < Duration::from_secs(60) {
                if !temporaries(d).is_empty() {
                    let killed = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status();
                    caught = killed.is_ok_and(|s| s.success());
                    break;
                }
                if child.try_wait().unwrap().is_some() {
                    break;
                }
                std::thread::sleep(Duration::from_micros(200));
            }
            let status = child.wait().unwrap();
            assert_eq!(temporaries(d), Vec::<String>::new(), "SIG{signal} left a temporary");
            // The signal may have come just after the rename (the archive is then whole):
            // that run proves nothing, so start again, as when the poll missed the write.
            if caught && !out.exists() {
                assert_eq!(status.code(), Some(code), "SIG{signal}: {status:?}");
                break;
            }
            caught = false;
            let _ = std::fs::remove_file(&out);
        }
        assert!(caught, "SIG{signal}: never caught trace-rays writing");
    }
}
