//! Reading GPU buffers back to the host.

use crate::GpuError;

/// Map a `MAP_READ` buffer, wait for the GPU, and copy its contents out.
pub fn read_bytes(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    read_prefix(device, buffer, buffer.size())
}

/// [`read_bytes`] of the buffer's first `len` bytes (a multiple of 4, at most its size).
pub fn read_prefix(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    len: u64,
) -> Result<Vec<u8>, GpuError> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, ..len, move |result| {
        let _ = tx.send(result);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Device(e.to_string()))?;
    rx.recv()
        .map_err(|e| GpuError::Device(e.to_string()))?
        .map_err(|e| GpuError::Device(e.to_string()))?;
    take_mapped(buffer, len)
}

/// The first `len` bytes of a mapped buffer as `T`s, copied out once, and the buffer unmapped.
pub(crate) fn take_mapped<T: bytemuck::Pod>(
    buffer: &wgpu::Buffer,
    len: u64,
) -> Result<Vec<T>, GpuError> {
    let values = {
        let view = buffer
            .get_mapped_range(..len)
            .map_err(|e| GpuError::Device(e.to_string()))?;
        bytemuck::pod_collect_to_vec(&view)
    };
    buffer.unmap();
    Ok(values)
}

/// [`read_bytes`] as `u32` words.
pub fn read_u32(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u32>, GpuError> {
    let bytes = read_bytes(device, buffer)?;
    Ok(bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}
