//! Embree 3 (Debian's libembree3, 3.13.5) through minimal `extern "C"` bindings of the
//! dozen rtc* calls used: single rays (`rtcIntersect1`/`rtcOccluded1`) on every kind and
//! 8-wide packets (`rtcIntersect8`) on primary rays; default build quality (MEDIUM) and
//! scene flags.
//!
//! Why not the `embree` crate (0.3.8): it has no 8-wide packet calls (only 1, 4, and
//! streams), its committed scene borrows the scene which borrows the device (a built
//! structure could not be stored beside its device), and it pulls in `cgmath`; the C API
//! we need is a handful of functions whose layouts are pinned below against the headers.

use super::{par_chunks_into, parts, Built, Competitor};
use crate::rays::RayKind;
use anyhow::{bail, Result};
use dynray_accel::BatchQuery;
use dynray_geom::{Hit, Ray, TriangleMesh};
use std::ffi::{c_char, c_void, CString};
use std::sync::atomic::{AtomicIsize, Ordering};
use std::sync::Arc;

mod ffi {
    //! The subset of Embree 3's C API used here (rtcore_*.h of 3.13.5, built with
    //! RTC_MAX_INSTANCE_LEVEL_COUNT = 1 and RTC_MIN_WIDTH = 0 as Debian's package is).
    #![allow(non_camel_case_types, missing_docs)]
    use std::ffi::{c_char, c_void};

    pub type RTCDevice = *mut c_void;
    pub type RTCScene = *mut c_void;
    pub type RTCGeometry = *mut c_void;
    pub type RTCMemoryMonitorFunction = Option<unsafe extern "C" fn(*mut c_void, isize, bool) -> bool>;

    pub const RTC_INVALID_GEOMETRY_ID: u32 = u32::MAX;
    pub const RTC_GEOMETRY_TYPE_TRIANGLE: u32 = 0;
    pub const RTC_BUFFER_TYPE_INDEX: u32 = 0;
    pub const RTC_BUFFER_TYPE_VERTEX: u32 = 1;
    pub const RTC_FORMAT_UINT3: u32 = 0x5003;
    pub const RTC_FORMAT_FLOAT3: u32 = 0x9003;
    pub const RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED: u32 = 33;
    pub const RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT: u32 = 0;
    pub const RTC_INTERSECT_CONTEXT_FLAG_COHERENT: u32 = 1;

    /// `struct RTCIntersectContext`: flags, filter, instID[1].
    #[repr(C)]
    pub struct RTCIntersectContext {
        pub flags: u32,
        pub filter: Option<unsafe extern "C" fn(*const c_void)>,
        pub inst_id: [u32; 1],
    }

    /// `struct RTC_ALIGN(16) RTCRay`.
    #[repr(C, align(16))]
    #[derive(Clone, Copy)]
    pub struct RTCRay {
        pub org: [f32; 3],
        pub tnear: f32,
        pub dir: [f32; 3],
        pub time: f32,
        pub tfar: f32,
        pub mask: u32,
        pub id: u32,
        pub flags: u32,
    }

    /// `struct RTC_ALIGN(16) RTCHit`.
    #[repr(C, align(16))]
    #[derive(Clone, Copy)]
    pub struct RTCHit {
        pub ng: [f32; 3],
        pub u: f32,
        pub v: f32,
        pub prim_id: u32,
        pub geom_id: u32,
        pub inst_id: [u32; 1],
    }

    /// `struct RTC_ALIGN(16) RTCRayHit`.
    #[repr(C, align(16))]
    #[derive(Clone, Copy)]
    pub struct RTCRayHit {
        pub ray: RTCRay,
        pub hit: RTCHit,
    }

    /// `struct RTC_ALIGN(32) RTCRay8` (structure of arrays).
    #[repr(C, align(32))]
    #[derive(Clone, Copy)]
    pub struct RTCRay8 {
        pub org_x: [f32; 8],
        pub org_y: [f32; 8],
        pub org_z: [f32; 8],
        pub tnear: [f32; 8],
        pub dir_x: [f32; 8],
        pub dir_y: [f32; 8],
        pub dir_z: [f32; 8],
        pub time: [f32; 8],
        pub tfar: [f32; 8],
        pub mask: [u32; 8],
        pub id: [u32; 8],
        pub flags: [u32; 8],
    }

