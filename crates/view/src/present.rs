//! Putting pixels in the window with wgpu: the frame's RGBA image (the CPU film, the GPU
//! backend's read-back film, a heat map) is uploaded as a texture, drawn into an
//! off-screen canvas the window's size, the egui panel drawn over it, and the canvas
//! copied to the window's surface. The canvas is what `--screenshot` reads back, so a
//! screenshot is exactly the window's content.
//!
//! The canvas is `Rgba8Unorm` (not sRGB): the image's bytes are already sRGB-encoded by
//! [`dynray_render::Film::to_srgb8`], and egui prefers a gamma-space target; nearest
//! sampling at equal sizes copies every byte unchanged.

use anyhow::{anyhow, bail, Context, Result};
use dynray_gpu::{DeviceImage, GpuContext, GpuOptions};
use std::sync::Arc;
use winit::window::Window;

const CANVAS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The blit: a full-window triangle whose fragments read the source texel under them
/// (nearest, by integer `textureLoad`, so equal sizes copy exactly).
const BLIT_WGSL: &str = r#"
struct Out { @builtin(position) pos: vec4<f32>, @location(0) uv: vec2<f32> };
@group(0) @binding(0) var src: texture_2d<f32>;
@vertex fn vs(@builtin(vertex_index) i: u32) -> Out {
    let p = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    var o: Out;
    o.pos = vec4<f32>(p * 2.0 - 1.0, 0.0, 1.0);
    o.uv = vec2<f32>(p.x, 1.0 - p.y);
    return o;
}
@fragment fn fs(o: Out) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(src));
    let texel = vec2<i32>(clamp(floor(o.uv * size), vec2<f32>(0.0), size - 1.0));
    return textureLoad(src, texel, 0);
}
"#;

/// The window's GPU side.
pub struct Presenter {
    /// The device, as the GPU backend opens them.
    context: Arc<GpuContext>,
    /// The context is the one the job's GPU options name (so the backend may use it).
    shared: bool,
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: String,
    config: wgpu::SurfaceConfiguration,
    /// The surface's format without sRGB encoding (what the final blit writes).
    surface_view_format: wgpu::TextureFormat,
    canvas: wgpu::Texture,
    image: Option<wgpu::Texture>,
    layout: wgpu::BindGroupLayout,
    to_canvas: wgpu::RenderPipeline,
    to_surface: wgpu::RenderPipeline,
    egui: egui_wgpu::Renderer,
}

/// What egui drew this frame.
pub struct PanelPaint<'a> {
    /// Triangles.
    pub primitives: &'a [egui::ClippedPrimitive],
    /// Texture changes (fonts, images).
    pub textures: &'a egui::TexturesDelta,
    /// Pixels per point.
    pub pixels_per_point: f32,
}

