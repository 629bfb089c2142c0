//! Tests of the scene language (seed 003 Appendix A): one per production, one per error
//! path, evaluation of expressions and transforms, a property test of expression
//! evaluation, and the example scenes of `examples/`.

use dynray_scene::scn::{auto_sphere_detail, eval_expr, Value};
use dynray_scene::{
    load_scn, parse_scn_str, LightKind, LoadError, Material, NormalSource, Projection, Scene, Settings, Shading,
};
use glam::{DVec3, Vec3};
use std::path::{Path, PathBuf};

fn parse(text: &str) -> Scene {
    parse_scn_str("test.scn", text, Path::new(".")).unwrap_or_else(|e| panic!("unexpected error:\n{e}"))
}

/// The error of `text`: (line, column, message, rendered).
fn fail(text: &str) -> (usize, usize, String, String) {
    fail_in(text, Path::new("."))
}

fn fail_in(text: &str, dir: &Path) -> (usize, usize, String, String) {
    match parse_scn_str("test.scn", text, dir) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(LoadError::Scene { line, column, message, rendered, .. }) => (line, column, message, rendered),
        Err(e) => panic!("expected a scene diagnostic, got {e:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-4
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

fn positions(s: &Scene, actor: usize) -> Vec<Vec3> {
    s.actors[actor].world_mesh().positions.iter().map(|p| Vec3::from_array(*p)).collect()
}

const TRI: &str = "mesh { vertices { 3 <0,0,0> <1,0,0> <0,1,0> } triangles { 1 <0,1,2> } }";

// ---- actors and models ----------------------------------------------------------------

#[test]
fn mesh_inline_vertices_and_triangles() {
    let s = parse(TRI);
    assert_eq!(s.actors.len(), 1);
    assert_eq!(s.actors[0].world_mesh().indices, vec![[0, 1, 2]]);
    assert_eq!(positions(&s, 0), vec![v(0., 0., 0.), v(1., 0., 0.), v(0., 1., 0.)]);
    assert!(s.actors[0].world_mesh().normals.is_none());
    // No material: the default one.
    assert_eq!(s.materials, vec![Material::default()]);
}

#[test]
fn mesh_inline_normal_indices_split_vertices() {
    let s = parse(
        "mesh { vertices { 4 <0,0,0> <1,0,0> <0,1,0> <1,1,0> } normals { 2 <0,0,1> <0,0,-2> }
           triangles { 2 <0,1,2>/<0,0,0> <1,3,2>/<1,1,1> } }",
    );
    let m = &s.actors[0].world_mesh();
    assert_eq!(m.triangle_count(), 2);
    // Vertices 1 and 2 are used with two normals each: 6 output vertices.
    assert_eq!(m.vertex_count(), 6);
    let n = m.normals.as_ref().unwrap();
    assert_eq!(n[m.indices[0][0] as usize], [0.0, 0.0, 1.0]);
    assert_eq!(n[m.indices[1][0] as usize], [0.0, 0.0, -1.0], "normals are normalised");
}

#[test]
fn mesh_inline_normals_per_vertex_when_counts_match() {
    let s = parse(
        "mesh { vertices { 3 <0,0,0> <1,0,0> <0,1,0> } normals { 3 <0,0,1> <0,0,1> <0,0,1> }
           triangles { 1 <0,1,2> } }",
    );
    let m = &s.actors[0].world_mesh();
    assert_eq!(m.vertex_count(), 3);
    assert_eq!(m.normals.as_ref().unwrap()[2], [0.0, 0.0, 1.0]);
}

#[test]
fn mesh_inline_components_are_expressions() {
    let s = parse("define h = 0.5 mesh { vertices { 1 + 2 <0,0,0> <2*h,0,0> <0,h+h,0> } triangles { 1 <0,1,1+1> } }");
    assert_eq!(positions(&s, 0)[1], v(1., 0., 0.));
}

fn write_ply(dir: &Path, name: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(
        &p,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    p
}

#[test]
fn mesh_file_is_relative_to_the_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("models")).unwrap();
    write_ply(&dir.path().join("models"), "tri.ply");
    let scene = dir.path().join("a.scn");
    std::fs::write(&scene, "mesh { file \"models/tri.ply\" transform { translate <0,0,5> } }").unwrap();
    let s = load_scn(&scene).unwrap();
    assert_eq!(s.actors[0].world_mesh().triangle_count(), 1);
    assert_eq!(positions(&s, 0)[1], v(1., 0., 5.));
}

/// Regression: a mesh file's warnings (here its `.mtl` is missing) were dropped when the
/// mesh was read from a scene file, so the scene rendered grey without a word.
#[test]
fn mesh_file_warnings_reach_the_scene_report() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("tri.obj");
    std::fs::write(
        &obj,
        "mtllib gone.mtl
v 0 0 0
v 1 0 0
v 0 1 0
usemtl red
f 1 2 3
",
    )
    .unwrap();
    let scene = dir.path().join("a.scn");
    // Read twice (two actors): the same warning is reported once.
    std::fs::write(
        &scene,
        "light { position <0, 5, 0> color rgb(1, 1, 1) }\n\
         mesh { file \"tri.obj\" }\nmesh { file \"tri.obj\" transform { translate <2,0,0> } }",
    )
    .unwrap();
    for r in [dynray_scene::load_file_report(&scene).unwrap(), dynray_scene::load_scn_report(&scene).unwrap()] {
        assert_eq!(r.scene.actors.len(), 2);
        let mtl: Vec<_> = r.warnings.iter().filter(|w| w.message.contains("gone.mtl")).collect();
        assert_eq!(mtl.len(), 1, "one warning naming the .mtl, once: {:?}", r.warnings);
        assert_eq!(mtl[0].path.file_name().unwrap(), "tri.obj", "it names the mesh file");
        assert_eq!(mtl[0].line, Some(1));
        assert!(mtl[0].to_string().contains("tri.obj:1: material library"), "{}", mtl[0]);
    }
    // The same scene without a missing library warns about nothing.
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert_eq!(dynray_scene::load_file_report(&scene).unwrap().warnings, vec![]);
}

#[test]
fn mesh_file_errors_point_at_the_file_name() {
    let (line, col, msg, rendered) = fail("\n  mesh { file \"missing.ply\" }");
    assert_eq!((line, col), (2, 15));
    assert!(msg.contains("cannot load mesh file `missing.ply`"), "{msg}");
    assert!(rendered.contains("No such file"), "{rendered}");
    let (_, _, msg, rendered) = fail("mesh { file \"x.stl\" }");
    assert!(msg.contains("x.stl"), "{msg}");
    assert!(rendered.contains("unknown file type"), "{rendered}");
}

#[test]
fn mesh_file_and_inline_data_do_not_mix() {
    let dir = tempfile::tempdir().unwrap();
    write_ply(dir.path(), "tri.ply");
    let (_, _, msg, _) = fail_in("mesh { file \"tri.ply\" vertices { 1 <0,0,0> } }", dir.path());
    assert!(msg.contains("`vertices` cannot be combined with `file`"), "{msg}");
}

