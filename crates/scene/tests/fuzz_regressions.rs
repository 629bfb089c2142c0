//! Inputs the fuzz targets found (docs/fuzzing.md, "Findings"), minimised, each a clean
//! error naming the file now. Each test is named after what the input did before.

use dynray_scene::formats::npz::{check_npy_header, MAX_NPY_HEADER_BYTES};
use dynray_scene::load_file;
use std::io::Write;
use std::path::Path;
use std::time::{Duration, Instant};

/// A version-1 `.npy` of `header` (padded as numpy pads it) and `data`.
fn npy(header: &str, data: &[u8]) -> Vec<u8> {
    let mut h = header.to_string();
    h.push_str(&" ".repeat((64 - (10 + h.len() + 1) % 64) % 64));
    h.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(h.len() as u16).to_le_bytes());
    out.extend_from_slice(h.as_bytes());
    out.extend_from_slice(data);
    out
}

/// An `.npz` holding `vertices.npy` and `faces.npy` as given, stored.
fn write_npz(path: &Path, vertices: &[u8], faces: &[u8]) {
    let mut npz = npyz::npz::NpzWriter::new(std::fs::File::create(path).unwrap());
    let zip = npz.zip_writer();
    for (name, bytes) in [("vertices.npy", vertices), ("faces.npy", faces)] {
        zip.start_file(name, Default::default()).unwrap();
        zip.write_all(bytes).unwrap();
    }
    zip.finish().unwrap();
}

/// Found by the `npy` target: 30 unclosed brackets in an array's header sent npyz's
/// header parser (py_literal, a backtracking grammar) into time exponential in the
/// nesting — 20 took 40 s, 30 would take hours. Refused before npyz parses it now.
#[test]
fn a_deeply_nested_npy_header_hung_the_reader() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nested.npz");
    let header = format!("{{'descr': '<f4', {} 'fortran_order': False, 'shape': (1, 3), }}", "[".repeat(30));
    let faces = npy("{'descr': '<i4', 'fortran_order': False, 'shape': (1, 3), }", &[0; 12]);
    write_npz(&path, &npy(&header, &[0; 12]), &faces);
    let start = Instant::now();
    let e = load_file(&path).unwrap_err().to_string();
    assert!(start.elapsed() < Duration::from_secs(5), "{:?}", start.elapsed());
    assert!(e.contains("nested.npz") && e.contains("array `vertices`") && e.contains("nests brackets"), "{e}");
}

#[test]
fn npy_headers_are_checked_for_length_and_nesting_only() {
    // What numpy writes, structured or not, quoted brackets included.
    let plain = npy("{'descr': '<f4', 'fortran_order': False, 'shape': (7, 3), }", &[]);
    assert_eq!(check_npy_header(&plain), Ok(()));
    let quoted = npy("{'descr': '<f4', 'x': '[[[[\\'(((', 'shape': (7, 3), }", &[]);
    assert_eq!(check_npy_header(&quoted), Ok(()));
    // Three levels (a structured dtype's list of fields) is past what dynray reads.
    let structured = npy("{'descr': [('x', '<f4')], 'fortran_order': False, 'shape': (7,), }", &[]);
    assert!(check_npy_header(&structured).unwrap_err().contains("more than 2 deep"));
    // Version 2 gives a 4-byte length: past numpy's own limit is an error, read or not.
    let mut long = b"\x93NUMPY\x02\x00".to_vec();
    long.extend_from_slice(&(MAX_NPY_HEADER_BYTES as u32 + 1).to_le_bytes());
    assert!(check_npy_header(&long).unwrap_err().contains("10001 bytes"));
    // Not an .npy at all, or cut short: npyz's to report.
    assert_eq!(check_npy_header(b"PK\x03\x04"), Ok(()));
    assert_eq!(check_npy_header(b"\x93NUMPY\x02\x00\x10"), Ok(()));
}

/// Found by the `gltf` target: a GLB whose header gives a total length below its own 12
/// bytes underflowed gltf's `length - 12` (a panic with overflow checks, a wrapped
/// length without).
#[test]
fn a_glb_shorter_than_its_header_underflowed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("short.glb");
    let json = br#"{"asset":{"version":"2.0"}}  "#;
    let mut glb = b"glTF".to_vec();
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(json);
    std::fs::write(&path, &glb).unwrap();
    let e = load_file(&path).unwrap_err().to_string();
    assert!(e.contains("short.glb") && e.contains("total length of 2 bytes"), "{e}");
    // The same file with its true length loads (it has no meshes: that error instead).
    let total = glb.len() as u32;
    glb[8..12].copy_from_slice(&total.to_le_bytes());
    std::fs::write(&path, &glb).unwrap();
    let e = load_file(&path).unwrap_err().to_string();
    assert!(!e.contains("total length"), "{e}");
}

/// Found by the `gltf` target: an animation channel whose target path is not one glTF
/// defines (`"trans(ation"`) passed gltf-json's validation, which skips channel targets,
/// and the gltf crate's `property()` then unwrapped it: a panic in every build.
#[test]
fn an_unknown_animation_path_panicked() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("path.gltf");
    let gltf = r#"{
      "asset": {"version": "2.0"},
      "scenes": [{"nodes": [0]}],
      "nodes": [{"name": "n", "mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 2}}]}],
      "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 1, "type": "SCALAR"},
                    {"bufferView": 0, "componentType": 5126, "count": 1, "type": "VEC3"},
                    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}],
      "animations": [{"samplers": [{"input": 0, "output": 1}],
                      "channels": [{"sampler": 0, "target": {"node": 0, "path": "trans(ation"}}]}]
    }"#;
    std::fs::write(&path, gltf).unwrap();
    let e = load_file(&path).unwrap_err().to_string();
    assert!(e.contains("path.gltf") && e.contains("channel 0: the target path is not one of"), "{e}");
}
