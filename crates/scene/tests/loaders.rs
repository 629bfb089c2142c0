//! Bad input for every loader: one test per case with the message checked (file, and
//! line where the format has lines), a peak-allocation check on absurd counts, and a
//! seeded fuzz loop over every parser. Happy paths and real models are in formats.rs.

mod support;

use dynray_scene::{load_file, LoadError};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::path::Path;
use support::*;

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
// glTF

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
    // A device would be read forever; outside the model's folder, it is not even looked at.
    if Path::new("/dev/zero").exists() {
        let json = std::fs::read_to_string(&p).unwrap().replace("tri.bin", "file:///dev/zero");
        let msg = error_of(&write(dir.path(), "zero.gltf", json.as_bytes()));
        assert!(msg.contains("/dev/zero is outside"), "{msg}");
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