/// A mesh file without normals: two triangles folded 90° along the x axis.
fn write_fold(dir: &Path) {
    std::fs::write(dir.join("fold.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\n").unwrap();
}

/// What each actor was asked for and what its mesh holds.
fn shading_of(s: &Scene) -> Vec<(Shading, NormalSource)> {
    s.actors.iter().map(|a| (a.shading, a.normal_source)).collect()
}

#[test]
fn mesh_shading_parameter() {
    let dir = tempfile::tempdir().unwrap();
    write_fold(dir.path());
    let parse_in = |text: &str| parse_scn_str("t.scn", text, dir.path()).unwrap_or_else(|e| panic!("{text}:\n{e}"));
    let generated = |crease_deg, split_vertices| NormalSource::Generated { crease_deg, split_vertices };
    let cases: [(&str, Shading, NormalSource); 7] = [
        // A file without normals is smoothed by default; the fold's 90° stays hard.
        ("mesh { file \"fold.obj\" }", Shading::Auto, generated(60.0, 2)),
        ("mesh { file \"fold.obj\" shading auto }", Shading::Auto, generated(60.0, 2)),
        ("mesh { file \"fold.obj\" shading flat }", Shading::Flat, NormalSource::Geometric),
        ("mesh { file \"fold.obj\" shading smooth }", Shading::Smooth { crease_deg: 60.0 }, generated(60.0, 2)),
        ("mesh { shading smooth 120 file \"fold.obj\" }", Shading::Smooth { crease_deg: 120.0 }, generated(120.0, 0)),
        // An expression, and a crease left out before another parameter.
        (
            "define c = 45 mesh { file \"fold.obj\" shading smooth c * 2 + 30 }",
            Shading::Smooth { crease_deg: 120.0 },
            generated(120.0, 0),
        ),
        (
            "mesh { file \"fold.obj\" shading smooth material { color rgb(1, 0, 0) } }",
            Shading::Smooth { crease_deg: 60.0 },
            generated(60.0, 2),
        ),
    ];
    for (text, shading, source) in cases {
        let s = parse_in(text);
        assert_eq!(shading_of(&s), [(shading, source)], "{text}");
        assert_eq!(s.actors[0].mesh.normals.is_some(), source != NormalSource::Geometric, "{text}");
    }
    let s = parse_in("mesh { file \"fold.obj\" shading smooth transform { translate <1, 0, 0> } }");
    assert_eq!(shading_of(&s), [(Shading::Smooth { crease_deg: 60.0 }, generated(60.0, 2))]);
    assert_eq!(positions(&s, 0)[1], v(2., 0., 0.));
    // A defined object keeps its shading in every instance.
    let s = parse_in(
        "define f mesh { file \"fold.obj\" shading flat } object f object { f transform { translate <0,0,3> } }",
    );
    assert_eq!(shading_of(&s), [(Shading::Flat, NormalSource::Geometric); 2]);
}

#[test]
fn inline_meshes_boxes_and_spheres_keep_the_normals_they_have() {
    const FOLD: &str = "vertices { 4 <0,0,0> <1,0,0> <0,1,0> <0,0,1> } triangles { 2 <0,1,2> <0,3,1> }";
    // Seed 003: a triangle without normals uses its own.
    let s = parse(&format!("mesh {{ {FOLD} }}"));
    assert_eq!(shading_of(&s), [(Shading::Flat, NormalSource::Geometric)]);
    assert!(s.actors[0].mesh.normals.is_none());
    let s = parse(&format!("mesh {{ {FOLD} shading smooth 100 }}"));
    assert_eq!(
        shading_of(&s),
        [(Shading::Smooth { crease_deg: 100.0 }, NormalSource::Generated { crease_deg: 100.0, split_vertices: 0 })]
    );
    // Normals that are given are kept; `shading flat` drops them.
    let given = "vertices { 3 <0,0,0> <1,0,0> <0,1,0> } normals { 3 <0,0,1> <0,1,1> <1,0,1> } triangles { 1 <0,1,2> }";
    let s = parse(&format!("mesh {{ {given} }}"));
    assert_eq!(shading_of(&s), [(Shading::Auto, NormalSource::FromSource)]);
    assert_eq!(s.actors[0].mesh.normals.as_ref().unwrap()[1], Vec3::new(0.0, 1.0, 1.0).normalize().to_array());
    let s = parse(&format!("mesh {{ {given} shading flat }}"));
    assert_eq!(shading_of(&s), [(Shading::Flat, NormalSource::Geometric)]);
    // A box keeps its flat face normals, a sphere its analytic ones.
    let s = parse("box { center <0,0,0> orientation <0,0,0> scale <1,1,1> } sphere { center <0,0,0> radius 1 }");
    assert_eq!(shading_of(&s), [(Shading::Auto, NormalSource::FromSource); 2]);
    let (_, _, msg, _) = fail("box { center <0,0,0> orientation <0,0,0> scale <1,1,1> shading smooth }");
    assert!(msg.contains("unknown parameter `shading` in `box`"), "{msg}");
}

#[test]
fn shading_errors_point_at_the_text() {
    const M: &str = "mesh { vertices { 3 <0,0,0> <1,0,0> <0,1,0> } triangles { 1 <0,1,2> }";
    let (line, col, msg, rendered) = fail(&format!("{M}\n  shading glossy }}"));
    assert_eq!((line, col), (2, 11));
    assert_eq!(msg, "unknown shading `glossy`");
    assert!(rendered.contains("expected `auto`, `flat` or `smooth`"), "{rendered}");
    assert!(rendered.contains("test.scn:2:11"), "{rendered}");
    let (_, _, _, rendered) = fail(&format!("{M} shading smoth }}"));
    assert!(rendered.contains("did you mean `smooth`?"), "{rendered}");
    // The error points at the crease, however it is written.
    let col = M.len() + "  shading smooth ".len() + 1;
    for crease in ["200", "-1", "180.5", "90 * 3"] {
        let (line, c, msg, rendered) = fail(&format!("{M}  shading smooth {crease} }}"));
        assert_eq!((line, c), (1, col), "{crease}: {msg}");
        assert!(msg.starts_with("crease angle is ") && msg.ends_with("but it must lie in 0..=180 degrees"), "{msg}");
        assert!(rendered.contains(&format!("test.scn:1:{col}")), "{rendered}");
    }
    // The ends of the range are accepted.
    parse(&format!("{M} shading smooth 0 }}"));
    parse(&format!("{M} shading smooth 180 }}"));
    let (_, _, msg, _) = fail(&format!("{M} shading smooth <1, 2, 3> }}"));
    assert!(msg.contains("crease angle must be a real, found a vector"), "{msg}");
    let (_, _, msg, _) = fail(&format!("{M} shading 45 }}"));
    assert!(msg.contains("expected `auto`, `flat` or `smooth` after `shading`, found number `45`"), "{msg}");
    let (_, _, msg, _) = fail(&format!("{M} shading }}"));
    assert!(msg.contains("expected `auto`, `flat` or `smooth` after `shading`, found `}`"), "{msg}");
    let (_, _, msg, _) = fail(&format!("{M} shading flat shading smooth }}"));
    assert!(msg.contains("duplicated parameter `shading` in `mesh`"), "{msg}");
    let (_, _, msg, _) = fail(&format!("{M} shading smooth unknown_name }}"));
    assert!(msg.contains("unknown name `unknown_name`"), "{msg}");
}

#[test]
fn box_has_center_edge_lengths_and_rotation_in_degrees() {
    let s = parse("box { center <1,2,3> orientation <0,0,0> scale <2,4,6> }");
    let b = s.actors[0].world_mesh().bounds();
    assert!(close(b.min, v(0., 0., 0.)) && close(b.max, v(2., 4., 6.)), "{b:?}");
    assert_eq!(s.actors[0].world_mesh().triangle_count(), 12);
    let s = parse("box { center <0,0,0> orientation <0,0,90> scale <2,1,1> }");
    let e = s.actors[0].world_mesh().bounds().extent();
    assert!(close(e, v(1., 2., 1.)), "rotated 90° about z: {e}");
}

#[test]
fn sphere_detail_setting_controls_tessellation() {
    let s = parse("settings { sphere_detail 16 } sphere { center <0,0,0> radius 2 }");
    // 16 slices, 8 stacks: 16 + 2·16·6 + 16 triangles.
    assert_eq!(s.actors[0].world_mesh().triangle_count(), 16 + 2 * 16 * 6 + 16);
    for p in positions(&s, 0) {
        assert!((p.length() - 2.0).abs() < 1e-5, "vertex {p} not on the sphere");
    }
    // The setting applies to spheres written before it, too.
    let s2 = parse("sphere { center <0,0,0> radius 2 } settings { sphere_detail 16 }");
    assert_eq!(s2.actors[0].world_mesh().triangle_count(), s.actors[0].world_mesh().triangle_count());
}

#[test]
fn sphere_auto_detail_follows_image_size() {
    let small = auto_sphere_detail(&Settings { width: 64, height: 64, ..Settings::default() });
    let large = auto_sphere_detail(&Settings { width: 1920, height: 1080, ..Settings::default() });
    assert!(small < large, "{small} {large}");
    // The silhouette error of a full-image sphere stays under a quarter pixel.
    let r = 960.0f64;
    let n = large as f64;
    assert!(r * (1.0 - (std::f64::consts::PI / n).cos()) <= 0.25);
    let s = parse("settings { image_width 64 image_height 64 } sphere { center <0,0,0> radius 1 }");
    let k = small as usize;
    assert_eq!(s.actors[0].world_mesh().triangle_count(), 2 * k + 2 * k * (k / 2 - 2));
}

#[test]
fn define_adds_no_actor_and_object_name_places_an_instance() {
    let s = parse("define bola sphere { center <0,0,0> radius 1 }");
    assert!(s.actors.is_empty());
    let s = parse("define bola sphere { center <0,0,0> radius 1 } object bola object bola");
    assert_eq!(s.actors.len(), 2);
    assert_eq!(s.actors[0].name.as_deref(), Some("bola"));
}

#[test]
fn object_block_applies_material_and_transform_modifiers() {
    let s = parse(&format!(
        "define t {TRI}
         object {{ t material {{ color rgb(1,0,0) }} transform {{ translate <0,0,1> }} transform {{ translate <1,0,0> }} }}"
    ));
    assert_eq!(positions(&s, 0)[0], v(1., 0., 1.));
    let m = &s.materials[s.actors[0].materials[0] as usize];
    assert_eq!(m.diffuse, Vec3::new(1.0, 0.0, 0.0) * 0.9);
}

#[test]
fn object_modifier_replaces_the_defined_material() {
    let s = parse(
        "define red material { color rgb(1,0,0) } define blue material { color rgb(0,0,1) }
         define b sphere { center <0,0,0> radius 1 material red }
         object b object { b material blue }",
    );
    assert_eq!(s.materials.len(), 2);
    assert_eq!(s.materials[s.actors[0].materials[0] as usize].name, "red");
    assert_eq!(s.materials[s.actors[1].materials[0] as usize].name, "blue");
}

#[test]
fn shared_materials_are_stored_once() {
    let s = parse("define m material { color rgb(1,1,1) } sphere { center <0,0,0> radius 1 material m } box { center <0,0,0> orientation <0,0,0> scale <1,1,1> material m }");
    assert_eq!(s.materials.len(), 1);
}

// ---- lights -------------------------------------------------------------------------

#[test]
fn point_light_with_color_and_falloff() {
    let s = parse("light { position <1,2,3> color rgb(0.5,0.5,0.5) falloff 2 }");
    assert_eq!(s.lights.len(), 1);
    assert_eq!(s.lights[0].kind, LightKind::Point { position: v(1., 2., 3.), falloff: 2 });
    assert_eq!(s.lights[0].color, Vec3::splat(0.5));
}

#[test]
fn point_light_defaults_white_without_falloff() {
    let s = parse("light { position <0,0,0> }");
    assert_eq!(s.lights[0].kind, LightKind::Point { position: Vec3::ZERO, falloff: 0 });
    assert_eq!(s.lights[0].color, Vec3::ONE);
}

#[test]
fn directional_light() {
    let s = parse("light { direction <0,-1,0> color rgb(1,1,1) }");
    assert_eq!(s.lights[0].kind, LightKind::Directional { direction: v(0., -1., 0.) });
}

#[test]
fn named_light_is_placed_only_by_light_name() {
    let s = parse("define luz1 light { position <0,0,0> color rgb(1,1,1) }");
    assert!(s.lights.is_empty());
    let s = parse("define luz1 light { position <0,0,0> color rgb(1,1,1) } light luz1 light luz1");
    assert_eq!(s.lights.len(), 2);
}

#[test]
fn light_errors() {
    let (_, _, msg, _) = fail("light { color rgb(1,1,1) }");
    assert!(msg.contains("missing parameter `position` or `direction`"), "{msg}");
    let (_, _, msg, _) = fail("light { position <0,0,0> direction <0,1,0> }");
    assert!(msg.contains("not both"), "{msg}");
    let (_, _, msg, _) = fail("light { direction <0,1,0> falloff 1 }");
    assert!(msg.contains("only to point lights"), "{msg}");
    let (_, _, msg, _) = fail("light { position <0,0,0> falloff 1.5 }");
    assert!(msg.contains("must be an integer"), "{msg}");
    let (_, _, msg, _) = fail("light { direction <0,0,0> }");
    assert!(msg.contains("zero vector"), "{msg}");
}

// ---- camera, environment, settings ----------------------------------------------------

#[test]
fn perspective_camera() {
    let s = parse("camera { perspective position <0,0,10> to <0,0,0> up <0,1,0> angle 30 }");
    let c = s.camera.unwrap();
    assert_eq!(c.position, v(0., 0., 10.));
    assert_eq!(c.look_at, Vec3::ZERO);
    assert_eq!(c.up, Vec3::Y);
    assert_eq!(c.projection, Projection::Perspective { fov_y_deg: 30.0 });
    let s = parse("camera { perspective position <0,0,10> to <0,0,0> up <0,1,0> }");
    assert_eq!(s.camera.unwrap().projection, Projection::Perspective { fov_y_deg: 45.0 });
}

#[test]
fn parallel_camera_angle_is_the_view_height() {
    let s = parse("camera { parallel position <0,0,10> to <0,0,0> up <0,1,0> angle 4 }");
    assert_eq!(s.camera.unwrap().projection, Projection::Parallel { height: 4.0 });
    let s = parse("camera { parallel position <0,0,10> to <0,0,0> up <0,1,0> }");
    let Projection::Parallel { height } = s.camera.unwrap().projection else { panic!() };
    assert!((height - 20.0 * 22.5f32.to_radians().tan()).abs() < 1e-4);
}

#[test]
fn named_camera() {
    let s = parse("define c camera { perspective position <0,0,1> to <0,0,0> up <0,1,0> } camera c");
    assert!(s.camera.is_some());
    assert!(parse("define c camera { perspective position <0,0,1> to <0,0,0> up <0,1,0> }").camera.is_none());
}

#[test]
fn camera_errors() {
    let (_, _, msg, _) = fail("camera { position <0,0,1> to <0,0,0> up <0,1,0> }");
    assert!(msg.contains("missing parameter `parallel` or `perspective`"), "{msg}");
    let (_, _, msg, _) = fail("camera { parallel perspective position <0,0,1> to <0,0,0> up <0,1,0> }");
    assert!(msg.contains("not both"), "{msg}");
    let (_, _, msg, _) = fail("camera { perspective position <0,0,1> to <0,0,1> up <0,1,0> }");
    assert!(msg.contains("same point"), "{msg}");
    let (_, _, msg, _) = fail("camera { perspective position <0,0,1> to <0,0,0> up <0,0,3> }");
    assert!(msg.contains("parallel to the view"), "{msg}");
    let (_, _, msg, _) = fail("camera { perspective position <0,0,1> to <0,0,0> up <0,1,0> angle 180 }");
    assert!(msg.contains("180"), "{msg}");
    let cam = "camera { perspective position <0,0,1> to <0,0,0> up <0,1,0> }";
    let (line, _, msg, rendered) = fail(&format!("{cam}\n{cam}"));
    assert_eq!(line, 2);
    assert!(msg.contains("second `camera`"), "{msg}");
    assert!(rendered.contains("the first is here"), "{rendered}");
}

#[test]
fn environment_block() {
    let s = parse("environment { background rgb(0.1,0.2,0.3) ambient rgb(0.5,0.5,0.5) ior 1.33 }");
    assert_eq!(s.environment.background, v(0.1, 0.2, 0.3));
    assert_eq!(s.environment.ambient, Vec3::splat(0.5));
    assert_eq!(s.environment.ior, 1.33);
    let (_, _, msg, _) = fail("environment { ior 0 }");
    assert!(msg.contains("must be positive"), "{msg}");
}

#[test]
fn settings_block_with_real_min_weight() {
    let s = parse("settings { image_width 320 image_height 200 min_weight 0.05 max_recursion_level 5 }");
    assert_eq!((s.settings.width, s.settings.height), (320, 200));
    assert_eq!(s.settings.min_weight, 0.05);
    assert_eq!(s.settings.max_recursion_level, 5);
    let (_, _, msg, _) = fail("settings { image_width 0 }");
    assert!(msg.contains("outside 1..="), "{msg}");
    let (_, _, msg, _) = fail("settings { image_width 320.5 }");
    assert!(msg.contains("must be an integer"), "{msg}");
    let (_, _, msg, _) = fail("settings { min_weight 2 }");
    assert!(msg.contains("[0, 1]"), "{msg}");
}

// ---- materials ------------------------------------------------------------------------

#[test]
fn material_color_times_finish() {
    let s = parse(
        "sphere { center <0,0,0> radius 1 material { color rgb(1,0.5,0) finish { ambient 0.2 diffuse 0.6 spot 0.3 shine 50 specular 0.4 transparency 0.1 ior 1.5 } } }",
    );
    let m = &s.materials[0];
    assert_eq!(m.ambient, v(1., 0.5, 0.) * 0.2);
    assert_eq!(m.diffuse, v(1., 0.5, 0.) * 0.6);
    assert_eq!(m.spot, Vec3::splat(0.3));
    assert_eq!(m.shine, 50.0);
    assert_eq!(m.specular, Vec3::splat(0.4));
    assert_eq!(m.transparency, Vec3::splat(0.1));
    assert_eq!(m.ior, 1.5);
}

#[test]
fn named_material_keeps_its_name() {
    let s = parse("define gold material { color rgb(1,0.8,0.2) } sphere { center <0,0,0> radius 1 material gold }");
    assert_eq!(s.materials[0].name, "gold");
}

#[test]
fn material_errors() {
    let (_, _, msg, _) = fail("sphere { center <0,0,0> radius 1 material { finish { diffuse 1 } } }");
    assert!(msg.contains("missing parameter `color` in `material`"), "{msg}");
    let (_, _, msg, _) = fail("sphere { center <0,0,0> radius 1 material { color rgb(1,1,1) finish { glow 1 } } }");
    assert!(msg.contains("unknown parameter `glow` in `finish`"), "{msg}");
    let (_, _, msg, _) = fail("sphere { center <0,0,0> radius 1 material { color <1,1,1> } }");
    assert!(msg.contains("must be a colour, found a vector"), "{msg}");
    let (_, _, msg, _) = fail("material { color rgb(1,1,1) }");
    assert!(msg.contains("places nothing"), "{msg}");
}

// ---- transforms -----------------------------------------------------------------------

fn transformed(point: &str, ops: &str) -> Vec3 {
    let s = parse(&format!(
        "mesh {{ vertices {{ 3 {point} <0,0,0> <0,0,0> }} triangles {{ 1 <0,1,2> }} transform {{ {ops} }} }}"
    ));
    positions(&s, 0)[0]
}

#[test]
fn translate_and_axis_rotations() {
    assert!(close(transformed("<1,2,3>", "translate <1,1,1>"), v(2., 3., 4.)));
    assert!(close(transformed("<0,1,0>", "rotate_x 90"), v(0., 0., 1.)));
    assert!(close(transformed("<0,0,1>", "rotate_y 90"), v(1., 0., 0.)));
    assert!(close(transformed("<1,0,0>", "rotate_z 90"), v(0., 1., 0.)));
}

#[test]
fn rotate_about_a_base_point_lands_where_geometry_says() {
    // A quarter turn about the vertical line through (1, 0, 0): (2, 0, 0) -> (1, 0, -1).
    assert!(close(transformed("<2,0,0>", "rotate <1,0,0> <0,1,0> 90"), v(1., 0., -1.)));
    // A third of a turn about the diagonal through (1,1,1) cycles the axes:
    // p - b = (1,0,0) -> (0,1,0).
    assert!(close(transformed("<2,1,1>", "rotate <1,1,1> <1,1,1> 120"), v(1., 2., 1.)));
    // The base point itself never moves, and distances to it are kept.
    let p = transformed("<3,-1,2>", "rotate <1,2,3> <0.3,-0.5,0.8> 37");
    assert!(((p - v(1., 2., 3.)).length() - (v(3., -1., 2.) - v(1., 2., 3.)).length()).abs() < 1e-4);
    assert!(close(transformed("<1,2,3>", "rotate <1,2,3> <0.3,-0.5,0.8> 37"), v(1., 2., 3.)));
}

#[test]
fn scale_about_a_base_point() {
    assert!(close(transformed("<2,2,2>", "scale <1,1,1> <2,3,4>"), v(3., 4., 5.)));
}

#[test]
fn transforms_apply_in_written_order() {
    assert!(close(transformed("<1,0,0>", "scale <0,0,0> <2,1,1> translate <-1,-1,0>"), v(1., -1., 0.)));
    assert!(close(transformed("<1,0,0>", "translate <-1,-1,0> scale <0,0,0> <2,1,1>"), v(0., -1., 0.)));
    assert!(close(transformed("<1,0,0>", "rotate_z 90 translate <1,0,0>"), v(1., 1., 0.)));
}

#[test]
fn named_transform() {
    let s =
        parse(&format!("define tri {TRI} define up transform {{ translate <0,5,0> }} object {{ tri transform up }}"));
    assert_eq!(positions(&s, 0)[0], v(0., 5., 0.));
}

#[test]
fn a_byte_order_mark_is_not_an_error() {
    // Issue 43: a UTF-8 BOM (what some editors write first) was "unexpected character".
    let s = parse("\u{feff}sphere { center <0,0,0> radius 1 }");
    assert_eq!(s.actors.len(), 1);
}

#[test]
fn numbers_past_f32_say_so() {
    // Issue 43: this was "sphere radius is 1e39, but a radius must be positive".
    let (_, _, msg, _) = fail("sphere { center <0,0,0> radius 1e39 }");
    assert!(msg.contains("sphere radius is 1e39, beyond a 32-bit float's range"), "{msg}");
    let (_, _, msg, _) = fail("sphere { center <0,0,0> radius -1 }");
    assert!(msg.contains("but a radius must be positive"), "{msg}");
}

#[test]
fn transform_errors() {
    let (_, _, msg, _) = fail(&format!("define t {TRI} object {{ t transform {{ shear <1,1,1> }} }}"));
    assert!(msg.contains("unknown parameter `shear` in `transform`"), "{msg}");
    let (_, _, msg, _) = fail(&format!("define t {TRI} object {{ t transform {{ rotate <0,0,0> <0,0,0> 3 }} }}"));
    assert!(msg.contains("rotation axis is the zero vector"), "{msg}");
    let (_, _, msg, _) = fail(&format!("define t {TRI} object {{ t transform {{ scale <0,0,0> <1,0,1> }} }}"));
    assert!(msg.contains("contain a zero"), "{msg}");
}

// ---- define, expressions --------------------------------------------------------------

#[test]
fn define_values_with_and_without_equals() {
    let s = parse("define r 2 define c = <1,2,3> sphere { center c * r radius r / 2 }");
    let b = s.actors[0].world_mesh().bounds();
    assert!(close(b.center(), v(2., 4., 6.)), "{b:?}");
}

#[test]
fn define_can_alias_any_definition() {
    let s = parse(
        "define bola sphere { center <0,0,0> radius 1 } define ball = bola object ball
         define m material { color rgb(1,0,0) } define m2 m sphere { center <0,0,0> radius 1 material m2 }",
    );
    assert_eq!(s.actors.len(), 2);
    assert_eq!(s.materials[s.actors[1].materials[0] as usize].name, "m");
}

#[test]
fn redefinition_replaces_from_then_on() {
    let s = parse("define r = 1 sphere { center <0,0,0> radius r } define r = 3 sphere { center <0,0,0> radius r }");
    assert!((s.actors[0].world_mesh().bounds().max.x - 1.0).abs() < 1e-5);
    assert!((s.actors[1].world_mesh().bounds().max.x - 3.0).abs() < 1e-5);
}

#[test]
fn expression_precedence_and_unary_signs() {
    assert_eq!(eval_expr("1 + 2 * 3").unwrap(), Value::Real(7.0));
    assert_eq!(eval_expr("(1 + 2) * 3").unwrap(), Value::Real(9.0));
    assert_eq!(eval_expr("10 - 4 - 3").unwrap(), Value::Real(3.0));
    assert_eq!(eval_expr("12 / 3 / 2").unwrap(), Value::Real(2.0));
    assert_eq!(eval_expr("-2 * -+3").unwrap(), Value::Real(6.0));
    assert_eq!(eval_expr("1.5e1 + .5").unwrap(), Value::Real(15.5));
}

#[test]
fn expression_types() {
    assert_eq!(eval_expr("<1,2,3> * 2").unwrap(), Value::Vector(DVec3::new(2.0, 4.0, 6.0)));
    assert_eq!(eval_expr("2 * <1,2,3> - <1,1,1>").unwrap(), Value::Vector(DVec3::new(1.0, 3.0, 5.0)));
    assert_eq!(eval_expr("<2,4,6> / 2").unwrap(), Value::Vector(DVec3::new(1.0, 2.0, 3.0)));
    assert_eq!(eval_expr("rgb(1,0.5,0) * 0.5").unwrap(), Value::Color(DVec3::new(0.5, 0.25, 0.0)));
    assert_eq!(eval_expr("rgb(1,0.5,0) * rgb(0.5,1,1)").unwrap(), Value::Color(DVec3::new(0.5, 0.5, 0.0)));
    assert_eq!(eval_expr("-<1,2,3>").unwrap(), Value::Vector(DVec3::new(-1.0, -2.0, -3.0)));
    assert_eq!(eval_expr("<1+1, 2*2, (3)>").unwrap(), Value::Vector(DVec3::new(2.0, 4.0, 3.0)));
}

#[test]
fn type_mismatches_are_reported() {
    for (text, needle) in [
        ("<1,2,3> + rgb(1,1,1)", "vectors and colours do not mix"),
        ("<1,2,3> * <1,2,3>", "multiply a vector by a real"),
        ("1 + <1,2,3>", "cannot be added"),
        ("2 / <1,1,1>", "only a vector or colour can be divided"),
        ("<1, <1,1,1>, 3>", "must be a real, found a vector"),
        ("1 / 0", "division by zero"),
    ] {
        let e = eval_expr(text).expect_err(text);
        let LoadError::Scene { message, .. } = &e else { panic!("{e:?}") };
        assert!(message.contains(needle), "{text}: {message}");
    }
    let (line, col, msg, _) = fail("sphere { center <0,0,0> radius <1,1,1> }");
    assert_eq!((line, col), (1, 32));
    assert!(msg.contains("sphere radius must be a real, found a vector"), "{msg}");
}

#[test]
fn names_are_resolved_and_checked() {
    let (_, _, msg, _) = fail("sphere { center origin radius 1 }");
    assert!(msg.contains("unknown name `origin`"), "{msg}");
    let (_, _, _, rendered) = fail("define bola sphere { center <0,0,0> radius 1 } object bolla");
    assert!(rendered.contains("did you mean `bola`?"), "{rendered}");
    let (_, _, _, rendered) = fail("shpere { center <0,0,0> radius 1 }");
    assert!(rendered.contains("did you mean `sphere`?"), "{rendered}");
    let (_, _, msg, rendered) = fail("define m material { color rgb(1,1,1) }\nsphere { center m radius 1 }");
    assert!(msg.contains("`m` is a material, not a value"), "{msg}");
    assert!(rendered.contains("defined here"), "{rendered}");
    let (_, _, msg, _) = fail("define r = 1 object r");
    assert!(msg.contains("`r` is a real, not an object"), "{msg}");
    let (_, _, msg, _) = fail("light nowhere");
    assert!(msg.contains("unknown name `nowhere`"), "{msg}");
    let (_, _, msg, _) = fail("define sphere = 1");
    assert!(msg.contains("keyword"), "{msg}");
}

// ---- include --------------------------------------------------------------------------

#[test]
fn include_is_relative_to_the_including_file() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("lib");
    std::fs::create_dir(&sub).unwrap();
    std::fs::write(sub.join("colors.scn"), "define red = rgb(1,0,0)").unwrap();
    std::fs::write(sub.join("mats.scn"), "include \"colors.scn\" define m material { color red }").unwrap();
    std::fs::write(
        dir.path().join("main.scn"),
        "include \"lib/mats.scn\" sphere { center <0,0,0> radius 1 material m }",
    )
    .unwrap();
    let s = load_scn(&dir.path().join("main.scn")).unwrap();
    assert_eq!(s.materials[0].name, "m");
    assert_eq!(s.materials[0].diffuse, v(0.9, 0., 0.));
}

