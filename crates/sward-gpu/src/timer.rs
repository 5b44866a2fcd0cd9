//! GPU timestamps around the passes of a frame. Written while recording, read after that frame's
//! fence has signalled (never waiting on the GPU), converted with `timestampPeriod` and masked to
//! the queue's valid bits.

use std::sync::Arc;

use ash::vk;

use crate::context::Context;
use crate::error::{vk_check, Result};

/// The points of a frame that get a timestamp, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Stamp {
    /// Before anything.
    Start = 0,
    /// After the depth pyramid of the occluders (nothing when occlusion culling is off).
    Occluded = 1,
    /// After the trample map's frame (nothing without generated grass to trample).
    Trampled = 2,
    /// After the physics.
    Simulated = 3,
    /// After the cull and the ordering of the visible lists (Bezier and generated grass).
    Ordered = 4,
    /// After the blades' shadows in the near cascade (nothing without blade shadows).
    Shadowed = 5,
    /// After the compute passes that draw blades (the compute route's rasterizer and splats).
    Culled = 6,
    /// After the draw.
    Drawn = 7,
    /// After the viewer's UI.
    Ui = 8,
}

/// Timestamps per frame.
pub const STAMPS: u32 = 9;

impl Stamp {
    /// Every stamp after `Start`, in order: a measurement that times one thing writes them all
    /// back to back (a query never written leaves the pool's results unavailable, and the
    /// whole reading lost).
    pub const AFTER_START: [Stamp; STAMPS as usize - 1] = [
        Stamp::Occluded,
        Stamp::Trampled,
        Stamp::Simulated,
        Stamp::Ordered,
        Stamp::Shadowed,
        Stamp::Culled,
        Stamp::Drawn,
        Stamp::Ui,
    ];
}

pub use sward_core::timing::PassTimes;

/// Timestamps of each frame's passes, read back a frame later.
pub struct GpuTimer {
    pool: vk::QueryPool,
    period_ns: f64,
    valid_mask: u64,
    /// Whether the commands that write the stamps were submitted since the last reset.
    pending: bool,
    id: u64,
    ctx: Arc<Context>,
}

/// Timers made so far.
static TIMERS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

impl GpuTimer {
    /// A timer with its query pool.
    pub fn new(ctx: &Arc<Context>) -> Result<GpuTimer> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(STAMPS);
        let pool = unsafe { ctx.device.create_query_pool(&info, None) }.map_err(vk_check("creating a query pool"))?;
        let families = unsafe {
            ctx.instance
                .get_physical_device_queue_family_properties(ctx.physical_device)
        };
        let bits = families[ctx.queue_family as usize].timestamp_valid_bits;
        let valid_mask = if bits >= 64 { u64::MAX } else { (1u64 << bits) - 1 };
        Ok(GpuTimer {
            pool,
            period_ns: ctx.info.timestamp_period as f64,
            valid_mask,
            pending: false,
            id: TIMERS.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            ctx: ctx.clone(),
        })
    }

    /// This timer among every timer made so far (a query pool's handle may be reused once it
    /// is destroyed; this number is not).
    pub fn id(&self) -> u64 {
        self.id
    }

    /// Start a frame's stamps (records a reset of the pool).
    pub fn begin(&mut self, cmd: vk::CommandBuffer) {
        unsafe { self.ctx.device.cmd_reset_query_pool(cmd, self.pool, 0, STAMPS) };
        self.pending = true;
        self.stamp(cmd, Stamp::Start);
    }

    /// Write `stamp` once all earlier commands have finished.
    pub fn stamp(&self, cmd: vk::CommandBuffer, stamp: Stamp) {
        let stage = vk::PipelineStageFlags2::ALL_COMMANDS;
        unsafe {
            self.ctx
                .device
                .cmd_write_timestamp2(cmd, stage, self.pool, stamp as u32)
        };
    }

    /// The pass times of the last frame recorded, once its fence has signalled; `None` before any
    /// frame or if the results are not there yet.
    pub fn read(&self) -> Option<PassTimes> {
        if !self.pending {
            return None;
        }
        let mut ticks = [0u64; STAMPS as usize];
        let flags = vk::QueryResultFlags::TYPE_64;
        unsafe { self.ctx.device.get_query_pool_results(self.pool, 0, &mut ticks, flags) }.ok()?;
        let ms = |a: Stamp, b: Stamp| {
            let delta = (ticks[b as usize] & self.valid_mask).wrapping_sub(ticks[a as usize] & self.valid_mask)
                & self.valid_mask;
            delta as f64 * self.period_ns * 1e-6
        };
        Some(PassTimes {
            occluders: ms(Stamp::Start, Stamp::Occluded),
            trample: ms(Stamp::Occluded, Stamp::Trampled),
            simulate: ms(Stamp::Trampled, Stamp::Simulated),
            cull: ms(Stamp::Simulated, Stamp::Ordered) + ms(Stamp::Shadowed, Stamp::Culled),
            shadows: ms(Stamp::Ordered, Stamp::Shadowed),
            draw: ms(Stamp::Culled, Stamp::Drawn),
            ui: ms(Stamp::Drawn, Stamp::Ui),
        })
    }
}

