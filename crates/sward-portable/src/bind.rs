//! What a portable pipeline's group 0 binds: each pipeline with the frame's uniform blocks it
//! reads (`Reading`, found by naga in its WGSL), and its bind groups made once (`BindGroups`)
//! from what a pass hands over — the frame's buffer at `FRAME`, which becomes the blocks the
//! pipeline reads, each at its binding and place in the buffer (sward-core `declared::BLOCKS`).

use std::num::NonZeroU64;
use std::ops::Deref;

use sward_core::declared::{self, bindings};

use crate::PortableError;

/// Where a pass hands over the frame's buffer: not a binding of its own, but each of the
/// frame's blocks the pipeline reads, at its binding.
pub(crate) const FRAME: u32 = u32::MAX;

/// A pipeline and the frame's uniform blocks its entry points read (their bindings): a
/// pipeline's group 0 is laid out from its WGSL, so it binds those blocks and no others.
#[derive(Clone)]
pub(crate) struct Reading<P> {
    pipeline: P,
    blocks: Vec<u32>,
    /// Every binding of group 0 its entry points use: what its group is laid out with.
    used: Vec<u32>,
}

impl<P> Reading<P> {
    /// `pipeline`, whose entry points `entries` of WGSL `text` read the frame's blocks they
    /// name.
    pub fn new(pipeline: P, text: &str, entries: &[&str]) -> Result<Reading<P>, PortableError> {
        let used = bindings_used(text, entries)?;
        Ok(Reading {
            pipeline,
            blocks: used
                .iter()
                .copied()
                .filter(|b| bindings::FRAME_BLOCKS.contains(b))
                .collect(),
            used,
        })
    }
}

impl<P> Reading<P> {
    /// Every binding of group 0 its entry points use (what a group laid out by hand holds).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn bindings_used(&self) -> &[u32] {
        &self.used
    }
}

impl<P> Deref for Reading<P> {
    type Target = P;

    fn deref(&self) -> &P {
        &self.pipeline
    }
}

/// The frame's blocks that entry points `entries` of `text` read, as naga sees them (the same
/// analysis wgpu lays a pipeline's group out by).
pub(crate) fn blocks_read(text: &str, entries: &[&str]) -> Result<Vec<u32>, PortableError> {
    let used = bindings_used(text, entries)?;
    Ok(used
        .into_iter()
        .filter(|b| bindings::FRAME_BLOCKS.contains(b))
        .collect())
}

/// The ids of the overrides `text` declares (`@id(n) override`).
pub(crate) fn overrides_declared(text: &str) -> Result<Vec<u32>, PortableError> {
    let module = naga::front::wgsl::parse_str(text).map_err(|e| PortableError::Shader {
        pipeline: "a pipeline's overrides",
        message: e.message().to_string(),
    })?;
    Ok(module
        .overrides
        .iter()
        .filter_map(|(_, o)| o.id.map(u32::from))
        .collect())
}

/// Every binding that entry points `entries` of `text` use, as naga sees them.
fn bindings_used(text: &str, entries: &[&str]) -> Result<Vec<u32>, PortableError> {
    use naga::valid::{Capabilities, ValidationFlags, Validator};
    let failed = |message: String| PortableError::Shader {
        pipeline: "a pipeline's bindings",
        message,
    };
    let module = naga::front::wgsl::parse_str(text).map_err(|e| failed(e.message().to_string()))?;
    let info = Validator::new(ValidationFlags::empty(), Capabilities::all())
        .validate(&module)
        .map_err(|e| failed(e.as_inner().to_string()))?;
    let mut used = Vec::new();
    for (index, entry) in module.entry_points.iter().enumerate() {
        if !entries.contains(&entry.name.as_str()) {
            continue;
        }
        let uses = info.get_entry_point(index);
        for (handle, global) in module.global_variables.iter() {
            let Some(binding) = &global.binding else { continue };
            if !uses[handle].is_empty() && !used.contains(&binding.binding) {
                used.push(binding.binding);
            }
        }
    }
    Ok(used)
}