#[test]
fn include_errors_name_the_included_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.scn"), "\n\nsphere { radius 1 center <0,0> }").unwrap();
    let (line, col, _, rendered) = fail_in("include \"bad.scn\"", dir.path());
    assert_eq!((line, col), (3, 30));
    assert!(rendered.contains("bad.scn:3:30"), "{rendered}");
    assert!(rendered.contains("included from test.scn:1:9"), "{rendered}");
}

#[test]
fn include_missing_file_cycle_and_depth() {
    let dir = tempfile::tempdir().unwrap();
    let (_, _, msg, _) = fail_in("include \"nope.scn\"", dir.path());
    assert!(msg.contains("cannot open"), "{msg}");
    std::fs::write(dir.path().join("a.scn"), "include \"b.scn\"").unwrap();
    std::fs::write(dir.path().join("b.scn"), "include \"a.scn\"").unwrap();
    let err = load_scn(&dir.path().join("a.scn")).unwrap_err();
    assert!(err.to_string().contains("include cycle"), "{err}");
    // A chain deeper than the limit, without a cycle.
    let n = dynray_scene::scn::MAX_INCLUDE_DEPTH + 5;
    for i in 0..n {
        std::fs::write(dir.path().join(format!("d{i}.scn")), format!("include \"d{}.scn\"", i + 1)).unwrap();
    }
    std::fs::write(dir.path().join(format!("d{n}.scn")), "").unwrap();
    let err = load_scn(&dir.path().join("d0.scn")).unwrap_err();
    assert!(err.to_string().contains("nested more than"), "{err}");
}

