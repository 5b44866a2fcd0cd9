//! The streamed field's passes (`stream.wesl`, which the Vulkan renderer's `passes/stream.rs`
//! runs too): every held blade carried to a moved frame origin first, then the blades of the
//! tiles entering the window made there — a row of workgroups per slot, or per entering tile.

use sward_core::declared::bindings;

use super::{FrameParts, TILE_GROUPS};
use crate::field::PortableField;
use crate::shaders::{ShaderModules, STREAM_SOURCES};
use crate::{compute_pipeline, dispatch, Bound, Dispatch, Groups, PortableError, Reading, FRAME};

/// The streamed field's pipelines.
#[derive(Clone)]
pub(crate) struct StreamPasses {
    rebase: Reading<wgpu::ComputePipeline>,
    make: Reading<wgpu::ComputePipeline>,
}

impl StreamPasses {
    pub fn new(device: &wgpu::Device, modules: &ShaderModules) -> Result<StreamPasses, PortableError> {
        let [rebase, make] = &STREAM_SOURCES;
        Ok(StreamPasses {
            rebase: compute_pipeline(device, rebase, modules)?,
            make: compute_pipeline(device, make, modules)?,
        })
    }

    /// Where `field` streams: its blades carried to a moved origin, its entering tiles made.
    pub fn record(&self, parts: &FrameParts, encoder: &mut wgpu::CommandEncoder, field: &PortableField) {
        let Some(stream) = &field.stream else {
            return;
        };
        let buffer = Bound::Buffer;
        let rebasing = [(FRAME, buffer(parts.frame)), (bindings::BLADES, buffer(&field.blades))];
        let making = [
            (FRAME, buffer(parts.frame)),
            (bindings::BLADES, buffer(&field.blades)),
            (bindings::ETAS, buffer(&field.etas)),
            (bindings::GROUND, buffer(parts.ground)),
            (bindings::TRAMPLE, buffer(parts.trample)),
            (bindings::ACTIVE_TILES, buffer(&stream.entering)),
            (bindings::PAINT, buffer(parts.paint)),
        ];
        let mut dispatches: Vec<Dispatch> = Vec::new();
        if stream.moved {
            let groups = Groups::Direct([TILE_GROUPS, field.tiles_len()]);
            dispatches.push((&self.rebase, &rebasing[..], groups));
        }
        if stream.entered > 0 {
            dispatches.push((&self.make, &making[..], Groups::Direct([TILE_GROUPS, stream.entered])));
        }
        dispatch((parts.device, parts.groups), encoder, &dispatches);
    }
}
