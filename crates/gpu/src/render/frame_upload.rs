//! The frame on the device (group 0 of the render kernels): the BVH through [`GpuBvh`],
//! the mesh arrays shading reads, materials, lights, camera and settings as Pod mirrors
//! of shaders/render_scene.wgsl, and the CPU sampler's sub-pixel positions and cumulative
//! keys (one `next_u32` per sample, re-uploaded per pass of the cumulative tracer). Between
//! frames each array is compared with what was uploaded last and only changed ones are
//! written (a plain byte comparison: cheap next to tracing, and exact).

use super::work::Kernels;
use crate::{buffer, GpuBvh, GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};
use dynray_accel::Bvh;
use dynray_render::{
    shadow_filter, BsdfDesc, CameraRays, EmitterDesc, EmitterTable, LobeDesc, Sampler, MAX_LEVEL_CAP, MAX_PATH_DEPTH,
};
use dynray_scene::{Frame, LightKind, Material, Microfacet};
use std::sync::Arc;

/// `Material` of render_scene.wgsl: 96 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuMaterial {
    ambient: [f32; 3],
    shine: f32,
    diffuse: [f32; 3],
    /// The usable ior (positive, finite, else 1), as whitted.rs' `sane_ior`.
    ior: f32,
    spot: [f32; 3],
    has_spot: u32,
    specular: [f32; 3],
    _pad0: u32,
    transparency: [f32; 3],
    _pad1: u32,
    shadow_filter: [f32; 3],
    _pad2: u32,
}
const _: () = assert!(std::mem::size_of::<GpuMaterial>() == 96);

/// `Light` of render_scene.wgsl: 64 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuLight {
    position: [f32; 3],
    kind: u32,
    direction: [f32; 3],
    falloff: i32,
    color: [f32; 3],
    cos_inner: f32,
    cos_outer: f32,
    _pad: [u32; 3],
}
const _: () = assert!(std::mem::size_of::<GpuLight>() == 64);

/// `PtEmitter` of path_shade.wgsl: 80 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct PtEmitter {
    position: [f32; 3],
    kind: u32,
    direction: [f32; 3],
    falloff: i32,
    color: [f32; 3],
    cos_inner: f32,
    cos_outer: f32,
    first: u32,
    count: u32,
    total: f32,
    spot: u32,
    _pad: [u32; 3],
}
const _: () = assert!(std::mem::size_of::<PtEmitter>() == 80);

/// `PtLobe` of path_shade.wgsl: 64 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct PtLobe {
    a: [f32; 3],
    kind: u32,
    b: [f32; 3],
    prob: f32,
    c: [f32; 3],
    p0: f32,
    ax: f32,
    ay: f32,
    dist: u32,
    _pad: u32,
}
const _: () = assert!(std::mem::size_of::<PtLobe>() == 64);

/// `PtMaterial` of path_shade.wgsl: 288 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct PtMaterial {
    emission: [f32; 3],
    lobe_count: u32,
    two_sided: u32,
    has_smooth: u32,
    _pad: [u32; 2],
    lobes: [PtLobe; 4],
}
const _: () = assert!(std::mem::size_of::<PtMaterial>() == 288);

/// `PathParams` of path_shade.wgsl: 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
struct PathParams {
    environment: [f32; 3],
    emitter_count: u32,
    max_depth: u32,
    any_hittable: u32,
    clip_near: f32,
    clip_far: f32,
    has_clip: u32,
    _pad: [u32; 3],
}
const _: () = assert!(std::mem::size_of::<PathParams>() == 48);

