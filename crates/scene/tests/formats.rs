//! Loaders on well-formed input: PLY in every encoding and option, hand-built glTF and
//! OBJ/MTL features, and the real models of `shared/scenes` with their published counts.

mod support;

use dynray_scene::{load_file_unshaded, LightKind, LoadError, LoadReport, Scene};
use support::*;

// These tests check what the format loaders read from the files, so they load without
// applying shading (generated normals and split vertices are `shading.rs`'s, tested in
// tests/shading.rs).
fn load_file(p: &std::path::Path) -> Result<Scene, LoadError> {
    load_file_unshaded(p).map(|r| r.scene)
}

fn load_file_report(p: &std::path::Path) -> Result<LoadReport, LoadError> {
    load_file_unshaded(p)
}

// ---------------------------------------------------------------------------------------
// PLY

#[test]
fn ply_ascii_fans_polygons_of_4_and_5_vertices_in_file_order() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "pent.ply", &ply(Enc::Ascii, &pentagon_header(), &pentagon_rows()));
    let s = load_file(&p).unwrap();
    let m = one_mesh(&s);
    assert_eq!(m.indices, PENTAGON_FAN);
    assert_eq!(m.positions[1], [0.3, 0.95, 0.0]);
    assert_eq!(m.normals, None);
    assert_eq!(s.lights.len(), 1, "a bare mesh gets the default light");
    assert_eq!(s.materials.len(), 1, "and the default material");
    assert_eq!(s.camera, Some(dynray_scene::Camera::default_view(&s)), "and the default view");
}

#[test]
fn ply_binary_little_and_big_endian_and_gzip_read_the_same_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let h = pentagon_header();
    let r = pentagon_rows();
    let ascii = load_file(&write(dir.path(), "a.ply", &ply(Enc::Ascii, &h, &r))).unwrap();
    for (name, bytes) in [
        ("le.ply", ply(Enc::Le, &h, &r)),
        ("be.PLY", ply(Enc::Be, &h, &r)),
        ("a.ply.gz", gzip(&ply(Enc::Ascii, &h, &r))),
        ("be.ply.gz", gzip(&ply(Enc::Be, &h, &r))),
    ] {
        let s = load_file(&write(dir.path(), name, &bytes)).unwrap();
        assert_eq!(one_mesh(&s), one_mesh(&ascii), "{name}");
    }
}

#[test]
fn ply_reads_normals_only_when_all_three_are_present() {
    let dir = tempfile::tempdir().unwrap();
    for enc in [Enc::Ascii, Enc::Le, Enc::Be] {
        let h = format!(
            "element vertex 3\n{XYZ}property float nx\nproperty float ny\nproperty float nz\n\
             element face 1\nproperty list uchar int vertex_indices\n"
        );
        let mut rows: Vec<Vec<V>> = (0..3)
            .map(|i| {
                let mut v = vtx(i as f32, (i * i) as f32, 0.0);
                v.extend([V::F32(0.0), V::F32(0.0), V::F32(1.0)]);
                v
            })
            .collect();
        rows.push(face(&[0, 1, 2]));
        let s = load_file(&write(dir.path(), "n.ply", &ply(enc, &h, &rows))).unwrap();
        assert_eq!(one_mesh(&s).normals, Some(vec![[0.0, 0.0, 1.0]; 3]));

        let h = format!("element vertex 3\n{XYZ}property float nx\nproperty float ny\nelement face 1\nproperty list uchar int vertex_indices\n");
        let rows: Vec<Vec<V>> = (0..3)
            .map(|i| {
                let mut v = vtx(i as f32, (i * i) as f32, 0.0);
                v.extend([V::F32(0.0), V::F32(0.0)]);
                v
            })
            .chain([face(&[0, 1, 2])])
            .collect();
        let s = load_file(&write(dir.path(), "n2.ply", &ply(enc, &h, &rows))).unwrap();
        assert_eq!(one_mesh(&s).normals, None);
        assert_eq!(one_mesh(&s).positions[2], [2.0, 4.0, 0.0]);
    }
}

