//! Meshes given as numpy arrays in an `.npz`: every accepted dtype and order gives the
//! same mesh, and every bad input is an error naming the file and the array.

use dynray_scene::formats::npz;
use dynray_scene::{load_file, LoadError, NormalSource, DEFAULT_CREASE_DEG};
use npyz::npz::NpzWriter;
use npyz::{AutoSerialize, Order, WriterBuilder};
use std::path::Path;

const VERTICES: [[f64; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.5]];
const FACES: [[i64; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

/// Writes `(name, rows, order)` arrays of element type `T` (rows of 3, or other widths
/// given as flat data with `shape`).
fn add<T: AutoSerialize + Copy>(npz: &mut NpzWriter<std::fs::File>, name: &str, rows: &[[T; 3]], order: Order) {
    let flat: Vec<T> = match order {
        Order::C => rows.iter().flatten().copied().collect(),
        Order::Fortran => (0..3).flat_map(|j| rows.iter().map(move |r| r[j])).collect(),
    };
    let mut w = npz
        .array::<T>(name, Default::default())
        .unwrap()
        .default_dtype()
        .shape(&[rows.len() as u64, 3])
        .order(order)
        .begin_nd()
        .unwrap();
    w.extend(flat).unwrap();
    w.finish().unwrap();
}

/// Fills an archive with arrays.
type Fill = Box<dyn Fn(&mut NpzWriter<std::fs::File>)>;

fn archive(path: &Path, fill: impl FnOnce(&mut NpzWriter<std::fs::File>)) {
    let mut npz = NpzWriter::new(std::fs::File::create(path).unwrap());
    fill(&mut npz);
    npz.zip_writer().finish().unwrap();
}

#[test]
fn every_dtype_and_order_gives_the_same_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.npz");
    archive(&plain, |z| {
        add(z, "vertices", &VERTICES.map(|v| v.map(|x| x as f32)), Order::C);
        add(z, "faces", &FACES, Order::C);
    });
    let want = npz::load(&plain).unwrap();
    assert_eq!(want.positions[3], [0.0, 0.0, 1.5]);
    assert_eq!(want.indices, vec![[0, 1, 2], [0, 2, 3]]);
    let variants: [(&str, Fill); 3] = [
        (
            "f64 Fortran, u32",
            Box::new(|z| {
                add(z, "vertices", &VERTICES, Order::Fortran);
                add(z, "faces", &FACES.map(|f| f.map(|i| i as u32)), Order::C);
            }),
        ),
        (
            "f32, i32 Fortran",
            Box::new(|z| {
                add(z, "vertices", &VERTICES.map(|v| v.map(|x| x as f32)), Order::C);
                add(z, "faces", &FACES.map(|f| f.map(|i| i as i32)), Order::Fortran);
            }),
        ),
        (
            "f64, u64",
            Box::new(|z| {
                add(z, "vertices", &VERTICES, Order::C);
                add(z, "faces", &FACES.map(|f| f.map(|i| i as u64)), Order::C);
            }),
        ),
    ];
    for (i, (what, fill)) in variants.iter().enumerate() {
        let path = dir.path().join(format!("v{i}.npz"));
        archive(&path, fill);
        assert_eq!(npz::load(&path).unwrap(), want, "{what}");
    }
    // The general loader knows the extension and gives a scene with one actor.
    let scene = load_file(&plain).unwrap();
    assert_eq!(scene.actors.len(), 1);
    assert_eq!(scene.frame(0.0).mesh.triangle_count(), 2);
    // Arrays have no normals: rendering gets smooth ones (the fold is 90°: split), and
    // the triangles keep their positions.
    let a = &scene.actors[0];
    assert_eq!(a.normal_source, NormalSource::Generated { crease_deg: DEFAULT_CREASE_DEG, split_vertices: 2 });
    for (t, want) in FACES.iter().enumerate() {
        for k in 0..3 {
            assert_eq!(a.mesh.positions[a.mesh.indices[t][k] as usize], want_positions(&want.map(|i| i as usize))[k]);
        }
    }
}

fn want_positions(face: &[usize; 3]) -> [[f32; 3]; 3] {
    face.map(|i| VERTICES[i].map(|x| x as f32))
}

#[test]
fn bad_arrays_are_errors_naming_the_file_and_the_array() {
    let dir = tempfile::tempdir().unwrap();
    let f32v = VERTICES.map(|v| v.map(|x| x as f32));
    let cases: Vec<(&str, Fill, &str)> = vec![
        ("no-faces", Box::new(move |z| add(z, "vertices", &f32v, Order::C)), "no array `faces`"),
        (
            "negative",
            Box::new(move |z| {
                add(z, "vertices", &f32v, Order::C);
                add(z, "faces", &[[0i64, -1, 2]], Order::C);
            }),
            "faces row 0: index -1 is outside 0..4",
        ),
        (
            "too-big",
            Box::new(move |z| {
                add(z, "vertices", &f32v, Order::C);
                add(z, "faces", &[[0i64, 1, 2], [0, 1, 4]], Order::C);
            }),
            "faces row 1: index 4",
        ),
        (
            "float-faces",
            Box::new(move |z| {
                add(z, "vertices", &f32v, Order::C);
                add(z, "faces", &[[0.0f32, 1.0, 2.0]], Order::C);
            }),
            "array `faces`: dtype must be int32",
        ),
        (
            "nan",
            Box::new(move |z| {
                add(z, "vertices", &[[0.0f32, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]], Order::C);
                add(z, "faces", &[[0i64, 1, 2]], Order::C);
            }),
            "nan.npz",
        ),
    ];
    for (name, fill, needle) in cases {
        let path = dir.path().join(format!("{name}.npz"));
        archive(&path, fill);
        let e = npz::load(&path).unwrap_err();
        let text = e.to_string();
        assert!(text.contains(&format!("{name}.npz")) && text.contains(needle), "{name}: {text}");
        assert!(matches!(e, LoadError::Parse { .. } | LoadError::Mesh { .. }), "{name}: {e:?}");
    }
    // A (K, 2) array is a shape error.
    let flat = dir.path().join("shape.npz");
    let mut z = NpzWriter::new(std::fs::File::create(&flat).unwrap());
    let mut w =
        z.array::<f32>("vertices", Default::default()).unwrap().default_dtype().shape(&[2, 2]).begin_nd().unwrap();
    w.extend([0.0f32; 4]).unwrap();
    w.finish().unwrap();
    z.zip_writer().finish().unwrap();
    let e = npz::load(&flat).unwrap_err().to_string();
    assert!(e.contains("array `vertices`: shape must be (K, 3), found [2, 2]"), "{e}");
    // Not a zip at all.
    let junk = dir.path().join("junk.npz");
    std::fs::write(&junk, b"not a zip").unwrap();
    assert!(npz::load(&junk).unwrap_err().to_string().contains("junk.npz"));
}
