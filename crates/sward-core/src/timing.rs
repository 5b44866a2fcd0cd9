//! What a renderer's GPU passes took in one frame, as both renderers and the Bevy plugin report
//! it (the Vulkan renderer measures it with timestamps around its passes).

/// Per-pass GPU times of one frame, in milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// Drawing the occluders into the depth pyramid and reducing it (occlusion culling).
    pub occluders: f64,
    /// The trample map: the colliders stamped, the grass recovering.
    pub trample: f64,
    /// The physics.
    pub simulate: f64,
    /// Cull and ordering, and on the compute route the blades rasterized and splatted by compute.
    pub cull: f64,
    /// The near cascade of the shadow map: terrain, colliders and the blades near the eye.
    pub shadows: f64,
    /// The draw.
    pub draw: f64,
    /// The viewer's UI.
    pub ui: f64,
}

impl PassTimes {
    /// The whole frame with the UI.
    pub fn total(&self) -> f64 {
        self.frame() + self.ui
    }

    /// The grass frame: occluders, trample map, simulate, cull, blade shadows and draw.
    pub fn frame(&self) -> f64 {
        self.occluders + self.trample + self.simulate + self.cull + self.shadows + self.draw
    }
}
