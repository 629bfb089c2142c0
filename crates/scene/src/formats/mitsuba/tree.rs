//! Mitsuba XML as an owned element tree: `include`s expanded in place, `default`
//! parameters substituted into every `$name` of an attribute value, each element
//! remembering its file and line for errors.
//!
//! roxmltree parses each file (a read-only DOM that keeps byte positions); the tree is
//! copied out of it so that one scene can hold elements of several files and refer to
//! ids across them, forward as well as backward (Mitsuba resolves `ref`s after parsing
//! the whole scene, and the Cornell box's `cbox-rgb.xml` relies on it).

use crate::LoadError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Deepest `include` nesting accepted (a cycle is reported before this is reached).
const MAX_INCLUDE_DEPTH: usize = 16;

/// Largest scene file read, bytes (a scene description is text; meshes are separate).
const MAX_XML_BYTES: u64 = 64 << 20;

/// One XML element.
#[derive(Clone, Debug)]
pub(super) struct Elem {
    pub tag: String,
    /// Attributes in document order, `$name` already substituted.
    pub attrs: Vec<(String, String)>,
    pub children: Vec<Elem>,
    /// The file the element is written in.
    pub file: Arc<PathBuf>,
    /// The scene file the loading started from (an include's elements name files
    /// relative to it too, as Mitsuba's file resolver does).
    pub root: Arc<PathBuf>,
    /// 1-based line of its start tag.
    pub line: usize,
}

impl Elem {
    /// The attribute `name`, if present.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str())
    }

    /// The attribute `name`, or an error naming the element.
    pub fn required(&self, name: &str) -> Result<&str, LoadError> {
        self.attr(name).ok_or_else(|| self.error(format!("<{}> needs a `{name}` attribute", self.tag)))
    }

    /// An error at this element.
    pub fn error(&self, message: impl Into<String>) -> LoadError {
        LoadError::parse(&self.file, Some(self.line), message)
    }

    /// Errors on any attribute not in `allowed` (a misspelt attribute would otherwise be
    /// silently ignored).
    pub fn only_attrs(&self, allowed: &[&str]) -> Result<(), LoadError> {
        match self.attrs.iter().find(|(k, _)| !allowed.contains(&k.as_str())) {
            Some((k, _)) => Err(self.error(format!("<{}>: unknown attribute `{k}`", self.tag))),
            None => Ok(()),
        }
    }

    /// A path written in this element's file: relative to that file's folder, or where
    /// that does not exist, to the main scene file's folder (Mitsuba's resolver searches
    /// both; the Cornell box's fragments name meshes relative to the main file). It must
    /// stay inside the main file's folder tree ([`crate::reference`]).
    pub fn resolve(&self, name: &str) -> Result<PathBuf, LoadError> {
        let here = self.file.parent().unwrap_or(Path::new("")).join(name);
        let main = self.root.parent().unwrap_or(Path::new("")).join(name);
        let path = if here.exists() || !main.exists() { here } else { main };
        crate::reference::Root::of(&self.root, &[]).check(&path).map_err(|m| self.error(m))
    }
}

/// Reads `path` as a Mitsuba scene: the `<scene>` root with includes expanded.
pub(super) fn read_scene(path: &Path) -> Result<Elem, LoadError> {
    let mut defaults = HashMap::new();
    let mut stack = Vec::new();
    read_file(path, &Arc::new(path.to_path_buf()), &mut defaults, &mut stack)
}

fn read_file(
    path: &Path,
    root: &Arc<PathBuf>,
    defaults: &mut HashMap<String, String>,
    stack: &mut Vec<PathBuf>,
) -> Result<Elem, LoadError> {
    let canonical = std::fs::canonicalize(path).map_err(|e| LoadError::io(path, e))?;
    if stack.contains(&canonical) {
        return Err(LoadError::parse(path, None, "include cycle: this file includes itself"));
    }
    if stack.len() >= MAX_INCLUDE_DEPTH {
        return Err(LoadError::parse(path, None, format!("includes nested deeper than {MAX_INCLUDE_DEPTH}")));
    }
    let len = std::fs::metadata(path).map_err(|e| LoadError::io(path, e))?.len();
    if len > MAX_XML_BYTES {
        return Err(LoadError::parse(path, None, format!("{len} bytes: larger than the {MAX_XML_BYTES}-byte limit")));
    }
    let text = dynray_geom::file::read_to_string(path).map_err(|e| LoadError::io(path, e))?;
    let doc = roxmltree::Document::parse(&text).map_err(|e| {
        let pos = e.pos();
        LoadError::parse(path, Some(pos.row as usize), format!("XML: {e}"))
    })?;
    let file = Arc::new(path.to_path_buf());
    let root_elem = doc.root_element();
    let line = doc.text_pos_at(root_elem.range().start).row as usize;
    if root_elem.tag_name().name() != "scene" {
        return Err(LoadError::parse(
            path,
            Some(line),
            format!("the root element is <{}>; a Mitsuba scene starts with <scene>", root_elem.tag_name().name()),
        ));
    }
    check_depth(&doc, root_elem, path)?;
    stack.push(canonical);
    let scene = convert(&doc, root_elem, &file, root, defaults, stack);
    stack.pop();
    scene
}