fn pt_emitter(e: &EmitterDesc) -> PtEmitter {
    let mut g = PtEmitter::zeroed();
    match *e {
        EmitterDesc::Area { first, count, total } => {
            g.kind = 0;
            g.first = first;
            g.count = count;
            g.total = total;
        }
        EmitterDesc::Point { position, intensity, falloff, kind } => {
            g.kind = 1;
            g.position = position.to_array();
            g.color = intensity.to_array();
            g.falloff = falloff;
            if let LightKind::Spot { direction, cos_inner, cos_outer, .. } = kind {
                g.spot = 1;
                g.direction = direction.normalize_or_zero().to_array();
                g.cos_inner = cos_inner;
                g.cos_outer = cos_outer;
            }
        }
        EmitterDesc::Directional { towards_light, irradiance } => {
            g.kind = 2;
            g.position = towards_light.to_array();
            g.color = irradiance.to_array();
        }
        EmitterDesc::Environment => g.kind = 3,
    }
    g
}

fn pt_lobe((lobe, prob): &(LobeDesc, f32)) -> PtLobe {
    let mut g = PtLobe::zeroed();
    g.prob = *prob;
    match *lobe {
        LobeDesc::Diffuse(c) => {
            g.kind = 0;
            g.a = c.to_array();
        }
        LobeDesc::Phong(c, n) => {
            g.kind = 1;
            g.a = c.to_array();
            g.p0 = n;
        }
        LobeDesc::Mirror(c) => {
            g.kind = 2;
            g.a = c.to_array();
        }
        LobeDesc::Conductor { eta, k, scale, rough } => {
            g.kind = 3;
            g.a = eta.to_array();
            g.b = k.to_array();
            g.c = scale.to_array();
            if let Some((dist, ax, ay)) = rough {
                g.dist = match dist {
                    Microfacet::Beckmann => 1,
                    Microfacet::Ggx => 2,
                };
                g.ax = ax;
                g.ay = ay;
            }
        }
        LobeDesc::Dielectric { eta, r, t } => {
            g.kind = 4;
            g.a = r.to_array();
            g.b = t.to_array();
            g.p0 = eta;
        }
    }
    g
}

/// A material as the path tracer sees it: the BSDF `BsdfDesc` converts from the CPU's,
/// the emission as lights.rs reads it (finite, at least 0).
fn pt_material(m: &Material, env_ior: f32) -> PtMaterial {
    let b = BsdfDesc::of(m, env_ior);
    let mut g = PtMaterial::zeroed();
    let e = if m.emission.is_finite() { m.emission.max(dynray_scene::Color::ZERO) } else { dynray_scene::Color::ZERO };
    g.emission = e.to_array();
    g.lobe_count = b.lobes.len().min(4) as u32;
    g.two_sided = u32::from(b.two_sided);
    for (slot, l) in g.lobes.iter_mut().zip(&b.lobes) {
        *slot = pt_lobe(l);
    }
    g.has_smooth = u32::from(
        g.lobes[..g.lobe_count as usize].iter().any(|l| !(l.kind == 2 || l.kind == 4 || (l.kind == 3 && l.dist == 0))),
    );
    g
}

/// `SceneParams` of render_scene.wgsl: 128 bytes (a vec3 and a scalar per 16-byte row).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub(crate) struct SceneParams {
    cam_origin: [f32; 3],
    cam_parallel: u32,
    cam_forward: [f32; 3],
    cam_width: f32,
    cam_right: [f32; 3],
    cam_height: f32,
    cam_up: [f32; 3],
    spp: u32,
    background: [f32; 3],
    env_ior: f32,
    ambient: [f32; 3],
    eps_base: f32,
    width: u32,
    height: u32,
    pub max_level: u32,
    min_weight: f32,
    light_count: u32,
    any_transparent: u32,
    has_normals: u32,
    material_count: u32,
}
const _: () = assert!(std::mem::size_of::<SceneParams>() == 128);

fn sane_ior(ior: f32) -> f32 {
    if ior.is_finite() && ior > 0.0 {
        ior
    } else {
        1.0
    }
}

