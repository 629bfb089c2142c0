//! The bytes glTF refers to: buffers and images given by URI (relative paths, `file:`,
//! `data:…;base64,`), the `.glb` binary chunk, and buffer views.
//!
//! dynray reads these itself instead of through gltf's `import` feature, which would
//! also bring gltf's own image decoding (it decodes every image of a file, used or not).
//! The checks gltf 1.4 lacks are made here: a relative URI that percent-decodes to
//! invalid UTF-8 (gltf panics on it) is an error, a URI must name a regular file (a
//! device such as `/dev/zero` would be read forever), and a file must stay inside the
//! glTF file's folder tree (crate::reference: no `/etc/passwd`, no `../../`).

use base64::engine::general_purpose::{GeneralPurpose, GeneralPurposeConfig};
use base64::engine::DecodePaddingMode;
use base64::Engine;
use std::path::{Path, PathBuf};

/// Standard base64, padded or not (exporters differ).
const BASE64: GeneralPurpose = GeneralPurpose::new(
    &base64::alphabet::STANDARD,
    GeneralPurposeConfig::new().with_decode_padding_mode(DecodePaddingMode::Indifferent),
);

/// What a URI names.
#[derive(Debug, PartialEq)]
pub(super) enum Uri<'a> {
    /// Inline data: the media type (may be empty) and the base64 text.
    Data { media_type: &'a str, base64: &'a str },
    /// A file on disk (relative URIs resolved against the glTF file's directory).
    File(PathBuf),
}

/// Parses `uri`, resolving relative ones against `base`.
pub(super) fn parse<'u>(base: &Path, uri: &'u str) -> Result<Uri<'u>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        return match rest.split_once(";base64,") {
            Some((media_type, base64)) => Ok(Uri::Data { media_type, base64 }),
            None => Err("a data URI must be base64 (`data:…;base64,…`)".to_string()),
        };
    }
    if let Some(rest) = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:")) {
        return Ok(Uri::File(PathBuf::from(rest)));
    }
    if uri.contains(':') {
        return Err(format!("URI scheme of `{uri}` is not supported (only relative, file: and data:)"));
    }
    let rel = percent_decode(uri).ok_or_else(|| format!("URI `{uri}` does not decode to UTF-8"))?;
    Ok(Uri::File(base.join(rel)))
}

/// The bytes `uri` names (module docs). Errors name the file or the URI's problem.
pub(super) fn read(base: &Path, uri: &str) -> Result<Vec<u8>, String> {
    match parse(base, uri)? {
        Uri::Data { base64, .. } => BASE64.decode(base64).map_err(|e| format!("data URI: {e}")),
        Uri::File(file) => {
            let file = crate::reference::Root::folder(base, &[]).check(&file)?;
            check_regular_file(&file)?;
            dynray_geom::file::read(&file).map_err(|e| format!("{}: {e}", file.display()))
        }
    }
}

/// Checks that `file` exists and is a regular file.
pub(super) fn check_regular_file(file: &Path) -> Result<(), String> {
    match std::fs::metadata(file) {
        Ok(m) if m.is_file() => Ok(()),
        Ok(_) => Err(format!("{} is not a regular file", file.display())),
        Err(e) => Err(format!("{}: {e}", file.display())),
    }
}

/// Every buffer of `document`, in order: URIs read, the binary chunk for the one that
/// names it. Each must hold at least its declared `byteLength`.
pub(super) fn read_buffers(
    document: &gltf::Document,
    base: &Path,
    blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, String> {
    let mut blob = blob;
    let mut out = Vec::with_capacity(document.buffers().len());
    for buffer in document.buffers() {
        let label = format!("buffer {}", buffer.index());
        let data = match buffer.source() {
            gltf::buffer::Source::Uri(uri) => read(base, uri).map_err(|m| format!("{label}: {m}"))?,
            gltf::buffer::Source::Bin => {
                blob.take().ok_or_else(|| format!("{label} names the binary chunk, which the file lacks"))?
            }
        };
        if data.len() < buffer.length() {
            let from = match buffer.source() {
                gltf::buffer::Source::Uri(u) => match parse(base, u) {
                    Ok(Uri::File(f)) => f.display().to_string(),
                    _ => "its data URI".to_string(),
                },
                gltf::buffer::Source::Bin => "the binary chunk".to_string(),
            };
            return Err(format!(
                "{label}: {from} has {} bytes, but the buffer declares byteLength {}",
                data.len(),
                buffer.length()
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// The bytes of a buffer view, checked to lie inside its buffer.
pub(super) fn view_bytes<'b>(view: &gltf::buffer::View, buffers: &'b [Vec<u8>]) -> Result<&'b [u8], String> {
    let data = buffers.get(view.buffer().index()).map_or(&[][..], Vec::as_slice);
    view.offset()
        .checked_add(view.length())
        .and_then(|end| data.get(view.offset()..end))
        .ok_or_else(|| format!("buffer view {} runs past its buffer ({} bytes)", view.index(), data.len()))
}

/// `%XX` decoding as the glTF importer does it; `None` when the result is not UTF-8.
pub(super) fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        match (b[i], b.get(i + 1).copied().and_then(hex), b.get(i + 2).copied().and_then(hex)) {
            (b'%', Some(h), Some(l)) => {
                out.push((h * 16 + l) as u8);
                i += 3;
            }
            (c, _, _) => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris_must_name_regular_files() {
        assert_eq!(percent_decode("a%20b%2Fc%zz%4"), Some("a b/c%zz%4".into()));
        assert_eq!(percent_decode("%FF"), None);
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a b.bin"), [7u8; 4]).unwrap();
        assert_eq!(read(dir.path(), "a%20b.bin").unwrap(), vec![7; 4]);
        assert_eq!(read(dir.path(), "data:application/octet-stream;base64,AAEC").unwrap(), vec![0, 1, 2]);
        assert_eq!(read(dir.path(), "data:;base64,AAE").unwrap(), vec![0, 1], "unpadded base64");
        assert!(read(dir.path(), "data:text/plain,hello").unwrap_err().contains("base64"));
        assert!(read(dir.path(), "data:;base64,!!!").unwrap_err().contains("data URI"));
        assert!(read(dir.path(), "%FF.bin").unwrap_err().contains("UTF-8"));
        assert!(read(dir.path(), ".").unwrap_err().contains("not a regular file"));
        assert!(read(dir.path(), "missing.bin").unwrap_err().contains("missing.bin"));
        assert!(read(dir.path(), "http://example.com/x.bin").unwrap_err().contains("not supported"));
        if Path::new("/dev/zero").exists() {
            // Outside the glTF's folder: refused before its type is even looked at.
            assert!(read(dir.path(), "file:///dev/zero").unwrap_err().contains("outside"));
        }
        // Inside the folder, a named pipe is still no buffer.
        let fifo = dir.path().join("pipe.bin");
        if std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success()) {
            assert!(read(dir.path(), "pipe.bin").unwrap_err().contains("not a regular file"));
        }
    }
}
