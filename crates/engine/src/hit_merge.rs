//! Joining the slice archives of `trace-rays --rows A..B` into the archive one run over
//! every row writes (`dynray merge-hits`, Python's `dynray.merge_hits` and
//! `dynray.distributed`): the same array names in the same order, the same dtypes and
//! shapes, and the same bytes, because the arrays go through the trace job's own writer
//! (hit_file.rs) with the same zip options.
//!
//! Each part names its rows in its `rows` array (`[A, B, N]`, int64). The parts are put
//! in row order and must cover `0..N` of one ray file exactly, with one query: a gap, an
//! overlap, parts of files of different lengths, or mixed arrays (closest hits and
//! `--occluded`, other `--fields`) are errors naming the files. Parts are read array by
//! array, so memory holds one part's array at a time, never the whole result.

use crate::hit_file::{check_npz_output, stored, write_npz, HitField, Npz, RowSpan};
use anyhow::{bail, Context, Result};
use npyz::WriterBuilder;
use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What a merge did.
#[derive(Clone, Debug, PartialEq)]
pub struct MergeSummary {
    /// Parts joined.
    pub parts: usize,
    /// Rays in the merged archive (the ray file's rows).
    pub rays: u64,
    /// The arrays written, in archive order.
    pub arrays: Vec<String>,
    /// Checking the parts and writing the archive.
    pub time: Duration,
}

impl std::fmt::Display for MergeSummary {
    /// `3 parts, 1000000 rays (t, prim, u, v); 120.5 ms`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = if self.parts == 1 { "" } else { "s" };
        write!(
            f,
            "{} part{s}, {} rays ({}); {:.1} ms",
            self.parts,
            self.rays,
            self.arrays.join(", "),
            self.time.as_secs_f64() * 1e3
        )
    }
}

/// One array of a part: its name, the numpy dtype text, and the values per row (1, or
/// 3 for `normal` and `point`).
#[derive(Clone, Debug, PartialEq, Eq)]
struct Column {
    name: String,
    descr: &'static str,
    width: u64,
}

/// A checked part: its file, rows and arrays (in archive order, `rows` left out).
#[derive(Debug)]
struct Part {
    path: PathBuf,
    span: RowSpan,
    columns: Vec<Column>,
}

/// The dtype and row width trace-rays writes for an array name, `None` for a name it
/// never writes.
fn column_of(name: &str) -> Option<Column> {
    let (descr, width) = match name {
        "occluded" => ("'|b1'", 1),
        "prim" => ("'<i8'", 1),
        "normal" | "point" => ("'<f4'", 3),
        _ if name.parse::<HitField>().is_ok() => ("'<f4'", 1),
        _ => return None,
    };
    Some(Column { name: name.to_string(), descr, width })
}

fn open_archive(path: &Path) -> Result<npyz::npz::NpzArchive<BufReader<std::fs::File>>> {
    let file = dynray_geom::file::open(path).with_context(|| format!("{}: cannot open", path.display()))?;
    npyz::npz::NpzArchive::new(BufReader::new(file))
        .with_context(|| format!("{}: not a .npz archive (a zip of .npy arrays)", path.display()))
}