/// What the GPU counted while drawing a frame: how much geometry the tessellator made and how many
/// pixels were shaded. Shows whether a frame is bound by rasterisation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DrawCounts {
    /// Tessellation evaluation invocations (blade vertices made).
    pub tessellated_vertices: u64,
    /// Primitives reaching the clipper (blade triangles, plus sky and ground).
    pub primitives: u64,
    /// Fragment shader invocations (shaded pixels; one per pixel per primitive with MSAA).
    pub fragments: u64,
}

/// A pipeline-statistics query around a frame, read after its fence like the timestamps.
pub struct DrawCounter {
    pool: vk::QueryPool,
    pending: bool,
    ctx: Arc<Context>,
}

const COUNTED: vk::QueryPipelineStatisticFlags = vk::QueryPipelineStatisticFlags::from_raw(
    vk::QueryPipelineStatisticFlags::TESSELLATION_EVALUATION_SHADER_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES.as_raw()
        | vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS.as_raw(),
);

impl DrawCounter {
    /// `None` where the device has no pipeline statistics.
    pub fn new(ctx: &Arc<Context>) -> Result<Option<DrawCounter>> {
        if !ctx.info.pipeline_statistics {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .query_count(1)
            .pipeline_statistics(COUNTED);
        let pool = unsafe { ctx.device.create_query_pool(&info, None) }.map_err(vk_check("creating a query pool"))?;
        Ok(Some(DrawCounter {
            pool,
            pending: false,
            ctx: ctx.clone(),
        }))
    }

    /// Reset the query and start counting the frame's primitives and fragments.
    pub fn begin(&mut self, cmd: vk::CommandBuffer) {
        unsafe {
            self.ctx.device.cmd_reset_query_pool(cmd, self.pool, 0, 1);
            self.ctx
                .device
                .cmd_begin_query(cmd, self.pool, 0, vk::QueryControlFlags::empty());
        }
        self.pending = true;
    }

    /// Stop counting.
    pub fn end(&self, cmd: vk::CommandBuffer) {
        unsafe { self.ctx.device.cmd_end_query(cmd, self.pool, 0) };
    }

    /// Counters are returned in flag-bit order: tessellation evaluation (bit 10) comes after
    /// clipping primitives (bit 6) and fragment invocations (bit 7).
    pub fn read(&self) -> Option<DrawCounts> {
        if !self.pending {
            return None;
        }
        // One query of three counters: ash counts queries by elements, so the element is [u64; 3].
        let mut results = [[0u64; 3]];
        let flags = vk::QueryResultFlags::TYPE_64;
        unsafe {
            self.ctx
                .device
                .get_query_pool_results(self.pool, 0, &mut results, flags)
        }
        .ok()?;
        let values = results[0];
        Some(DrawCounts {
            primitives: values[0],
            fragments: values[1],
            tessellated_vertices: values[2],
        })
    }
}

impl Drop for DrawCounter {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_query_pool(self.pool, None) };
    }
}

impl Drop for GpuTimer {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_query_pool(self.pool, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A measurement that writes `Stamp::AFTER_START` writes every query of the pool once: a
    /// stamp added to the frame and left out of the list would leave its query unwritten and
    /// the whole reading unavailable on some drivers (the bandwidth probe's NaN on the H100).
    #[test]
    fn after_start_holds_every_stamp_but_the_first_once_in_order() {
        let ids: Vec<u32> = Stamp::AFTER_START.iter().map(|&s| s as u32).collect();
        assert_eq!(ids, (1..STAMPS).collect::<Vec<u32>>());
        assert_eq!(Stamp::Start as u32, 0);
    }
}