#[test]
fn ply_skips_extra_properties_and_elements_in_every_encoding() {
    let dir = tempfile::tempdir().unwrap();
    // Extra vertex properties before, between and after x/y/z (including a list), an
    // extra face property and list, and extra elements before, between and after.
    let h = "element material 2\nproperty uchar red\nproperty list uchar float coeffs\n\
             element vertex 3\nproperty double confidence\nproperty float x\nproperty ushort flags\n\
             property float y\nproperty float z\nproperty list uchar int neighbours\n\
             element edge 1\nproperty int vertex1\nproperty int vertex2\n\
             element face 1\nproperty uchar flags\nproperty list uchar int vertex_indices\n\
             property list uchar float texcoord\nproperty int tag\n\
             element junk 0\nproperty int nothing\n";
    let vert = |x: f32, y: f32, z: f32| {
        vec![V::F64(0.5), V::F32(x), V::U16(7), V::F32(y), V::F32(z), V::U8(2), V::I32(9), V::I32(8)]
    };
    let rows = vec![
        vec![V::U8(255), V::U8(2), V::F32(0.25), V::F32(0.5)],
        vec![V::U8(1), V::U8(0)],
        vert(0.0, 0.0, 0.0),
        vert(1.0, 0.0, 0.0),
        vert(0.0, 1.0, 0.0),
        vec![V::I32(0), V::I32(1)],
        vec![V::U8(3), V::U8(3), V::I32(0), V::I32(1), V::I32(2), V::U8(2), V::F32(0.0), V::F32(1.0), V::I32(-5)],
    ];
    for enc in [Enc::Ascii, Enc::Le, Enc::Be] {
        let s = load_file(&write(dir.path(), "extra.ply", &ply(enc, h, &rows))).unwrap();
        let m = one_mesh(&s);
        assert_eq!(m.positions, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        assert_eq!(m.indices, vec![[0, 1, 2]]);
    }
}

#[test]
fn ply_accepts_every_integer_list_type() {
    let dir = tempfile::tempdir().unwrap();
    for (count_ty, item_ty, cnt, items) in [
        ("uchar", "int", V::U8(3), [V::I32(0), V::I32(1), V::I32(2)]),
        ("uint8", "uint32", V::U8(3), [V::U32(0), V::U32(1), V::U32(2)]),
        ("int", "int", V::I32(3), [V::I32(0), V::I32(1), V::I32(2)]),
        ("ushort", "uint", V::U16(3), [V::U32(0), V::U32(1), V::U32(2)]),
        ("uchar", "ushort", V::U8(3), [V::U16(0), V::U16(1), V::U16(2)]),
        ("uchar", "uchar", V::U8(3), [V::U8(0), V::U8(1), V::U8(2)]),
    ] {
        let h = format!("element vertex 3\n{XYZ}element face 1\nproperty list {count_ty} {item_ty} vertex_index\n");
        let mut f = vec![cnt];
        f.extend(items);
        let rows = vec![vtx(0.0, 0.0, 0.0), vtx(1.0, 0.0, 0.0), vtx(0.0, 1.0, 0.0), f];
        for enc in [Enc::Ascii, Enc::Le, Enc::Be] {
            let s = load_file(&write(dir.path(), "l.ply", &ply(enc, &h, &rows))).unwrap();
            assert_eq!(one_mesh(&s).indices, vec![[0, 1, 2]], "list {count_ty} {item_ty}");
        }
    }
}

#[test]
fn ply_face_element_may_come_before_the_vertex_element() {
    let dir = tempfile::tempdir().unwrap();
    let h = format!("element face 2\nproperty list uchar int vertex_indices\nelement vertex 5\n{XYZ}");
    let mut rows = pentagon_rows();
    rows.rotate_right(2);
    for enc in [Enc::Ascii, Enc::Le] {
        let s = load_file(&write(dir.path(), "fv.ply", &ply(enc, &h, &rows))).unwrap();
        assert_eq!(one_mesh(&s).indices, PENTAGON_FAN);
    }
}

#[test]
fn ply_property_less_element_with_an_absurd_count_is_skipped_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let h = format!("element nothing 99999999999\n{}", pentagon_header());
    for enc in [Enc::Ascii, Enc::Le] {
        let s = load_file(&write(dir.path(), "n.ply", &ply(enc, &h, &pentagon_rows()))).unwrap();
        assert_eq!(one_mesh(&s).indices, PENTAGON_FAN);
    }
}

// ---------------------------------------------------------------------------------------
// glTF