/// Reads and checks one part's `rows` and array headers (not its data).
fn read_part(path: &Path) -> Result<Part> {
    let file_len = std::fs::metadata(path).map(|m| m.len()).unwrap_or(u64::MAX);
    let mut npz = open_archive(path)?;
    // Archive order (the zip's entries), not the name index's hash order.
    let zip = npz.zip_archive();
    let mut names = Vec::with_capacity(zip.len());
    for i in 0..zip.len() {
        let entry = zip.by_index(i).with_context(|| format!("{}: unreadable archive entry {i}", path.display()))?;
        let name = npyz::npz::array_name_from_file_name(entry.name())
            .with_context(|| format!("{}: entry {:?} is not a .npy array", path.display(), entry.name()))?
            .to_string();
        // npyz's header parser is exponential in bracket nesting: look before it does.
        let mut prefix = Vec::new();
        entry
            .take(dynray_scene::formats::npz::NPY_PREFIX_BYTES as u64)
            .read_to_end(&mut prefix)
            .with_context(|| format!("{}: unreadable array `{name}`", path.display()))?;
        dynray_scene::formats::npz::check_npy_header(&prefix)
            .map_err(|m| anyhow::anyhow!("{}: array `{name}`: {m}", path.display()))?;
        names.push(name);
    }
    let Some(npy) = npz.by_name(RowSpan::ARRAY).with_context(|| format!("{}: unreadable `rows`", path.display()))?
    else {
        bail!("{}: no `rows` array: not a slice archive (write parts with `trace-rays --rows A..B`)", path.display());
    };
    if npy.dtype().descr() != "'<i8'" || npy.shape() != [3] {
        bail!("{}: `rows` must be three int64 values [A, B, N]", path.display());
    }
    let rows: Vec<i64> = npy.into_vec().with_context(|| format!("{}: unreadable `rows`", path.display()))?;
    let span = match rows[..] {
        [a, b, n] if 0 <= a && a <= b && b <= n => RowSpan { start: a as u64, end: b as u64, total: n as u64 },
        _ => bail!("{}: `rows` {rows:?} is not [A, B, N] with 0 <= A <= B <= N", path.display()),
    };
    let mut columns = Vec::new();
    for name in names.iter().filter(|n| *n != RowSpan::ARRAY) {
        let Some(column) = column_of(name) else {
            bail!("{}: array `{name}` is not one trace-rays writes", path.display());
        };
        let npy = npz
            .by_name(name)
            .with_context(|| format!("{}: unreadable array `{name}`", path.display()))?
            .with_context(|| format!("{}: array `{name}` vanished", path.display()))?;
        let want_shape: Vec<u64> = if column.width == 1 { vec![span.len()] } else { vec![span.len(), column.width] };
        let descr = npy.dtype().descr();
        if descr != column.descr || npy.shape() != want_shape || (column.width > 1 && npy.order() != npyz::Order::C) {
            bail!(
                "{}: array `{name}` is {descr} of shape {:?}{}; rows {}..{} need {} of shape {want_shape:?} in C order",
                path.display(),
                npy.shape(),
                if npy.order() == npyz::Order::C { "" } else { " in Fortran order" },
                span.start,
                span.end,
                column.descr
            );
        }
        // The header's rows are the span's, and the span is bounded by the file: no
        // allocation later can exceed what the file holds.
        let item = if column.descr == "'|b1'" {
            1
        } else if column.descr == "'<i8'" {
            8
        } else {
            4
        };
        if span.len().checked_mul(column.width * item).is_none_or(|bytes| bytes > file_len) {
            bail!("{}: array `{name}` promises more than the file's {file_len} bytes hold", path.display());
        }
        columns.push(column);
    }
    if columns.is_empty() {
        bail!("{}: holds no hits, only `rows`", path.display());
    }
    Ok(Part { path: path.to_path_buf(), span, columns })
}