/// Deepest element nesting a scene file may have: real Mitsuba scenes nest a handful of
/// levels (scene > shape > bsdf > texture > …); the conversion below recurses per level,
/// so a hostile file of 200,000 nested elements would otherwise overflow the stack.
const MAX_ELEMENT_DEPTH: usize = 64;

/// Refuses a document nested deeper than [`MAX_ELEMENT_DEPTH`], by an iterative walk,
/// naming the line of the first element too deep.
fn check_depth(doc: &roxmltree::Document<'_>, root: roxmltree::Node<'_, '_>, path: &Path) -> Result<(), LoadError> {
    // Element depth per node, in document order (a parent comes before its children).
    let mut depth = vec![0u32; doc.descendants().count()];
    for n in root.descendants().filter(|n| n.is_element()) {
        let parent = n.parent_element().filter(|p| p.id() != n.id());
        let d = parent.map_or(1, |p| depth[p.id().get_usize()] + 1);
        depth[n.id().get_usize()] = d;
        if d as usize > MAX_ELEMENT_DEPTH {
            let line = doc.text_pos_at(n.range().start).row as usize;
            return Err(LoadError::parse(
                path,
                Some(line),
                format!("elements nested more than {MAX_ELEMENT_DEPTH} deep"),
            ));
        }
    }
    Ok(())
}

/// Copies `node` (and its children) out of the DOM, expanding includes and defaults.
fn convert(
    doc: &roxmltree::Document<'_>,
    node: roxmltree::Node<'_, '_>,
    file: &Arc<PathBuf>,
    root: &Arc<PathBuf>,
    defaults: &mut HashMap<String, String>,
    stack: &mut Vec<PathBuf>,
) -> Result<Elem, LoadError> {
    let line = doc.text_pos_at(node.range().start).row as usize;
    let mut attrs = Vec::new();
    for a in node.attributes() {
        attrs.push((a.name().to_string(), substitute(a.value(), defaults, file, line)?));
    }
    let mut e = Elem {
        tag: node.tag_name().name().to_string(),
        attrs,
        children: Vec::new(),
        file: file.clone(),
        root: root.clone(),
        line,
    };
    for child in node.children().filter(|c| c.is_element()) {
        let c = convert(doc, child, file, root, defaults, stack)?;
        match c.tag.as_str() {
            "default" => {
                c.only_attrs(&["name", "value"])?;
                let (name, value) = (c.required("name")?, c.required("value")?);
                // A default never replaces a value already set (Mitsuba: parameters
                // given to the loader win; the first default for a name stands).
                defaults.entry(name.to_string()).or_insert_with(|| value.to_string());
            }
            "include" => {
                c.only_attrs(&["filename"])?;
                let path = c.resolve(c.required("filename")?)?;
                let included = read_file(&path, root, defaults, stack)
                    .map_err(|err| c.error(format!("in the included file: {err}")))?;
                e.children.extend(included.children);
            }
            _ => e.children.push(c),
        }
    }
    Ok(e)
}

/// Replaces every `$name` in `value` by its default; an unknown name is an error.
fn substitute(value: &str, defaults: &HashMap<String, String>, file: &Path, line: usize) -> Result<String, LoadError> {
    if !value.contains('$') {
        return Ok(value.to_string());
    }
    let mut out = String::new();
    let mut rest = value;
    while let Some(i) = rest.find('$') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let n = after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len());
        let name = &after[..n];
        match defaults.get(name) {
            Some(v) if !name.is_empty() => out.push_str(v),
            _ => {
                return Err(LoadError::parse(
                    file,
                    Some(line),
                    format!("`${name}`: no <default name=\"{name}\"> defines this parameter"),
                ))
            }
        }
        rest = &after[n..];
    }
    out.push_str(rest);
    Ok(out)
}
