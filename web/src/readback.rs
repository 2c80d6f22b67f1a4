//! Reading an rgba16float texture back without blocking: the same code waits for the
//! map natively (the device poll runs the callback) and in a browser (the page's event
//! loop does, while the future is pending).

/// Reading a texture back failed: the map was refused or the device was lost.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("reading the texture back failed: {0}")]
pub struct ReadbackError(pub String);

/// The texels of `texture` (rgba16float, 2D or 3D, x fastest, then y, then layer or
/// slice) as f32 quadruples.
pub async fn read_rgba16f(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<[f32; 4]>, ReadbackError> {
    let size = texture.size();
    let row = size.width * 8;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let rows = size.height * size.depth_or_array_layers;
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("web readback"),
        size: u64::from(padded) * u64::from(rows),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(size.height),
            },
        },
        size,
    );
    queue.submit([encoder.finish()]);
    let slice = staging.slice(..);
    let (tx, rx) = futures_channel::oneshot::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| ReadbackError(e.to_string()))?;
    rx.await
        .map_err(|e| ReadbackError(e.to_string()))?
        .map_err(|e| ReadbackError(e.to_string()))?;
    let mut out = Vec::with_capacity((size.width * rows) as usize);
    {
        let data = slice
            .get_mapped_range()
            .map_err(|e| ReadbackError(e.to_string()))?;
        for chunk in data.chunks_exact(padded as usize) {
            let halves: &[half::f16] = bytemuck::cast_slice(&chunk[..row as usize]);
            out.extend(
                halves
                    .chunks_exact(4)
                    .map(|h| [h[0].to_f32(), h[1].to_f32(), h[2].to_f32(), h[3].to_f32()]),
            );
        }
    }
    staging.unmap();
    Ok(out)
}
