//! Build parameters of the A-buffer and the A-PIT, with named presets.

use dynray_geom::Vec3;

/// Where the cube of A-buffers is centred.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Observer {
    /// The centre of the mesh's bounding box (the registry's default: it has no camera).
    BoundsCenter,
    /// A given point, e.g. the camera position (the seed's choice).
    Point(Vec3),
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

    /// All presets, for tests that loop over them.
    pub fn presets() -> [Self; 3] {
        [Self::fast(), Self::default(), Self::high_quality()]
    }

    /// The same parameters with the cube centred on `p`.
    pub fn with_observer(self, p: Vec3) -> Self {
        Self { observer: Observer::Point(p), ..self }
    }
}

impl Default for ApitParams {
    /// 128² pixels per face, centred on the mesh's bounding box.
    fn default() -> Self {
        Self { resolution: 128, observer: Observer::BoundsCenter, fragment_budget: 32 }
    }
}
