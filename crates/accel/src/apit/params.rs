//! Build parameters of the A-buffer and the A-PIT, with named presets.

use crate::structure_params::{out_of_range, unknown_key, value, ParamKey, StructureParams};
use crate::BuildError;
use dynray_geom::Vec3;

/// Where the cube of A-buffers is centred.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Observer {
    /// The centre of the mesh's bounding box, whatever the camera (`observer=center`).
    BoundsCenter,
    /// A given point, e.g. the camera position (the seed's choice).
    Point(Vec3),
    /// Follow the camera (`observer=eye`, the default): the eye given to
    /// [`crate::AccelSpec::build`] or [`crate::Accel::update_for_eye`] becomes
    /// [`Observer::Point`]; until one is given, the bounds centre.
    Eye,
}

/// Parameters of [`crate::apit::Apit`] and [`crate::apit::ABuffer`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApitParams {
    /// Pixels per side of each of the six cube faces (1..=4096). Independent of any image
    /// size. Useful range 32–512: higher splits dense frustums finer but multiplies the
    /// fragments of large triangles and the frustums an escaping ray walks through.
    pub resolution: u32,
    /// Centre of the cube.
    pub observer: Observer,
    /// Fragments allowed per triangle on average (plus one per pixel) before the triangles
    /// covering the most pixels are tested by every ray instead of being rasterised.
    /// Bounds memory on scenes of many large triangles close to the observer; useful
    /// range 16–1024 (typical meshes stay far below: a few fragments per triangle).
    pub fragment_budget: u32,
}

impl ApitParams {
    /// Largest accepted resolution: 6·4096² pixels already need 400 MB of pixel heads.
    pub const MAX_RESOLUTION: u32 = 4096;

    /// 64² pixels per face: fast build, long per-pixel lists.
    pub fn fast() -> Self {
        Self { resolution: 64, ..Self::default() }
    }

    /// 256² pixels per face: short lists, more fragments and longer walks.
    pub fn high_quality() -> Self {
        Self { resolution: 256, ..Self::default() }
    }

    /// The same parameters with the cube centred on `p`.
    pub fn with_observer(self, p: Vec3) -> Self {
        Self { observer: Observer::Point(p), ..self }
    }
}

impl Default for ApitParams {
    /// 128² pixels per face, following the eye (centred on the mesh's bounding box
    /// until an eye is given).
    fn default() -> Self {
        Self { resolution: 128, observer: Observer::Eye, fragment_budget: 32 }
    }
}

impl StructureParams for ApitParams {
    const STRUCTURE: &'static str = "apit";
    const KEYS: &'static [ParamKey] = &[
        ParamKey { name: "resolution", doc: "pixels per cube-face side, 32–512 (1–4096 accepted; default 128)" },
        ParamKey {
            name: "fragment_budget",
            doc: "fragments per triangle before big ones go to every ray, 16–1024 (default 32)",
        },
        ParamKey { name: "observer", doc: "`eye` (cube on the camera, default) or `center` (on the mesh box)" },
    ];

    fn presets() -> Vec<(&'static str, Self)> {
        vec![("fast", Self::fast()), ("default", Self::default()), ("high_quality", Self::high_quality())]
    }

    fn set(&mut self, key: &str, v: &str) -> Result<(), BuildError> {
        let s = Self::STRUCTURE;
        match key {
            "resolution" => self.resolution = value::u32(s, key, v)?,
            "fragment_budget" => self.fragment_budget = value::u32(s, key, v)?,
            "observer" => {
                let i = value::choice(s, key, v, &["eye", "center"], "eye or center")?;
                self.observer = [Observer::Eye, Observer::BoundsCenter][i];
            }
            _ => return Err(unknown_key::<Self>(key)),
        }
        Ok(())
    }

    /// Rejects a resolution outside 1..=[`ApitParams::MAX_RESOLUTION`] and an observer
    /// that is not a finite point.
    fn validate(&self) -> Result<(), BuildError> {
        let err = out_of_range::<Self>;
        if !(1..=Self::MAX_RESOLUTION).contains(&self.resolution) {
            return err("resolution", format!("{} is outside 1..={}", self.resolution, Self::MAX_RESOLUTION));
        }
        if let Observer::Point(p) = self.observer {
            if !p.is_finite() {
                return err("observer", format!("{p} is not a finite point"));
            }
        }
        Ok(())
    }
}
