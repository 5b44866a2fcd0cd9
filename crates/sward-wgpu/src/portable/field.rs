//! The Bezier field on the GPU for the portable passes: the blades (64 bytes each, sward-core's
//! `Blade`) and their collision strengths η, uploaded once and read back for tests and tools.

use sward_core::Blade;
use wgpu::util::DeviceExt;

use super::PortableError;

/// Bytes of one blade on the GPU.
const BLADE_BYTES: u64 = std::mem::size_of::<Blade>() as u64;

/// A field's blades and collision strengths in storage buffers.
pub struct PortableField {
    pub(crate) blades: wgpu::Buffer,
    pub(crate) etas: wgpu::Buffer,
    count: u32,
}

impl PortableField {
    /// Upload `blades` (each at collision strength 0), or say how many fit where the device's
    /// storage bindings are too small for them.
    pub fn new(device: &wgpu::Device, blades: &[Blade]) -> Result<PortableField, PortableError> {
        let limit = device.limits().max_storage_buffer_binding_size;
        let bytes = blades.len() as u64 * BLADE_BYTES;
        if bytes > limit || blades.len() > u32::MAX as usize {
            return Err(PortableError::FieldTooLarge {
                blades: blades.len(),
                bytes,
                limit,
                fits: limit / BLADE_BYTES,
            });
        }
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        // A binding is never empty: an empty field holds one unused blade.
        let first = [<Blade as bytemuck::Zeroable>::zeroed()];
        let contents = if blades.is_empty() { &first[..] } else { blades };
        let etas = vec![0.0f32; contents.len()];
        Ok(PortableField {
            blades: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("sward blades"),
                contents: bytemuck::cast_slice(contents),
                usage,
            }),
            etas: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("sward collision strengths"),
                contents: bytemuck::cast_slice(&etas),
                usage,
            }),
            count: blades.len() as u32,
        })
    }

    /// Blades in the field.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// The blades and their collision strengths as the GPU holds them, once the work submitted
    /// so far has finished (native backends: this waits for the device).
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<(Vec<Blade>, Vec<f32>), PortableError> {
        let n = self.count as usize;
        let blades: Vec<Blade> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &self.blades)?);
        let etas: Vec<f32> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &self.etas)?);
        Ok((blades[..n].to_vec(), etas[..n].to_vec()))
    }
}

/// The bytes of `buffer`, copied into a mappable buffer and mapped.
fn read_buffer(device: &wgpu::Device, queue: &wgpu::Queue, buffer: &wgpu::Buffer) -> Result<Vec<u8>, PortableError> {
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward read-back"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
    queue.submit([encoder.finish()]);
    let (sender, receiver) = std::sync::mpsc::channel();
    staging.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| PortableError::Readback(e.to_string()))?;
    match receiver.try_recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(PortableError::Readback(e.to_string())),
        Err(_) => {
            return Err(PortableError::Readback(
                "the buffer was not mapped after the device went idle".into(),
            ))
        }
    }
    let bytes = staging.slice(..).get_mapped_range().to_vec();
    staging.unmap();
    Ok(bytes)
}
