//! A texture read back to the host through wgpu: its texels, row after row, without the
//! padding wgpu's copies need. Shared by the tests and the `meadow` example.

/// The texels of single-sample `texture` (on `device`, copied through `queue`), tightly packed.
pub fn texels(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture) -> Vec<u8> {
    let texel = texture.format().block_copy_size(None).expect("a colour format") as usize;
    let (width, height) = (texture.width() as usize, texture.height() as usize);
    let row = (width * texel).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as usize);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back"),
        size: (row * height) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row as u32),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    buffer.slice(..).map_async(wgpu::MapMode::Read, |r| r.expect("mapped"));
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("the read-back finishes");
    let data = buffer.slice(..).get_mapped_range().unwrap();
    data.chunks(row).flat_map(|r| &r[..width * texel]).copied().collect()
}
