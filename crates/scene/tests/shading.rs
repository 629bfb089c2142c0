//! The shading policy of the loaders (`shading.rs`): files without normals are smoothed
//! for rendering, files with normals keep them, `load_mesh` and `load_file_unshaded`
//! return the files' vertices as they are, and the triangles' positions never change.

mod support;

use dynray_geom::{TriangleMesh, Vec3};
use dynray_scene::formats::ply;
use dynray_scene::{load_file, load_file_unshaded, load_mesh, NormalSource, Scene, Shading, DEFAULT_CREASE_DEG};
use support::*;

/// Every triangle of `a` and `b` has the same three positions, bit for bit, in order.
#[track_caller]
fn assert_same_triangles(a: &TriangleMesh, b: &TriangleMesh) {
    assert_eq!(a.triangle_count(), b.triangle_count());
    for (t, (ta, tb)) in a.indices.iter().zip(&b.indices).enumerate() {
        for k in 0..3 {
            let (pa, pb) = (a.positions[ta[k] as usize], b.positions[tb[k] as usize]);
            assert_eq!(pa.map(f32::to_bits), pb.map(f32::to_bits), "triangle {t} corner {k}");
        }
    }
}

fn sources(s: &Scene) -> Vec<NormalSource> {
    s.actors.iter().map(|a| a.normal_source).collect()
}

#[test]
fn the_bunny_is_smoothed_for_rendering_and_load_mesh_keeps_the_file() {
    let Some(p) = model("bunny/bun_zipper.ply") else { return };
    let file = ply::load(&p).unwrap();
    let raw = load_mesh(&p).unwrap();
    assert_eq!(raw, file, "load_mesh returns the file's vertices unchanged");
    assert_eq!(raw.vertex_count(), 35_947);
    assert!(raw.normals.is_none());

    let scene = load_file(&p).unwrap();
    let a = &scene.actors[0];
    assert_eq!(a.shading, Shading::Auto);
    let NormalSource::Generated { crease_deg, split_vertices } = a.normal_source else {
        panic!("{:?}", a.normal_source)
    };
    assert_eq!(crease_deg, DEFAULT_CREASE_DEG);
    // A scan: nearly every vertex keeps one normal; the splits are where it folds.
    assert!(split_vertices > 0 && split_vertices < 1000, "{split_vertices}");
    let frame = scene.frame(0.0);
    assert_eq!(frame.mesh.vertex_count(), 35_947 + split_vertices);
    assert_same_triangles(&frame.mesh, &raw);
    let normals = frame.mesh.normals.as_ref().unwrap();
    // Unit everywhere a triangle uses (the scan's unused vertices keep a zero normal).
    for t in &frame.mesh.indices {
        for &v in t {
            let len = Vec3::from_array(normals[v as usize]).length();
            assert!((len - 1.0).abs() < 1e-5, "vertex {v}: |n| = {len}");
        }
    }
    // Shading normals face the same side as their triangles: with a crease below 90°
    // every face a corner averages is within 90° of the corner's own.
    for t in 0..frame.mesh.triangle_count() {
        let tri = frame.mesh.triangle(t);
        let ng = (tri.p1 - tri.p0).cross(tri.p2 - tri.p0);
        for &v in &frame.mesh.indices[t] {
            assert!(Vec3::from_array(normals[v as usize]).dot(ng) > 0.0, "triangle {t} vertex {v}");
        }
    }

    // The unshaded load is the file's, and applying the shading gives `load_file`'s.
    let mut unshaded = load_file_unshaded(&p).unwrap().scene;
    assert_eq!(unshaded.actors[0].mesh, file);
    assert_eq!(unshaded.actors[0].normal_source, NormalSource::Geometric);
    unshaded.apply_shading().unwrap();
    assert_eq!(unshaded, scene);
}

#[test]
fn a_cornell_box_keeps_its_right_angles_hard() {
    let Some(p) = model("cornell-box/mcguire-obj/CornellBox-Original.obj") else { return };
    let scene = load_file(&p).unwrap();
    assert!(sources(&scene).iter().all(|s| matches!(s, NormalSource::Generated { crease_deg: 60.0, .. })));
    let mesh = scene.frame(0.0).mesh;
    let normals = mesh.normals.as_ref().unwrap();
    let mut worst = 0.0f32;
    for t in 0..mesh.triangle_count() {
        let tri = mesh.triangle(t);
        let ng = (tri.p1 - tri.p0).cross(tri.p2 - tri.p0).normalize();
        for &v in &mesh.indices[t] {
            let n = Vec3::from_array(normals[v as usize]);
            worst = worst.max(n.cross(ng).length().atan2(n.dot(ng)).to_degrees());
        }
    }
    // The walls are slightly warped quads (the file says so), smoothed within
    // themselves (0.41° at worst); a 90° edge smoothed would put corners 45° off.
    assert!(worst < 1.0, "a corner normal is {worst}° from its face");
    assert_same_triangles(&mesh, &load_mesh(&p).unwrap());
}