// ---- lexical and syntax errors ----------------------------------------------------------

#[test]
fn comments_are_skipped() {
    let s = parse("// line comment\n/* block\n comment */ sphere { /* inside */ center <0,0,0> // here\n radius 1 }");
    assert_eq!(s.actors.len(), 1);
}

#[test]
fn lexical_errors() {
    let (line, col, msg, _) = fail("sphere { center <0,0,0> radius 1 } $");
    assert_eq!((line, col), (1, 36));
    assert!(msg.contains("unexpected character `$`"), "{msg}");
    let (_, _, msg, _) = fail("include \"open");
    assert!(msg.contains("unterminated string"), "{msg}");
    let (line, _, msg, _) = fail("\n/* never closed");
    assert_eq!(line, 2);
    assert!(msg.contains("unterminated comment"), "{msg}");
    let (_, _, msg, _) = fail("define x = 3abc");
    assert!(msg.contains("malformed number"), "{msg}");
}

#[test]
fn rendered_diagnostic_shows_place_line_and_caret() {
    let (line, col, msg, rendered) = fail("// scene\nsphere { center <0,,0,0> radius 1 }");
    assert_eq!((line, col), (2, 20));
    assert!(msg.starts_with("expected an expression"), "{msg}");
    assert!(rendered.contains("test.scn:2:20"), "{rendered}");
    assert!(rendered.contains("sphere { center <0,,0,0> radius 1 }"), "{rendered}");
    let caret_line = rendered.lines().find(|l| l.contains('^')).expect("a caret line");
    let src_line = rendered.lines().find(|l| l.contains("sphere {")).unwrap();
    assert_eq!(caret_line.find('^').unwrap(), src_line.find(",,").unwrap() + 1, "{rendered}");
}

