//! The portable simulation pass: simulate.wgsl over a field, its frame's uniforms packed by
//! sward-core from the frame's description (`FrameUniforms::pack`), recorded into the caller's
//! encoder.

use sward_core::gpu::{FramePlan, FrameUniforms};
use sward_core::FrameDesc;

use super::field::PortableField;
use super::shaders::{PipelineSource, SIMULATE_SOURCE};
use super::{ready, PortableError};

/// Invocations per workgroup (simulate.wgsl's `WORKGROUP`).
const WORKGROUP: u32 = 64;

/// The simulation's pipeline and the frame's uniform buffer.
pub struct PortableSimulation {
    pipeline: wgpu::ComputePipeline,
    frame: wgpu::Buffer,
    max_groups: u32,
}

impl PortableSimulation {
    /// The pipeline on `device`, or why this device cannot run it.
    pub fn new(adapter: &wgpu::Adapter, device: &wgpu::Device) -> Result<PortableSimulation, PortableError> {
        let info = adapter.get_info();
        if !adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
        {
            return Err(PortableError::NoCompute(format!("{:?} ({})", info.backend, info.name)));
        }
        let pipeline = compute_pipeline(device, &SIMULATE_SOURCE)?;
        let frame = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward frame"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let max_groups = device.limits().max_compute_workgroups_per_dimension;
        Ok(PortableSimulation {
            pipeline,
            frame,
            max_groups,
        })
    }

    /// Write the frame `desc` describes (its `steps` fixed steps from its time) for `field`, and
    /// record its simulation into `encoder`.
    pub fn record(
        &self,
        queue: &wgpu::Queue,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        desc: &FrameDesc,
        field: &PortableField,
    ) {
        let plan = FramePlan {
            blade_count: field.count(),
            ..FramePlan::default()
        };
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&FrameUniforms::pack(desc, &plan)));
        if field.count() == 0 || desc.steps == 0 {
            return;
        }
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward simulate"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[entry(0, &self.frame), entry(1, &field.blades), entry(2, &field.etas)],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sward simulate"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        let [x, y] = groups(field.count(), self.max_groups);
        pass.dispatch_workgroups(x, y, 1);
    }
}

/// Workgroups across and down for `blades` invocations, at most `max` a dimension: a row of
/// them first, then as many rows as it takes (simulate.wgsl finds the blade from both).
fn groups(blades: u32, max: u32) -> [u32; 2] {
    let needed = blades.div_ceil(WORKGROUP);
    let across = needed.min(max.max(1));
    [across, needed.div_ceil(across)]
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// A compute pipeline from `source`, its compile errors caught (not left to the device's
/// uncaptured-error handler, which panics) and said in one sentence.
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    source: &PipelineSource,
) -> Result<wgpu::ComputePipeline, PortableError> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(source.name),
        source: wgpu::ShaderSource::Wgsl(source.text().into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(source.name),
        layout: None,
        module: &module,
        entry_point: Some(source.entry),
        compilation_options: Default::default(),
        cache: None,
    });
    match ready(scope.pop()).flatten() {
        None => Ok(pipeline),
        Some(error) => Err(PortableError::Shader {
            pipeline: source.name,
            message: one_line(&error.to_string()),
        }),
    }
}

/// A many-line message on one line, for a one-sentence error.
fn one_line(message: &str) -> String {
    message.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_big_field_takes_rows_of_workgroups_within_the_limit() {
        assert_eq!(groups(1, 65535), [1, 1]);
        assert_eq!(groups(64 * 65535, 65535), [65535, 1]);
        let [x, y] = groups(64 * 65535 + 1, 65535);
        assert_eq!([x, y], [65535, 2]);
        assert!(x as u64 * y as u64 * 64 > 64 * 65535);
    }
}