/// True when `a` and `b` are one file (the same inode, whatever the names and links).
#[cfg(unix)]
fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Puts the parts in row order and checks that they cover one ray file's rows exactly
/// once with one query.
fn check_coverage(parts: &mut [Part]) -> Result<()> {
    parts.sort_by_key(|p| (p.span.start, p.span.end));
    let first = &parts[0];
    for p in &parts[1..] {
        if p.span.total != first.span.total {
            bail!(
                "{} holds rows of a {}-ray file, {} of a {}-ray file: parts of different ray files",
                first.path.display(),
                first.span.total,
                p.path.display(),
                p.span.total
            );
        }
        if p.columns != first.columns {
            let names = |p: &Part| p.columns.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", ");
            bail!(
                "{} holds {}, {} holds {}: parts of different queries (closest hits and --occluded, or other --fields)",
                first.path.display(),
                names(first),
                p.path.display(),
                names(p)
            );
        }
    }
    let mut covered = 0u64;
    let mut previous: Option<&Part> = None;
    // An empty part (A..A) holds no row: it can neither fill a gap nor overlap another.
    for p in parts.iter().filter(|p| !p.span.is_empty()) {
        if p.span.start > covered {
            let after = previous.map_or(String::new(), |q| format!(" between {} and", q.path.display()));
            bail!(
                "rows {covered}..{} are in no part (a gap{after} {}, which holds rows {}..{})",
                p.span.start,
                p.path.display(),
                p.span.start,
                p.span.end
            );
        }
        if let Some(q) = previous.filter(|_| p.span.start < covered) {
            bail!(
                "{} (rows {}..{}) and {} (rows {}..{}) overlap",
                q.path.display(),
                q.span.start,
                q.span.end,
                p.path.display(),
                p.span.start,
                p.span.end
            );
        }
        covered = p.span.end;
        previous = Some(p);
    }
    let total = parts[0].span.total;
    if covered < total {
        let last = previous.map_or("every part is empty".to_string(), |q| {
            format!("the last, {}, ends at row {covered}", q.path.display())
        });
        bail!("rows {covered}..{total} are in no part ({last})");
    }
    Ok(())
}

/// One array of the merged archive: the parts' arrays one after the other, through the
/// writer and zip options of `trace-rays` (`hit_file::write_array` / `write_rows`).
fn merge_column<T>(npz: &mut Npz, column: &Column, parts: &[Part], total: u64) -> std::io::Result<()>
where
    T: npyz::AutoSerialize + npyz::Serialize + npyz::Deserialize + Copy,
{
    let shape: Vec<u64> = if column.width == 1 { vec![total] } else { vec![total, column.width] };
    let bytes = total * column.width * std::mem::size_of::<T>() as u64;
    let mut w = npz.array::<T>(&column.name, stored(bytes))?.default_dtype().shape(&shape).begin_nd()?;
    for p in parts {
        let named = |e: &dyn std::fmt::Display| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("{}: `{}`: {e}", p.path.display(), column.name),
            )
        };
        let mut npz = open_archive(&p.path).map_err(|e| named(&format!("{e:#}")))?;
        let npy = npz.by_name(&column.name).map_err(|e| named(&e))?.ok_or_else(|| named(&"vanished"))?;
        let values: Vec<T> = npy.into_vec().map_err(|e| named(&e))?;
        if values.len() as u64 != p.span.len() * column.width {
            return Err(named(&"changed while being merged"));
        }
        w.extend(values)?;
    }
    w.finish()
}

