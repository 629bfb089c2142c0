//! PLY reader: ASCII, binary little- and big-endian, optionally gzip-compressed (`.ply.gz`).
//!
//! Reads `vertex` x/y/z (and nx/ny/nz when all three are present) and the `face` element's
//! index list (`vertex_indices` or `vertex_index`); polygons are fan-triangulated in file
//! order, so triangle numbers follow the faces of the file. Every other element and
//! property is parsed and skipped. Counts in the header are never trusted for allocation:
//! a header claiming more than the file holds gives an error at the first missing element.

use crate::LoadError;
use dynray_geom::TriangleMesh;
use std::io::Read;
use std::path::Path;

/// Most bytes a `.ply.gz` may decompress to: past any real mesh (a 28-million-triangle
/// scan is about 0.5 GiB of binary PLY), and a bound on what a compression bomb (deflate
/// inflates zeros about 1000-fold) can make the reader allocate (docs/limits.md).
pub const MAX_DECOMPRESSED_BYTES: u64 = 2 << 30;

/// Reads a `.ply` or `.ply.gz` file into a validated mesh.
pub fn load(path: &Path) -> Result<TriangleMesh, LoadError> {
    let raw = dynray_geom::file::read(path).map_err(|e| LoadError::io(path, e))?;
    let bytes = if raw.starts_with(&[0x1f, 0x8b]) {
        gunzip(&raw, MAX_DECOMPRESSED_BYTES).map_err(|e| LoadError::parse(path, None, e))?
    } else {
        raw
    };
    let mesh = parse(path, &bytes)?;
    mesh.validate().map_err(|source| LoadError::Mesh { path: path.to_path_buf(), source })?;
    Ok(mesh)
}

/// The gzip members of `raw`, decompressed, or an error once they pass `limit` bytes
/// (nothing past `limit + 1` bytes is ever allocated).
fn gunzip(raw: &[u8], limit: u64) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(raw)
        .take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| format!("corrupt gzip data: {e}"))?;
    if out.len() as u64 > limit {
        return Err(format!(
            "the gzip data decompresses to more than {} MiB (from {} bytes), past the reader's budget",
            limit >> 20,
            raw.len()
        ));
    }
    Ok(out)
}

/// Parses PLY bytes (already decompressed). `path` only labels errors.
pub fn parse(path: &Path, bytes: &[u8]) -> Result<TriangleMesh, LoadError> {
    let header = Header::parse(path, bytes)?;
    let body = &bytes[header.body_start..];
    let mut sink = Sink::new(&header, path)?;
    match header.format {
        Format::Ascii => read_ascii(path, &header, body, &mut sink)?,
        Format::BinaryLe => read_binary::<true>(path, &header, body, &mut sink)?,
        Format::BinaryBe => read_binary::<false>(path, &header, body, &mut sink)?,
    }
    Ok(sink.finish())
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Format {
    Ascii,
    BinaryLe,
    BinaryBe,
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Debug)]
enum Property {
    Scalar { name: String, ty: Scalar },
    List { name: String, count: Scalar, item: Scalar },
}

impl Property {
    fn name(&self) -> &str {
        match self {
            Property::Scalar { name, .. } | Property::List { name, .. } => name,
        }
    }
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Property>,
    /// Header line declaring it, for messages.
    line: usize,
}

struct Header {
    format: Format,
    elements: Vec<Element>,
    body_start: usize,
    /// Line number (1-based) of the first body line, for ASCII messages.
    body_line: usize,
}