    /// `struct RTC_ALIGN(32) RTCHit8`.
    #[repr(C, align(32))]
    #[derive(Clone, Copy)]
    pub struct RTCHit8 {
        pub ng_x: [f32; 8],
        pub ng_y: [f32; 8],
        pub ng_z: [f32; 8],
        pub u: [f32; 8],
        pub v: [f32; 8],
        pub prim_id: [u32; 8],
        pub geom_id: [u32; 8],
        pub inst_id: [[u32; 8]; 1],
    }

    /// `struct RTC_ALIGN(32) RTCRayHit8`.
    #[repr(C, align(32))]
    #[derive(Clone, Copy)]
    pub struct RTCRayHit8 {
        pub ray: RTCRay8,
        pub hit: RTCHit8,
    }

    // Sizes as the C compiler lays the headers out (a mismatch would corrupt memory).
    const _: () = assert!(std::mem::size_of::<RTCIntersectContext>() == 24);
    const _: () = assert!(std::mem::size_of::<RTCRay>() == 48);
    const _: () = assert!(std::mem::size_of::<RTCHit>() == 32);
    const _: () = assert!(std::mem::size_of::<RTCRayHit>() == 80);
    const _: () = assert!(std::mem::size_of::<RTCRay8>() == 384);
    const _: () = assert!(std::mem::size_of::<RTCHit8>() == 256);
    const _: () = assert!(std::mem::size_of::<RTCRayHit8>() == 640);

    #[link(name = "embree3")]
    extern "C" {
        pub fn rtcNewDevice(config: *const c_char) -> RTCDevice;
        pub fn rtcReleaseDevice(device: RTCDevice);
        pub fn rtcGetDeviceError(device: RTCDevice) -> u32;
        pub fn rtcGetDeviceProperty(device: RTCDevice, prop: u32) -> isize;
        pub fn rtcSetDeviceMemoryMonitorFunction(device: RTCDevice, f: RTCMemoryMonitorFunction, user: *mut c_void);
        pub fn rtcNewScene(device: RTCDevice) -> RTCScene;
        pub fn rtcReleaseScene(scene: RTCScene);
        pub fn rtcAttachGeometry(scene: RTCScene, geometry: RTCGeometry) -> u32;
        pub fn rtcCommitScene(scene: RTCScene);
        pub fn rtcNewGeometry(device: RTCDevice, kind: u32) -> RTCGeometry;
        pub fn rtcReleaseGeometry(geometry: RTCGeometry);
        pub fn rtcCommitGeometry(geometry: RTCGeometry);
        pub fn rtcSetNewGeometryBuffer(
            geometry: RTCGeometry,
            kind: u32,
            slot: u32,
            format: u32,
            byte_stride: usize,
            item_count: usize,
        ) -> *mut c_void;
        pub fn rtcIntersect1(scene: RTCScene, ctx: *mut RTCIntersectContext, rayhit: *mut RTCRayHit);
        pub fn rtcOccluded1(scene: RTCScene, ctx: *mut RTCIntersectContext, ray: *mut RTCRay);
        pub fn rtcIntersect8(
            valid: *const i32,
            scene: RTCScene,
            ctx: *mut RTCIntersectContext,
            rayhit: *mut RTCRayHit8,
        );
        pub fn rtcOccluded8(valid: *const i32, scene: RTCScene, ctx: *mut RTCIntersectContext, ray: *mut RTCRay8);
    }
}

use ffi::*;

/// Counts the bytes Embree holds (its memory monitor callback adds every allocation and
/// subtracts every free).
unsafe extern "C" fn monitor(user: *mut c_void, bytes: isize, _post: bool) -> bool {
    // SAFETY: `user` is the `AtomicIsize` boxed in `Embree`, which outlives the device.
    unsafe { (*(user as *const AtomicIsize)).fetch_add(bytes, Ordering::Relaxed) };
    true
}

/// An Embree device (its own thread pool sized like ours) shared by both variants.
pub struct Embree {
    device: RTCDevice,
    ray8: bool,
    // Boxed so its address stays fixed while the device's monitor points at it.
    bytes: Box<AtomicIsize>,
}

