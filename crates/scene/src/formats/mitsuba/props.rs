//! The properties of one Mitsuba object (`<float name="fov" value="40"/>`, `<rgb …>`,
//! `<transform name="to_world">`, nested objects): taken by name as the object's reader
//! asks for them, each at most once; whatever is left when the reader is done is an error
//! naming it (`finish`), so a misspelt or unsupported parameter never passes silently.

use super::spectrum::{spectrum_to_srgb, uniform_to_srgb};
use super::transform::parse_transform;
use super::tree::Elem;
use crate::LoadError;
use glam::{DMat4, DVec3};

/// Tags of property elements; any other child is a nested object.
const PROPERTY_TAGS: &[&str] =
    &["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform"];

/// The not-yet-read children of an object element.
pub(super) struct Props<'a> {
    pub elem: &'a Elem,
    left: Vec<&'a Elem>,
}

impl<'a> Props<'a> {
    /// The properties and nested objects of `elem`, whose attributes may only be `type`,
    /// `id` and `name`.
    pub fn new(elem: &'a Elem) -> Result<Self, LoadError> {
        elem.only_attrs(&["type", "id", "name"])?;
        Ok(Self { elem, left: elem.children.iter().collect() })
    }

    /// Takes the property element named `name`, checking its tag is one of `tags`.
    fn take(&mut self, name: &str, tags: &[&str]) -> Result<Option<&'a Elem>, LoadError> {
        let Some(i) =
            self.left.iter().position(|e| PROPERTY_TAGS.contains(&e.tag.as_str()) && e.attr("name") == Some(name))
        else {
            return Ok(None);
        };
        let e = self.left.remove(i);
        if !tags.contains(&e.tag.as_str()) {
            return Err(e.error(format!("`{name}` is a <{}>; expected {}", e.tag, list(tags))));
        }
        if let Some(dup) = self.left.iter().find(|o| o.attr("name") == Some(name)) {
            return Err(dup.error(format!("`{name}` is given twice (first at line {})", e.line)));
        }
        Ok(Some(e))
    }

    /// The tag of the unread property `name` (`"float"`, `"string"`, …), if there is one.
    pub fn tag_of(&self, name: &str) -> Option<&'a str> {
        self.left
            .iter()
            .find(|e| PROPERTY_TAGS.contains(&e.tag.as_str()) && e.attr("name") == Some(name))
            .map(|e| e.tag.as_str())
    }

    /// A `<float>` (an `<integer>` is accepted too).
    pub fn float(&mut self, name: &str, default: f64) -> Result<f64, LoadError> {
        match self.take(name, &["float", "integer"])? {
            Some(e) => number(e, e.required("value")?),
            None => Ok(default),
        }
    }

    /// An `<integer>`.
    pub fn integer(&mut self, name: &str, default: i64) -> Result<i64, LoadError> {
        match self.take(name, &["integer"])? {
            Some(e) => {
                e.only_attrs(&["name", "value"])?;
                let v = e.required("value")?;
                v.trim().parse::<i64>().map_err(|_| e.error(format!("`{name}`: `{v}` is not an integer")))
            }
            None => Ok(default),
        }
    }

    /// A `<boolean>`.
    pub fn boolean(&mut self, name: &str, default: bool) -> Result<bool, LoadError> {
        match self.take(name, &["boolean"])? {
            Some(e) => {
                e.only_attrs(&["name", "value"])?;
                match e.required("value")?.trim() {
                    "true" => Ok(true),
                    "false" => Ok(false),
                    v => Err(e.error(format!("`{name}`: `{v}` is not true or false"))),
                }
            }
            None => Ok(default),
        }
    }

    /// A `<string>` and the element it came from.
    pub fn string(&mut self, name: &str) -> Result<Option<(String, &'a Elem)>, LoadError> {
        match self.take(name, &["string"])? {
            Some(e) => {
                e.only_attrs(&["name", "value"])?;
                Ok(Some((e.required("value")?.to_string(), e)))
            }
            None => Ok(None),
        }
    }

    /// A colour: `<rgb>`, `<spectrum>` (a wavelength:value list or one value) or
    /// `<float>` (grey). `emitter` says whether it is an emitter's radiance or
    /// intensity, which Mitsuba converts unbounded (`spectrum.rs`).
    pub fn color(&mut self, name: &str, emitter: bool) -> Result<Option<DVec3>, LoadError> {
        let Some(e) = self.take(name, &["rgb", "spectrum", "float"])? else { return Ok(None) };
        if e.tag == "spectrum" && e.attr("filename").is_some() {
            return Err(e.error(format!("`{name}`: spectra from files are not supported; give wavelength:value pairs")));
        }
        e.only_attrs(&["name", "value"])?;
        let v = e.required("value")?;
        let c = match e.tag.as_str() {
            "float" => DVec3::splat(number(e, v)?),
            "rgb" => {
                let xs = numbers(e, v)?;
                match xs.as_slice() {
                    [g] => DVec3::splat(*g),
                    [r, g, b] => DVec3::new(*r, *g, *b),
                    _ => return Err(e.error(format!("`{name}`: an <rgb> value has 1 or 3 numbers, not {}", xs.len()))),
                }
            }
            _ => {
                let points = spectrum_points(e, v)?;
                let rgb = match points.as_slice() {
                    [(None, value)] => uniform_to_srgb(*value, emitter),
                    _ => {
                        let pts: Vec<(f64, f64)> = points.iter().map(|(w, v)| (w.unwrap_or(0.0), *v)).collect();
                        spectrum_to_srgb(&pts, !emitter)
                    }
                };
                DVec3::new(rgb[0] as f64, rgb[1] as f64, rgb[2] as f64)
            }
        };
        Ok(Some(c))
    }

    /// A `<point>` or `<vector>`: `x`, `y`, `z` attributes (missing ones 0) or `value`.
    pub fn point(&mut self, name: &str) -> Result<Option<DVec3>, LoadError> {
        let Some(e) = self.take(name, &["point", "vector"])? else { return Ok(None) };
        xyz(e, 0.0).map(Some)
    }

    /// A `<transform>` as its matrix (`transform.rs`).
    pub fn transform(&mut self, name: &str) -> Result<Option<DMat4>, LoadError> {
        match self.take(name, &["transform"])? {
            Some(e) => parse_transform(e).map(Some),
            None => Ok(None),
        }
    }

    /// Takes every nested object (a child that is not a property) with tag `tag`.
    pub fn objects(&mut self, tag: &str) -> Vec<&'a Elem> {
        let (taken, left): (Vec<&Elem>, Vec<&Elem>) = self.left.iter().partition(|e| e.tag == tag);
        self.left = left;
        taken
    }

    /// Errors on the first child nobody read.
    pub fn finish(self) -> Result<(), LoadError> {
        let what = format!(
            "<{}{}>",
            self.elem.tag,
            self.elem.attr("type").map(|t| format!(" type=\"{t}\"")).unwrap_or_default()
        );
        match self.left.first() {
            None => Ok(()),
            Some(e) => match e.attr("name") {
                Some(n) if PROPERTY_TAGS.contains(&e.tag.as_str()) => {
                    Err(e.error(format!("{what}: parameter `{n}` (<{}>) is not supported by dynray", e.tag)))
                }
                _ => Err(e.error(format!("{what}: a nested <{}> is not supported here", e.tag))),
            },
        }
    }
}