#[test]
fn gltf_triangle_with_node_transform_and_material() {
    let dir = tempfile::tempdir().unwrap();
    let mat = r#","materials":[{"name":"glassy","alphaMode":"BLEND","pbrMetallicRoughness":{"baseColorFactor":[1,0.5,0.25,0.25]}}]"#;
    let p = gltf_triangle(dir.path(), "t.gltf", 3, r#","indices":1,"material":0"#, mat);
    let s = load_file(&p).unwrap();
    let m = one_mesh(&s);
    assert_eq!(m.indices, vec![[0, 1, 2]]);
    assert_eq!(m.positions[1], [1.0, 0.0, 5.0], "node translation applied");
    assert_eq!(s.materials[0].name, "glassy");
    assert_eq!(s.materials[0].transparency, glam::Vec3::splat(0.75));
    assert!((s.materials[0].diffuse.y / s.materials[0].diffuse.x - 0.5).abs() < 1e-6);
    assert_eq!(s.lights.len(), 1);
    // Non-indexed reads the positions in order.
    let p = gltf_triangle(dir.path(), "n.gltf", 3, "", "");
    assert_eq!(one_mesh(&load_file(&p).unwrap()).indices, vec![[0, 1, 2]]);
}

#[test]
fn gltf_points_are_skipped_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let p = gltf_triangle(dir.path(), "pts.gltf", 3, r#","mode":0"#, "");
    assert!(error_of(&p).contains("the mesh has no triangles"));
    let mut json = std::fs::read_to_string(&p).unwrap();
    json = json.replace(
        r#"{"attributes":{"POSITION":0},"mode":0}"#,
        r#"{"attributes":{"POSITION":0},"mode":0},{"attributes":{"POSITION":0}}"#,
    );
    let p = write(dir.path(), "mixed.gltf", json.as_bytes());
    let r = load_file_report(&p).unwrap();
    assert_eq!(r.scene.triangle_count(), 1);
    assert_eq!(r.warnings.len(), 1);
    assert!(r.warnings[0].to_string().contains("mixed.gltf: mesh 0 primitive 0: mode Points"), "{}", r.warnings[0]);
}

// ---------------------------------------------------------------------------------------
// OBJ/MTL features

#[test]
fn obj_materials_groups_normals_and_missing_library() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "lib.mtl",
        b"newmtl mirror\nKd 0.1 0.1 0.1\nKs 0.9 0.9 0.9\nNs 200\nillum 3\n\nnewmtl glass\nKd 1 1 1\nd 0.2\nNi 1.5\n",
    );
    let obj = b"mtllib lib.mtl\n\
        v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\n\
        vn 0 0 1\n\
        o first\nusemtl mirror\nf 1//1 2//1 3//1 4//1 5//1\n\
        o second\nusemtl glass\nf 1 2 3\nusemtl nosuch\nf 3 4 5\n";
    let p = write(dir.path(), "m.obj", obj);
    let r = load_file_report(&p).unwrap();
    let s = &r.scene;
    assert_eq!(s.actors.len(), 3);
    assert_eq!(s.actors[0].name.as_deref(), Some("first"));
    assert_eq!(s.actors[0].mesh.triangle_count(), 3, "pentagon fanned into 3");
    assert_eq!(s.actors[0].mesh.normals.as_ref().map(Vec::len), Some(5));
    assert_eq!(s.actors[1].mesh.normals, None);
    let mirror = &s.materials[s.actors[0].materials[0] as usize];
    assert_eq!(mirror.name, "mirror");
    assert_eq!(mirror.specular, glam::Vec3::splat(0.9));
    assert_eq!(mirror.shine, 200.0);
    let glass = &s.materials[s.actors[1].materials[0] as usize];
    assert_eq!(glass.ior, 1.5);
    assert!((glass.transparency.x - 0.8).abs() < 1e-6);
    let fallback = &s.materials[s.actors[2].materials[0] as usize];
    assert_eq!(fallback, &dynray_scene::Material::default());
    assert_eq!(r.warnings.len(), 1);
    assert_eq!(r.warnings[0].line, Some(14));
    assert!(r.warnings[0].message.contains("`nosuch`"));
    // Frame triangle order is file order: first's fan, then second's two faces.
    let f = s.frame(0.0);
    assert_eq!(f.mesh.triangle(0).p2, glam::Vec3::new(1.0, 1.0, 0.0));
    assert_eq!(f.mesh.triangle(4).p0, glam::Vec3::new(1.0, 1.0, 0.0));

    // Without its library: loads with the default material and a warning naming it.
    std::fs::remove_file(dir.path().join("lib.mtl")).unwrap();
    let r = load_file_report(&p).unwrap();
    assert!(r.scene.actors.iter().all(|a| a.materials.iter().all(|&m| m == 0)));
    assert_eq!(r.scene.materials, vec![dynray_scene::Material::default()]);
    assert!(
        r.warnings[0].to_string().starts_with(&format!("{}:1: material library", p.display())),
        "{}",
        r.warnings[0]
    );
    assert!(r.warnings[0].message.contains("lib.mtl"));
}