// SAFETY: Embree devices are thread-safe (the API may be called from any thread).
unsafe impl Send for Embree {}
// SAFETY: as above.
unsafe impl Sync for Embree {}

impl Embree {
    /// A device with `threads` build threads (the same count as our rayon pool).
    pub fn new(threads: usize) -> Result<Self> {
        let config = CString::new(format!("threads={threads}"))?;
        // SAFETY: plain C calls with a valid NUL-terminated string.
        let device = unsafe { rtcNewDevice(config.as_ptr() as *const c_char) };
        if device.is_null() {
            // SAFETY: a null device asks for the thread-local error of the failed creation.
            bail!("rtcNewDevice failed (error {})", unsafe { rtcGetDeviceError(std::ptr::null_mut()) });
        }
        let bytes = Box::new(AtomicIsize::new(0));
        // SAFETY: the device is valid; the counter outlives it (released in Drop first).
        let ray8 = unsafe {
            rtcSetDeviceMemoryMonitorFunction(device, Some(monitor), &*bytes as *const AtomicIsize as *mut c_void);
            rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0
        };
        Ok(Self { device, ray8, bytes })
    }

    /// True when the library and CPU run 8-wide packets natively.
    pub fn native_ray8(&self) -> bool {
        self.ray8
    }

    fn error(&self) -> u32 {
        // SAFETY: valid device.
        unsafe { rtcGetDeviceError(self.device) }
    }

    /// Builds a scene of one triangle mesh (copied into Embree's own buffers).
    fn build(self: &Arc<Self>, mesh: &TriangleMesh) -> Result<EmbreeScene> {
        let before = self.bytes.load(Ordering::Relaxed);
        // SAFETY: valid device; buffers are written within the sizes Embree allocated
        // (Embree pads vertex buffers itself for its 16-byte loads); every handle is
        // checked before use and the scene keeps the device alive through its Arc.
        unsafe {
            let scene = rtcNewScene(self.device);
            let geom = rtcNewGeometry(self.device, RTC_GEOMETRY_TYPE_TRIANGLE);
            if scene.is_null() || geom.is_null() {
                bail!("embree: cannot create a scene or geometry (error {})", self.error());
            }
            let v =
                rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, mesh.positions.len())
                    as *mut [f32; 3];
            let i = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, mesh.indices.len())
                as *mut [u32; 3];
            if v.is_null() || i.is_null() {
                rtcReleaseGeometry(geom);
                rtcReleaseScene(scene);
                bail!("embree: cannot allocate the mesh buffers (error {})", self.error());
            }
            std::ptr::copy_nonoverlapping(mesh.positions.as_ptr(), v, mesh.positions.len());
            std::ptr::copy_nonoverlapping(mesh.indices.as_ptr(), i, mesh.indices.len());
            rtcCommitGeometry(geom);
            rtcAttachGeometry(scene, geom);
            rtcReleaseGeometry(geom);
            rtcCommitScene(scene);
            let err = self.error();
            if err != 0 {
                rtcReleaseScene(scene);
                bail!("embree: scene commit failed (error {err})");
            }
            let bytes = self.bytes.load(Ordering::Relaxed) - before;
            Ok(EmbreeScene { scene, bytes: usize::try_from(bytes).ok(), _device: self.clone() })
        }
    }
}

impl Drop for Embree {
    fn drop(&mut self) {
        // SAFETY: every scene holds an Arc to this device, so none is left.
        unsafe { rtcReleaseDevice(self.device) };
    }
}

/// A committed Embree scene.
pub struct EmbreeScene {
    scene: RTCScene,
    bytes: Option<usize>,
    _device: Arc<Embree>,
}

// SAFETY: rtcIntersect*/rtcOccluded* on a committed scene are thread-safe.
unsafe impl Send for EmbreeScene {}
// SAFETY: as above.
unsafe impl Sync for EmbreeScene {}

impl Drop for EmbreeScene {
    fn drop(&mut self) {
        // SAFETY: the scene is valid and released once.
        unsafe { rtcReleaseScene(self.scene) };
    }
}

