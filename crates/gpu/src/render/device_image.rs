//! A live image kept on the device (shaders/resolve.wgsl): a renderer with this target
//! ([`crate::GpuRenderer::set_target`]) adds every frame's samples into per-pixel sums
//! there and encodes them as sRGB RGBA rows, which a window on the same device copies
//! into its texture — the GPU backend's image presented without a read-back.

use crate::{buffer, kernel, GpuContext, GpuError};
use dynray_render::Film;
use dynray_scene::Color;
use std::sync::Arc;

/// The resolve kernels' parameters (shaders/resolve.wgsl `Resolve`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct Resolve {
    width: u32,
    pixels: u32,
    spp: u32,
    base: u32,
    n: u32,
    row_words: u32,
    first_pixel: u32,
    pad: u32,
}

/// Per-pixel sums of the samples rendered into it, and their 8-bit encoding.
pub struct DeviceImage {
    ctx: Arc<GpuContext>,
    width: u32,
    height: u32,
    /// RGB sum and weight per pixel, row-major.
    acc: wgpu::Buffer,
    /// RGBA8 rows of `row_bytes` bytes (a multiple of 256, as texture copies want).
    rgba: wgpu::Buffer,
    row_bytes: u32,
    accumulate: wgpu::ComputePipeline,
    encode: wgpu::ComputePipeline,
}

impl std::fmt::Debug for DeviceImage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DeviceImage").field("width", &self.width).field("height", &self.height).finish()
    }
}

impl DeviceImage {
    /// A black `width` × `height` image on `ctx`'s device.
    pub fn new(ctx: Arc<GpuContext>, width: u32, height: u32) -> Result<Self, GpuError> {
        let (width, height) = (width.max(1), height.max(1));
        let pixels = width as u64 * height as u64;
        let row_bytes = (4 * width).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let acc = buffer::output(&ctx, "image sums", 16 * pixels)?;
        let rgba = buffer::output(&ctx, "image rgba", row_bytes as u64 * height as u64)?;
        let mut p = kernel::compile(&ctx, "resolve", crate::shader::RESOLVE, &["accumulate", "encode"])?;
        let encode = p.pop().expect("two entries");
        let accumulate = p.pop().expect("two entries");
        let image = DeviceImage { ctx, width, height, acc, rgba, row_bytes, accumulate, encode };
        image.clear();
        Ok(image)
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The encoded pixels: `height` rows of [`Self::bytes_per_row`] bytes, RGBA8 (sRGB
    /// values, opaque), valid after a render into this image.
    pub fn rgba(&self) -> &wgpu::Buffer {
        &self.rgba
    }

    /// Bytes from one row of [`Self::rgba`] to the next.
    pub fn bytes_per_row(&self) -> u32 {
        self.row_bytes
    }

    /// Forgets every sample (the next render starts the image afresh).
    pub fn clear(&self) {
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        enc.clear_buffer(&self.acc, 0, None);
        enc.clear_buffer(&self.rgba, 0, None);
        self.ctx.queue.submit([enc.finish()]);
    }

    /// The accumulated image as a film (sums and weights read back): what saving it needs.
    pub fn read_film(&self) -> Result<Film, GpuError> {
        let n = self.width as usize * self.height as usize;
        let mut acc = vec![[0.0f32; 4]; n];
        let staging = buffer::staging(&self.ctx, 16 * n as u64);
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(&self.acc, 0, &staging, 0, 16 * n as u64);
        self.ctx.queue.submit([enc.finish()]);
        buffer::read_into(&self.ctx, &staging, &mut acc)?;
        let sum = acc.iter().map(|a| Color::new(a[0], a[1], a[2])).collect();
        let weight = acc.iter().map(|a| a[3]).collect();
        Ok(Film::from_sums(self.width, self.height, sum, weight))
    }

    fn params(&self) -> Resolve {
        Resolve {
            width: self.width,
            pixels: self.width * self.height,
            row_words: self.row_bytes / 4,
            ..Default::default()
        }
    }

    /// Records the addition of samples `base .. base + n` (radiance in `samples[0..n]`,
    /// `spp` per pixel, pixel-major) into the sums.
    pub(crate) fn accumulate(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        samples: &wgpu::Buffer,
        spp: u32,
        base: u32,
        n: u32,
    ) {
        if n == 0 {
            return;
        }
        let first = base / spp;
        let last = (base + n - 1) / spp;
        let r = Resolve { spp, base, n, first_pixel: first, ..self.params() };
        let u = buffer::uniform(&self.ctx, "resolve", &r);
        let group = kernel::bind(&self.ctx, &self.accumulate, &[(0, &u), (1, samples), (2, &self.acc)]);
        dispatch_2d(encoder, &self.accumulate, &group, last - first + 1);
    }

    /// Records the encoding of every pixel into [`Self::rgba`].
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        let r = self.params();
        let u = buffer::uniform(&self.ctx, "resolve", &r);
        let group = kernel::bind(&self.ctx, &self.encode, &[(0, &u), (2, &self.acc), (3, &self.rgba)]);
        dispatch_2d(encoder, &self.encode, &group, r.pixels);
    }
}

/// One invocation per item, in rows of at most 65,535 workgroups.
fn dispatch_2d(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    group: &wgpu::BindGroup,
    items: u32,
) {
    let groups = items.div_ceil(kernel::WORKGROUP).max(1);
    let x = groups.min(65_535);
    let mut pass =
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("resolve"), timestamp_writes: None });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(x, groups.div_ceil(x), 1);
}

#[cfg(test)]
mod tests {
    use super::Resolve;

    /// The Rust mirror and shaders/resolve.wgsl's `Resolve` agree on size and offsets
    /// (naga lays the WGSL struct out; DESIGN.md asks this of every device struct).
    #[test]
    fn resolve_matches_its_wgsl_declaration() {
        let src = crate::shader::RESOLVE;
        let module = naga::front::wgsl::parse_str(src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(src)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("resolve.wgsl: {e:?}"));
        let (members, span) = module
            .types
            .iter()
            .find_map(|(_, t)| match (&t.name, &t.inner) {
                (Some(n), naga::TypeInner::Struct { members, span }) if n == "Resolve" => {
                    Some((members.clone(), *span))
                }
                _ => None,
            })
            .expect("a Resolve struct");
        assert_eq!(span as usize, std::mem::size_of::<Resolve>());
        let offsets: Vec<u32> = members.iter().map(|m| m.offset).collect();
        let names: Vec<&str> = members.iter().map(|m| m.name.as_deref().unwrap_or("")).collect();
        assert_eq!(names, ["width", "pixels", "spp", "base", "n", "row_words", "first_pixel", "pad"]);
        assert_eq!(offsets, [0, 4, 8, 12, 16, 20, 24, 28]);
        let r = Resolve { width: 1, pixels: 2, spp: 3, base: 4, n: 5, row_words: 6, first_pixel: 7, pad: 8 };
        let words: &[u32] = bytemuck::cast_slice(bytemuck::bytes_of(&r));
        assert_eq!(words, [1, 2, 3, 4, 5, 6, 7, 8], "fields in declaration order");
    }
}
