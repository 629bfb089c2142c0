//! Loader tests: every format on hand-built files (ASCII/binary/gzip PLY, OBJ/MTL, glTF),
//! one test per bad-input case with the message checked, a cheap seeded fuzz loop per
//! parser, and the real models of `shared/scenes` with their published counts.

use dynray_scene::{load_file, load_file_report, LightKind, LoadError, Scene};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::io::Write;
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------
// allocation meter: "fails fast without allocating" is checked, not assumed

/// The system allocator, counting live bytes per thread so a test can measure the peak
/// its own loading reached while other tests run on other threads.
struct Metered;

thread_local! {
    static LIVE: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
}

fn track(delta: isize) {
    // `try_with`: allocations during thread teardown find the slots gone; skip them.
    let _ = LIVE.try_with(|live| {
        let now = live.get() + delta;
        live.set(now);
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(now)));
    });
}

// SAFETY: every call forwards to `System` with the caller's arguments unchanged; the
// bookkeeping touches only const-initialised thread-locals, which never allocate.
unsafe impl GlobalAlloc for Metered {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            track(layout.size() as isize);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        track(-(layout.size() as isize));
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            track(new_size as isize - layout.size() as isize);
        }
        p
    }
}

#[global_allocator]
static METER: Metered = Metered;

/// Peak bytes allocated (above the level at the start) by this thread while `f` runs.
fn peak_bytes(f: impl FnOnce()) -> usize {
    let start = LIVE.with(Cell::get);
    PEAK.with(|p| p.set(start));
    f();
    (PEAK.with(Cell::get) - start).max(0) as usize
}

// ---------------------------------------------------------------------------------------
// helpers

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

/// Loads a file that must fail and returns the message, checking that it names the file.
fn error_of(path: &Path) -> String {
    let e = match load_file(path) {
        Ok(s) => panic!("{} loaded ({} triangles) but should fail", path.display(), s.triangle_count()),
        Err(e) => e,
    };
    let msg = e.to_string();
    assert!(msg.starts_with(&path.display().to_string()), "message does not name the file: {msg}");
    msg
}

fn one_mesh(s: &Scene) -> &dynray_geom::TriangleMesh {
    assert_eq!(s.actors.len(), 1);
    &s.actors[0].mesh
}

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes")
}

/// The shared model, or `None` (with a note) when this checkout has no shared scenes.
fn model(rel: &str) -> Option<PathBuf> {
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
enum Enc {
    Ascii,
    Le,
    Be,
}

/// A scalar value tagged with its PLY type.
#[derive(Clone, Copy)]
enum V {
    U8(u8),
    I32(i32),
    U32(u32),
    U16(u16),
    F32(f32),
    F64(f64),
}

fn put(out: &mut Vec<u8>, enc: Enc, v: V) {
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
fn ply(enc: Enc, header: &str, rows: &[Vec<V>]) -> Vec<u8> {
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

fn vtx(x: f32, y: f32, z: f32) -> Vec<V> {
    vec![V::F32(x), V::F32(y), V::F32(z)]
}

fn face(ix: &[i32]) -> Vec<V> {
    let mut r = vec![V::U8(ix.len() as u8)];
    r.extend(ix.iter().map(|&i| V::I32(i)));
    r
}

const XYZ: &str = "property float x\nproperty float y\nproperty float z\n";

/// Five vertices of a pentagon, one pentagon face and one quad face.
fn pentagon_rows() -> Vec<Vec<V>> {
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

fn pentagon_header() -> String {
    format!("element vertex 5\n{XYZ}element face 2\nproperty list uchar int vertex_indices\n")
}

const PENTAGON_FAN: [[u32; 3]; 5] = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [4, 3, 2], [4, 2, 1]];

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
    assert_eq!(s.camera, None, "and a framing camera");
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
// bad input: one test each, message checked

#[test]
fn missing_file_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["absent.ply", "absent.obj", "absent.glb", "absent.gltf", "absent.ply.gz"] {
        let p = dir.path().join(name);
        assert!(matches!(load_file(&p), Err(LoadError::Io { .. })));
        error_of(&p);
    }
}

#[test]
fn unknown_extension_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "model.stl", b"solid x\n");
    assert!(matches!(load_file(&p), Err(LoadError::UnknownFormat { .. })));
    let msg = error_of(&p);
    assert!(msg.contains("unknown file type"), "{msg}");
    // Decided by name before reading: a missing file of unknown type says so too.
    assert!(matches!(load_file(Path::new("nowhere/x.3ds")), Err(LoadError::UnknownFormat { .. })));
}