#[test]
fn normals_in_files_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    // PLY with nx ny nz: a fold whose file normals all point up.
    let header = format!(
        "element vertex 4\n{XYZ}property float nx\nproperty float ny\nproperty float nz\n\
         element face 2\nproperty list uchar int vertex_indices\n"
    );
    let v = |x, y, z| [vtx(x, y, z), vtx(0.0, 1.0, 0.0)].concat();
    let rows = vec![
        v(0.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(0.0, 1.0, 0.0),
        v(0.0, 0.0, 1.0),
        face(&[0, 1, 2]),
        face(&[0, 3, 1]),
    ];
    let p = write(dir.path(), "n.ply", &ply(Enc::Ascii, &header, &rows));
    let s = load_file(&p).unwrap();
    assert_eq!(sources(&s), [NormalSource::FromSource]);
    assert_eq!(s.actors[0].mesh, load_mesh(&p).unwrap());
    assert_eq!(s.actors[0].mesh.normals, Some(vec![[0.0, 1.0, 0.0]; 4]));

    // OBJ: with `vn` kept, without smoothed.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 1 0\n";
    let with = write(dir.path(), "with.obj", format!("{obj}f 1//1 2//1 3//1\nf 1//1 4//1 2//1\n").as_bytes());
    let without = write(dir.path(), "without.obj", format!("{obj}f 1 2 3\nf 1 4 2\n").as_bytes());
    assert_eq!(sources(&load_file(&with).unwrap()), [NormalSource::FromSource]);
    let s = load_file(&without).unwrap();
    assert_eq!(sources(&s), [NormalSource::Generated { crease_deg: 60.0, split_vertices: 2 }]);
    assert_same_triangles(&s.frame(0.0).mesh, &load_mesh(&without).unwrap());
    assert!(load_mesh(&without).unwrap().normals.is_none());

    // glTF: a primitive without NORMAL is smoothed (one triangle: its own normal).
    let g = gltf_triangle(dir.path(), "t.gltf", 3, "", "");
    let s = load_file(&g).unwrap();
    assert_eq!(sources(&s), [NormalSource::Generated { crease_deg: 60.0, split_vertices: 0 }]);
    assert_eq!(s.actors[0].mesh.normals, Some(vec![[0.0, 0.0, 1.0]; 3]));
    assert!(load_mesh(&g).unwrap().normals.is_none());
}

#[test]
fn seam_copies_of_a_uv_mapped_obj_smooth_across_the_seam() {
    // A strip of two quads bent 20° along x = 1, where the texture seam duplicates the
    // vertices (same positions, different uvs): the copies must get one normal.
    let dir = tempfile::tempdir().unwrap();
    let (c, s) = (20f32.to_radians().cos(), 20f32.to_radians().sin());
    let obj = format!(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv {x} 0 {z}\nv {x} 1 {z}\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0\nvt 0.5 1\nvt 0 0.5\nvt 0 0.6\n\
         f 1/1 2/2 3/3 4/4\nf 2/7 5/5 6/6 3/8\n",
        x = 1.0 + c,
        z = -s
    );
    let p = write(dir.path(), "seam.obj", obj.as_bytes());
    let raw = load_mesh(&p).unwrap();
    assert_eq!(raw.vertex_count(), 8, "tobj keeps one vertex per (position, uv): the seam is doubled");
    let scene = load_file(&p).unwrap();
    let m = scene.frame(0.0).mesh;
    assert_eq!(m.vertex_count(), 8, "nothing to split at 20°");
    let n = m.normals.as_ref().unwrap();
    let at = |x: f32, y: f32| -> Vec<[u32; 3]> {
        (0..m.vertex_count()).filter(|&v| m.positions[v] == [x, y, 0.0]).map(|v| n[v].map(f32::to_bits)).collect()
    };
    for y in [0.0, 1.0] {
        let copies = at(1.0, y);
        assert_eq!(copies.len(), 2, "two copies of (1, {y})");
        assert_eq!(copies[0], copies[1], "the seam copies of (1, {y}) share one normal");
        // Halfway between the two quads' normals.
        let want = Vec3::new(10f32.to_radians().sin(), 0.0, 10f32.to_radians().cos());
        let got = Vec3::from_array(n[(0..8).find(|&v| m.positions[v] == [1.0, y, 0.0]).unwrap()]);
        assert!((got - want).length() < 1e-5, "{got} != {want}");
    }
    assert_same_triangles(&m, &raw);
}