fn list(tags: &[&str]) -> String {
    tags.iter().map(|t| format!("<{t}>")).collect::<Vec<_>>().join(" or ")
}

/// One finite number.
pub(super) fn number(e: &Elem, text: &str) -> Result<f64, LoadError> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(e.error(format!("<{}>: `{text}` is not a finite number", e.tag))),
    }
}

/// Numbers separated by commas and/or white space.
pub(super) fn numbers(e: &Elem, text: &str) -> Result<Vec<f64>, LoadError> {
    text.split(|c: char| c == ',' || c.is_whitespace()).filter(|s| !s.is_empty()).map(|s| number(e, s)).collect()
}

/// `x`/`y`/`z` attributes (missing ones `default`) or a `value` of 1 or 3 numbers.
pub(super) fn xyz(e: &Elem, default: f64) -> Result<DVec3, LoadError> {
    e.only_attrs(&["name", "x", "y", "z", "value"])?;
    if let Some(v) = e.attr("value") {
        if e.attr("x").is_some() || e.attr("y").is_some() || e.attr("z").is_some() {
            return Err(e.error(format!("<{}>: give either `value` or `x`/`y`/`z`, not both", e.tag)));
        }
        let xs = numbers(e, v)?;
        return match xs.as_slice() {
            [a] => Ok(DVec3::splat(*a)),
            [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
            _ => Err(e.error(format!("<{}>: `value` has 1 or 3 numbers, not {}", e.tag, xs.len()))),
        };
    }
    let get = |k: &str| e.attr(k).map_or(Ok(default), |v| number(e, v));
    Ok(DVec3::new(get("x")?, get("y")?, get("z")?))
}

/// `400:0.5, 500:0.7` (wavelengths increasing) or one value (`(None, v)`).
fn spectrum_points(e: &Elem, text: &str) -> Result<Vec<(Option<f64>, f64)>, LoadError> {
    if !text.contains(':') {
        return Ok(vec![(None, number(e, text)?)]);
    }
    let mut out: Vec<(Option<f64>, f64)> = Vec::new();
    for pair in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let Some((w, v)) = pair.split_once(':') else {
            return Err(e.error(format!("<spectrum>: `{pair}` is not wavelength:value")));
        };
        let (w, v) = (number(e, w)?, number(e, v)?);
        if out.last().is_some_and(|p| p.0.is_some_and(|l| w <= l)) {
            return Err(e.error(format!("<spectrum>: wavelength {w} does not increase")));
        }
        out.push((Some(w), v));
    }
    if out.is_empty() {
        return Err(e.error("<spectrum>: no values"));
    }
    Ok(out)
}