/// Merges the slice archives `parts` (any order) into `output`, written atomically as
/// `trace-rays` writes a run over every row; `output` must not be one of the parts.
pub fn merge_hits(parts: &[PathBuf], output: &Path) -> Result<MergeSummary> {
    let t0 = Instant::now();
    check_npz_output(output, "merge-hits")?;
    if parts.is_empty() {
        bail!("no parts to merge: give the archives of `trace-rays --rows A..B`");
    }
    if let Some(p) = parts.iter().find(|p| same_file(p, output)) {
        bail!("{}: the output is one of the parts ({}); name another file", output.display(), p.display());
    }
    let mut parts: Vec<Part> = parts.iter().map(|p| read_part(p)).collect::<Result<_>>()?;
    check_coverage(&mut parts)?;
    let total = parts[0].span.total;
    let columns = parts[0].columns.clone();
    write_npz(output, |npz| {
        for c in &columns {
            match c.descr {
                "'|b1'" => merge_column::<bool>(npz, c, &parts, total)?,
                "'<i8'" => merge_column::<i64>(npz, c, &parts, total)?,
                _ => merge_column::<f32>(npz, c, &parts, total)?,
            }
        }
        Ok(())
    })?;
    Ok(MergeSummary {
        parts: parts.len(),
        rays: total,
        arrays: columns.into_iter().map(|c| c.name).collect(),
        time: t0.elapsed(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(name: &str, start: u64, end: u64, total: u64) -> Part {
        Part {
            path: PathBuf::from(name),
            span: RowSpan { start, end, total },
            columns: vec![column_of("t").unwrap(), column_of("prim").unwrap()],
        }
    }

    fn coverage(parts: Vec<Part>) -> Result<Vec<String>, String> {
        let mut parts = parts;
        check_coverage(&mut parts).map_err(|e| e.to_string())?;
        Ok(parts.iter().map(|p| p.path.display().to_string()).collect())
    }

    /// A part whose `rows` header nests brackets 30 deep would hang npyz's parser (it is
    /// exponential in the nesting; docs/fuzzing.md): refused at once, naming the part.
    #[test]
    fn a_nested_array_header_in_a_part_is_refused_at_once() {
        use std::io::Write;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("part.npz");
        let header = format!("{{'descr': '<i8', {} 'fortran_order': False, 'shape': (3,), }}", "[".repeat(30));
        let mut zip = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
        zip.start_file(
            "rows.npy",
            zip::write::FileOptions::default().compression_method(zip::CompressionMethod::Stored),
        )
        .unwrap();
        zip.write_all(&crate::hit_file::npy_with_header(&header, &[0; 24])).unwrap();
        zip.finish().unwrap();
        let start = std::time::Instant::now();
        let e = read_part(&path).err().unwrap().to_string();
        assert!(start.elapsed().as_secs() < 5, "took {:?}", start.elapsed());
        assert!(e.contains("part.npz") && e.contains("`rows`") && e.contains("nests brackets"), "{e}");
    }

    #[test]
    fn parts_are_sorted_by_their_first_row_and_may_be_empty() {
        let got = coverage(vec![part("c", 6, 10, 10), part("a", 0, 3, 10), part("e", 3, 3, 10), part("b", 3, 6, 10)]);
        assert_eq!(got.unwrap(), ["a", "e", "b", "c"]);
        assert!(coverage(vec![part("z", 0, 0, 0)]).is_ok());
    }

    #[test]
    fn gaps_overlaps_and_missing_ends_name_the_parts() {
        let e = coverage(vec![part("a", 0, 3, 10), part("b", 4, 10, 10)]).unwrap_err();
        assert!(e.contains("rows 3..4 are in no part") && e.contains("between a and b"), "{e}");
        let e = coverage(vec![part("a", 0, 5, 10), part("b", 4, 10, 10)]).unwrap_err();
        assert_eq!(e, "a (rows 0..5) and b (rows 4..10) overlap");
        let e = coverage(vec![part("a", 1, 10, 10)]).unwrap_err();
        assert!(e.starts_with("rows 0..1 are in no part"), "{e}");
        let e = coverage(vec![part("a", 0, 4, 10), part("b", 4, 4, 10)]).unwrap_err();
        assert_eq!(e, "rows 4..10 are in no part (the last, a, ends at row 4)");
        let e = coverage(vec![part("a", 0, 0, 10)]).unwrap_err();
        assert_eq!(e, "rows 0..10 are in no part (every part is empty)");
        // An empty slice inside another's rows holds nothing to overlap.
        assert!(coverage(vec![part("a", 0, 10, 10), part("b", 4, 4, 10)]).is_ok());
        let e = coverage(vec![part("a", 0, 4, 10), part("b", 4, 9, 9)]).unwrap_err();
        assert!(e.contains("parts of different ray files"), "{e}");
        let mut other = part("b", 4, 10, 10);
        other.columns = vec![column_of("occluded").unwrap()];
        let e = coverage(vec![part("a", 0, 4, 10), other]).unwrap_err();
        assert!(e.contains("a holds t, prim, b holds occluded: parts of different queries"), "{e}");
    }

    #[test]
    fn only_the_arrays_trace_rays_writes_are_accepted() {
        for name in HitField::NAMES.iter().chain(&["occluded"]) {
            assert!(column_of(name).is_some(), "{name}");
        }
        assert_eq!(column_of("point").unwrap().width, 3);
        assert!(column_of("depth").is_none() && column_of("rows").is_none());
    }
}