fn material(m: &Material) -> GpuMaterial {
    GpuMaterial {
        ambient: m.ambient.to_array(),
        shine: m.shine,
        diffuse: m.diffuse.to_array(),
        ior: sane_ior(m.ior),
        spot: m.spot.to_array(),
        has_spot: u32::from(m.spot != dynray_scene::Color::ZERO),
        specular: m.specular.to_array(),
        _pad0: 0,
        transparency: m.transparency.to_array(),
        _pad1: 0,
        shadow_filter: shadow_filter(m).to_array(),
        _pad2: 0,
    }
}

fn light(l: &dynray_scene::Light) -> GpuLight {
    let mut g = GpuLight {
        position: [0.0; 3],
        kind: 0,
        direction: [0.0; 3],
        falloff: 0,
        color: l.color.to_array(),
        cos_inner: 0.0,
        cos_outer: 0.0,
        _pad: [0; 3],
    };
    match l.kind {
        LightKind::Point { position, falloff } => {
            g.position = position.to_array();
            g.falloff = falloff;
        }
        LightKind::Spot { position, direction, cos_inner, cos_outer, falloff } => {
            g.kind = 1;
            g.position = position.to_array();
            g.direction = direction.normalize_or_zero().to_array();
            g.cos_inner = cos_inner;
            g.cos_outer = cos_outer;
            g.falloff = falloff;
        }
        LightKind::Directional { direction } => {
            g.kind = 2;
            g.direction = (-direction.normalize_or_zero()).to_array();
        }
    }
    g
}

/// Why a frame cannot be rendered on the GPU (`path`: with the path tracer, whose camera
/// rays honour clip planes).
pub(crate) fn check_supported(frame: &Frame, path: bool) -> Result<(), GpuError> {
    // A texture is only looked up where the mesh has texture coordinates (intersector.rs).
    if frame.mesh.uvs.is_some() && frame.materials.iter().any(|m| m.diffuse_texture.is_some()) {
        return Err(GpuError::Unsupported {
            what: "textured materials (the GPU strategies shade untextured surfaces only; use --backend cpu)".into(),
        });
    }
    // camera.wgsl's rays run over [0, ∞), as CameraRays' without clip planes; the path
    // tracer's trace kernel (pt_trace) clips them as CameraRays::ray_at does.
    if !path && frame.camera.clip != dynray_scene::Clip::NONE {
        return Err(GpuError::Unsupported {
            what: "a camera with near/far clip planes (Mitsuba's near_clip/far_clip; use --backend cpu)".into(),
        });
    }
    Ok(())
}

/// One array of group 0 with the bytes it holds.
struct Array {
    what: &'static str,
    buffer: wgpu::Buffer,
    bytes: Vec<u8>,
}

impl Array {
    /// Uploads `data` unless it equals what the buffer holds; the bytes written.
    fn sync<T: Pod>(
        ctx: &GpuContext,
        slot: &mut Option<Array>,
        what: &'static str,
        data: &[T],
    ) -> Result<u64, GpuError> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        match slot {
            Some(a) if a.bytes == bytes => Ok(0),
            Some(a) if a.bytes.len() == bytes.len() && !bytes.is_empty() => {
                ctx.queue.write_buffer(&a.buffer, 0, bytes);
                a.bytes.copy_from_slice(bytes);
                Ok(bytes.len() as u64)
            }
            _ => {
                let buffer = buffer::storage(ctx, what, data, wgpu::BufferUsages::empty())?;
                *slot = Some(Array { what, buffer, bytes: bytes.to_vec() });
                Ok(bytes.len() as u64)
            }
        }
    }
}

/// What a render needs of a frame, on the device.
/// The tree a render traces: built on the host (uploaded when it changed) or on the
/// device ([`GpuBvh::build`]), taken as it is.
pub(crate) enum Tree<'a> {
    Host(&'a Bvh),
    Device(GpuBvh),
    /// The tree already on the device (perhaps refitted there since).
    Kept,
}

