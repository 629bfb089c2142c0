//! The Mitsuba 3 scene loader: one test per element it reads, the shared reference and
//! Cornell box files, and every error path (each naming the file and line).

use dynray_scene::{load_file, load_file_report, BsdfKind, Clip, Color, LightKind, Microfacet, Projection, Scene};
use glam::Vec3;
use std::path::{Path, PathBuf};

fn shared(rel: &str) -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared").join(rel);
    assert!(p.exists(), "{} is missing: the tests need the shared data beside the checkout", p.display());
    p
}

/// Writes `files` (name, text) into a fresh folder and loads the first.
fn load_texts(files: &[(&str, &str)]) -> (tempfile::TempDir, Result<Scene, String>) {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let r = load_file(&dir.path().join(files[0].0)).map_err(|e| e.to_string());
    (dir, r)
}

fn scene_of(body: &str) -> Result<Scene, String> {
    load_texts(&[("s.xml", &format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n"))]).1
}

fn error_of(body: &str) -> String {
    match scene_of(body) {
        Ok(_) => panic!("expected an error for:\n{body}"),
        Err(e) => e,
    }
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

const SENSOR: &str = r#"<sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform></sensor>"#;

#[test]
fn reference_sphere_scene() {
    let r = load_file_report(&shared("reference/sphere/sphere_d2.xml")).unwrap();
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let s = r.scene;
    let cam = s.camera.unwrap();
    assert_eq!(cam.position, Vec3::new(0.0, 1.0, 6.0));
    assert!(close((cam.look_at - cam.position).normalize(), Vec3::new(0.0, -1.0, -6.0).normalize(), 1e-6));
    // fov 40° along x on 256 × 192: 2·atan(tan 20° · 192/256) = 30.537° vertically.
    let Projection::Perspective { fov_y_deg } = cam.projection else { panic!("perspective") };
    let want = 2.0 * ((20f64).to_radians().tan() * 0.75).atan().to_degrees();
    assert!((fov_y_deg as f64 - want).abs() < 1e-4 && (want - 30.537).abs() < 1e-3, "{fov_y_deg}");
    assert_eq!((s.settings.width, s.settings.height, s.settings.spp), (256, 192, Some(4096)));
    assert_eq!(cam.clip, Clip { near: 0.01, far: 100000.0 });
    assert_eq!(s.settings.max_recursion_level, 1, "max_depth 2 is Whitted level 1");
    assert_eq!(s.lights.len(), 1);
    let l = s.lights[0];
    assert_eq!(l.kind, LightKind::Point { position: Vec3::new(0.0, 4.0, 3.0), falloff: 2 });
    assert!(close(l.color, Color::splat(25.0 / std::f32::consts::PI), 1e-5));
    assert_eq!(s.environment.background, Color::ZERO);
    assert_eq!(s.environment.ambient, Color::ZERO);
    assert_eq!(s.actors.len(), 2);
    let f = s.frame(0.0);
    // The sphere: an icosphere of radius 1 at the origin; the plane at y = -1, facing +y.
    assert_eq!(s.actors[0].mesh.triangle_count(), 81_920);
    let b = s.actors[0].bounds();
    assert!(close(b.min, Vec3::splat(-1.0), 1e-5) && close(b.max, Vec3::splat(1.0), 1e-5), "{b:?}");
    let plane = &f.mesh.positions[f.mesh.positions.len() - 4..];
    assert!(plane.iter().all(|p| (p[1] + 1.0).abs() < 1e-4 && (p[0].abs() - 1000.0).abs() < 1e-2));
    let [i0, i1, i2] = f.mesh.indices[f.mesh.indices.len() - 1];
    let p = |i: u32| Vec3::from_array(f.mesh.positions[i as usize]);
    assert!((p(i1) - p(i0)).cross(p(i2) - p(i0)).normalize().y > 0.999, "the plane faces up");
    let diffuse = |m: usize| match s.materials[m].bsdf.map(|b| b.kind) {
        Some(BsdfKind::Diffuse { reflectance }) => reflectance,
        other => panic!("{other:?}"),
    };
    assert_eq!(diffuse(s.actors[0].materials[0] as usize), Color::splat(0.8));
    assert_eq!(diffuse(s.actors[1].materials[0] as usize), Color::splat(0.5));
}

#[test]
fn cornell_box_spectral_and_rgb_files() {
    let s = load_file(&shared("scenes/cornell-box/mitsuba-cbox/cbox.xml")).unwrap();
    assert_eq!(s.actors.len(), 8);
    assert_eq!(
        (s.settings.width, s.settings.height, s.settings.spp, s.settings.max_recursion_level),
        (256, 256, Some(128), 5)
    );
    let lamp: Vec<Color> = s.materials.iter().map(|m| m.emission).filter(|e| e.max_element() > 0.0).collect();
    // Mitsuba 3.9.1 scalar_rgb turns the lamp's spectrum into this colour.
    assert_eq!(lamp.len(), 1);
    assert!(close(lamp[0], Color::new(20.7108, 10.8546, 2.77115), 2e-3), "{}", lamp[0]);
    assert!(s.lights.is_empty());
    let cam = s.camera.unwrap();
    assert_eq!(cam.position, Vec3::new(278.0, 273.0, -800.0));
    // `fov_axis smaller` on a square image: the given angle is vertical.
    let Projection::Perspective { fov_y_deg } = cam.projection else { panic!("perspective") };
    assert!((fov_y_deg - 39.3077).abs() < 1e-4, "{fov_y_deg}");
    // The rgb version: includes, `$` defaults from an included file, and a `ref` to an
    // emitter defined after the include that uses it.
    let rgb = load_file(&shared("scenes/cornell-box/mitsuba-cbox/cbox-rgb.xml")).unwrap();
    assert_eq!(rgb.actors.len(), 8);
    assert_eq!(rgb.settings.spp, Some(256));
    let e: Vec<Color> = rgb.materials.iter().map(|m| m.emission).filter(|e| e.max_element() > 0.0).collect();
    assert_eq!(e, vec![Color::new(18.387, 10.9873, 2.75357)]);
    // The luminaire sits 0.5 below the ceiling and faces down.
    let f = rgb.frame(0.0);
    let lamp_actor = rgb.actors.iter().position(|a| rgb.materials[a.materials[0] as usize].emission.x > 0.0).unwrap();
    let r = f.actor_ranges[lamp_actor].clone();
    let [i0, i1, i2] = f.mesh.indices[r.start as usize];
    let p = |i: u32| Vec3::from_array(f.mesh.positions[i as usize]);
    assert!((p(i0).y - 548.3).abs() < 1e-3);
    assert!((p(i1) - p(i0)).cross(p(i2) - p(i0)).y < 0.0);
}

#[test]
fn shapes_transforms_and_bsdfs() {
    let s = scene_of(&format!(
        r#"{SENSOR}
        <shape type="rectangle"><transform name="to_world"><matrix value="2 0 0 1  0 2 0 0  0 0 2 0  0 0 0 1"/></transform>
            <bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>
        <shape type="cube"><transform name="to_world"><scale x="1" y="2" z="3"/><translate x="10"/></transform>
            <bsdf type="roughconductor"><rgb name="eta" value="1.5"/><rgb name="k" value="0, 1, 2"/></bsdf></shape>
        <shape type="sphere"><float name="radius" value="0.5"/><point name="center" value="0, 3, 0"/>
            <bsdf type="twosided"><bsdf type="roughconductor"><string name="distribution" value="ggx"/>
            <float name="alpha_u" value="0.2"/><float name="alpha_v" value="0.4"/></bsdf></bsdf></shape>
        <shape type="sphere" id="glass"><bsdf type="dielectric"><string name="int_ior" value="water"/><float name="ext_ior" value="1.1"/></bsdf>
            <boolean name="flip_normals" value="true"/></shape>"#
    ))
    .unwrap();
    assert_eq!(s.actors.len(), 4);
    let b0 = s.actors[0].bounds();
    assert!(close(b0.min, Vec3::new(-1.0, -2.0, 0.0), 1e-6) && close(b0.max, Vec3::new(3.0, 2.0, 0.0), 1e-6), "{b0:?}");
    let b1 = s.actors[1].bounds();
    assert!(
        close(b1.min, Vec3::new(9.0, -2.0, -3.0), 1e-5) && close(b1.max, Vec3::new(11.0, 2.0, 3.0), 1e-5),
        "{b1:?}"
    );
    let b2 = s.actors[2].bounds();
    assert!(close(b2.min, Vec3::new(-0.5, 2.5, -0.5), 1e-5) && close(b2.max, Vec3::new(0.5, 3.5, 0.5), 1e-5), "{b2:?}");
    let bsdf = |a: usize| s.materials[s.actors[a].materials[0] as usize].bsdf.unwrap();
    match bsdf(0).kind {
        BsdfKind::Conductor { eta, k, roughness: None, .. } => {
            assert!(
                close(eta, Vec3::new(0.143036, 0.375307, 1.442045), 1e-6)
                    && close(k, Vec3::new(3.982997, 2.385556, 1.603359), 1e-6)
            )
        }
        other => panic!("{other:?}"),
    }
    match bsdf(1).kind {
        BsdfKind::Conductor { eta, k, roughness: Some(r), .. } => {
            assert_eq!((eta, k), (Color::splat(1.5), Color::new(0.0, 1.0, 2.0)));
            assert_eq!((r.distribution, r.alpha_u, r.alpha_v), (Microfacet::Beckmann, 0.1, 0.1));
        }
        other => panic!("{other:?}"),
    }
    let b = bsdf(2);
    assert!(b.two_sided);
    match b.kind {
        BsdfKind::Conductor { roughness: Some(r), .. } => {
            assert_eq!((r.distribution, r.alpha_u, r.alpha_v), (Microfacet::Ggx, 0.2, 0.4))
        }
        other => panic!("{other:?}"),
    }
    match bsdf(3).kind {
        BsdfKind::Dielectric { int_ior, ext_ior, .. } => assert_eq!((int_ior, ext_ior), (1.333, 1.1)),
        other => panic!("{other:?}"),
    }
    // flip_normals turns the sphere inside out: its normals point to the centre.
    let glass = &s.actors[3];
    assert!(glass
        .mesh
        .normals
        .as_ref()
        .unwrap()
        .iter()
        .zip(&glass.mesh.positions)
        .all(|(n, p)| Vec3::from_array(*n).dot(Vec3::from_array(*p)) < 0.0));
    assert_eq!(glass.name.as_deref(), Some("glass"));
}

#[test]
fn default_bsdf_emitters_and_fov_axes() {
    let s = scene_of(
        r#"<sensor type="perspective"><float name="fov" value="60"/><string name="fov_axis" value="y"/>
            <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/></film></sensor>
        <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
        <emitter type="constant"><spectrum name="radiance" value="1"/></emitter>
        <emitter type="point"><transform name="to_world"><translate x="1" y="2" z="3"/></transform><float name="intensity" value="2"/></emitter>"#,
    )
    .unwrap();
    let m = &s.materials[s.actors[0].materials[0] as usize];
    assert_eq!(m.emission, Color::new(1.0, 2.0, 3.0));
    // Mitsuba's default BSDF is diffuse 0.5, but black on an emitter (shape.cpp): a lamp
    // reflects nothing.
    assert_eq!(m.bsdf.unwrap().kind, BsdfKind::Diffuse { reflectance: Color::ZERO });
    assert_eq!(m.diffuse, Color::ZERO);
    // A flat spectrum of 1 in an emitter is E white, not sRGB white (Mitsuba 3.9.1).
    assert!(close(s.environment.background, Color::new(1.20479, 0.948291, 0.908916), 5e-4));
    assert_eq!(s.lights[0].kind, LightKind::Point { position: Vec3::new(1.0, 2.0, 3.0), falloff: 2 });
    assert_eq!(s.camera.unwrap().projection, Projection::Perspective { fov_y_deg: 60.0 });
    // Mitsuba's default clip planes.
    assert_eq!(s.camera.unwrap().clip, Clip { near: 1e-2, far: 1e4 });
    assert_eq!(s.settings.max_recursion_level, 64, "no integrator: unbounded depth, capped");
    for (axis, w, h, want) in [
        ("x", 200, 100, 32.2042),
        ("smaller", 100, 200, 32.2042),
        ("larger", 200, 100, 32.2042),
        ("diagonal", 300, 400, 49.5826),
    ] {
        let s = scene_of(&format!(
            r#"<sensor type="perspective"><float name="fov" value="60"/><string name="fov_axis" value="{axis}"/>
            <film type="hdrfilm"><integer name="width" value="{w}"/><integer name="height" value="{h}"/></film></sensor>"#
        ))
        .unwrap();
        let Projection::Perspective { fov_y_deg } = s.camera.unwrap().projection else { panic!() };
        let want = if axis == "smaller" {
            2.0 * ((30f32).to_radians().tan() * 200.0 / 100.0).atan().to_degrees()
        } else {
            want
        };
        assert!((fov_y_deg - want).abs() < 1e-3, "{axis}: {fov_y_deg} vs {want}");
    }
}

#[test]
fn errors_name_the_file_line_and_element() {
    let cases: &[(&str, &str)] = &[
        ("\n<shape type=\"disk\"/>", "s.xml:3: <shape type=\"disk\"> is not supported"),
        ("<shape type=\"cube\">\n<float name=\"radius\" value=\"2\"/></shape>", "s.xml:3: <shape type=\"cube\">: parameter `radius` (<float>) is not supported"),
        ("<shape type=\"cube\"><ref id=\"nope\"/></shape>", "<ref id=\"nope\">: no element has this id"),
        ("<shape type=\"cube\"><bsdf type=\"plastic\"/></shape>", "<bsdf type=\"plastic\"> is not supported"),
        ("<integer name=\"x\" value=\"$missing\"/>", "`$missing`: no <default name=\"missing\">"),
        ("<integrator type=\"volpath\"/>", "<integrator type=\"volpath\"> is not supported"),
        ("<integrator type=\"path\"><integer name=\"max_depth\" value=\"two\"/></integrator>", "`max_depth`: `two` is not an integer"),
        ("<bsdf type=\"diffuse\" id=\"a\"/><bsdf type=\"diffuse\" id=\"a\"/>", "id `a` is used twice"),
        ("<shape type=\"cube\"><bsdf type=\"twosided\"><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf></shape>", "exactly one nested <bsdf>"),
        ("<shape type=\"cube\"><transform name=\"to_world\"><translate x=\"nan\"/></transform></shape>", "`nan` is not a finite number"),
        ("<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/><transform name=\"to_world\"><scale x=\"-1\"/></transform></sensor>", "mirrors the image"),
        ("<sensor type=\"orthographic\"/>", "<sensor type=\"orthographic\"> is not supported"),
        ("<emitter type=\"spot\"/>", "<emitter type=\"spot\"> is not supported"),
        ("<shape type=\"obj\"><string name=\"filename\" value=\"missing.obj\"/></shape>", "missing.obj"),
        ("<shape type=\"cube\"><bsdf type=\"conductor\"><string name=\"material\" value=\"Unobtainium\"/></bsdf></shape>", "conductor material `Unobtainium` is not known"),
        ("<shape type=\"cube\"><bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"1 2\"/></bsdf></shape>", "an <rgb> value has 1 or 3 numbers"),
        ("<texture type=\"bitmap\"/>", "<texture> is not supported at the top level"),
        ("<shape type=\"cube\"><bsdf type=\"diffuse\"><spectrum name=\"reflectance\" value=\"500:1, 400:2\"/></bsdf></shape>", "wavelength 400 does not increase"),
        ("<shape type=\"cube\" typo=\"1\"/>", "unknown attribute `typo`"),
    ];
    for (body, want) in cases {
        let e = error_of(body);
        assert!(e.contains(want), "for {body}\n  got: {e}\n want: …{want}…");
        assert!(e.contains("s.xml:"), "names the file and line: {e}");
    }
    // Malformed XML: roxmltree's message with the line.
    let (_, r) = load_texts(&[("bad.xml", "<scene version=\"3.0.0\">\n<shape type=\"cube\">\n</scene>\n")]);
    let e = r.unwrap_err();
    assert!(e.contains("bad.xml:3: XML:"), "{e}");
    let (_, r) = load_texts(&[("root.xml", "<shapes/>")]);
    assert!(r.unwrap_err().contains("a Mitsuba scene starts with <scene>"));
}

#[test]
fn includes_defaults_and_cycles() {
    let (_, r) = load_texts(&[
        ("main.xml", "<scene version=\"3.0.0\">\n<default name=\"w\" value=\"33\"/>\n<include filename=\"sub.xml\"/>\n</scene>"),
        ("sub.xml", "<scene version=\"3.0.0\"><sensor type=\"perspective\"><float name=\"fov\" value=\"30\"/><film type=\"hdrfilm\"><integer name=\"width\" value=\"$w\"/></film></sensor></scene>"),
    ]);
    assert_eq!(r.unwrap().settings.width, 33);
    let (_, r) = load_texts(&[
        ("a.xml", "<scene version=\"3.0.0\">\n<include filename=\"b.xml\"/></scene>"),
        ("b.xml", "<scene version=\"3.0.0\">\n\n<include filename=\"a.xml\"/></scene>"),
    ]);
    let e = r.unwrap_err();
    assert!(e.contains("a.xml:2") && e.contains("b.xml:3") && e.contains("include cycle"), "{e}");
}

/// Meshes from files: an OBJ's faces (its own materials dropped for the XML's BSDF)
/// and `face_normals`.
#[test]
fn obj_shapes_take_the_xml_bsdf() {
    let (_, r) = load_texts(&[
        (
            "s.xml",
            "<scene version=\"3.0.0\"><shape type=\"obj\"><string name=\"filename\" value=\"q.obj\"/><boolean name=\"face_normals\" value=\"true\"/>\
             <bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"0.1, 0.2, 0.3\"/></bsdf></shape></scene>",
        ),
        ("q.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n"),
    ]);
    let s = r.unwrap();
    assert_eq!(s.actors.len(), 1);
    assert_eq!(s.actors[0].mesh.triangle_count(), 2);
    assert_eq!(s.actors[0].shading, dynray_scene::Shading::Flat);
    assert_eq!(
        s.materials[s.actors[0].materials[0] as usize].bsdf.unwrap().kind,
        BsdfKind::Diffuse { reflectance: Color::new(0.1, 0.2, 0.3) }
    );
}

/// Regression (issue 43): 200,000 nested elements overflowed the stack (the conversion
/// recurses per level, exit 134); now an error naming the line, at once.
#[test]
fn deeply_nested_elements_are_an_error_not_a_stack_overflow() {
    let n = 200_000;
    let body = format!("{}{}", "<shape type=\"obj\">".repeat(n), "</shape>".repeat(n));
    let e = error_of(&body);
    assert!(e.contains("nested more than 64 deep"), "{e}");
    // Real scenes (the Cornell boxes and the sphere above) load: their depth is a handful.
}
