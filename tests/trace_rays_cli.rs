//! `trace-rays --rows A..B` and `merge-hits` (docs/trace-rays.md, "Slices"): a slice's
//! hits are the same rows of a full run's, bit for bit, whatever the ray file's dtype and
//! order; slices merged in any order give the full run's archive, array for array and
//! byte for byte; bad ranges and bad sets of parts are clean errors naming the file, and
//! leave no output behind.

mod support;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Output;
use support::{dynray, ok};

fn bunny() -> String {
    support::scenes_dir().join("bunny/bun_zipper.ply").to_string_lossy().into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().expect("temporary paths are UTF-8")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A clean failure: exit 1, one `dynray:` message mentioning every needle, no panic.
#[track_caller]
fn fails_with(o: Output, needles: &[&str]) {
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "expected exit 1, got {:?}: {err}", o.status);
    assert!(err.starts_with("dynray: ") && !err.contains("panicked"), "{err}");
    for needle in needles {
        assert!(err.contains(needle), "message should mention {needle:?}: {err}");
    }
}

/// Rays at the bunny: a fan from the front (hits, with shared origins for the packets)
/// and pseudo-random rays from around its box towards it (hits and misses), a miss and a
/// clipped ray; about 2,600 rows.
fn rays() -> Vec<[f32; 8]> {
    let mut rows = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            let x = -0.1 + 0.2 * i as f32 / 39.0;
            let y = 0.03 + 0.16 * j as f32 / 39.0;
            rows.push([x, y, 1.0, 0.0, 0.0, -1.0, 0.0, f32::INFINITY]);
        }
    }
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    for _ in 0..1000 {
        let o = [next() * 0.6 - 0.3, next() * 0.5 - 0.1, next() * 0.6 - 0.3];
        let target = [next() * 0.16 - 0.095, next() * 0.16 + 0.03, next() * 0.12 - 0.06];
        rows.push([o[0], o[1], o[2], target[0] - o[0], target[1] - o[1], target[2] - o[2], 0.0, f32::INFINITY]);
    }
    rows.push([0.0, 0.1, 1.0, 0.0, 1.0, 0.0, 0.0, f32::INFINITY]); // misses upwards
    rows.push([-0.02, 0.1, 1.0, 0.0, 0.0, -1.0, 0.0, 0.5]); // clipped before the bunny
    rows
}

/// Writes `rows` as an (N, 8) .npy of float32 or float64, in C or Fortran order.
fn write_npy(path: &Path, rows: &[[f32; 8]], wide: bool, fortran: bool) {
    use npyz::WriterBuilder;
    let order = if fortran { npyz::Order::Fortran } else { npyz::Order::C };
    // Fortran order stores column after column.
    let values: Vec<f32> = if fortran {
        (0..8).flat_map(|j| rows.iter().map(move |r| r[j])).collect()
    } else {
        rows.iter().flatten().copied().collect()
    };
    let file = std::fs::File::create(path).unwrap();
    let shape = [rows.len() as u64, 8];
    if wide {
        let mut w = npyz::WriteOptions::<f64>::new()
            .default_dtype()
            .shape(&shape)
            .order(order)
            .writer(file)
            .begin_nd()
            .unwrap();
        w.extend(values.iter().map(|&x| x as f64)).unwrap();
        w.finish().unwrap();
    } else {
        let mut w = npyz::WriteOptions::<f32>::new()
            .default_dtype()
            .shape(&shape)
            .order(order)
            .writer(file)
            .begin_nd()
            .unwrap();
        w.extend(values).unwrap();
        w.finish().unwrap();
    }
}

/// The archive's entries in zip order: name and the whole stored `.npy` (header and
/// data bytes).
fn entries(path: &Path) -> Vec<(String, Vec<u8>)> {
    let mut npz = npyz::npz::NpzArchive::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let zip = npz.zip_archive();
    (0..zip.len())
        .map(|i| {
            let mut entry = zip.by_index(i).unwrap();
            let mut bytes = Vec::new();
            entry.read_to_end(&mut bytes).unwrap();
            (entry.name().to_string(), bytes)
        })
        .collect()
}

fn array<T: npyz::Deserialize>(path: &Path, name: &str) -> (Vec<u64>, Vec<T>) {
    let mut npz = npyz::npz::NpzArchive::open(path).unwrap();
    let npy = npz.by_name(name).unwrap().unwrap_or_else(|| panic!("{}: no array {name}", path.display()));
    (npy.shape().to_vec(), npy.into_vec().unwrap())
}