#[test]
fn syntax_errors_say_what_was_expected() {
    for (text, needle) in [
        ("sphere { center <0,0,0> radius 1", "expected `}` to close `sphere`"),
        ("sphere center <0,0,0> radius 1 }", "expected `{` to open `sphere`"),
        ("sphere { center <0,0 0> radius 1 }", "expected `,` between vector components"),
        ("sphere { center <0,0,0,0> radius 1 }", "expected `>` to close the vector"),
        ("sphere { center (1 radius 1 }", "expected `)` to close `(`"),
        ("42", "expected a statement"),
        ("object { }", "expected the name of a defined object"),
        (
            "define b sphere { center <0,0,0> radius 1 } object { b radius 2 }",
            "expected `material`, `transform` or `}`",
        ),
        ("include bola", "expected a quoted file name"),
        ("sphere { center <0,0,0> radius 1 5 }", "expected a parameter of `sphere`"),
    ] {
        let (_, _, msg, _) = fail(text);
        assert!(msg.contains(needle), "{text}: {msg}");
    }
}

#[test]
fn unknown_duplicated_and_missing_parameters() {
    let (_, col, msg, rendered) = fail("sphere { centre <0,0,0> radius 1 }");
    assert_eq!(col, 10);
    assert!(msg.contains("unknown parameter `centre` in `sphere`"), "{msg}");
    assert!(rendered.contains("expected one of: center, radius, material, transform"), "{rendered}");
    assert!(rendered.contains("did you mean `center`?"), "{rendered}");
    let (_, col, msg, rendered) = fail("sphere { center <0,0,0> radius 1 radius 2 }");
    assert_eq!(col, 34);
    assert!(msg.contains("duplicated parameter `radius` in `sphere`"), "{msg}");
    assert!(rendered.contains("first given here"), "{rendered}");
    let (_, _, msg, _) =
        fail("box { center <0,0,0> orientation <0,0,0> scale <1,1,1> material { color rgb(1,1,1) } material { color rgb(1,1,1) } }");
    assert!(msg.contains("duplicated parameter `material`"), "{msg}");
    let (_, _, msg, _) = fail("box { center <0,0,0> scale <1,1,1> }");
    assert!(msg.contains("missing parameter `orientation` in `box`"), "{msg}");
    let (_, _, msg, _) = fail("sphere { center <0,0,0> }");
    assert!(msg.contains("missing parameter `radius` in `sphere`"), "{msg}");
    let (_, _, msg, _) = fail("sphere { center <0,0,0> radius -1 }");
    assert!(msg.contains("must be positive"), "{msg}");
}

