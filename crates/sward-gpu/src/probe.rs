//! Measurements of the device itself for the bench: the memory bandwidth a compute shader reaches
//! with the grass passes' access pattern, the yardstick for their bandwidth floor.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::pipelines::{compute_set_layout, compute_wgsl, ComputeOptions};
use crate::shaders::{self, ShaderSet};
use crate::timer::{GpuTimer, Stamp};

/// The fewest timestamp ticks a copy must take for its time to be a measurement rather than
/// the timer's resolution.
const RESOLVED_TICKS: f64 = 100.0;

/// Bytes read plus bytes written per second (GB/s) by `bandwidth.wesl` copying `bytes` bytes,
/// median of 7 runs; `None` where the device's timestamps did not resolve the copy (no
/// reading, or fewer than `RESOLVED_TICKS` ticks).
pub fn shader_bandwidth(ctx: &Arc<Context>, bytes: u64) -> Result<Option<f64>> {
    let d = &ctx.device;
    let elements = bytes / 16;
    let groups = (elements.div_ceil(256) as u32).min(ctx.info.max_workgroups_x);
    let bytes = groups as u64 * 256 * 16;
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let src = Buffer::new(ctx, "bandwidth source", bytes, usage, MemoryLocation::GpuOnly)?;
    let dst = Buffer::new(ctx, "bandwidth destination", bytes, usage, MemoryLocation::GpuOnly)?;
    // Only the two bindings the probe uses: some drivers read every binding of a bound set.
    let set_layout = compute_set_layout(
        d,
        vk::DescriptorType::STORAGE_BUFFER,
        &[1, 2],
        "creating the bandwidth set layout",
    )?;
    let layouts = [set_layout];
    let layout =
        unsafe { d.create_pipeline_layout(&vk::PipelineLayoutCreateInfo::default().set_layouts(&layouts), None) }
            .map_err(vk_check("creating the bandwidth pipeline layout"))?;
    let sizes = [vk::DescriptorPoolSize {
        ty: vk::DescriptorType::STORAGE_BUFFER,
        descriptor_count: 2,
    }];
    let pool = unsafe {
        d.create_descriptor_pool(
            &vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes),
            None,
        )
    }
    .map_err(vk_check("creating the bandwidth descriptor pool"))?;
    let result = (|| {
        let set = unsafe {
            d.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(pool)
                    .set_layouts(&layouts),
            )
        }
        .map_err(vk_check("allocating the bandwidth descriptor set"))?[0];
        let infos = [&src, &dst].map(|b| {
            [vk::DescriptorBufferInfo {
                buffer: b.raw,
                offset: 0,
                range: vk::WHOLE_SIZE,
            }]
        });
        let writes: Vec<_> = infos
            .iter()
            .enumerate()
            .map(|(i, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(1 + i as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        ctx.update_descriptor_sets(&writes);
        let probe = (&ShaderSet::embedded(), &shaders::BANDWIDTH);
        let pipeline = compute_wgsl(ctx, layout, probe, ComputeOptions::default(), &[])?;
        let timed = time_copies(ctx, pipeline, layout, set, groups);
        unsafe { d.destroy_pipeline(pipeline, None) };
        timed
    })();
    unsafe {
        d.destroy_descriptor_pool(pool, None);
        d.destroy_pipeline_layout(layout, None);
        d.destroy_descriptor_set_layout(set_layout, None);
    }
    let seconds = result?;
    let resolved = seconds * 1e9 >= RESOLVED_TICKS * ctx.info.timestamp_period as f64;
    Ok(resolved.then(|| 2.0 * bytes as f64 / seconds / 1e9))
}

/// Median seconds of one copy dispatch (0 where the timer gave no reading).
fn time_copies(
    ctx: &Arc<Context>,
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    set: vk::DescriptorSet,
    groups: u32,
) -> Result<f64> {
    let d = &ctx.device;
    let mut timer = GpuTimer::new(ctx)?;
    let mut seconds = Vec::new();
    for _ in 0..7 {
        ctx.submit_and_wait("measuring shader bandwidth", |cmd| unsafe {
            timer.begin(cmd);
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, 0, &[set], &[]);
            d.cmd_dispatch(cmd, groups, 1, 1);
            for stamp in Stamp::AFTER_START {
                timer.stamp(cmd, stamp);
            }
        })?;
        if let Some(t) = timer.read() {
            seconds.push(t.total() / 1000.0);
        }
    }
    seconds.sort_by(f64::total_cmp);
    Ok(seconds.get(seconds.len() / 2).copied().unwrap_or(0.0))
}