#[test]
fn obj_emitters_become_point_lights_on_the_side_facing_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "l.mtl", b"newmtl lamp\nKd 1 1 1\nKe 2 2 2\nnewmtl white\nKd 1 1 1\n");
    // Floor 4x4 at y = 0; two 1x1 lamps at y = 2, one wound facing up (away from the
    // floor), one facing down.
    let obj = b"mtllib l.mtl\n\
        v -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\n\
        v -1.5 2 -0.5\nv -0.5 2 -0.5\nv -0.5 2 0.5\nv -1.5 2 0.5\n\
        v 0.5 2 -0.5\nv 0.5 2 0.5\nv 1.5 2 0.5\nv 1.5 2 -0.5\n\
        g floor\nusemtl white\nf 1 2 3 4\n\
        g up\nusemtl lamp\nf 8 7 6 5\n\
        g down\nusemtl lamp\nf 12 11 10 9\n";
    let s = load_file(&write(dir.path(), "lamps.obj", obj)).unwrap();
    assert_eq!(s.lights.len(), 2, "one light per emitting actor, no default light");
    for (light, x) in s.lights.iter().zip([-1.0, 1.0]) {
        let LightKind::Point { position, falloff } = light.kind else { panic!() };
        assert_eq!(falloff, 2);
        assert!((position.x - x).abs() < 1e-6 && position.z.abs() < 1e-6, "{position}");
        assert!(position.y < 2.0 && position.y > 1.99, "below its lamp, towards the floor: {position}");
        assert_eq!(light.color, glam::Vec3::splat(2.0), "Ke x area 1");
        assert!(light.emitter_stand_in, "the path tracer samples the lamp itself");
    }
    // The lamps' material emits (the path tracer's area light), the floor's does not.
    let f = s.frame(0.0);
    let emission: Vec<f32> = f.materials_of.iter().map(|&m| f.materials[m as usize].emission.x).collect();
    assert_eq!(emission, [0.0, 0.0, 2.0, 2.0, 2.0, 2.0]);
}

