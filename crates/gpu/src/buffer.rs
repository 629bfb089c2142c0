//! Uploads of Pod slices and read-backs: the only place buffers are created and mapped.

use crate::{GpuContext, GpuError};
use bytemuck::Pod;
use wgpu::util::DeviceExt;

/// A storage buffer holding `data` (one zeroed element when `data` is empty: bindings
/// cannot be empty), after checking it fits the adapter's binding limit.
pub(crate) fn storage<T: Pod>(
    ctx: &GpuContext,
    what: &'static str,
    data: &[T],
    extra: wgpu::BufferUsages,
) -> Result<wgpu::Buffer, GpuError> {
    let bytes: &[u8] = bytemuck::cast_slice(data);
    ctx.check_binding(what, bytes.len() as u64)?;
    let zero = vec![0u8; std::mem::size_of::<T>().max(4)];
    let contents = if bytes.is_empty() { &zero[..] } else { bytes };
    Ok(ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(what),
        contents,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | extra,
    }))
}

/// An uninitialised storage buffer of `bytes` bytes (at least 4) the kernels write.
pub(crate) fn output(ctx: &GpuContext, what: &'static str, bytes: u64) -> Result<wgpu::Buffer, GpuError> {
    ctx.check_binding(what, bytes)?;
    Ok(ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(what),
        size: bytes.max(4),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    }))
}

/// A uniform buffer holding one Pod value.
pub(crate) fn uniform<T: Pod>(ctx: &GpuContext, what: &'static str, value: &T) -> wgpu::Buffer {
    ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(what),
        contents: bytemuck::bytes_of(value),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    })
}

/// A buffer the CPU maps to read `bytes` bytes copied from a storage buffer.
pub(crate) fn staging(ctx: &GpuContext, bytes: u64) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back"),
        size: bytes.max(4),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Waits for the queue and copies the first `len` elements of `staging` (already filled
/// by a submitted copy) into `out`.
pub(crate) fn read_into<T: Pod>(ctx: &GpuContext, staging: &wgpu::Buffer, out: &mut [T]) -> Result<(), GpuError> {
    let bytes = std::mem::size_of_val(out) as u64;
    if bytes == 0 {
        return Ok(());
    }
    let slice = staging.slice(..bytes);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    wait(ctx)?;
    rx.recv()
        .map_err(|e| GpuError::Device { what: "read-back", message: e.to_string() })?
        .map_err(|e| GpuError::Device { what: "read-back", message: e.to_string() })?;
    {
        let view =
            slice.get_mapped_range().map_err(|e| GpuError::Device { what: "read-back", message: e.to_string() })?;
        out.copy_from_slice(bytemuck::cast_slice(&view));
    }
    staging.unmap();
    Ok(())
}

/// Copies the first `out.len()` elements of the device buffer `src` (made with
/// `COPY_SRC`) into `out`, through a staging buffer.
pub(crate) fn read_back<T: Pod>(ctx: &GpuContext, src: &wgpu::Buffer, out: &mut [T]) -> Result<(), GpuError> {
    let bytes = std::mem::size_of_val(out) as u64;
    if bytes == 0 {
        return Ok(());
    }
    let staging = staging(ctx, bytes);
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    enc.copy_buffer_to_buffer(src, 0, &staging, 0, bytes);
    ctx.queue.submit([enc.finish()]);
    read_into(ctx, &staging, out)
}

/// Blocks until every submitted command has finished.
pub(crate) fn wait(ctx: &GpuContext) -> Result<(), GpuError> {
    ctx.device
        .poll(wgpu::PollType::Wait { submission_index: None, timeout: None })
        .map(|_| ())
        .map_err(|e| GpuError::Device { what: "wait", message: e.to_string() })
}