impl Presenter {
    /// Opens a device that can present to `window` (Vulkan: a GPU driver, or lavapipe),
    /// as a [`GpuContext`] the GPU backend can share: the one `gpu` names where it can
    /// present, else the best that can (then not shared, [`Self::shared_context`]).
    pub fn new(window: Arc<Window>, display: winit::event_loop::OwnedDisplayHandle, gpu: &GpuOptions) -> Result<Self> {
        let mut desc = wgpu::InstanceDescriptor::new_with_display_handle(Box::new(display));
        desc.backends = wgpu::Backends::VULKAN;
        let instance = wgpu::Instance::new(desc);
        let size = window.inner_size();
        let surface = instance.create_surface(window).context("cannot make a drawing surface for the window")?;
        let no_adapter = |e: dynray_gpu::GpuError| {
            anyhow!(
                "no Vulkan adapter can present to this window ({e}); install a Vulkan driver \
                 (Debian: mesa-vulkan-drivers, which has the lavapipe software adapter)"
            )
        };
        let (ctx, shared) = match GpuContext::for_surface(&instance, &surface, gpu) {
            Ok(ctx) => (ctx, true),
            Err(_) if *gpu != GpuOptions::default() => {
                (GpuContext::for_surface(&instance, &surface, &GpuOptions::default()).map_err(no_adapter)?, false)
            }
            Err(e) => return Err(no_adapter(e)),
        };
        let ctx = Arc::new(ctx);
        let adapter_name = ctx.adapter().name.clone();
        let (device, queue) = (ctx.device().clone(), ctx.queue().clone());
        let adapter = ctx.wgpu_adapter();
        let name = adapter_name;
        let caps = surface.get_capabilities(adapter);
        let Some(&format) = caps.formats.iter().find(|f| !f.is_srgb()).or_else(|| caps.formats.first()) else {
            bail!("{name}: the window's surface offers no format");
        };
        let surface_view_format = format.remove_srgb_suffix();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: if surface_view_format != format { vec![surface_view_format] } else { vec![] },
        };
        surface.configure(&device, &config);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("blit"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    multisampled: false,
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
                count: None,
            }],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("blit"),
            source: wgpu::ShaderSource::Wgsl(BLIT_WGSL.into()),
        });
        let to_canvas = blit_pipeline(&device, &layout, &module, CANVAS_FORMAT);
        let to_surface = blit_pipeline(&device, &layout, &module, surface_view_format);
        let canvas = canvas(&device, config.width, config.height);
        let egui = egui_wgpu::Renderer::new(&device, CANVAS_FORMAT, egui_wgpu::RendererOptions::default());
        Ok(Presenter {
            context: ctx,
            shared,
            surface,
            device,
            queue,
            adapter: name,
            config,
            surface_view_format,
            canvas,
            image: None,
            layout,
            to_canvas,
            to_surface,
            egui,
        })
    }

    /// The adapter presenting.
    pub fn adapter(&self) -> &str {
        &self.adapter
    }

    /// The window's device, when it is the one the job's GPU options ask for: the GPU
    /// backend traces on it, and its image reaches the window without a read-back.
    pub fn shared_context(&self) -> Option<&Arc<GpuContext>> {
        self.shared.then_some(&self.context)
    }

    /// Makes the GPU backend's image on the device the image shown: its rows are copied
    /// into the window's texture on the device.
    pub fn show_device_image(&mut self, image: &DeviceImage) {
        let (width, height) = (image.width(), image.height());
        self.image_texture(width, height);
        let texture = self.image.as_ref().expect("made above");
        let mut enc = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("image") });
        enc.copy_buffer_to_texture(
            wgpu::TexelCopyBufferInfo {
                buffer: image.rgba(),
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(image.bytes_per_row()),
                    rows_per_image: None,
                },
            },
            texture.as_image_copy(),
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
        self.queue.submit([enc.finish()]);
    }

    /// The image texture, (re)made at `width` × `height`.
    fn image_texture(&mut self, width: u32, height: u32) {
        let fits = self.image.as_ref().is_some_and(|t| t.width() == width && t.height() == height);
        if !fits {
            self.image = Some(self.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("image"),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            }));
        }
    }

    /// Follows the window's new size.
    pub fn resize(&mut self, width: u32, height: u32) {
        let (width, height) = (width.max(1), height.max(1));
        if (width, height) != (self.config.width, self.config.height) {
            self.config.width = width;
            self.config.height = height;
            self.surface.configure(&self.device, &self.config);
            self.canvas = canvas(&self.device, width, height);
        }
    }

    /// Makes `rgba` (`width` × `height`, 4 bytes a pixel) the image shown.
    pub fn upload(&mut self, rgba: &[u8], width: u32, height: u32) {
        let (width, height) = (width.max(1), height.max(1));
        self.image_texture(width, height);
        let texture = self.image.as_ref().expect("made above");
        if rgba.len() != 4 * width as usize * height as usize {
            return;
        }
        self.queue.write_texture(
            texture.as_image_copy(),
            rgba,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * width), rows_per_image: Some(height) },
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
    }

    /// Draws the image and the panel into the canvas and shows it; with `capture`, reads
    /// the canvas back (RGBA, the window's size) after drawing.
    pub fn present(&mut self, panel: Option<PanelPaint<'_>>, capture: bool) -> Result<Option<image::RgbaImage>> {
        let (w, h) = (self.config.width, self.config.height);
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let canvas_view = self.canvas.create_view(&wgpu::TextureViewDescriptor::default());
        let screen = panel
            .as_ref()
            .map(|p| egui_wgpu::ScreenDescriptor { size_in_pixels: [w, h], pixels_per_point: p.pixels_per_point });
        let mut extra = Vec::new();
        if let (Some(p), Some(screen)) = (&panel, &screen) {
            for (id, deltas) in &p.textures.set {
                for delta in deltas {
                    self.egui.update_texture(&self.device, &self.queue, *id, delta);
                }
            }
            extra = self.egui.update_buffers(&self.device, &self.queue, &mut encoder, p.primitives, screen);
        }
        {
            let mut pass = cleared_pass(&mut encoder, "canvas", &canvas_view).forget_lifetime();
            if let Some(image) = &self.image {
                let group = self.bind(image);
                // The image keeps its aspect ratio, centred.
                let (x, y, vw, vh) = fit((image.width(), image.height()), (w, h));
                pass.set_viewport(x, y, vw, vh, 0.0, 1.0);
                pass.set_pipeline(&self.to_canvas);
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..3, 0..1);
                pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
            }
            if let (Some(p), Some(screen)) = (&panel, &screen) {
                self.egui.render(&mut pass, p.primitives, screen);
            }
        }
        let readback = capture.then(|| {
            let row = (4 * w).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
            let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("screenshot"),
                size: row as u64 * h as u64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            encoder.copy_texture_to_buffer(
                self.canvas.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: None },
                },
                wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
            );
            (buffer, row)
        });
        // Copy the canvas to the window, when the window has a texture to give.
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => Some(t),
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.device, &self.config);
                None
            }
            _ => None,
        };
        if let Some(frame) = &frame {
            let view = frame.texture.create_view(&wgpu::TextureViewDescriptor {
                format: Some(self.surface_view_format),
                ..Default::default()
            });
            let group = self.bind(&self.canvas);
            let mut pass = cleared_pass(&mut encoder, "present", &view);
            pass.set_pipeline(&self.to_surface);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        self.queue.submit(extra.into_iter().chain([encoder.finish()]));
        if let Some(frame) = frame {
            self.queue.present(frame);
        }
        if let Some(p) = &panel {
            for id in &p.textures.free {
                self.egui.free_texture(id);
            }
        }
        let Some((buffer, row)) = readback else { return Ok(None) };
        let slice = buffer.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::Wait { submission_index: None, timeout: None })
            .map_err(|e| anyhow!("screenshot: {e}"))?;
        rx.recv().context("screenshot")?.map_err(|e| anyhow!("screenshot: {e}"))?;
        let data = slice.get_mapped_range().map_err(|e| anyhow!("screenshot: {e}"))?;
        let mut pixels = Vec::with_capacity(4 * w as usize * h as usize);
        for y in 0..h as usize {
            let start = y * row as usize;
            pixels.extend_from_slice(&data[start..start + 4 * w as usize]);
        }
        drop(data);
        buffer.unmap();
        Ok(image::RgbaImage::from_raw(w, h, pixels))
    }

    fn bind(&self, texture: &wgpu::Texture) -> wgpu::BindGroup {
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("blit"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) }],
        })
    }
}

