//! Structure parameters as text: the one trait every params struct implements, so the
//! command line (`--accel bih:max_prims=5`), the bench and the tests read, list, preset
//! and validate them the same way.
//!
//! Each params struct owns its keys (name, one-line doc with the useful range), its named
//! presets and its validation; [`crate::AccelSpec`] only picks the struct by kind.

use crate::BuildError;

/// One `key=value` parameter a structure accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParamKey {
    /// The key as written on the command line.
    pub name: &'static str,
    /// One line: what it changes and its useful range.
    pub doc: &'static str,
}

/// The key every structure accepts besides its own: a named preset, applied before the
/// other keys whatever their order.
pub const PRESET_KEY: ParamKey =
    ParamKey { name: "preset", doc: "named preset the other keys start from (default: `default`)" };

/// A structure's build parameters, settable by name from text.
pub trait StructureParams: Sized + Clone + Default + std::fmt::Debug {
    /// The structure family named in errors (`bvh`, `kdtree`, …); [`crate::AccelSpec`]
    /// replaces it with the exact kind (`kdtree-ropes`) through [`BuildError::in_structure`].
    const STRUCTURE: &'static str;

    /// Keys [`StructureParams::set`] accepts, besides [`PRESET_KEY`].
    const KEYS: &'static [ParamKey];

    /// Every named preset, `default` among them, in the order listings show them.
    fn presets() -> Vec<(&'static str, Self)>;

    /// Sets one field from its text. Unknown keys give [`BuildError::UnknownParam`],
    /// unparsable values [`BuildError::BadValue`]; ranges are checked by
    /// [`StructureParams::validate`], once every key is set.
    fn set(&mut self, key: &str, value: &str) -> Result<(), BuildError>;

    /// Rejects values outside the documented ranges with [`BuildError::Param`].
    fn validate(&self) -> Result<(), BuildError>;

    /// The preset called `name`, or [`BuildError::UnknownPreset`] listing them.
    fn preset(name: &str) -> Result<Self, BuildError> {
        let presets = Self::presets();
        presets.iter().find(|(n, _)| *n == name).map(|(_, p)| p.clone()).ok_or_else(|| BuildError::UnknownPreset {
            structure: Self::STRUCTURE,
            preset: name.to_string(),
            known: presets.iter().map(|(n, _)| *n).collect(),
        })
    }

    /// Every accepted key, `preset` first, for error messages and listings.
    fn key_names() -> Vec<&'static str> {
        std::iter::once(PRESET_KEY.name).chain(Self::KEYS.iter().map(|k| k.name)).collect()
    }

    /// The defaults (or `preset=…`, wherever it appears), then every other pair in order,
    /// then [`StructureParams::validate`].
    fn from_pairs(pairs: &[(String, String)]) -> Result<Self, BuildError> {
        let mut p = match pairs.iter().find(|(k, _)| k == PRESET_KEY.name) {
            Some((_, name)) => Self::preset(name)?,
            None => Self::default(),
        };
        for (k, v) in pairs.iter().filter(|(k, _)| k != PRESET_KEY.name) {
            p.set(k, v)?;
        }
        p.validate()?;
        Ok(p)
    }
}

/// The error for a key that `P` does not know, listing the ones it does.
pub fn unknown_key<P: StructureParams>(key: &str) -> BuildError {
    BuildError::UnknownParam { structure: P::STRUCTURE, key: key.to_string(), known: P::key_names() }
}

/// The `validate` failure of `P` for field `name` (outside its documented range), named
/// after the structure so the message says whose parameter it is.
pub fn out_of_range<P: StructureParams>(name: &'static str, message: String) -> Result<(), BuildError> {
    Err(BuildError::Param { structure: P::STRUCTURE, name, message })
}

/// Value parsers shared by the `set` implementations, so every structure spells numbers,
/// switches and "off" alike.
pub mod value {
    use crate::BuildError;

    fn bad(structure: &'static str, key: &str, value: &str, expected: &'static str) -> BuildError {
        BuildError::BadValue { structure, key: key.to_string(), value: value.to_string(), expected }
    }

    /// A whole number.
    pub fn u32(structure: &'static str, key: &str, value: &str) -> Result<u32, BuildError> {
        value.trim().parse().map_err(|_| bad(structure, key, value, "a whole number"))
    }

    /// A number (`inf` and `nan` parse; validation rejects them where they make no sense).
    pub fn f32(structure: &'static str, key: &str, value: &str) -> Result<f32, BuildError> {
        value.trim().parse().map_err(|_| bad(structure, key, value, "a number"))
    }

    /// `on`/`true`/`yes`/`1` or `off`/`false`/`no`/`0`.
    pub fn bool(structure: &'static str, key: &str, value: &str) -> Result<bool, BuildError> {
        match value.trim() {
            "on" | "true" | "yes" | "1" => Ok(true),
            "off" | "false" | "no" | "0" => Ok(false),
            _ => Err(bad(structure, key, value, "on or off")),
        }
    }

    /// `off`/`none` (None), `on` (`Some(on)`, the documented default factor) or a number.
    pub fn opt_f32(structure: &'static str, key: &str, value: &str, on: f32) -> Result<Option<f32>, BuildError> {
        match value.trim() {
            "off" | "none" => Ok(None),
            "on" => Ok(Some(on)),
            v => v.parse().map(Some).map_err(|_| bad(structure, key, value, "a number, on or off")),
        }
    }

    /// One of `choices`, returned as its index.
    pub fn choice(
        structure: &'static str,
        key: &str,
        value: &str,
        choices: &[&str],
        expected: &'static str,
    ) -> Result<usize, BuildError> {
        choices.iter().position(|c| *c == value.trim()).ok_or_else(|| bad(structure, key, value, expected))
    }
}
