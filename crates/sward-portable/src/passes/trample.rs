//! The trample map on the portable renderer (sward-core's `trample`, SPEC §11): its texels, a
//! storage buffer kept from frame to frame, and the record of `trample.wesl`, which lets the
//! grass recover and stamps the colliders and cutters once a frame, before the simulation reads
//! it (a blade held down along a trail, a mown blade stepped as a stub).

use sward_core::declared::bindings;
#[cfg(feature = "blocking")]
use sward_core::trample::Texel;
use sward_core::trample::TrampleParams;

use super::FrameParts;
#[cfg(feature = "blocking")]
use crate::field::read_buffer;
use crate::shaders::{ShaderModules, TRAMPLE_SOURCE};
use crate::{compute_pipeline, dispatch, Bound, Groups, PortableError, Reading, FRAME};

/// Bytes of one texel: the push (two floats), the mown height and its cell's tag.
const TEXEL_BYTES: u64 = 16;

/// Texels along a side per workgroup side (trample.wesl `@workgroup_size(16, 16)`).
const TEXELS_PER_GROUP: u32 = 16;

/// The map's texels and what they were made for.
pub(crate) struct TrampleTexels {
    pub buffer: wgpu::Buffer,
    /// The resolution and the bits of the texel size the texels hold; a change starts the map
    /// upright.
    made_for: (u32, u32),
    /// Whether the next frame clears the texels first.
    fresh: bool,
    /// Whether a map too large for the device was said in the log.
    said_too_large: bool,
}

impl TrampleTexels {
    /// One texel (bound where the map is off), until a frame asks for a map.
    pub fn new(device: &wgpu::Device) -> TrampleTexels {
        TrampleTexels {
            buffer: texel_buffer(device, 1),
            made_for: (0, 0),
            fresh: true,
            said_too_large: false,
        }
    }

    /// Fit the texels to `map`: whether the buffer was made anew (the passes' bind groups then
    /// hold the old one), or None where the map does not fit the device's bindings (said once
    /// in the log; the grass then runs without it).
    pub fn prepare(&mut self, device: &wgpu::Device, map: &TrampleParams) -> Option<bool> {
        let texels = map.resolution as u64 * map.resolution as u64;
        let limits = device.limits();
        let fits = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        if texels * TEXEL_BYTES > fits {
            if !std::mem::replace(&mut self.said_too_large, true) {
                log::warn!(
                    "a trample map of {0}×{0} texels needs {1} bytes, more than this device binds at once ({fits}); the grass runs without it (a smaller trample.resolution fits)",
                    map.resolution,
                    texels * TEXEL_BYTES
                );
            }
            return None;
        }
        let words = (map.resolution, map.texel_size().to_bits());
        if words.0 == 0 || words == self.made_for {
            return Some(false);
        }
        let grown = texels * TEXEL_BYTES > self.buffer.size();
        if grown {
            self.buffer = texel_buffer(device, texels);
        }
        self.made_for = words;
        self.fresh = true;
        Some(grown)
    }

    /// Clear the texels where they are new, then the workgroups of the map's pass.
    pub fn begin_frame(&mut self, encoder: &mut wgpu::CommandEncoder) -> [u32; 2] {
        if self.fresh {
            encoder.clear_buffer(&self.buffer, 0, None);
            self.fresh = false;
        }
        let side = self.made_for.0.div_ceil(TEXELS_PER_GROUP);
        [side, side]
    }

    /// Bytes of GPU memory the texels hold.
    pub fn bytes(&self) -> u64 {
        self.buffer.size()
    }

    #[cfg(feature = "blocking")]
    /// Every texel as the GPU holds it now, row by row (for tests and tools).
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<Texel>, PortableError> {
        let words: Vec<[u32; 4]> = bytemuck::pod_collect_to_vec(&read_buffer(device, queue, &self.buffer)?);
        let texels = self.made_for.0 as usize * self.made_for.0 as usize;
        Ok(words.iter().take(texels).map(|&w| Texel::from_words(w)).collect())
    }
}

fn texel_buffer(device: &wgpu::Device, texels: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sward trample map"),
        size: texels * TEXEL_BYTES,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// The trample map's step (`trample.wesl`): the one pass that writes the map.
#[derive(Clone)]
pub(crate) struct TramplePass {
    step: Reading<wgpu::ComputePipeline>,
}

impl TramplePass {
    pub fn new(device: &wgpu::Device, modules: &ShaderModules) -> Result<TramplePass, PortableError> {
        Ok(TramplePass {
            step: compute_pipeline(device, &TRAMPLE_SOURCE, modules)?,
        })
    }

    /// The map's step over `texel_groups` workgroups (`TrampleTexels::begin_frame`), before the
    /// simulation reads it.
    pub fn record(&self, parts: &FrameParts, encoder: &mut wgpu::CommandEncoder, texel_groups: [u32; 2]) {
        let buffer = Bound::Buffer;
        let trampling = [
            (FRAME, buffer(parts.frame)),
            (bindings::GROUND, buffer(parts.ground)),
            (bindings::TRAMPLE, buffer(parts.trample)),
        ];
        let step = (&self.step, &trampling[..], Groups::Direct(texel_groups));
        dispatch((parts.device, parts.groups), encoder, &[step]);
    }
}
