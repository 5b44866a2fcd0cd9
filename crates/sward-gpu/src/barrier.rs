//! Barriers written as "what came before → what comes next" (synchronization2). The grass frame
//! is: transfer (counter reset) → compute (simulate) → compute (cull) → indirect + vertex /
//! tessellation reads (draw).

use ash::vk;

/// One access: the stages that perform it and how they touch memory.
#[derive(Clone, Copy, Debug)]
pub struct Access {
    /// The pipeline stages that touch the memory.
    pub stages: vk::PipelineStageFlags2,
    /// How they touch it.
    pub access: vk::AccessFlags2,
}

impl Access {
    /// A copy or fill writes.
    pub const TRANSFER_WRITE: Access = Access {
        stages: vk::PipelineStageFlags2::TRANSFER,
        access: vk::AccessFlags2::TRANSFER_WRITE,
    };
    /// A copy reads.
    pub const TRANSFER_READ: Access = Access {
        stages: vk::PipelineStageFlags2::TRANSFER,
        access: vk::AccessFlags2::TRANSFER_READ,
    };
    /// Compute shaders read and write storage buffers.
    pub const COMPUTE_READ_WRITE: Access = Access {
        stages: vk::PipelineStageFlags2::COMPUTE_SHADER,
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_READ.as_raw() | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
        ),
    };
    /// A compute pass dispatched indirectly: its dispatch size, then its storage reads and writes.
    pub const INDIRECT_COMPUTE_READ: Access = Access {
        stages: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::DRAW_INDIRECT.as_raw() | vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw(),
        ),
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::INDIRECT_COMMAND_READ.as_raw()
                | vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
                | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
        ),
    };
    /// What the draw pass reads: the indirect commands and, in the vertex and tessellation
    /// stages, the visible list and the blades.
    pub const DRAW_READ: Access = Access {
        stages: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::DRAW_INDIRECT.as_raw()
                | vk::PipelineStageFlags2::VERTEX_SHADER.as_raw()
                | vk::PipelineStageFlags2::TESSELLATION_CONTROL_SHADER.as_raw()
                | vk::PipelineStageFlags2::TESSELLATION_EVALUATION_SHADER.as_raw()
                | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw(),
        ),
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::INDIRECT_COMMAND_READ.as_raw() | vk::AccessFlags2::SHADER_STORAGE_READ.as_raw(),
        ),
    };
    /// Colour attachments are written (and read, for blending).
    pub const COLOR_ATTACHMENT: Access = Access {
        stages: vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE.as_raw() | vk::AccessFlags2::COLOR_ATTACHMENT_READ.as_raw(),
        ),
    };
    /// Depth testing reads and writes the depth attachment.
    pub const DEPTH_ATTACHMENT: Access = Access {
        stages: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
        ),
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw()
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw(),
        ),
    };
    /// Shaders sampling an image: the cull pass (depth pyramid), fragment shading (shadow map).
    pub const SAMPLED_READ: Access = Access {
        stages: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw() | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw(),
        ),
        access: vk::AccessFlags2::SHADER_SAMPLED_READ,
    };
    /// Nothing to wait for (fresh contents).
    pub const NOTHING: Access = Access {
        stages: vk::PipelineStageFlags2::TOP_OF_PIPE,
        access: vk::AccessFlags2::NONE,
    };
    /// Presentation reads through a semaphore; nothing to wait for in the pipeline.
    pub const PRESENT: Access = Access {
        stages: vk::PipelineStageFlags2::BOTTOM_OF_PIPE,
        access: vk::AccessFlags2::NONE,
    };
    /// The host reads mapped memory.
    pub const HOST_READ: Access = Access {
        stages: vk::PipelineStageFlags2::HOST,
        access: vk::AccessFlags2::HOST_READ,
    };
}

/// A global memory barrier from `before` to `after`.
pub fn memory(device: &ash::Device, cmd: vk::CommandBuffer, before: Access, after: Access) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(before.stages)
        .src_access_mask(before.access)
        .dst_stage_mask(after.stages)
        .dst_access_mask(after.access)];
    let dependency = vk::DependencyInfo::default().memory_barriers(&barrier);
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
}

/// A layout transition of a whole image (every mip level).
#[allow(clippy::too_many_arguments)]
pub fn image(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    (old_layout, before): (vk::ImageLayout, Access),
    (new_layout, after): (vk::ImageLayout, Access),
) {
    let barrier = [vk::ImageMemoryBarrier2::default()
        .src_stage_mask(before.stages)
        .src_access_mask(before.access)
        .dst_stage_mask(after.stages)
        .dst_access_mask(after.access)
        .old_layout(old_layout)
        .new_layout(new_layout)
        .image(image)
        .subresource_range(vk::ImageSubresourceRange {
            level_count: vk::REMAINING_MIP_LEVELS,
            ..crate::image::subresource_range(aspect)
        })];
    let dependency = vk::DependencyInfo::default().image_memory_barriers(&barrier);
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
}