pub(crate) struct FrameUpload {
    ctx: Arc<GpuContext>,
    bvh: Option<(GpuBvh, Vec<u8>)>,
    arrays: [Option<Array>; 8],
    params: Option<(wgpu::Buffer, SceneParams)>,
    /// The path tracer's tables (placeholders of one element for the other integrators):
    /// emitters, emissive triangles, emitter per triangle, BSDF per material.
    path_arrays: [Option<Array>; 4],
    path_params: Option<(wgpu::Buffer, PathParams)>,
    /// Samples of the uploaded sub-pixel positions.
    pub samples: u32,
    pub spp: u32,
    seed: u64,
    width: u32,
}

impl FrameUpload {
    pub fn new(ctx: Arc<GpuContext>) -> Self {
        Self {
            ctx,
            bvh: None,
            arrays: Default::default(),
            params: None,
            path_arrays: Default::default(),
            path_params: None,
            samples: 0,
            spp: 1,
            seed: 0,
            width: 1,
        }
    }

    /// The cumulative integrator's key of every pixel sample of pass `first_sample / spp`
    /// (the first `next_u32` of the CPU's sampler of sample `first_sample + s`, as the
    /// CPU render loop makes it): what the GPU's choices hash, so that they are the
    /// CPU's. Returns the bytes written.
    pub fn sync_keys(&mut self, first_sample: u32) -> Result<u64, GpuError> {
        let (w, spp, seed) = (self.width.max(1), self.spp, self.seed);
        let pixels = self.samples / spp;
        let mut keys = Vec::with_capacity(self.samples as usize);
        for p in 0..pixels {
            for s in 0..spp {
                keys.push(Sampler::new(seed, w, p % w, p / w, first_sample.wrapping_add(s), spp).next_u32());
            }
        }
        Array::sync(&self.ctx, &mut self.arrays[7], "sample keys", &keys)
    }

    /// The BVH uploaded, once [`Self::sync`] ran.
    pub fn bvh(&self) -> Option<&GpuBvh> {
        self.bvh.as_ref().map(|(b, _)| b)
    }

    /// The same, to change on the device (a refit).
    pub fn bvh_mut(&mut self) -> Option<&mut GpuBvh> {
        self.bvh.as_mut().map(|(b, _)| b)
    }

    pub fn params(&self) -> Option<SceneParams> {
        self.params.as_ref().map(|p| p.1)
    }

    /// Brings the device's copy up to `frame` (with `tree` built on its mesh) and sample
    /// positions for `spp` and `seed`; returns the bytes written.
    /// `path`: with the path tracer's tables.
    pub fn sync(&mut self, frame: &Frame, tree: Tree<'_>, spp: u32, seed: u64, path: bool) -> Result<u64, GpuError> {
        let ctx = self.ctx.clone();
        let mut written = 0;
        let bvh = match tree {
            Tree::Host(bvh) => bvh,
            Tree::Device(g) => {
                // Built on the device: nothing to upload; an empty key makes the next
                // host tree upload in full.
                self.bvh = Some((g, Vec::new()));
                return self.sync_frame(frame, spp, seed, path);
            }
            Tree::Kept => {
                let Some((_, key)) = &mut self.bvh else {
                    return Err(GpuError::Unsupported { what: "rendering the kept tree before any tree".into() });
                };
                // It may have changed on the device: a later host tree uploads in full.
                key.clear();
                return self.sync_frame(frame, spp, seed, path);
            }
        };
        let key: Vec<u8> = [
            bytemuck::cast_slice::<_, u8>(bvh.nodes()),
            bytemuck::cast_slice(bvh.triangles()),
            bytemuck::cast_slice(bvh.triangle_ids()),
        ]
        .concat();
        match &mut self.bvh {
            Some((_, k)) if *k == key => {}
            Some((g, k)) => {
                g.update(bvh)?;
                written += key.len() as u64;
                *k = key;
            }
            None => {
                written += key.len() as u64;
                self.bvh = Some((GpuBvh::upload(ctx.clone(), bvh)?, key));
            }
        }
        Ok(written + self.sync_frame(frame, spp, seed, path)?)
    }