#[test]
fn truncated_ascii_ply_says_how_many_elements_were_found() {
    let dir = tempfile::tempdir().unwrap();
    let mut rows = pentagon_rows();
    rows.truncate(3); // 3 of 5 vertices, no faces
    let p = write(dir.path(), "cut.ply", &ply(Enc::Ascii, &pentagon_header(), &rows));
    let msg = error_of(&p);
    assert!(msg.contains("file ends after 3 of the 5 `vertex` elements"), "{msg}");
}

#[test]
fn truncated_binary_ply_says_where_it_ends() {
    let dir = tempfile::tempdir().unwrap();
    for enc in [Enc::Le, Enc::Be] {
        let full = ply(enc, &pentagon_header(), &pentagon_rows());
        // Cut in the middle of vertex 2's y coordinate.
        let body_start = full.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let p = write(dir.path(), "cut.ply", &full[..body_start + 12 * 2 + 6]);
        let msg = error_of(&p);
        assert!(msg.contains("file ends inside `vertex` element 2 of the 5"), "{msg}");
        // Cut inside the last face's index list.
        let p = write(dir.path(), "cut2.ply", &full[..full.len() - 3]);
        let msg = error_of(&p);
        assert!(msg.contains("file ends inside `face` element 1 of the 2"), "{msg}");
    }
}

#[test]
fn lying_header_claiming_more_faces_fails() {
    let dir = tempfile::tempdir().unwrap();
    let h = pentagon_header().replace("element face 2", "element face 7");
    let p = write(dir.path(), "lie.ply", &ply(Enc::Ascii, &h, &pentagon_rows()));
    assert!(error_of(&p).contains("file ends after 2 of the 7 `face` elements"));
    let p = write(dir.path(), "lie_bin.ply", &ply(Enc::Le, &h, &pentagon_rows()));
    assert!(error_of(&p).contains("file ends inside `face` element 2 of the 7"));
}

#[test]
fn absurd_counts_fail_fast_without_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let h =
        format!("element vertex 99999999999\n{XYZ}element face 99999999999\nproperty list uint uint vertex_indices\n");
    let rows = vec![vtx(0.0, 0.0, 0.0)];
    for (enc, what) in
        [(Enc::Ascii, "file ends after 1 of the 99999999999 `vertex`"), (Enc::Le, "inside `vertex` element 1")]
    {
        let p = write(dir.path(), "huge.ply", &ply(enc, &h, &rows));
        let msg = error_of(&p);
        assert!(msg.contains(what), "{msg}");
    }
    // A face claiming 4 billion indices in a tiny body.
    let h = format!("element vertex 3\n{XYZ}element face 1\nproperty list uint uint vertex_indices\n");
    let rows = vec![vtx(0.0, 0.0, 0.0), vtx(1.0, 0.0, 0.0), vtx(0.0, 1.0, 0.0), vec![V::U32(u32::MAX), V::U32(0)]];
    let p = write(dir.path(), "list.ply", &ply(Enc::Be, &h, &rows));
    assert!(error_of(&p).contains("file ends inside `face` element 0"));
    // None of these may allocate anywhere near what the counts claim (the meter itself
    // is checked on a 2 MiB buffer first).
    assert!(peak_bytes(|| drop(std::hint::black_box(vec![1u8; 2 << 20]))) >= 2 << 20);
    let h =
        format!("element vertex 99999999999\n{XYZ}element face 99999999999\nproperty list uint uint vertex_indices\n");
    for enc in [Enc::Ascii, Enc::Le, Enc::Be] {
        let p = write(dir.path(), "huge.ply", &ply(enc, &h, &[vtx(0.0, 0.0, 0.0)]));
        let peak = peak_bytes(|| assert!(load_file(&p).is_err()));
        assert!(peak < 1 << 20, "{peak} bytes allocated for a {}-byte file", std::fs::metadata(&p).unwrap().len());
    }
    let peak = peak_bytes(|| assert!(load_file(&dir.path().join("list.ply")).is_err()));
    assert!(peak < 1 << 20, "{peak} bytes for a list claiming 4 billion indices");
    let p = gltf_triangle(dir.path(), "huge.gltf", u32::MAX as usize, "", "");
    let peak = peak_bytes(|| assert!(load_file(&p).is_err()));
    assert!(peak < 1 << 20, "{peak} bytes for a glTF accessor claiming 4 billion vertices");
    // A count too large even for u64.
    let p = write(dir.path(), "big.ply", b"ply\nformat ascii 1.0\nelement vertex 1e99\nend_header\n");
    assert!(error_of(&p).contains(":3: element count `1e99`"));
}