#[test]
fn mesh_counts_and_indices_are_checked() {
    let (_, _, msg, _) = fail("mesh { vertices { 3 <0,0,0> <1,0,0> } triangles { 1 <0,1,2> } }");
    assert!(msg.contains("expected 1 more vertex"), "{msg}");
    let (_, _, msg, _) = fail("mesh { vertices { 2 <0,0,0> <1,0,0> <0,1,0> } triangles { 1 <0,1,2> } }");
    assert!(msg.contains("expected `}` to close `vertices` after its 2 entries"), "{msg}");
    let (_, _, msg, _) = fail("mesh { vertices { 3 <0,0,0> <1,0,0> <0,1,0> } triangles { 1 <0,1,3> } }");
    assert!(msg.contains("vertex index 3 out of range"), "{msg}");
    let (_, _, msg, _) = fail("mesh { vertices { 3 <0,0,0> <1,0,0> <0,1,0> } triangles { 1 <0,1,2>/<0,0,0> } }");
    assert!(msg.contains("no `normals` block"), "{msg}");
    let (_, _, msg, _) =
        fail("mesh { vertices { 3 <0,0,0> <1,0,0> <0,1,0> } normals { 1 <0,0,1> } triangles { 1 <0,1,2>/<0,1,0> } }");
    assert!(msg.contains("normal index 1 out of range"), "{msg}");
    let (_, _, msg, _) = fail("mesh { vertices { 3 <0,0,0> <1,0,0> <0,1,0> } }");
    assert!(msg.contains("missing parameter `triangles`"), "{msg}");
    let (_, _, msg, _) = fail("mesh { vertices { 0 } triangles { 1 <0,1,2> } }");
    assert!(msg.contains("outside 1..="), "{msg}");
}