    /// The frame's arrays and parameters (everything but the tree); returns the bytes
    /// written.
    fn sync_frame(&mut self, frame: &Frame, spp: u32, seed: u64, path: bool) -> Result<u64, GpuError> {
        let ctx = self.ctx.clone();
        let mut written = 0;
        let mesh = &frame.mesh;
        let mut materials: Vec<GpuMaterial> = frame.materials.iter().map(material).collect();
        // The fallback of intersector.rs for a triangle whose index names no material.
        materials.push(material(&Material::default()));
        let lights: Vec<GpuLight> = frame.lights.iter().map(light).collect();
        let normals: &[[f32; 3]] = mesh.normals.as_deref().unwrap_or(&[]);
        let [a0, a1, a2, a3, a4, a5, a6, a7] = &mut self.arrays;
        written += Array::sync(&ctx, a0, "mesh positions", &mesh.positions)?;
        written += Array::sync(&ctx, a1, "mesh indices", &mesh.indices)?;
        written += Array::sync(&ctx, a2, "mesh normals", normals)?;
        written += Array::sync(&ctx, a3, "material ids", &frame.materials_of)?;
        written += Array::sync(&ctx, a4, "materials", &materials)?;
        written += Array::sync(&ctx, a5, "lights", &lights)?;

        let (w, h) = (frame.settings.width, frame.settings.height);
        let spp = spp.max(1);
        let samples = w as u64 * h as u64 * spp as u64;
        let samples = u32::try_from(samples).map_err(|_| GpuError::Unsupported {
            what: format!("{w}x{h} pixels at {spp} samples ({samples} samples; at most 2^32 - 1)"),
        })?;
        let mut offsets = Vec::with_capacity(samples as usize);
        let mut keys = Vec::with_capacity(samples as usize);
        for y in 0..h {
            for x in 0..w {
                for s in 0..spp {
                    let mut sampler = Sampler::new(seed, w, x, y, s, spp);
                    let (ox, oy) = sampler.pixel_offset();
                    offsets.push([ox, oy]);
                    // The first pass's keys (Self::sync_keys).
                    keys.push(sampler.next_u32());
                }
            }
        }
        written += Array::sync(&ctx, a6, "sample positions", &offsets)?;
        written += Array::sync(&ctx, a7, "sample keys", &keys)?;
        self.samples = samples;
        self.spp = spp;
        self.seed = seed;
        self.width = w;

        let cam = CameraRays::new(&frame.camera, w, h).basis();
        let diag = mesh.bounds().extent().length();
        let diag = if diag.is_finite() && diag > 0.0 { diag } else { 1.0 };
        let env = &frame.environment;
        let params = SceneParams {
            cam_origin: cam.origin.to_array(),
            cam_parallel: u32::from(cam.parallel),
            cam_forward: cam.forward.to_array(),
            cam_width: cam.width,
            cam_right: cam.right.to_array(),
            cam_height: cam.height,
            cam_up: cam.up.to_array(),
            spp,
            background: env.background.to_array(),
            env_ior: sane_ior(env.ior),
            ambient: env.ambient.to_array(),
            eps_base: diag * 1e-5,
            width: w,
            height: h,
            max_level: frame.settings.max_recursion_level.min(MAX_LEVEL_CAP),
            min_weight: frame.settings.min_weight,
            light_count: lights.len() as u32,
            any_transparent: u32::from(frame.materials.iter().any(|m| shadow_filter(m) != dynray_scene::Color::ZERO)),
            has_normals: u32::from(mesh.normals.is_some()),
            material_count: materials.len() as u32,
        };
        written += self.sync_path(frame, path)?;
        match &mut self.params {
            Some((_, p)) if *p == params => {}
            Some((b, p)) => {
                ctx.queue.write_buffer(b, 0, bytemuck::bytes_of(&params));
                *p = params;
                written += 128;
            }
            None => {
                self.params = Some((buffer::uniform(&ctx, "scene params", &params), params));
                written += 128;
            }
        }
        Ok(written)
    }