impl Header {
    fn parse(path: &Path, bytes: &[u8]) -> Result<Header, LoadError> {
        let mut pos = 0;
        let mut line_no = 0;
        let mut format = None;
        let mut elements: Vec<Element> = Vec::new();
        loop {
            let Some(end) = bytes[pos..].iter().position(|&b| b == b'\n') else {
                return Err(LoadError::parse(path, Some(line_no + 1), "header ends before `end_header`"));
            };
            line_no += 1;
            let line = std::str::from_utf8(&bytes[pos..pos + end])
                .map_err(|_| LoadError::parse(path, Some(line_no), "header is not text"))?
                .trim_end_matches('\r')
                .trim();
            pos += end + 1;
            let words: Vec<&str> = line.split_whitespace().collect();
            let err = |m: String| LoadError::parse(path, Some(line_no), m);
            if line_no == 1 {
                if line != "ply" {
                    return Err(err(format!("not a PLY file: expected `ply`, found `{line}`")));
                }
                continue;
            }
            match words.as_slice() {
                [] => {}
                ["comment", ..] | ["obj_info", ..] => {}
                ["format", f, _version] => {
                    format = Some(match *f {
                        "ascii" => Format::Ascii,
                        "binary_little_endian" => Format::BinaryLe,
                        "binary_big_endian" => Format::BinaryBe,
                        other => return Err(err(format!("unknown format `{other}`"))),
                    })
                }
                ["element", name, count] => {
                    let count = count
                        .parse::<u64>()
                        .map_err(|_| err(format!("element count `{count}` is not a non-negative integer")))?;
                    elements.push(Element { name: name.to_string(), count, props: Vec::new(), line: line_no });
                }
                ["property", "list", count, item, name] => {
                    let el = elements.last_mut().ok_or_else(|| err("property before any element".into()))?;
                    let count = Scalar::from_name(count).ok_or_else(|| err(format!("unknown type `{count}`")))?;
                    let item = Scalar::from_name(item).ok_or_else(|| err(format!("unknown type `{item}`")))?;
                    if !count.is_integer() {
                        return Err(err("a list count must have an integer type".into()));
                    }
                    el.props.push(Property::List { name: name.to_string(), count, item });
                }
                ["property", ty, name] => {
                    let el = elements.last_mut().ok_or_else(|| err("property before any element".into()))?;
                    let ty = Scalar::from_name(ty).ok_or_else(|| err(format!("unknown type `{ty}`")))?;
                    el.props.push(Property::Scalar { name: name.to_string(), ty });
                }
                ["end_header"] => break,
                _ => return Err(err(format!("unexpected header line `{line}`"))),
            }
        }
        let format = format.ok_or_else(|| LoadError::parse(path, None, "header has no `format` line"))?;
        Ok(Header { format, elements, body_start: pos, body_line: line_no + 1 })
    }
}

/// What the reader does with each property value of the vertex and face elements.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    Skip,
    Pos(usize),
    Normal(usize),
    Indices,
}

struct Sink<'a> {
    path: &'a Path,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    has_normals: bool,
    /// Vertices the header declares.
    vertex_count: u64,
    indices: Vec<[u32; 3]>,
    poly: Vec<u32>,
    cur_pos: [f32; 3],
    cur_normal: [f32; 3],
}

impl<'a> Sink<'a> {
    fn new(h: &Header, path: &'a Path) -> Result<Self, LoadError> {
        let vertex = h.elements.iter().find(|e| e.name == "vertex");
        let Some(vertex) = vertex else {
            return Err(LoadError::parse(path, None, "no `vertex` element in the header"));
        };
        for axis in ["x", "y", "z"] {
            if !vertex.props.iter().any(|p| p.name() == axis && matches!(p, Property::Scalar { .. })) {
                return Err(LoadError::parse(
                    path,
                    Some(vertex.line),
                    format!("vertex element has no scalar `{axis}` property"),
                ));
            }
        }
        let has_normals = ["nx", "ny", "nz"].iter().all(|n| vertex.props.iter().any(|p| p.name() == *n));
        let face = h.elements.iter().find(|e| e.name == "face");
        if let Some(face) = face {
            if !face.props.iter().any(is_index_list) {
                return Err(LoadError::parse(path, Some(face.line), "face element has no `vertex_indices` list"));
            }
        }
        Ok(Self {
            path,
            positions: Vec::new(),
            normals: Vec::new(),
            has_normals,
            vertex_count: vertex.count,
            indices: Vec::new(),
            poly: Vec::new(),
            cur_pos: [0.0; 3],
            cur_normal: [0.0; 3],
        })
    }