#[test]
fn seed_unit_cube_with_misplaced_brace_is_explained() {
    // The seed's printed unit cube closes `vertices` after `triangles`.
    let (line, _, msg, rendered) = fail(
        "mesh\n{\n  vertices\n{\n  8\n  <-0.5, -0.5, 0.5>\n  <0.5, -0.5, 0.5>\n  <0.5, 0.5, 0.5>\n  <-0.5, 0.5, 0.5>\n  \
         <-0.5, -0.5, -0.5>\n  <0.5, -0.5, -0.5>\n  <0.5, 0.5, -0.5>\n  <-0.5, 0.5, -0.5>\n  normals\n  {\n    6\n  }\n}\n",
    );
    assert_eq!(line, 14);
    assert!(msg.contains("expected `}` to close `vertices`"), "{msg}");
    assert!(rendered.contains("before `normals`"), "{rendered}");
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    for depth in [250usize, 100_000] {
        let text = format!("define x = {}1{}", "(".repeat(depth), ")".repeat(depth));
        let (_, _, msg, _) = fail(&text);
        assert!(msg.contains("nested more than"), "{msg}");
        let text = format!("define x = {}1", "-".repeat(depth));
        let (_, _, msg, _) = fail(&text);
        assert!(msg.contains("nested more than"), "{msg}");
        let text = format!("define x = {}1,1,1>", "<".repeat(depth));
        let (_, _, msg, _) = fail(&text);
        assert!(msg.contains("nested more than"), "{msg}");
    }
    // Moderate nesting is fine.
    assert_eq!(eval_expr(&format!("{}1{}", "(".repeat(60), ")".repeat(60))).unwrap(), Value::Real(1.0));
    // Long flat expressions do not recurse.
    let long = vec!["1"; 50_000].join(" + ");
    assert_eq!(eval_expr(&long).unwrap(), Value::Real(50_000.0));
}

#[test]
fn overflow_is_an_error() {
    let (_, _, msg, _) = fail("sphere { center <0,0,0> radius 1e300 * 1e300 }");
    assert!(msg.contains("finite"), "{msg}");
    let (_, _, msg, _) = fail("sphere { center <1e300,0,0> radius 1 }");
    assert!(msg.contains("too large"), "{msg}");
}

// ---- property tests -------------------------------------------------------------------

mod prop {
    use super::*;
    use proptest::prelude::*;

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Ty {
        Real,
        Vector,
        Color,
    }

    /// An expression as text with the value a direct computation gives (`None`: a
    /// division by zero somewhere, which the evaluator must report as an error).
    #[derive(Clone, Debug)]
    struct Ex {
        text: String,
        value: Option<Value>,
    }

    fn lit() -> impl Strategy<Value = Ex> {
        prop_oneof![(-50i32..50).prop_map(|i| i as f64), (-1000i32..1000).prop_map(|i| i as f64 / 8.0)].prop_map(|x| {
            Ex { text: if x < 0.0 { format!("({x:?})") } else { format!("{x:?}") }, value: Some(Value::Real(x)) }
        })
    }

    fn real3(v: &[Ex]) -> Option<DVec3> {
        let mut c = [0.0; 3];
        for (i, e) in v.iter().enumerate() {
            match e.value? {
                Value::Real(x) => c[i] = x,
                _ => return None,
            }
        }
        Some(DVec3::from_array(c))
    }

    fn direct(op: char, a: Value, b: Value) -> Option<Value> {
        use Value::*;
        Some(match (op, a, b) {
            ('+', Real(a), Real(b)) => Real(a + b),
            ('-', Real(a), Real(b)) => Real(a - b),
            ('*', Real(a), Real(b)) => Real(a * b),
            ('/', Real(a), Real(b)) if b != 0.0 => Real(a / b),
            ('+', Vector(a), Vector(b)) => Vector(a + b),
            ('-', Vector(a), Vector(b)) => Vector(a - b),
            ('+', Color(a), Color(b)) => Color(a + b),
            ('-', Color(a), Color(b)) => Color(a - b),
            ('*', Color(a), Color(b)) => Color(a * b),
            ('*', Real(s), Vector(v)) | ('*', Vector(v), Real(s)) => Vector(v * s),
            ('*', Real(s), Color(v)) | ('*', Color(v), Real(s)) => Color(v * s),
            ('/', Vector(v), Real(s)) if s != 0.0 => Vector(v / s),
            ('/', Color(v), Real(s)) if s != 0.0 => Color(v / s),
            _ => return None,
        })
    }

    fn bin(op: char, a: Ex, b: Ex) -> Ex {
        let value = match (a.value, b.value) {
            (Some(x), Some(y)) => direct(op, x, y),
            _ => None,
        };
        Ex { text: format!("({} {op} {})", a.text, b.text), value }
    }

    fn neg(a: Ex) -> Ex {
        Ex { text: format!("-{}", a.text), value: a.value.map(|v| -v) }
    }