/// The bits of a float array, so NaN equals NaN and -0.0 differs from 0.0.
fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn trace(rays: &Path, out: &Path, extra: &[&str]) -> Output {
    let mesh = bunny();
    let mut args = vec!["trace-rays", mesh.as_str(), "--rays", s(rays), "-o", s(out)];
    args.extend_from_slice(extra);
    dynray(&args)
}

const FIELDS: [&str; 6] = ["t", "prim", "u", "v", "normal", "point"];

/// Asserts that `slice` holds rows a..b of `full`'s arrays, bit for bit, and `rows`.
#[track_caller]
fn assert_slice_of(slice: &Path, full: &Path, a: usize, b: usize, n: usize, names: &[&str]) {
    for &name in names {
        let width = if name == "normal" || name == "point" { 3 } else { 1 };
        let rows = a * width..b * width;
        match name {
            "prim" => assert_eq!(array::<i64>(slice, name).1, array::<i64>(full, name).1[rows], "{name}"),
            "occluded" => assert_eq!(array::<bool>(slice, name).1, array::<bool>(full, name).1[rows], "{name}"),
            _ => {
                let (shape, got) = array::<f32>(slice, name);
                let want_shape = if width == 1 { vec![(b - a) as u64] } else { vec![(b - a) as u64, 3] };
                assert_eq!(shape, want_shape, "{name}");
                assert_eq!(bits(&got), bits(&array::<f32>(full, name).1[rows]), "{name}");
            }
        }
    }
    assert_eq!(array::<i64>(slice, "rows"), (vec![3], vec![a as i64, b as i64, n as i64]));
}

#[test]
fn row_slices_hold_the_same_rows_of_a_full_run_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let rows = rays();
    let n = rows.len();
    let path = dir.path().join("rays.npy");
    write_npy(&path, &rows, false, false);
    let fields = FIELDS.join(",");
    let full = dir.path().join("full.npz");
    ok(trace(&path, &full, &["--fields", &fields]));
    assert!(!entries(&full).iter().any(|(name, _)| name == "rows.npy"), "a full run has no `rows` array");
    let full_occ = dir.path().join("full-occ.npz");
    ok(trace(&path, &full_occ, &["--occluded"]));
    // A slice starting mid-fan (shared-origin packets cut in two), the empty slice, one
    // row, and slices reaching the last row.
    for (a, b) in [(0, 1), (5, 1203), (700, 700), (1203, n), (n, n), (n - 1, n)] {
        let range = format!("{a}..{b}");
        let out = dir.path().join(format!("slice-{a}-{b}.npz"));
        let o = ok(trace(&path, &out, &["--fields", &fields, "--rows", &range]));
        assert!(stderr(&o).contains(&format!("rows {a}..{b} of {n}: {} rays", b - a)), "{}", stderr(&o));
        assert_slice_of(&out, &full, a, b, n, &FIELDS);
        let names: Vec<String> = entries(&out).into_iter().map(|(name, _)| name).collect();
        assert_eq!(names.last().map(String::as_str), Some("rows.npy"), "`rows` comes after the hits");
        let occ = dir.path().join(format!("occ-{a}-{b}.npz"));
        ok(trace(&path, &occ, &["--occluded", "--rows", &range]));
        assert_slice_of(&occ, &full_occ, a, b, n, &["occluded"]);
    }
}

#[test]
fn float64_and_fortran_order_slices_equal_the_float32_rows() {
    let dir = tempfile::tempdir().unwrap();
    let rows = rays();
    let n = rows.len();
    let plain = dir.path().join("f32.npy");
    write_npy(&plain, &rows, false, false);
    let full = dir.path().join("full.npz");
    ok(trace(&plain, &full, &[]));
    for (wide, fortran, what) in
        [(true, false, "float64"), (false, true, "Fortran order"), (true, true, "float64 in Fortran order")]
    {
        let path = dir.path().join(format!("rays-{wide}-{fortran}.npy"));
        write_npy(&path, &rows, wide, fortran);
        for (a, b) in [(0, n), (333, 1999), (n - 3, n)] {
            let out = dir.path().join(format!("{wide}-{fortran}-{a}.npz"));
            let o = ok(trace(&path, &out, &["--rows", &format!("{a}..{b}")]));
            assert!(stderr(&o).contains(&format!("rays given as {what}, converted")), "{}", stderr(&o));
            assert_slice_of(&out, &full, a, b, n, &["t", "prim", "u", "v"]);
        }
    }
}

