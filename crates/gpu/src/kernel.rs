//! Compiling WGSL into compute pipelines (with errors as values, not wgpu's panics) and
//! dispatching one invocation per item.

use crate::{GpuContext, GpuError};

/// Invocations per workgroup of every 1-D kernel (the `@workgroup_size` in shaders/).
pub(crate) const WORKGROUP: u32 = 64;

/// Compiles `source` and makes a pipeline for each of `entries`, with the layout wgpu
/// derives from the shader (each entry point binds only what it uses).
pub(crate) fn compile(
    ctx: &GpuContext,
    label: &'static str,
    source: &str,
    entries: &[&str],
) -> Result<Vec<wgpu::ComputePipeline>, GpuError> {
    let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = ctx.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipelines = entries
        .iter()
        .map(|e| {
            ctx.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: None,
                module: &module,
                entry_point: Some(e),
                compilation_options: Default::default(),
                cache: None,
            })
        })
        .collect();
    match pollster::block_on(scope.pop()) {
        Some(e) => Err(GpuError::Device { what: label, message: e.to_string() }),
        None => Ok(pipelines),
    }
}

/// A bind group for `pipeline`'s group 0 with `buffers[i]` at binding `bindings[i]`.
pub(crate) fn bind(
    ctx: &GpuContext,
    pipeline: &wgpu::ComputePipeline,
    entries: &[(u32, &wgpu::Buffer)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> =
        entries.iter().map(|&(binding, b)| wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }).collect();
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    })
}

/// Records one dispatch of `pipeline` covering `items` invocations.
pub(crate) fn dispatch(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    group: &wgpu::BindGroup,
    items: u32,
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: None });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(items.div_ceil(WORKGROUP), 1, 1);
}