    /// Well-typed expressions of type `ty`, at most `depth` levels deep.
    fn typed(ty: Ty, depth: u32) -> BoxedStrategy<Ex> {
        let leaf: BoxedStrategy<Ex> = match ty {
            Ty::Real => lit().boxed(),
            Ty::Vector => [lit(), lit(), lit()]
                .prop_map(|v| Ex {
                    text: format!("<{}, {}, {}>", v[0].text, v[1].text, v[2].text),
                    value: real3(&v).map(Value::Vector),
                })
                .boxed(),
            Ty::Color => [lit(), lit(), lit()]
                .prop_map(|v| Ex {
                    text: format!("rgb({}, {}, {})", v[0].text, v[1].text, v[2].text),
                    value: real3(&v).map(Value::Color),
                })
                .boxed(),
        };
        if depth == 0 {
            return leaf;
        }
        let sub = move |t| typed(t, depth - 1);
        let same_op = prop_oneof![Just('+'), Just('-')];
        let mut options: Vec<BoxedStrategy<Ex>> = vec![
            leaf,
            sub(ty).prop_map(neg).boxed(),
            (same_op, sub(ty), sub(ty)).prop_map(|(o, a, b)| bin(o, a, b)).boxed(),
        ];
        match ty {
            Ty::Real => {
                options.push(
                    (prop_oneof![Just('*'), Just('/')], sub(Ty::Real), sub(Ty::Real))
                        .prop_map(|(o, a, b)| bin(o, a, b))
                        .boxed(),
                );
                // Components of vectors may themselves be expressions.
                options.push(
                    [sub(Ty::Real), sub(Ty::Real), sub(Ty::Real)]
                        .prop_map(|v| {
                            let value = real3(&v).map(|c| Value::Real(c.x + c.y * c.z));
                            Ex { text: format!("({} + {} * {})", v[0].text, v[1].text, v[2].text), value }
                        })
                        .boxed(),
                );
            }
            Ty::Vector | Ty::Color => {
                options.push((sub(Ty::Real), sub(ty)).prop_map(|(a, b)| bin('*', a, b)).boxed());
                options.push((sub(ty), sub(Ty::Real)).prop_map(|(a, b)| bin('*', a, b)).boxed());
                options.push((sub(ty), sub(Ty::Real)).prop_map(|(a, b)| bin('/', a, b)).boxed());
                if ty == Ty::Color {
                    options.push((sub(ty), sub(ty)).prop_map(|(a, b)| bin('*', a, b)).boxed());
                }
            }
        }
        proptest::strategy::Union::new(options).boxed()
    }

    fn any_expr() -> impl Strategy<Value = Ex> {
        prop_oneof![typed(Ty::Real, 4), typed(Ty::Vector, 3), typed(Ty::Color, 3)]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

        #[test]
        fn expressions_evaluate_like_direct_computation(e in any_expr()) {
            let got = eval_expr(&e.text);
            match e.value {
                Some(want) => {
                    let got = got.unwrap_or_else(|err| panic!("{}\n{err}", e.text));
                    // Same operations in the same order in f64: bit-identical.
                    prop_assert_eq!(got, want, "{}", e.text);
                }
                None => {
                    let err = got.expect_err(&e.text).to_string();
                    prop_assert!(err.contains("division by zero"), "{}: {}", e.text, err);
                }
            }
        }

        #[test]
        fn no_input_panics(text in "[ -~\n]{0,200}") {
            let _ = parse_scn_str("fuzz.scn", &text, Path::new("/nonexistent"));
        }

        #[test]
        fn token_soup_never_panics(words in proptest::collection::vec(prop_oneof![
            Just("sphere"), Just("box"), Just("mesh"), Just("object"), Just("light"), Just("camera"),
            Just("define"), Just("material"), Just("transform"), Just("{"), Just("}"), Just("<"), Just(">"),
            Just(","), Just("1"), Just("-"), Just("*"), Just("/"), Just("rgb("), Just(")"), Just("center"),
            Just("radius"), Just("x"), Just("vertices"), Just("triangles"), Just("finish"), Just("color"),
        ], 0..60)) {
            let _ = parse_scn_str("fuzz.scn", &words.join(" "), Path::new("/nonexistent"));
        }
    }
}

// ---- the example scenes ---------------------------------------------------------------

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

#[test]
fn example_whitted() {
    let s = load_scn(&examples_dir().join("whitted.scn")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.actors.len(), 64 + 2, "64 tiles and two spheres");
    assert_eq!(s.lights.len(), 2);
    assert!(s.camera.is_some());
    assert_eq!(s.materials.len(), 4);
    let glass = s.materials.iter().find(|m| m.name == "glass").unwrap();
    assert!(glass.transparency.x > 0.5 && glass.ior == 1.5);
}

#[test]
fn example_seed_examples() {
    let s = load_scn(&examples_dir().join("seed_examples.scn")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.actors.len(), 3, "unit cube and two ellipsoids");
    assert_eq!(s.lights.len(), 1, "luz1 is only defined");
    assert_eq!(s.actors[0].world_mesh().triangle_count(), 12);
    // The ellipsoids: bola scaled by <2,1,1> then moved to (-1,-1,0), and by <1,2,1> to (1,1,0).
    let b = s.actors[1].world_mesh().bounds();
    assert!(close(b.min, v(-3., -2., -1.)) && close(b.max, v(1., 0., 1.)), "{b:?}");
    let b = s.actors[2].world_mesh().bounds();
    assert!(close(b.min, v(0., -1., -1.)) && close(b.max, v(2., 3., 1.)), "{b:?}");
}

#[test]
fn example_materials_file_defines_only() {
    let s = load_scn(&examples_dir().join("materials.scn")).unwrap_or_else(|e| panic!("{e}"));
    assert!(s.actors.is_empty() && s.lights.is_empty() && s.camera.is_none());
}

/// The bunny scene names the bunny relative to `examples/` as it sits in the main
/// checkout (`../../shared/…`). In another layout (a separate worktree), the same text
/// is parsed with the path pointed at the shared folder found above the checkout.
#[test]
fn example_bunny_with_included_materials() {
    let dir = examples_dir();
    let path = dir.join("bunny.scn");
    let rel = "../../shared/scenes/bunny/bun_zipper.ply";
    let s = if dir.join(rel).exists() {
        load_scn(&path)
    } else {
        let Some(shared) = dir.ancestors().map(|a| a.join("shared/scenes/bunny/bun_zipper.ply")).find(|p| p.exists())
        else {
            eprintln!("skipping: no shared/scenes/bunny/bun_zipper.ply above {}", dir.display());
            return;
        };
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(rel));
        parse_scn_str("bunny.scn", &text.replace(rel, &shared.to_string_lossy()), &dir)
    }
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.actors.len(), 2, "bunny and floor");
    assert_eq!(s.lights.len(), 2);
    assert_eq!(s.actors[0].world_mesh().triangle_count(), 69451);
    let b = s.actors[0].world_mesh().bounds();
    assert!(b.min.y.abs() < 0.01, "the bunny sits on the floor: {b:?}");
    assert_eq!(s.materials[s.actors[0].materials[0] as usize].name, "glossy_brick");
}

/// Every ```scn block of the reference parses on its own (includes resolve from
/// `examples/`), so the documentation cannot drift from the parser.
#[test]
fn reference_examples_parse() {
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scene-language.md")).unwrap();
    let mut blocks = 0;
    let mut rest = doc.as_str();
    while let Some(start) = rest.find("```scn\n") {
        let body = &rest[start + 7..];
        let end = body.find("```").expect("closed block");
        let text = &body[..end];
        parse_scn_str("doc.scn", text, &examples_dir()).unwrap_or_else(|e| panic!("doc example fails:\n{text}\n{e}"));
        blocks += 1;
        rest = &body[end + 3..];
    }
    assert!(blocks >= 14, "only {blocks} examples found");
}