#[test]
fn face_index_out_of_range_names_the_face() {
    let dir = tempfile::tempdir().unwrap();
    let mut rows = pentagon_rows();
    rows[6] = face(&[4, 3, 9, 1]);
    let p = write(dir.path(), "oob.ply", &ply(Enc::Ascii, &pentagon_header(), &rows));
    let msg = error_of(&p);
    // The header is 10 lines (ply, format, comment, 4 + 2 declarations, end_header): the
    // faces are body lines 6 and 7, i.e. file lines 16 and 17.
    assert!(msg.contains(":17: face 1 uses vertex 9, but the file has 5 vertices"), "{msg}");
    let p = write(dir.path(), "oob.ply", &ply(Enc::Le, &pentagon_header(), &rows));
    assert!(error_of(&p).contains("face 1 uses vertex 9"));
    rows[6] = face(&[4, 3, -1, 1]);
    let p = write(dir.path(), "neg.ply", &ply(Enc::Be, &pentagon_header(), &rows));
    assert!(error_of(&p).contains("face 1 has an invalid vertex index -1"));
}

#[test]
fn non_finite_coordinates_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    for (enc, bad) in [(Enc::Ascii, f32::NAN), (Enc::Le, f32::INFINITY), (Enc::Be, f32::NEG_INFINITY)] {
        let mut rows = pentagon_rows();
        rows[2] = vtx(0.0, bad, 0.0);
        let p = write(dir.path(), "nan.ply", &ply(enc, &pentagon_header(), &rows));
        let msg = error_of(&p);
        assert!(msg.contains("vertex 2 has a non-finite coordinate"), "{msg}");
    }
    let p = write(dir.path(), "nan.obj", b"v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
    assert!(error_of(&p).contains("nan.obj:3: `v`: a coordinate must be finite, found NaN"));
    let p = write(dir.path(), "inf.obj", b"v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(error_of(&p).contains("inf.obj:2: "));
}

#[test]
fn empty_meshes_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let h = format!("element vertex 3\n{XYZ}element face 0\nproperty list uchar int vertex_indices\n");
    let rows = vec![vtx(0.0, 0.0, 0.0), vtx(1.0, 0.0, 0.0), vtx(0.0, 1.0, 0.0)];
    let p = write(dir.path(), "empty.ply", &ply(Enc::Ascii, &h, &rows));
    assert!(error_of(&p).contains("the mesh has no triangles"));
    let p = write(dir.path(), "nofaces.ply", &ply(Enc::Ascii, &format!("element vertex 3\n{XYZ}"), &rows));
    assert!(error_of(&p).contains("the mesh has no triangles"));
    let p = write(dir.path(), "empty.obj", b"# nothing but points\nv 0 0 0\nv 1 0 0\np 1 2\nl 1 2\n");
    assert!(error_of(&p).contains("the mesh has no triangles"));
    let p = write(dir.path(), "zero.obj", b"");
    assert!(error_of(&p).contains("the mesh has no triangles"));
}