fn context(flags: u32) -> RTCIntersectContext {
    // As rtcInitIntersectContext (an inline function, so not in the library).
    RTCIntersectContext { flags, filter: None, inst_id: [RTC_INVALID_GEOMETRY_ID] }
}

fn rtc_ray(r: &Ray) -> RTCRay {
    let (org, dir, tnear, tfar) = parts(r);
    RTCRay { org, tnear, dir, time: 0.0, tfar, mask: u32::MAX, id: 0, flags: 0 }
}

/// Single-ray queries on every ray kind.
struct Single(EmbreeScene);

/// `u`, `v` are Embree's barycentrics, which follow our convention (hit point
/// `(1-u-v)·p0 + u·p1 + v·p2`).
impl BatchQuery for Single {
    fn intersect_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        par_chunks_into(rays, hits, |rays, hits| self.closest(rays, hits));
    }

    fn occluded_into(&self, rays: &[Ray], out: &mut [bool]) {
        par_chunks_into(rays, out, |rays, out| self.occluded(rays, out));
    }
}

impl Single {
    fn closest(&self, rays: &[Ray], out: &mut [Hit]) {
        let mut ctx = context(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
        for (r, o) in rays.iter().zip(out) {
            let mut rh = RTCRayHit {
                ray: rtc_ray(r),
                hit: RTCHit {
                    ng: [0.0; 3],
                    u: 0.0,
                    v: 0.0,
                    prim_id: RTC_INVALID_GEOMETRY_ID,
                    geom_id: RTC_INVALID_GEOMETRY_ID,
                    inst_id: [RTC_INVALID_GEOMETRY_ID],
                },
            };
            // SAFETY: committed scene, initialised context and ray/hit.
            unsafe { rtcIntersect1(self.0.scene, &mut ctx, &mut rh) };
            *o = if rh.hit.geom_id != RTC_INVALID_GEOMETRY_ID {
                Hit { t: rh.ray.tfar, u: rh.hit.u, v: rh.hit.v, prim: rh.hit.prim_id }
            } else {
                Hit::MISS
            };
        }
    }

    fn occluded(&self, rays: &[Ray], out: &mut [bool]) {
        let mut ctx = context(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
        for (r, o) in rays.iter().zip(out) {
            let mut ray = rtc_ray(r);
            // SAFETY: committed scene, initialised context and ray.
            unsafe { rtcOccluded1(self.0.scene, &mut ctx, &mut ray) };
            // Embree marks an occluded ray by setting tfar to -inf.
            *o = ray.tfar == f32::NEG_INFINITY;
        }
    }
}

/// 8-wide packets (primary rays: coherent by construction, consecutive pixels of a row).
struct Packets(EmbreeScene);

/// The packet's valid mask (-1: lane active), aligned like the packet: Embree may load it
/// as one 256-bit vector.
#[repr(C, align(32))]
struct Valid8([i32; 8]);

impl Packets {
    fn packet(rays: &[Ray]) -> (Valid8, RTCRay8) {
        let mut valid = Valid8([0; 8]);
        let mut p = RTCRay8 {
            org_x: [0.0; 8],
            org_y: [0.0; 8],
            org_z: [0.0; 8],
            tnear: [0.0; 8],
            dir_x: [0.0; 8],
            dir_y: [0.0; 8],
            dir_z: [1.0; 8],
            time: [0.0; 8],
            tfar: [0.0; 8],
            mask: [u32::MAX; 8],
            id: [0; 8],
            flags: [0; 8],
        };
        for (k, r) in rays.iter().enumerate() {
            let (o, d, tmin, tmax) = parts(r);
            valid.0[k] = -1;
            (p.org_x[k], p.org_y[k], p.org_z[k]) = (o[0], o[1], o[2]);
            (p.dir_x[k], p.dir_y[k], p.dir_z[k]) = (d[0], d[1], d[2]);
            (p.tnear[k], p.tfar[k]) = (tmin, tmax);
            p.id[k] = k as u32;
        }
        (valid, p)
    }
}

/// Chunks of [`super::CHUNK`] rays (a multiple of 8) keep every packet inside one chunk,
/// so packets hold the same consecutive rays as a sequential pass would. `u`, `v` as for
/// [`Single`].
impl BatchQuery for Packets {
    fn intersect_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        par_chunks_into(rays, hits, |rays, hits| self.closest(rays, hits));
    }

    fn occluded_into(&self, rays: &[Ray], out: &mut [bool]) {
        par_chunks_into(rays, out, |rays, out| self.occluded(rays, out));
    }
}

const _: () = assert!(super::CHUNK.is_multiple_of(8), "packets must not straddle chunks");

impl Packets {
    fn closest(&self, rays: &[Ray], out: &mut [Hit]) {
        let mut ctx = context(RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
        for (rs, os) in rays.chunks(8).zip(out.chunks_mut(8)) {
            let (valid, ray) = Self::packet(rs);
            let mut rh = RTCRayHit8 {
                ray,
                hit: RTCHit8 {
                    ng_x: [0.0; 8],
                    ng_y: [0.0; 8],
                    ng_z: [0.0; 8],
                    u: [0.0; 8],
                    v: [0.0; 8],
                    prim_id: [RTC_INVALID_GEOMETRY_ID; 8],
                    geom_id: [RTC_INVALID_GEOMETRY_ID; 8],
                    inst_id: [[RTC_INVALID_GEOMETRY_ID; 8]],
                },
            };
            // SAFETY: committed scene, 32-byte aligned packet, valid mask for its lanes.
            unsafe { rtcIntersect8(valid.0.as_ptr(), self.0.scene, &mut ctx, &mut rh) };
            for (k, o) in os.iter_mut().enumerate() {
                *o = if rh.hit.geom_id[k] != RTC_INVALID_GEOMETRY_ID {
                    Hit { t: rh.ray.tfar[k], u: rh.hit.u[k], v: rh.hit.v[k], prim: rh.hit.prim_id[k] }
                } else {
                    Hit::MISS
                };
            }
        }
    }

    fn occluded(&self, rays: &[Ray], out: &mut [bool]) {
        let mut ctx = context(RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
        for (rs, os) in rays.chunks(8).zip(out.chunks_mut(8)) {
            let (valid, mut ray) = Self::packet(rs);
            // SAFETY: committed scene, 32-byte aligned packet, valid mask for its lanes.
            unsafe { rtcOccluded8(valid.0.as_ptr(), self.0.scene, &mut ctx, &mut ray) };
            for (k, o) in os.iter_mut().enumerate() {
                *o = ray.tfar[k] == f32::NEG_INFINITY;
            }
        }
    }
}

/// `embree single-ray`: rtcIntersect1 / rtcOccluded1 on every ray kind.
pub struct SingleRay(pub Arc<Embree>);

impl Competitor for SingleRay {
    fn name(&self) -> &'static str {
        "embree"
    }
    fn variant(&self) -> &'static str {
        "single-ray"
    }
    fn describe(&self) -> String {
        "Embree 3 (libembree3), rtcIntersect1 / rtcOccluded1 (any hit), incoherent context; \
         default build quality (MEDIUM) and scene flags"
            .into()
    }
    fn build(&self, mesh: &TriangleMesh) -> Result<Built> {
        let scene = self.0.build(mesh)?;
        Ok(Built { memory_bytes: scene.bytes, query: Box::new(Single(scene)), any_hit: true })
    }
}

/// `embree packet8`: rtcIntersect8 on primary rays.
pub struct Packet8(pub Arc<Embree>);

impl Competitor for Packet8 {
    fn name(&self) -> &'static str {
        "embree"
    }
    fn variant(&self) -> &'static str {
        "packet8"
    }
    fn describe(&self) -> String {
        "Embree 3 (libembree3), rtcIntersect8 packets of 8 consecutive primary rays, coherent context; \
         default build quality (MEDIUM) and scene flags"
            .into()
    }
    fn kinds(&self) -> Option<&'static [RayKind]> {
        Some(&[RayKind::Primary])
    }
    fn packets(&self) -> bool {
        true
    }
    fn build(&self, mesh: &TriangleMesh) -> Result<Built> {
        let scene = self.0.build(mesh)?;
        Ok(Built { memory_bytes: scene.bytes, query: Box::new(Packets(scene)), any_hit: true })
    }
}