    /// The path tracer's tables of `frame` (`path`), or one-element placeholders.
    fn sync_path(&mut self, frame: &Frame, path: bool) -> Result<u64, GpuError> {
        let ctx = self.ctx.clone();
        let env_ior = sane_ior(frame.environment.ior);
        let (emitters, area, of_prim, materials, params) = if path {
            let t = EmitterTable::new(frame);
            let emitters: Vec<PtEmitter> = t.emitters.iter().map(pt_emitter).collect();
            let area: Vec<[u32; 2]> = t.area_tris.iter().zip(&t.area_cdf).map(|(&p, c)| [p, c.to_bits()]).collect();
            // The same list as `materials` (the fallback last), converted as Bsdf::of does.
            let materials: Vec<PtMaterial> = frame
                .materials
                .iter()
                .chain(std::iter::once(&Material::default()))
                .map(|m| pt_material(m, env_ior))
                .collect();
            let clip = CameraRays::new(&frame.camera, frame.settings.width, frame.settings.height).clip();
            let params = PathParams {
                environment: t.environment.to_array(),
                emitter_count: emitters.len() as u32,
                max_depth: frame.settings.max_recursion_level.saturating_add(1).min(MAX_PATH_DEPTH),
                any_hittable: u32::from(t.any_hittable),
                clip_near: clip.near,
                clip_far: clip.far,
                has_clip: u32::from(clip != dynray_scene::Clip::NONE),
                _pad: [0; 3],
            };
            (emitters, area, t.emitter_of_prim, materials, params)
        } else {
            (
                vec![PtEmitter::zeroed()],
                vec![[0u32; 2]],
                vec![u32::MAX],
                vec![PtMaterial::zeroed()],
                PathParams::zeroed(),
            )
        };
        let [a0, a1, a2, a3] = &mut self.path_arrays;
        let mut written = Array::sync(&ctx, a0, "path emitters", &emitters)?;
        written += Array::sync(&ctx, a1, "emissive triangles", &area)?;
        written += Array::sync(&ctx, a2, "emitter of triangle", &of_prim)?;
        written += Array::sync(&ctx, a3, "path materials", &materials)?;
        match &mut self.path_params {
            Some((_, p)) if *p == params => {}
            Some((b, p)) => {
                ctx.queue.write_buffer(b, 0, bytemuck::bytes_of(&params));
                *p = params;
                written += 48;
            }
            None => {
                self.path_params = Some((buffer::uniform(&ctx, "path params", &params), params));
                written += 48;
            }
        }
        Ok(written)
    }

    /// Group 0 for `kernels` (made per render: cheap, and buffers may have been replaced).
    pub fn group(&self, kernels: &Kernels) -> wgpu::BindGroup {
        let (bvh, _) = self.bvh.as_ref().expect("sync before group");
        let [nodes, tris, ids] = bvh.buffers();
        let arr = |i: usize| &self.arrays[i].as_ref().expect("sync before group").buffer;
        let params = &self.params.as_ref().expect("sync before group").0;
        let parr = |i: usize| &self.path_arrays[i].as_ref().expect("sync before group").buffer;
        let path_params = &self.path_params.as_ref().expect("sync before group").0;
        let list: [(u32, &wgpu::Buffer); 17] = [
            (0, nodes),
            (1, tris),
            (2, ids),
            (3, arr(0)),
            (4, arr(1)),
            (5, arr(2)),
            (6, arr(3)),
            (7, arr(4)),
            (8, arr(5)),
            (9, params),
            (10, arr(6)),
            (11, arr(7)),
            (12, parr(0)),
            (13, parr(1)),
            (14, parr(2)),
            (15, parr(3)),
            (16, path_params),
        ];
        let entries: Vec<_> = list
            .iter()
            .map(|&(binding, b)| wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() })
            .collect();
        debug_assert!(self.arrays.iter().all(|a| a.as_ref().is_some_and(|a| !a.what.is_empty())));
        self.ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &kernels.scene_layout,
            entries: &entries,
        })
    }
}