#[test]
fn malformed_ply_headers_point_at_the_line() {
    let dir = tempfile::tempdir().unwrap();
    for (text, expect) in [
        (&b"plx\n"[..], ":1: not a PLY file"),
        (b"ply\nformat ascii 1.0\nelement vertex 3\nproperty flot x\nend_header\n", ":4: unknown type `flot`"),
        (b"ply\nformat utf9 1.0\nend_header\n", ":2: unknown format `utf9`"),
        (b"ply\nformat ascii 1.0\nproperty float x\nend_header\n", ":3: property before any element"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\n", ":4: header ends before `end_header`"),
        (b"ply\nelement vertex 1\nend_header\n", "header has no `format` line"),
        (
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
            ":3: vertex element has no scalar `y`",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty list float int x\nend_header\n",
            ":4: a list count must have an integer type",
        ),
        (b"ply\nformat ascii 1.0\nwhat is this\nend_header\n", ":3: unexpected header line"),
    ] {
        let p = write(dir.path(), "h.ply", text);
        let msg = error_of(&p);
        assert!(msg.contains(expect), "{msg} should contain {expect}");
    }
    let h = format!("element vertex 1\n{XYZ}");
    let p = write(dir.path(), "word.ply", &[ply(Enc::Ascii, &h, &[]), b"0 zero 0\n".to_vec()].concat());
    assert!(error_of(&p).contains(":9: expected a number for y, found `zero`"));
    let p = write(dir.path(), "short.ply", &[ply(Enc::Ascii, &h, &[]), b"0 0\n".to_vec()].concat());
    assert!(error_of(&p).contains(":9: `vertex` element 0 is missing its z"));
    let p = write(dir.path(), "bin.ply", &[ply(Enc::Ascii, &h, &[]), b"0 0 0\n\n1 \xff 0\n".to_vec()].concat());
    assert!(error_of(&p).contains(":11: ASCII body is not UTF-8 text"));
    let p = write(dir.path(), "bad.ply.gz", b"\x1f\x8b\x08\x00garbage");
    assert!(error_of(&p).contains("corrupt gzip data"));
}

#[test]
fn malformed_obj_number_names_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "bad.obj", b"# a triangle\nv 0 0 0\nv 1 0x 0\nv 0 1 0\nf 1 2 3\n");
    let msg = error_of(&p);
    assert!(msg.contains("bad.obj:3: `v`: expected a number for a coordinate, found `0x`"), "{msg}");
    for (text, expect) in [
        (&b"v 0 0\n"[..], ":1: `v`: expected x y z"),
        (b"v 0 0 0 0\n", ":1: `v`: the weight w must not be 0"),
        (b"vn 0 1\n", ":1: `vn`: expected 3 numbers"),
        (b"vt\n", ":1: `vt`: expected u [v [w]]"),
        (b"v 0 0 0\nf 1/x 1 1\n", ":2: `f`: vertex `1/x`: `x` is not an integer"),
        (b"v 0 0 0\n\nusemtl\n", ":3: `usemtl` without a material name"),
        (b"mtllib\n", ":1: `mtllib` without a file name"),
    ] {
        let p = write(dir.path(), "m.obj", text);
        let msg = error_of(&p);
        assert!(msg.contains(expect), "{msg} should contain {expect}");
    }
    let p = write(dir.path(), "latin1.obj", b"v 0 0 0\ng caf\xe9\n");
    assert!(error_of(&p).contains("latin1.obj:2: not UTF-8 text"));
}

#[test]
fn obj_face_index_out_of_range_names_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n";
    let p = write(dir.path(), "oob.obj", text);
    let msg = error_of(&p);
    assert!(msg.contains("oob.obj:5: `f`: vertex `4`: vertex index 4 is out of range: 3 defined so far"), "{msg}");
    let p = write(dir.path(), "rel.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
    assert!(error_of(&p).contains("rel.obj:4: `f`: vertex `-4`"));
    let p = write(dir.path(), "vt.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/-5 3/1\n");
    assert!(error_of(&p).contains("vt.obj:5: `f`: vertex `2/-5`: texture coordinate index -5"));
    let p = write(dir.path(), "vn.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n");
    assert!(error_of(&p).contains("vn.obj:4: `f`: vertex `1//1`: normal index 1 is out of range: 0"));
    let p = write(dir.path(), "zero.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    assert!(error_of(&p).contains("zero.obj:4: `f`: vertex `0`: vertex index 0 (OBJ indices start at 1)"));
}

#[test]
fn malformed_mtl_names_the_mtl_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.mtl", b"newmtl red\nKd 1 0\n");
    let p = write(dir.path(), "t.obj", b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    let msg = load_file(&p).unwrap_err().to_string();
    assert!(msg.starts_with(&dir.path().join("m.mtl").display().to_string()), "{msg}");
    assert!(msg.contains("m.mtl:2: `Kd`: expected 1 or 3 numbers, found 2"), "{msg}");
}

#[test]
fn corrupt_glb_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "junk.glb", b"glTF\x02\x00\x00\x00\xff\xff\x00\x00garbage");
    assert!(error_of(&p).contains("glTF"));
    let p = write(dir.path(), "text.glb", b"this is not a glb file at all");
    error_of(&p);
    let p = write(dir.path(), "bad.gltf", b"{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [");
    error_of(&p);
    if let Some(duck) = model("Duck/glTF-Binary/Duck.glb") {
        let bytes = std::fs::read(duck).unwrap();
        for cut in [12, 20, 100, bytes.len() / 2, bytes.len() - 1] {
            let p = write(dir.path(), "cut.glb", &bytes[..cut]);
            error_of(&p);
        }
    }
}