#[test]
fn obj_tolerates_tabs_weights_and_partly_coloured_vertices() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "t.mtl", b"newmtl\tred one\nKd 1 0 0\n");
    let obj = b"mtllib t.mtl\nv 0 0 0 1 0 0\nv 2 0 0 2\nv\t0\t1\t0\nusemtl\tred one\nf 1 2 3\n";
    let r = load_file_report(&write(dir.path(), "t.obj", obj)).unwrap();
    assert_eq!(r.warnings, vec![]);
    let m = one_mesh(&r.scene);
    assert_eq!(m.positions, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    assert_eq!(r.scene.materials[r.scene.actors[0].materials[0] as usize].name, "red one");
    let p = write(dir.path(), "w.obj", b"v 1e38 0 0 1e-10\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(error_of(&p).contains("w.obj:1: `v`: x y z / w is not finite"));
}

// ---------------------------------------------------------------------------------------
// real models

#[test]
fn bunny_counts() {
    let Some(p) = model("bunny/bun_zipper.ply") else { return };
    let s = load_file(&p).unwrap();
    let m = one_mesh(&s);
    assert_eq!(m.triangle_count(), 69_451);
    assert_eq!(m.vertex_count(), 35_947);
}

#[test]
fn dragon_res4_gz_counts() {
    let Some(p) = model("dragon/dragon_vrip_res4.ply.gz") else { return };
    let s = load_file(&p).unwrap();
    assert_eq!(one_mesh(&s).triangle_count(), 11_102);
}

#[test]
fn cornell_box_obj_matches_a_hand_count() {
    let Some(p) = model("cornell-box/mcguire-obj/CornellBox-Original.obj") else { return };
    let r = load_file_report(&p).unwrap();
    assert_eq!(r.warnings, vec![]);
    let s = r.scene;
    // SOURCE.md: 18 polygons, all quads = 36 triangles.
    assert_eq!(s.triangle_count(), 36);
    // Hand count: 72 `v` lines, of which the boxes' "Bottom" faces reuse the Right (short
    // box) and Front (tall box) faces' vertices, so 8 are never referenced: 64 per-actor
    // vertices (tobj de-duplicates within an actor only).
    assert_eq!(s.actors.iter().map(|a| a.mesh.vertex_count()).sum::<usize>(), 64);
    assert_eq!(s.materials.len(), 8);
    let f = s.frame(0.0);
    let names: Vec<&str> = f.materials_of.iter().map(|&m| f.materials[m as usize].name.as_str()).collect();
    let mut expect = Vec::new();
    for (name, n) in [
        ("floor", 2),
        ("ceiling", 2),
        ("backWall", 2),
        ("rightWall", 2),
        ("leftWall", 2),
        ("shortBox", 12),
        ("tallBox", 12),
        ("light", 2),
    ] {
        expect.extend(std::iter::repeat_n(name, n));
    }
    assert_eq!(names, expect, "triangles follow the file's faces");
    // Face 1 (floor) `f -4 -3 -2 -1` fans into (v1 v2 v3), (v1 v3 v4).
    let v = |x, y, z| glam::Vec3::new(x, y, z);
    assert_eq!(
        f.mesh.triangle(0),
        dynray_geom::Triangle::new(v(-1.01, 0.0, 0.99), v(1.0, 0.0, 0.99), v(1.0, 0.0, -1.04))
    );
    assert_eq!(
        f.mesh.triangle(1),
        dynray_geom::Triangle::new(v(-1.01, 0.0, 0.99), v(1.0, 0.0, -1.04), v(-0.99, 0.0, -1.04))
    );
    // The last face is the light; its `Ke 17 12 4` is one point light just below it.
    assert_eq!(f.mesh.triangle(35).p0.y, 1.98);
    assert_eq!(s.lights.len(), 1);
    let LightKind::Point { position, falloff } = s.lights[0].kind else { panic!("not a point light") };
    assert_eq!(falloff, 2);
    assert!((position.x + 0.005).abs() < 1e-4 && (position.z + 0.03).abs() < 1e-4, "{position}");
    assert!(position.y < 1.98 && position.y > 1.97, "below the lamp, inside the box: {position}");
    let area = 0.47 * 0.38;
    assert!((s.lights[0].color - glam::Vec3::new(17.0, 12.0, 4.0) * area).abs().max_element() < 1e-3);
    assert!(s.lights[0].emitter_stand_in, "Whitted's stand-in: the path tracer samples the lamp itself");
    let light = s.materials.iter().find(|m| m.name == "light").unwrap();
    assert!(light.ambient.x > 1.0, "the lamp's material is ambient-bright");
    assert_eq!(light.emission, glam::Vec3::new(17.0, 12.0, 4.0), "and emits Ke for the path tracer");
    assert!(s.materials.iter().filter(|m| m.name != "light").all(|m| m.emission == glam::Vec3::ZERO));
    let left = s.materials.iter().find(|m| m.name == "leftWall").unwrap();
    assert_eq!(left.diffuse, glam::Vec3::new(0.63, 0.065, 0.05));
    assert_eq!(left.shine, 10.0);
}

#[test]
fn duck_gltf_and_glb_agree() {
    let (Some(a), Some(b)) = (model("Duck/glTF/Duck.gltf"), model("Duck/glTF-Binary/Duck.glb")) else { return };
    let sa = load_file(&a).unwrap();
    let sb = load_file(&b).unwrap();
    for s in [&sa, &sb] {
        let m = one_mesh(s);
        assert_eq!(m.triangle_count(), 4_212);
        assert_eq!(m.vertex_count(), 2_399);
        assert!(m.normals.is_some());
        // The root node scales by 0.01: the duck is under 2 units across.
        let e = m.bounds().extent();
        assert!(e.max_element() < 2.0 && e.min_element() > 0.5, "{e}");
        assert_eq!(s.lights.len(), 1);
    }
    assert_eq!(one_mesh(&sa), one_mesh(&sb));
}

#[test]
fn cesium_man_bind_pose_stands_up() {
    for rel in ["CesiumMan/glTF/CesiumMan.gltf", "CesiumMan/glTF-Binary/CesiumMan.glb"] {
        let Some(p) = model(rel) else { return };
        let s = load_file(&p).unwrap();
        let m = one_mesh(&s);
        assert_eq!(m.triangle_count(), 4_672);
        assert_eq!(m.vertex_count(), 3_273);
        let e = m.bounds().extent();
        assert!(e.y > e.x && e.y > e.z, "the root node turns the Z-up model Y-up: {e}");
    }
}

#[test]
fn animated_morph_cube_loads_its_base_shape() {
    let Some(p) = model("AnimatedMorphCube/glTF/AnimatedMorphCube.gltf") else { return };
    let s = load_file(&p).unwrap();
    let m = one_mesh(&s);
    assert_eq!(m.triangle_count(), 12);
    assert_eq!(m.vertex_count(), 24);
    // Node scale 100 on a cube of edge 0.02 (the base shape; morph weights are 0).
    let e = m.bounds().extent();
    assert!((e - glam::Vec3::splat(2.0)).abs().max_element() < 1e-4, "{e}");
}