/// Rows outside the slice are not read: every other row of this file is NaN (which a
/// full run refuses, naming the row), yet the slice traces and equals the clean file's.
#[test]
fn rows_outside_the_slice_are_never_read() {
    let dir = tempfile::tempdir().unwrap();
    let rows = rays();
    let n = rows.len();
    let (a, b) = (1000, 1800);
    let poisoned: Vec<[f32; 8]> =
        rows.iter().enumerate().map(|(i, r)| if (a..b).contains(&i) { *r } else { [f32::NAN; 8] }).collect();
    for fortran in [false, true] {
        let path = dir.path().join(format!("poisoned-{fortran}.npy"));
        write_npy(&path, &poisoned, false, fortran);
        let out = dir.path().join("whole.npz");
        fails_with(trace(&path, &out, &[]), &[&format!("poisoned-{fortran}.npy"), "ray 0 has a non-finite"]);
        let slice = dir.path().join(format!("slice-{fortran}.npz"));
        ok(trace(&path, &slice, &["--rows", &format!("{a}..{b}")]));
        let clean = dir.path().join("clean.npy");
        write_npy(&clean, &rows, false, false);
        let full = dir.path().join("full.npz");
        ok(trace(&clean, &full, &[]));
        assert_slice_of(&slice, &full, a, b, n, &["t", "prim", "u", "v"]);
        // A bad row inside the slice is named by its row in the file.
        let out = dir.path().join("bad.npz");
        fails_with(trace(&path, &out, &["--rows", &format!("{}..{}", b - 5, b + 5)]), &[&format!("ray {b} has")]);
        assert!(!out.exists());
    }
}

#[test]
fn bad_row_ranges_are_errors_naming_the_file_or_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let rows = rays();
    let n = rows.len();
    let path = dir.path().join("rays.npy");
    write_npy(&path, &rows, false, false);
    let out = dir.path().join("hits.npz");
    for range in [format!("0..{}", n + 1), format!("{}..{}", n + 1, n + 1), format!("5..{}", u64::MAX)] {
        let o = trace(&path, &out, &["--rows", &range]);
        fails_with(o, &["rays.npy", &format!("rows {range} reach past the file's {n} rays")]);
        assert!(!out.exists(), "{range}");
    }
    for (range, needle) in
        [("9..3", "after the end"), ("0..=5", "B exclusive"), ("..5", "A..B"), ("5", "A..B"), ("-1..4", "A..B")]
    {
        let o = trace(&path, &out, &[&format!("--rows={range}")]);
        assert_eq!(o.status.code(), Some(2), "{range} is a usage error: {}", stderr(&o));
        assert!(stderr(&o).contains("--rows") && stderr(&o).contains(needle), "{range}: {}", stderr(&o));
        assert!(!out.exists(), "{range}");
    }
    let help = String::from_utf8_lossy(&ok(dynray(&["trace-rays", "--help"])).stdout).into_owned();
    assert!(help.contains("--rows <A..B>") && help.contains("B exclusive"), "{help}");
}

/// Traces `ranges` of `rays` into parts (named in the order given) with `extra` flags.
fn parts(dir: &Path, rays: &Path, tag: &str, ranges: &[(usize, usize)], extra: &[&str]) -> Vec<PathBuf> {
    ranges
        .iter()
        .map(|(a, b)| {
            let out = dir.join(format!("{tag}-{a}-{b}.npz"));
            let range = format!("{a}..{b}");
            let mut args = extra.to_vec();
            args.extend(["--rows", &range]);
            ok(trace(rays, &out, &args));
            out
        })
        .collect()
}

fn merge(parts: &[PathBuf], out: &Path) -> Output {
    let mut args = vec!["merge-hits"];
    args.extend(parts.iter().map(|p| s(p)));
    args.extend(["-o", s(out)]);
    dynray(&args)
}