/// The largest rectangle of `image`'s aspect inside `window`, centred: `(x, y, w, h)`.
/// Equal sizes give the whole window, so the image lands on it texel for pixel.
fn fit(image: (u32, u32), window: (u32, u32)) -> (f32, f32, f32, f32) {
    let (iw, ih) = (image.0.max(1) as f32, image.1.max(1) as f32);
    let (ww, wh) = (window.0.max(1) as f32, window.1.max(1) as f32);
    let s = (ww / iw).min(wh / ih);
    // Within half a pixel of the window's aspect: fill it (resolution scaling rounds).
    let (w, h) = if ((iw * s) - ww).abs() < 1.0 && ((ih * s) - wh).abs() < 1.0 { (ww, wh) } else { (iw * s, ih * s) };
    (((ww - w) * 0.5).floor(), ((wh - h) * 0.5).floor(), w, h)
}

/// A render pass that clears `view` to black first.
fn cleared_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            resolve_target: None,
            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
            depth_slice: None,
        })],
        depth_stencil_attachment: None,
        occlusion_query_set: None,
        timestamp_writes: None,
        multiview_mask: None,
    })
}

fn canvas(device: &wgpu::Device, width: u32, height: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("canvas"),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: CANVAS_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

fn blit_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("blit"),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("blit"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs"),
            buffers: &[],
            compilation_options: Default::default(),
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs"),
            targets: &[Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })],
            compilation_options: Default::default(),
        }),
        multiview_mask: None,
        cache: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_sizes_fill_the_window_and_others_keep_their_aspect() {
        assert_eq!(fit((640, 480), (640, 480)), (0.0, 0.0, 640.0, 480.0));
        assert_eq!(fit((320, 240), (640, 480)), (0.0, 0.0, 640.0, 480.0));
        assert_eq!(fit((100, 100), (300, 200)), (50.0, 0.0, 200.0, 200.0));
    }
}
