//! What sward costs a Bevy app, frame by frame, where [`SwardPlugin::timing`](crate::SwardPlugin)
//! is on: the GPU time of sward's passes (its own timestamps, the passes `sward bench` times) and
//! the host time of sward's two systems, the extract from the main world and the grass pass that
//! describes, packs and records the frame. The render world writes; the main world reads.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use bevy::ecs::prelude::*;
use sward_core::timing::PassTimes;

/// Frames kept when nobody takes them: a minute at 60 frames a second.
const KEPT: usize = 3600;

/// One frame of sward's work in the app.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GrassFrameTimes {
    /// Bevy's frame the grass was drawn in (1 for the first frame extracted).
    pub frame: u64,
    /// sward's GPU passes, as last read back (timestamps come back a frame or two later, so
    /// this is an earlier frame's; `None` until the first arrive).
    pub gpu: Option<PassTimes>,
    /// Host time of the extract: the colliders' spheres, the clock, a changed scene.
    pub extract: Duration,
    /// Host time of the grass pass: describing the frame, packing it and recording sward's
    /// passes into Bevy's command buffers (growing and uploading a changed field included),
    /// and any wait for the GPU.
    pub draw: Duration,
    /// Of `draw`, the time spent waiting for the GPU to finish the frame three before (zero
    /// while the GPU keeps up; an app paced by its display rarely waits).
    pub gpu_wait: Duration,
}

impl GrassFrameTimes {
    /// The host's own work sward adds to the frame: the extract and the grass pass, less any
    /// wait for the GPU.
    pub fn host(&self) -> Duration {
        self.extract + self.draw.saturating_sub(self.gpu_wait)
    }
}

/// sward's measures of the frames drawn since they were last taken (the last minute's at most).
/// In both worlds where [`SwardPlugin::timing`](crate::SwardPlugin) is on.
#[derive(Resource, Clone, Default)]
pub struct GrassTimings(Arc<Mutex<VecDeque<GrassFrameTimes>>>);

impl GrassTimings {
    /// The frames measured since the last call, oldest first.
    pub fn take(&self) -> Vec<GrassFrameTimes> {
        self.frames().drain(..).collect()
    }

    /// Keep a frame's measures, forgetting the oldest beyond a minute's.
    pub(crate) fn push(&self, times: GrassFrameTimes) {
        let mut frames = self.frames();
        if frames.len() == KEPT {
            frames.pop_front();
        }
        frames.push_back(times);
    }

    fn frames(&self) -> std::sync::MutexGuard<'_, VecDeque<GrassFrameTimes>> {
        // A panic elsewhere while holding the lock leaves only measures behind: keep going.
        self.0.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}