// ---------------------------------------------------------------------------------------
// hand-built glTF

/// A one-triangle glTF with its buffer in `tri.bin` and `extra` spliced into the
/// primitive; `count` is the POSITION accessor's count.
fn gltf_triangle(dir: &Path, name: &str, count: usize, prim_extra: &str, doc_extra: &str) -> PathBuf {
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
fn gltf_accessor_past_its_buffer_view_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let p = gltf_triangle(dir.path(), "long.gltf", 300, "", "");
    let msg = error_of(&p);
    assert!(msg.contains("POSITION") && msg.contains("runs past its buffer view"), "{msg}");
}

#[test]
fn gltf_index_out_of_range_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let p = gltf_triangle(dir.path(), "oob.gltf", 3, r#","indices":2"#, "");
    let msg = error_of(&p);
    assert!(msg.contains("mesh 0 primitive 0: triangle 0 uses vertex 7"), "{msg}");
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

#[test]
fn gltf_missing_or_short_buffer_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let p = gltf_triangle(dir.path(), "t.gltf", 3, "", "");
    std::fs::remove_file(dir.path().join("tri.bin")).unwrap();
    let msg = error_of(&p);
    assert!(msg.contains("glTF buffer 0: ") && msg.contains("tri.bin"), "{msg}");
    write(dir.path(), "tri.bin", &[0; 10]);
    let msg = error_of(&p);
    assert!(msg.contains("tri.bin"), "{msg}");
    // gltf itself panics on a URI that percent-decodes to invalid UTF-8.
    let json = std::fs::read_to_string(&p).unwrap().replace("tri.bin", "%FF.bin");
    let msg = error_of(&write(dir.path(), "ff.gltf", json.as_bytes()));
    assert!(msg.contains("does not decode to UTF-8"), "{msg}");
    // A device would be read forever.
    if Path::new("/dev/zero").exists() {
        let json = std::fs::read_to_string(&p).unwrap().replace("tri.bin", "file:///dev/zero");
        let msg = error_of(&write(dir.path(), "zero.gltf", json.as_bytes()));
        assert!(msg.contains("/dev/zero is not a regular file"), "{msg}");
    }
}