    fn roles(&self, el: &Element) -> Vec<Role> {
        el.props
            .iter()
            .map(|p| match (el.name.as_str(), p.name()) {
                ("vertex", "x") => Role::Pos(0),
                ("vertex", "y") => Role::Pos(1),
                ("vertex", "z") => Role::Pos(2),
                ("vertex", "nx") if self.has_normals => Role::Normal(0),
                ("vertex", "ny") if self.has_normals => Role::Normal(1),
                ("vertex", "nz") if self.has_normals => Role::Normal(2),
                ("face", _) if is_index_list(p) => Role::Indices,
                _ => Role::Skip,
            })
            .collect()
    }

    fn scalar(&mut self, role: Role, v: f64) {
        match role {
            Role::Pos(a) => self.cur_pos[a] = v as f32,
            Role::Normal(a) => self.cur_normal[a] = v as f32,
            _ => {}
        }
    }

    fn end_vertex(&mut self) {
        self.positions.push(self.cur_pos);
        if self.has_normals {
            self.normals.push(self.cur_normal);
        }
    }

    /// Fan-triangulates the polygon gathered in `poly`; faces of fewer than three
    /// vertices produce no triangle.
    fn end_face(&mut self, line: Option<usize>, face: u64) -> Result<(), LoadError> {
        // Checked against the declared count, not the vertices read so far, so that a
        // file declaring `face` before `vertex` reads; a short vertex section fails anyway.
        if let Some(&bad) = self.poly.iter().find(|&&i| i as u64 >= self.vertex_count) {
            return Err(LoadError::parse(
                self.path,
                line,
                format!("face {face} uses vertex {bad}, but the file has {} vertices", self.vertex_count),
            ));
        }
        for k in 1..self.poly.len().saturating_sub(1) {
            self.indices.push([self.poly[0], self.poly[k], self.poly[k + 1]]);
        }
        self.poly.clear();
        Ok(())
    }

    fn index(&mut self, v: f64, line: Option<usize>, face: u64) -> Result<(), LoadError> {
        if !(v >= 0.0 && v < u32::MAX as f64 && v.fract() == 0.0) {
            return Err(LoadError::parse(self.path, line, format!("face {face} has an invalid vertex index {v}")));
        }
        self.poly.push(v as u32);
        Ok(())
    }

    fn finish(self) -> TriangleMesh {
        TriangleMesh {
            positions: self.positions,
            indices: self.indices,
            normals: self.has_normals.then_some(self.normals),
            uvs: None,
        }
    }
}

fn is_index_list(p: &Property) -> bool {
    matches!(p, Property::List { name, .. } if name == "vertex_indices" || name == "vertex_index")
}

