//! Shared helpers of the loader tests: temp files, a PLY writer for every encoding, the
//! hand-built glTF triangle, and the shared models (skipped with a note when absent).
// Each test binary uses a subset of these helpers.
#![allow(dead_code)]

use dynray_scene::{load_file, Scene};
use std::io::Write;
use std::path::{Path, PathBuf};

pub fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

pub fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

/// Loads a file that must fail and returns the message, checking that it names the file.
pub fn error_of(path: &Path) -> String {
    let e = match load_file(path) {
        Ok(s) => panic!("{} loaded ({} triangles) but should fail", path.display(), s.triangle_count()),
        Err(e) => e,
    };
    let msg = e.to_string();
    assert!(msg.starts_with(&path.display().to_string()), "message does not name the file: {msg}");
    msg
}

/// The only actor's mesh in world space (actors keep theirs in local space).
pub fn one_mesh(s: &Scene) -> dynray_geom::TriangleMesh {
    assert_eq!(s.actors.len(), 1);
    s.actors[0].world_mesh()
}

pub fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes")
}

/// The shared model, or `None` (with a note) when this checkout has no shared scenes.
pub fn model(rel: &str) -> Option<PathBuf> {
    let candidates = [scenes_dir().join(rel), Path::new("/work/shared/scenes").join(rel)];
    let found = candidates.into_iter().find(|p| p.is_file());
    if found.is_none() {
        eprintln!("skipped: {rel} not found under shared/scenes");
    }
    found
}

/// PLY writer for tests: a header and body made from the same description in ASCII or
/// either binary byte order.
#[derive(Clone, Copy, PartialEq)]
pub enum Enc {
    Ascii,
    Le,
    Be,
}

/// A scalar value tagged with its PLY type.
#[derive(Clone, Copy)]
pub enum V {
    U8(u8),
    I32(i32),
    U32(u32),
    U16(u16),
    F32(f32),
    F64(f64),
}

pub fn put(out: &mut Vec<u8>, enc: Enc, v: V) {
    macro_rules! b {
        ($x:expr) => {
            match enc {
                Enc::Le => out.extend_from_slice(&$x.to_le_bytes()),
                Enc::Be => out.extend_from_slice(&$x.to_be_bytes()),
                Enc::Ascii => {
                    out.extend_from_slice(format!("{} ", $x).as_bytes());
                }
            }
        };
    }
    match v {
        V::U8(x) => b!(x),
        V::I32(x) => b!(x),
        V::U32(x) => b!(x),
        V::U16(x) => b!(x),
        V::F32(x) => b!(x),
        V::F64(x) => b!(x),
    }
}

/// Header lines (without `ply`/`format`/`end_header`) and rows of values; each row is
/// one element (one text line in ASCII).
pub fn ply(enc: Enc, header: &str, rows: &[Vec<V>]) -> Vec<u8> {
    let fmt = match enc {
        Enc::Ascii => "ascii",
        Enc::Le => "binary_little_endian",
        Enc::Be => "binary_big_endian",
    };
    let mut out = format!("ply\nformat {fmt} 1.0\ncomment made by the test\n{header}end_header\n").into_bytes();
    for row in rows {
        for &v in row {
            put(&mut out, enc, v);
        }
        if enc == Enc::Ascii {
            out.push(b'\n');
        }
    }
    out
}

pub fn vtx(x: f32, y: f32, z: f32) -> Vec<V> {
    vec![V::F32(x), V::F32(y), V::F32(z)]
}

pub fn face(ix: &[i32]) -> Vec<V> {
    let mut r = vec![V::U8(ix.len() as u8)];
    r.extend(ix.iter().map(|&i| V::I32(i)));
    r
}

pub const XYZ: &str = "property float x\nproperty float y\nproperty float z\n";

/// Five vertices of a pentagon, one pentagon face and one quad face.
pub fn pentagon_rows() -> Vec<Vec<V>> {
    vec![
        vtx(1.0, 0.0, 0.0),
        vtx(0.3, 0.95, 0.0),
        vtx(-0.8, 0.6, 0.0),
        vtx(-0.8, -0.6, 0.0),
        vtx(0.3, -0.95, 0.0),
        face(&[0, 1, 2, 3, 4]),
        face(&[4, 3, 2, 1]),
    ]
}

pub fn pentagon_header() -> String {
    format!("element vertex 5\n{XYZ}element face 2\nproperty list uchar int vertex_indices\n")
}

pub const PENTAGON_FAN: [[u32; 3]; 5] = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [4, 3, 2], [4, 2, 1]];

/// A one-triangle glTF with its buffer in `tri.bin` and `extra` spliced into the
/// primitive; `count` is the POSITION accessor's count.
pub fn gltf_triangle(dir: &Path, name: &str, count: usize, prim_extra: &str, doc_extra: &str) -> PathBuf {
    let mut bin = Vec::new();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        bin.extend_from_slice(&v.to_le_bytes());
    }
    for i in [0u16, 1, 2, 7] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    write(dir, "tri.bin", &bin);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"mesh":0,"translation":[0,0,5]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}{prim_extra}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":{count},"type":"VEC3","max":[1,1,0],"min":[0,0,0]}},
                     {{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}},
                     {{"bufferView":1,"byteOffset":2,"componentType":5123,"count":3,"type":"SCALAR"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":8}}],
        "buffers":[{{"byteLength":44,"uri":"tri.bin"}}]{doc_extra}}}"#
    );
    write(dir, name, json.as_bytes())
}