#[test]
fn merged_slices_are_the_full_runs_archive_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let rows = rays();
    let n = rows.len();
    let path = dir.path().join("rays.npy");
    write_npy(&path, &rows, false, false);
    let fields = FIELDS.join(",");
    for (tag, extra) in
        [("default", vec![]), ("fields", vec!["--fields", fields.as_str()]), ("occ", vec!["--occluded"])]
    {
        let full = dir.path().join(format!("{tag}-full.npz"));
        ok(trace(&path, &full, &extra));
        // Three parts given out of order, one of them cut inside a packet of the fan,
        // and an empty one.
        let ranges = [(1203, n), (0, 517), (517, 1203), (517, 517)];
        let parts = parts(dir.path(), &path, tag, &ranges, &extra);
        let merged = dir.path().join(format!("{tag}-merged.npz"));
        let o = ok(merge(&parts, &merged));
        assert!(stderr(&o).starts_with(&format!("4 parts, {n} rays (")), "{}", stderr(&o));
        // Same arrays in the same order, each entry's .npy (header and data) the same
        // bytes: what numpy reads from both is identical.
        let (got, want) = (entries(&merged), entries(&full));
        let names = |e: &[(String, Vec<u8>)]| e.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
        assert_eq!(names(&got), names(&want), "{tag}");
        for ((name, a), (_, b)) in got.iter().zip(&want) {
            assert!(a == b, "{tag}: {name} differs from the full run's");
        }
        // And the whole file: the same writer, the same zip options, and entries dated
        // as zip's default (no clock), so the archives are one byte string.
        assert!(std::fs::read(&merged).unwrap() == std::fs::read(&full).unwrap(), "{tag}: the files differ");
        assert!(parts.iter().all(|p| p.exists()), "the parts are kept");
    }
}

#[test]
fn gaps_overlaps_and_mixed_parts_are_refused_naming_the_files() {
    let dir = tempfile::tempdir().unwrap();
    let rows = rays();
    let n = rows.len();
    let path = dir.path().join("rays.npy");
    write_npy(&path, &rows, false, false);
    let d = dir.path();
    let out = d.join("merged.npz");
    let p = parts(d, &path, "p", &[(0, 500), (500, 1500), (600, 1500), (400, 1500), (1500, n)], &[]);
    let (head, mid, late, early, tail) = (&p[0], &p[1], &p[2], &p[3], &p[4]);
    let name = |p: &Path| p.file_name().unwrap().to_string_lossy().into_owned();

    let o = merge(&[head.clone(), late.clone(), tail.clone()], &out);
    fails_with(o, &["rows 500..600 are in no part", &name(head), &name(late)]);
    let o = merge(&[head.clone(), early.clone(), tail.clone()], &out);
    fails_with(o, &[&format!("{} (rows 0..500) and", name(head)), &name(early), "overlap"]);
    let o = merge(&[head.clone(), mid.clone()], &out);
    fails_with(o, &[&format!("rows 1500..{n} are in no part"), &name(mid)]);
    let o = merge(&[mid.clone(), tail.clone()], &out);
    fails_with(o, &["rows 0..500 are in no part"]);

    // Another query, other fields, another ray file.
    let occ = parts(d, &path, "occ", &[(500, 1500)], &["--occluded"]);
    fails_with(
        merge(&[head.clone(), occ[0].clone(), tail.clone()], &out),
        &["parts of different queries", &name(&occ[0])],
    );
    let more = parts(d, &path, "normal", &[(500, 1500)], &["--fields", "t,prim,u,v,normal"]);
    fails_with(merge(&[head.clone(), more[0].clone(), tail.clone()], &out), &["holds t, prim, u, v, normal"]);
    let shorter = d.join("shorter.npy");
    write_npy(&shorter, &rows[..n - 1], false, false);
    let other = parts(d, &shorter, "short", &[(1500, n - 1)], &[]);
    fails_with(
        merge(&[head.clone(), mid.clone(), other[0].clone()], &out),
        &["parts of different ray files", &name(&other[0])],
    );

    // A full run's archive is no part; the output may not be one of the parts (here
    // through another name of it), which stays as it was.
    let full = d.join("full.npz");
    ok(trace(&path, &full, &[]));
    fails_with(merge(std::slice::from_ref(&full), &out), &["full.npz", "no `rows` array"]);
    assert!(!out.exists());
    let before = std::fs::read(tail).unwrap();
    let alias = d.join("sub/../").join(name(tail));
    std::fs::create_dir(d.join("sub")).unwrap();
    fails_with(merge(&[head.clone(), mid.clone(), tail.clone()], &alias), &["the output is one of the parts"]);
    assert_eq!(std::fs::read(tail).unwrap(), before);
    fails_with(merge(&[head.clone(), mid.clone(), tail.clone()], &d.join("merged.npy")), &["name the output *.npz"]);
    assert!(std::fs::read_dir(d).unwrap().all(|e| !e.unwrap().file_name().to_string_lossy().ends_with(".tmp")));
}