fn read_ascii(path: &Path, h: &Header, body: &[u8], sink: &mut Sink) -> Result<(), LoadError> {
    let text = std::str::from_utf8(body).map_err(|e| {
        let line = h.body_line + body[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count();
        LoadError::parse(path, Some(line), "ASCII body is not UTF-8 text")
    })?;
    let mut lines = text.lines().enumerate().map(|(i, l)| (h.body_line + i, l)).filter(|(_, l)| !l.trim().is_empty());
    for el in &h.elements {
        if el.props.is_empty() {
            continue; // occupies no text; its count may be anything (see read_binary)
        }
        let roles = sink.roles(el);
        for n in 0..el.count {
            let Some((line_no, text_line)) = lines.next() else {
                return Err(LoadError::parse(
                    path,
                    None,
                    format!("file ends after {n} of the {} `{}` elements the header declares", el.count, el.name),
                ));
            };
            let line = Some(line_no);
            let mut words = text_line.split_whitespace();
            let mut next = |what: &str| -> Result<f64, LoadError> {
                let w = words.next().ok_or_else(|| {
                    LoadError::parse(path, line, format!("`{}` element {n} is missing its {what}", el.name))
                })?;
                w.parse::<f64>()
                    .map_err(|_| LoadError::parse(path, line, format!("expected a number for {what}, found `{w}`")))
            };
            for (p, &role) in el.props.iter().zip(&roles) {
                match p {
                    Property::Scalar { name, .. } => {
                        let v = next(name)?;
                        sink.scalar(role, v);
                    }
                    Property::List { name, .. } => {
                        let count = next(&format!("{name} count"))?;
                        if !(count >= 0.0 && count.fract() == 0.0) {
                            return Err(LoadError::parse(path, line, format!("invalid list length {count}")));
                        }
                        for _ in 0..count as u64 {
                            let v = next(name)?;
                            if role == Role::Indices {
                                sink.index(v, line, n)?;
                            }
                        }
                    }
                }
            }
            end_element(sink, el, line, n)?;
        }
    }
    Ok(())
}

fn end_element(sink: &mut Sink, el: &Element, line: Option<usize>, n: u64) -> Result<(), LoadError> {
    match el.name.as_str() {
        "vertex" => sink.end_vertex(),
        "face" => sink.end_face(line, n)?,
        _ => {}
    }
    Ok(())
}

fn read_binary<const LE: bool>(path: &Path, h: &Header, body: &[u8], sink: &mut Sink) -> Result<(), LoadError> {
    let mut at = 0usize;
    for el in &h.elements {
        if el.props.is_empty() {
            // Zero bytes per element: skipping it whole keeps a claim of 10^11 such
            // elements from looping for minutes (vertex and face always have properties).
            continue;
        }
        let roles = sink.roles(el);
        for n in 0..el.count {
            let truncated = || {
                LoadError::parse(
                    path,
                    None,
                    format!("file ends inside `{}` element {n} of the {} the header declares", el.name, el.count),
                )
            };
            for (p, &role) in el.props.iter().zip(&roles) {
                match p {
                    Property::Scalar { ty, .. } => {
                        let v = read_scalar::<LE>(body, &mut at, *ty).ok_or_else(truncated)?;
                        sink.scalar(role, v);
                    }
                    Property::List { count, item, .. } => {
                        let c = read_scalar::<LE>(body, &mut at, *count).ok_or_else(truncated)?;
                        if c < 0.0 {
                            return Err(LoadError::parse(
                                path,
                                None,
                                format!("`{}` element {n}: negative list length", el.name),
                            ));
                        }
                        let c = c as usize;
                        if role == Role::Indices {
                            for _ in 0..c {
                                let v = read_scalar::<LE>(body, &mut at, *item).ok_or_else(truncated)?;
                                sink.index(v, None, n)?;
                            }
                        } else {
                            let bytes = c.checked_mul(item.size()).ok_or_else(truncated)?;
                            at = at.checked_add(bytes).filter(|&e| e <= body.len()).ok_or_else(truncated)?;
                        }
                    }
                }
            }
            end_element(sink, el, None, n)?;
        }
    }
    Ok(())
}

#[inline]
fn read_scalar<const LE: bool>(body: &[u8], at: &mut usize, ty: Scalar) -> Option<f64> {
    let n = ty.size();
    let b = body.get(*at..*at + n)?;
    *at += n;
    macro_rules! num {
        ($t:ty) => {{
            let a = b.try_into().ok()?;
            (if LE { <$t>::from_le_bytes(a) } else { <$t>::from_be_bytes(a) }) as f64
        }};
    }
    Some(match ty {
        Scalar::I8 => b[0] as i8 as f64,
        Scalar::U8 => b[0] as f64,
        Scalar::I16 => num!(i16),
        Scalar::U16 => num!(u16),
        Scalar::I32 => num!(i32),
        Scalar::U32 => num!(u32),
        Scalar::F32 => num!(f32),
        Scalar::F64 => num!(f64),
    })
}

#[cfg(test)]
mod gzip_tests {
    use super::*;
    use std::io::Write;

    fn gz(data: &[u8]) -> Vec<u8> {
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        e.write_all(data).unwrap();
        e.finish().unwrap()
    }

    #[test]
    fn a_compression_bomb_stops_at_the_budget() {
        // 64 MiB of zeros squeeze into about 64 KiB: a small bomb against a 1 MiB budget.
        let bomb = gz(&vec![0u8; 64 << 20]);
        assert!(bomb.len() < 1 << 20);
        let e = gunzip(&bomb, 1 << 20).unwrap_err();
        assert!(e.contains("more than 1 MiB"), "{e}");
        let fine = gz(b"ply\nformat ascii 1.0\nend_header\n");
        assert_eq!(gunzip(&fine, 1 << 20).unwrap(), b"ply\nformat ascii 1.0\nend_header\n");
        // Exactly at the budget is allowed.
        assert_eq!(gunzip(&gz(&[7u8; 1000]), 1000).unwrap().len(), 1000);
    }
}