/// What a binding of a portable pipeline's group 0 holds.
#[derive(Clone, Copy)]
pub(crate) enum Bound<'a> {
    Buffer(&'a wgpu::Buffer),
    View(&'a wgpu::TextureView),
    Sampler(&'a wgpu::Sampler),
}

/// A pipeline whose group 0 a bind group is made for.
#[derive(Clone, Copy)]
pub(crate) enum Bindable<'a> {
    Compute(&'a Reading<wgpu::ComputePipeline>),
    Render(&'a Reading<wgpu::RenderPipeline>),
}

impl Bindable<'_> {
    /// The frame's blocks the pipeline reads.
    fn blocks(&self) -> &[u32] {
        match self {
            Bindable::Compute(p) => &p.blocks,
            Bindable::Render(p) => &p.blocks,
        }
    }

    /// Every binding its group is laid out with.
    fn used(&self) -> &[u32] {
        match self {
            Bindable::Compute(p) => &p.used,
            Bindable::Render(p) => &p.used,
        }
    }
}

/// A bind group by what it was made of: the pipeline and what each binding holds.
#[derive(Clone, PartialEq, Eq, Hash)]
enum MadeOf {
    Compute(wgpu::ComputePipeline, Vec<(u32, BoundKey)>),
    Render(wgpu::RenderPipeline, Vec<(u32, BoundKey)>),
}

#[derive(Clone, PartialEq, Eq, Hash)]
enum BoundKey {
    Buffer(wgpu::Buffer),
    View(wgpu::TextureView),
    Sampler(wgpu::Sampler),
}

/// Bind groups already made: a frame's passes bind the same buffers frame after frame, and
/// making a bind group is host work an engine's frame pays (its pipelines' layouts are their
/// own, so a group is made for each pipeline). Forgotten when there are more than a few frames'
/// worth (after the field or a view changed), so that they hold no dropped buffer for long.
#[derive(Default)]
pub(crate) struct BindGroups(std::sync::Mutex<std::collections::HashMap<MadeOf, wgpu::BindGroup>>);

/// Bind groups kept at most: the passes of every view, with room for a change of field.
const BIND_GROUPS_KEPT: usize = 256;

impl BindGroups {
    /// The group 0 of `pipeline` with those of `resources` it uses at their bindings (the
    /// frame's buffer at `FRAME`: the blocks the pipeline reads), made once. A pass may hand
    /// over more than a pipeline of it uses (the draws the shadow map, which a pipeline composed
    /// without shadows does not read).
    pub fn of(&self, device: &wgpu::Device, pipeline: Bindable, resources: &[(u32, Bound)]) -> wgpu::BindGroup {
        let resources: Vec<(u32, Bound)> = resources
            .iter()
            .copied()
            .filter(|(binding, _)| *binding == FRAME || pipeline.used().contains(binding))
            .collect();
        let resources = &resources[..];
        let keys = resources
            .iter()
            .map(|&(binding, bound)| {
                let key = match bound {
                    Bound::Buffer(b) => BoundKey::Buffer(b.clone()),
                    Bound::View(v) => BoundKey::View(v.clone()),
                    Bound::Sampler(v) => BoundKey::Sampler(v.clone()),
                };
                (binding, key)
            })
            .collect();
        let made_of = match pipeline {
            Bindable::Compute(p) => MadeOf::Compute((**p).clone(), keys),
            Bindable::Render(p) => MadeOf::Render((**p).clone(), keys),
        };
        let mut made = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(group) = made.get(&made_of) {
            return group.clone();
        }
        if made.len() >= BIND_GROUPS_KEPT {
            made.clear();
        }
        let entries = entries(pipeline.blocks(), resources);
        let layout = match pipeline {
            Bindable::Compute(p) => p.get_bind_group_layout(0),
            Bindable::Render(p) => p.get_bind_group_layout(0),
        };
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &entries,
        });
        made.insert(made_of, group.clone());
        group
    }

    /// Forget every group (the buffers they bind are let go).
    pub fn forget(&self) {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).clear();
    }
}

/// The entries of a group of a pipeline that reads the frame's `blocks`: `resources` at their
/// bindings, the frame's buffer (at `FRAME`) as each of those blocks.
fn entries<'a>(blocks: &[u32], resources: &[(u32, Bound<'a>)]) -> Vec<wgpu::BindGroupEntry<'a>> {
    let mut entries = Vec::new();
    for &(binding, bound) in resources {
        match (binding, bound) {
            (FRAME, Bound::Buffer(buffer)) => {
                entries.extend(declared::frame_blocks().filter(|(b, ..)| blocks.contains(b)).map(
                    |(binding, offset, size)| wgpu::BindGroupEntry {
                        binding,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer,
                            offset,
                            size: NonZeroU64::new(size),
                        }),
                    },
                ))
            }
            (binding, Bound::Buffer(b)) => entries.push(wgpu::BindGroupEntry {
                binding,
                resource: b.as_entire_binding(),
            }),
            (binding, Bound::View(v)) => entries.push(wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(v),
            }),
            (binding, Bound::Sampler(s)) => entries.push(wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::Sampler(s),
            }),
        }
    }
    entries
}

#[cfg(test)]
mod tests {
    use sward_core::declared::{bindings, BLOCKS};

    /// Each pipeline binds the frame's blocks its text reads and no others: every block naga
    /// finds read is named in the text (`var.member`), and the passes that read one subject bind
    /// that block alone (the generated grass's scans their grids, the cull's lay-out its culling
    /// block; the cull's scan none).
    #[test]
    fn each_pipeline_binds_the_blocks_it_reads() {
        for pipeline in crate::PIPELINES {
            let reads = crate::frame_blocks_read(pipeline).unwrap_or_else(|e| panic!("{e}"));
            let text = pipeline.text().unwrap_or_else(|e| panic!("{e}"));
            for block in BLOCKS.iter().filter(|b| reads.contains(&b.binding)) {
                let named = text.contains(&format!("{}.", block.var));
                assert!(named, "{}: binds {} without reading it", pipeline.name, block.var);
            }
            let only: Option<&[u32]> = match pipeline.name {
                "scan_generated" | "scan_billboards" => Some(&[bindings::GRIDS]),
                "lay_out_buckets" | "lay_out_buckets_narrow" => Some(&[bindings::CULLING]),
                "scan_buckets" | "scan_buckets_subgroups" => Some(&[]),
                _ => None,
            };
            if let Some(blocks) = only {
                assert_eq!(reads, blocks, "{}", pipeline.name);
            }
        }
    }
}