#[test]
fn gltf_node_cycle_is_an_error_not_a_hang() {
    let dir = tempfile::tempdir().unwrap();
    let p = gltf_triangle(dir.path(), "c.gltf", 3, "", "");
    let json = std::fs::read_to_string(&p).unwrap().replace(
        r#""nodes":[{"mesh":0,"translation":[0,0,5]}]"#,
        r#""nodes":[{"mesh":0,"children":[1]},{"children":[0]}]"#,
    );
    let p = write(dir.path(), "cycle.gltf", json.as_bytes());
    assert!(error_of(&p).contains("node 0 is reached twice"));
    // 40 levels of a node listing the next one twice: 2^40 paths if walked naively.
    let mut nodes: Vec<String> = (0..40).map(|i| format!(r#"{{"children":[{0},{0}]}}"#, i + 1)).collect();
    nodes.push(r#"{"mesh":0}"#.into());
    let json = std::fs::read_to_string(gltf_triangle(dir.path(), "d.gltf", 3, "", ""))
        .unwrap()
        .replace(r#""nodes":[{"mesh":0,"translation":[0,0,5]}]"#, &format!(r#""nodes":[{}]"#, nodes.join(",")));
    let p = write(dir.path(), "dag.gltf", json.as_bytes());
    assert!(error_of(&p).contains("is reached twice"));
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
    }
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
// fuzz: random bytes and mutated valid files never panic

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn mutate(rng: &mut Rng, base: &[u8]) -> Vec<u8> {
    let mut b = base.to_vec();
    for _ in 0..1 + rng.below(8) {
        match rng.below(5) {
            // Replace a number with one chosen to hit limits (indices, counts, offsets).
            4 => {
                let digits: Vec<usize> = (0..b.len()).filter(|&i| b[i].is_ascii_digit()).collect();
                if digits.is_empty() {
                    continue;
                }
                let start = digits[rng.below(digits.len())];
                let end = (start..b.len()).find(|&i| !b[i].is_ascii_digit()).unwrap_or(b.len());
                let v: &[u8] =
                    [&b"0"[..], b"1", b"2", b"3", b"7", b"255", b"65535", b"4294967295", b"18446744073709551616"]
                        [rng.below(9)];
                b.splice(start..end, v.iter().copied());
            }
            0 if !b.is_empty() => {
                let i = rng.below(b.len());
                b[i] = rng.next() as u8;
            }
            1 if !b.is_empty() => b.truncate(rng.below(b.len())),
            2 => {
                let i = rng.below(b.len() + 1);
                let tok: &[u8] = [&b"-1"[..], b"99999999999", b"nan", b" ", b"\n", b"/", b"0", b"1e40"][rng.below(8)];
                b.splice(i..i, tok.iter().copied());
            }
            _ if !b.is_empty() => {
                let i = rng.below(b.len());
                b[i] = b"0123456789 -/\n.e"[rng.below(16)];
            }
            _ => {}
        }
    }
    b
}

#[test]
fn fuzz_every_parser_with_random_and_mutated_input() {
    let dir = tempfile::tempdir().unwrap();
    let mut seeds: Vec<(&str, Vec<u8>)> = vec![
        ("ply", ply(Enc::Ascii, &pentagon_header(), &pentagon_rows())),
        ("ply", ply(Enc::Le, &pentagon_header(), &pentagon_rows())),
        ("ply", ply(Enc::Be, &pentagon_header(), &pentagon_rows())),
        ("obj", b"mtllib f.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\ng a\nusemtl m\nf 1/1/1 2/1/1 3/1/1\nf -1 -2 -3\n".to_vec()),
        ("mtl", b"newmtl m\nKa 0.1 0.1 0.1\nKd 1 0 0\nKs 1 1 1\nKe 1 1 1\nNs 10\nNi 1.5\nd 0.5\nTr 0.5\nillum 3\n".to_vec()),
        ("gltf", std::fs::read(gltf_triangle(dir.path(), "seed.gltf", 3, r#","indices":1"#, "")).unwrap()),
    ];
    for (ext, rel) in [("glb", "Duck/glTF-Binary/Duck.glb"), ("obj", "cornell-box/mcguire-obj/CornellBox-Original.obj")]
    {
        if let Some(p) = model(rel) {
            seeds.push((ext, std::fs::read(p).unwrap()));
        }
    }
    let mut outcomes = [0usize; 2];
    // DYNRAY_FUZZ_ROUNDS raises the count for a longer hunt (1,500 keeps the test fast).
    let rounds = std::env::var("DYNRAY_FUZZ_ROUNDS").ok().and_then(|r| r.parse().ok()).unwrap_or(1500);
    let seed = std::env::var("DYNRAY_FUZZ_SEED").ok().and_then(|r| r.parse().ok()).unwrap_or(0x9E37_79B9_7F4A_7C15u64);
    let mut rng = Rng(seed | 1);
    for round in 0..rounds {
        let (ext, bytes) = if round % 5 == 0 {
            let ext = ["ply", "obj", "glb", "gltf", "mtl"][rng.below(5)];
            let len = rng.below(300);
            (ext, (0..len).map(|_| rng.next() as u8).collect())
        } else {
            let (ext, base) = &seeds[rng.below(seeds.len())];
            (*ext, mutate(&mut rng, base))
        };
        let (file, bytes) = if ext == "mtl" {
            // An MTL is reached through an OBJ that uses it.
            write(dir.path(), "f.mtl", &bytes);
            ("m.obj", b"mtllib f.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n".to_vec())
        } else {
            (
                ["f.ply", "f.obj", "f.glb", "f.gltf"]
                    [["ply", "obj", "glb", "gltf"].iter().position(|e| *e == ext).unwrap()],
                bytes,
            )
        };
        let p = write(dir.path(), file, &bytes);
        match load_file(&p) {
            Ok(s) => {
                outcomes[0] += 1;
                assert!(s.triangle_count() > 0);
                assert!(s.actors.iter().all(|a| a.mesh.validate().is_ok()));
            }
            Err(e) => {
                outcomes[1] += 1;
                let msg = e.to_string();
                assert!(msg.contains(&dir.path().display().to_string()), "{msg}");
            }
        }
    }
    // Both outcomes must occur, or the mutations are too weak (or too strong) to test much.
    eprintln!("fuzz: {rounds} rounds, ok/err = {outcomes:?}");
    assert!(outcomes[0] > rounds / 30 && outcomes[1] > rounds / 30, "ok/err = {outcomes:?}");
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
    let light = s.materials.iter().find(|m| m.name == "light").unwrap();
    assert!(light.ambient.x > 1.0, "the lamp's material is ambient-bright");
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
