//! A field's AOVs with its camera rays marched on the device: the render loop's
//! camera-ray batches (`Integrator::radiance_batch`) sphere traced by [`GpuAdf`], each
//! hit turned into the engine's surface by [`AdfGeometry::surface_at`] with the device's
//! gradient, so the AOVs are the CPU's for the same hits.
//!
//! Shaded images of fields are the CPU's: the device kernels shade triangles only.

use crate::GpuAdf;
use dynray_adf::{AdfGeometry, Search};
use dynray_geom::Ray;
use dynray_render::{Aov, Integrator, RayCounts, Sampler};
use dynray_scene::Color;

/// One AOV of a field whose camera rays are marched on the device.
pub struct DeviceFieldAov<'a> {
    /// The AOV drawn.
    pub aov: Aov,
    /// The field on the device.
    pub device: &'a GpuAdf,
    /// The same field on the CPU, which turns a marched hit into a surface.
    pub geometry: AdfGeometry<'a>,
}

impl Integrator for DeviceFieldAov<'_> {
    fn name(&self) -> &'static str {
        self.aov.name()
    }

    fn radiance(&self, ray: &Ray, sampler: &mut Sampler, counts: &mut RayCounts) -> Color {
        let mut out = [Color::ZERO];
        self.radiance_batch(std::slice::from_ref(ray), std::slice::from_mut(sampler), &mut out, counts);
        out[0]
    }

    fn radiance_batch(&self, rays: &[Ray], _samplers: &mut [Sampler], out: &mut [Color], _counts: &mut RayCounts) {
        let need_gradient = matches!(self.aov, Aov::Normal);
        // A device lost mid-render has no image to fall back to: wgpu's message ends it.
        let marched = self.device.march(rays, Search::CoherentLinear, need_gradient).unwrap_or_else(|e| panic!("{e}"));
        for ((ray, m), o) in rays.iter().zip(marched).zip(out.iter_mut()) {
            let hit = m.t.map(|t| self.geometry.surface_at(ray, t, m.gradient, 0));
            *o = self.aov.of(hit.as_ref());
        }
    }
}
