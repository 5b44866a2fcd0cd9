//! The portable renderer's passes, one module each as the Vulkan renderer's (`sward-gpu`
//! `passes/`), each owning its pipelines and what it binds, and running the same WGSL; the
//! renderer (`renderer.rs`) records them in order:
//!
//! - `stream.rs`: the streamed field's window — its blades carried to a moved origin, the tiles
//!   entering it made;
//! - `trample.rs`: the trample map, stepped before the simulation reads it;
//! - `bezier.rs`: the Bezier field — simulate, then cull into distance buckets;
//! - `depth_pyramid.rs`: the depth pyramid the culls test against (ground, colliders, the
//!   nearest blades, the caller's depth);
//! - `generated.rs`: the instanced blades and the billboards generated each frame around the eye
//!   (patch lists, count, scan, place), and the billboards' painted texture;
//! - `splats.rs`: where the device has 64-bit atomic min/max, the generated grass made by the
//!   Vulkan renderer's passes, its far blades and billboards splatted or rasterized by compute
//!   into the splat target, resolved into the draw;
//! - `draw.rs`: the frame's draw into the caller's target (sky, ground, colliders, blades, the
//!   generated grass, the billboards).
//!
//! A pass records from `FrameParts`: the device, the bind groups made once and the frame's
//! buffers, borrowed from the renderer for one recording. Its group binds the frame's buffer at
//! `FRAME`: the blocks of the frame its pipelines read (`bind.rs`).

pub(crate) mod bezier;
pub(crate) mod depth_pyramid;
pub(crate) mod draw;
pub(crate) mod generated;
pub(crate) mod resolve;
pub(crate) mod shadows;
pub(crate) mod splats;
pub(crate) mod stream;
pub(crate) mod trample;

use crate::BindGroups;

/// Invocations per workgroup of the passes that take a blade each (blade.wesl `WORKGROUP`).
pub(crate) const WORKGROUP: u32 = 64;

/// Workgroups across a tile: a tile's blades, a blade an invocation (blade.wesl `WORKGROUP`).
pub(crate) const TILE_GROUPS: u32 = sward_core::tiles::TILE_BLADES / WORKGROUP;

/// What a frame's passes record with, borrowed from the renderer for one recording: the device
/// and the bind groups made once, the view's uniforms and the scenery's buffers every pass that
/// places grass reads.
pub(crate) struct FrameParts<'a> {
    pub device: &'a wgpu::Device,
    pub groups: &'a BindGroups,
    /// The view's uniforms (the frame's blocks).
    pub frame: &'a wgpu::Buffer,
    /// The ground mesh's vertices.
    pub ground: &'a wgpu::Buffer,
    /// The trample map's texels.
    pub trample: &'a wgpu::Buffer,
    /// The paint maps' texels.
    pub paint: &'a wgpu::Buffer,
}

/// Workgroups across and down for one invocation per blade, at most `max` a dimension: a row of
/// them first, then as many rows as it takes (blade.wesl `blade_index` finds the blade from both).
pub(crate) fn blade_groups(blades: u32, max: u32) -> [u32; 2] {
    let needed = blades.div_ceil(WORKGROUP).max(1);
    let across = needed.min(max.max(1));
    [across, needed.div_ceil(across)]
}

#[cfg(test)]
mod tests {
    use super::blade_groups;

    #[test]
    fn a_big_field_takes_rows_of_workgroups_within_the_limit() {
        assert_eq!(blade_groups(1, 65535), [1, 1]);
        assert_eq!(blade_groups(0, 65535), [1, 1]);
        assert_eq!(blade_groups(64 * 65535, 65535), [65535, 1]);
        let [x, y] = blade_groups(64 * 65535 + 1, 65535);
        assert_eq!([x, y], [65535, 2]);
        assert!(x as u64 * y as u64 * 64 > 64 * 65535);
    }
}
