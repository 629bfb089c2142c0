//! WGSL sources: the files of `shaders/` joined behind a prelude that fixes the
//! precision, the traversal stack and the engine's constants (WGSL has no includes).

use crate::Precision;
use dynray_geom::SLAB_MARGIN;

/// The triangle test and ray set-up every kernel shares.
pub(crate) const WATERTIGHT: &str = include_str!("../shaders/watertight.wgsl");
/// BVH closest-hit and any-hit traversal.
pub(crate) const BVH_TRAVERSE: &str = include_str!("../shaders/bvh_traverse.wgsl");
/// The batch-query entry points.
pub(crate) const TRACE_RAYS: &str = include_str!("../shaders/trace_rays.wgsl");

/// The frame's bindings (group 0) of the render kernels.
pub(crate) const RENDER_SCENE: &str = include_str!("../shaders/render_scene.wgsl");
/// The queues and outputs (group 1) of the render kernels.
pub(crate) const RENDER_WORK: &str = include_str!("../shaders/render_work.wgsl");
/// Camera rays, as the CPU's `CameraRays::ray_at`.
pub(crate) const CAMERA: &str = include_str!("../shaders/camera.wgsl");
/// The CPU Whitted integrator's shading.
pub(crate) const WHITTED_SHADE: &str = include_str!("../shaders/whitted_shade.wgsl");
/// The workgroup prefix sum compaction and the builders' scan share.
pub(crate) const WORKGROUP_SCAN: &str = include_str!("../shaders/workgroup_scan.wgsl");
/// Prefix-sum stream compaction.
pub(crate) const COMPACT: &str = include_str!("../shaders/compact.wgsl");
/// A live image's resolve on the device (render/device_image.rs).
pub(crate) const RESOLVE: &str = include_str!("../shaders/resolve.wgsl");
/// The path tracer's shading (the wavefront's third mode).
pub(crate) const PATH_SHADE: &str = include_str!("../shaders/path_shade.wgsl");
/// The wavefront strategy's kernels.
pub(crate) const WAVEFRONT: &str = include_str!("../shaders/wavefront.wgsl");
/// The megakernel strategy.
pub(crate) const MEGAKERNEL: &str = include_str!("../shaders/megakernel.wgsl");
/// The hybrid strategy's two kernels (it runs megakernel.wgsl's loop).
pub(crate) const HYBRID: &str = include_str!("../shaders/hybrid.wgsl");

/// Seed 001's distance field: point location, reconstruction, sphere tracing.
pub(crate) const ADF: &str = include_str!("../shaders/adf.wgsl");

/// The render kernels' module: every strategy's entry points over one set of bindings,
/// with `ray_stack` entries of the megakernel's private ray stack.
pub(crate) fn render_module(precision: Precision, stack: u32, ray_stack: u32) -> String {
    let mut s = assemble(
        precision,
        stack,
        &[
            WATERTIGHT,
            BVH_TRAVERSE,
            RENDER_SCENE,
            RENDER_WORK,
            WHITTED_SHADE,
            CAMERA,
            WORKGROUP_SCAN,
            COMPACT,
            WAVEFRONT,
            PATH_SHADE,
            MEGAKERNEL,
            HYBRID,
        ],
    );
    s.insert_str(0, &format!("const RAY_STACK: u32 = {ray_stack}u;\n"));
    s
}

/// Traversal stack sizes kernels are compiled for; a tree uses the smallest above its
/// depth (near-first descent pushes at most one node per level).
pub(crate) const STACK_SIZES: [u32; 3] = [32, 64, 128];

/// The stack size for a tree of depth `depth`, `None` when none is deep enough.
pub(crate) fn stack_for(depth: u32) -> Option<u32> {
    STACK_SIZES.into_iter().find(|&s| s > depth)
}

/// An f32 as a WGSL literal that parses back to the same bits (Rust's `{:e}` prints the
/// shortest round-tripping digits).
fn literal(x: f32) -> String {
    format!("{x:e}f")
}

/// The prelude: the `real` type, the stack size and the slab factors, the latter computed
/// in f32 here exactly as the CPU computes them (not by WGSL's abstract-float folding).
pub(crate) fn prelude(precision: Precision, stack: u32) -> String {
    format!(
        "alias real = {};\nconst STACK_SIZE: u32 = {stack}u;\nconst SLAB_SHRINK: f32 = {};\nconst SLAB_GROW: f32 = {};\n",
        precision.name(),
        literal(1.0 - SLAB_MARGIN),
        literal(1.0 + SLAB_MARGIN),
    )
}

/// `prelude` followed by `parts`.
pub(crate) fn assemble(precision: Precision, stack: u32, parts: &[&str]) -> String {
    let mut s = prelude(precision, stack);
    for p in parts {
        s.push('\n');
        s.push_str(p);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_round_trip() {
        for x in [1.0 - SLAB_MARGIN, 1.0 + SLAB_MARGIN, 0.1, 3.0e-39, f32::MAX] {
            let s = literal(x);
            assert_eq!(s.trim_end_matches('f').parse::<f32>().unwrap().to_bits(), x.to_bits(), "{s}");
        }
    }

    #[test]
    fn every_kernel_source_parses_and_validates() {
        // naga alone (no device): both precisions, every stack size.
        for p in [Precision::F64, Precision::F32] {
            for s in STACK_SIZES {
                let src = assemble(p, s, &[WATERTIGHT, BVH_TRAVERSE, TRACE_RAYS]);
                let module =
                    naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
                naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
                    .validate(&module)
                    .unwrap_or_else(|e| panic!("{p:?}/{s}: {e:?}"));
            }
        }
        for p in [Precision::F64, Precision::F32] {
            let src = render_module(p, 32, 12);
            let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
                .validate(&module)
                .unwrap_or_else(|e| panic!("render {p:?}: {e:?}"));
        }
        let src = assemble(Precision::F32, 1, &[ADF]);
        let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("adf: {e:?}"));
        assert_eq!(stack_for(18), Some(32));
        assert_eq!(stack_for(32), Some(64));
        assert_eq!(stack_for(200), None);
    }
}
