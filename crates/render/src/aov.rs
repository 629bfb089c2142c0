//! Arbitrary output variables: instead of colour, one property of what each pixel's
//! centre ray sees, for comparing renderers and debugging scenes.
//!
//! Every AOV is taken from the camera ray through the pixel centre (one sample, no
//! filtering): averaging triangle indices or depths across an edge would give values
//! that belong to no surface.

use crate::{Integrator, RayCounts, Sampler, SceneIntersector, SurfaceHit};
use dynray_geom::Ray;
use dynray_scene::Color;

/// The channel `render --aov` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    /// `t` of the centre ray's closest hit (the distance from the eye for perspective
    /// cameras, whose rays have unit directions); `+inf` where it sees nothing.
    Depth,
    /// The world-space unit shading normal at the hit, as the geometry orients it (not
    /// turned towards the camera); zero where the ray sees nothing.
    Normal,
    /// The index of the triangle hit (in the frame's mesh order), `-1` on a miss.
    /// Stored as `f32`: exact for indices below 2^24 (16.7 million triangles).
    Prim,
    /// The surface's diffuse reflectance (its base colour: the material's diffuse
    /// colour times its texture); zero on a miss.
    Albedo,
}

impl Aov {
    /// All AOVs, in the order listings show them.
    pub const ALL: &'static [Aov] = &[Aov::Depth, Aov::Normal, Aov::Prim, Aov::Albedo];

    /// The names of [`Self::ALL`], for command-line value lists.
    pub const NAMES: &'static [&'static str] = &["depth", "normal", "prim", "albedo"];

    /// The `--aov` spelling.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Depth => "depth",
            Aov::Normal => "normal",
            Aov::Prim => "prim",
            Aov::Albedo => "albedo",
        }
    }

    /// The EXR channel names the AOV is written as: one channel for scalars (`Z` is
    /// OpenEXR's name for depth), red/green/blue for vectors and colours.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Aov::Depth => &["Z"],
            Aov::Prim => &["prim"],
            Aov::Normal | Aov::Albedo => &["R", "G", "B"],
        }
    }
}

impl Aov {
    /// The AOV's value for a ray whose closest surface is `hit` (`None`: it escapes).
    pub fn of(self, hit: Option<&SurfaceHit<'_>>) -> Color {
        match (self, hit) {
            (Aov::Depth, Some(h)) => Color::splat(h.t),
            (Aov::Depth, None) => Color::splat(f32::INFINITY),
            (Aov::Prim, Some(h)) => Color::splat(h.at.prim as f32),
            (Aov::Prim, None) => Color::splat(-1.0),
            (Aov::Normal, Some(h)) => h.ns,
            (Aov::Albedo, Some(h)) => h.diffuse(),
            (Aov::Normal | Aov::Albedo, None) => Color::ZERO,
        }
    }
}

impl std::str::FromStr for Aov {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Aov::ALL
            .iter()
            .copied()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown AOV `{s}` (expected one of: {})", Aov::NAMES.join(", ")))
    }
}

impl std::fmt::Display for Aov {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// An integrator that returns one AOV instead of radiance (scalars in every channel).
pub struct AovIntegrator<'a> {
    aov: Aov,
    scene: &'a SceneIntersector<'a>,
}

impl<'a> AovIntegrator<'a> {
    /// The AOV `aov` of whatever `scene` shows.
    pub fn new(aov: Aov, scene: &'a SceneIntersector<'a>) -> Self {
        Self { aov, scene }
    }
}

impl Integrator for AovIntegrator<'_> {
    fn name(&self) -> &'static str {
        self.aov.name()
    }

    fn radiance(&self, ray: &Ray, _sampler: &mut Sampler, _counts: &mut RayCounts) -> Color {
        self.aov.of(self.scene.intersect(ray).as_ref())
    }
}
