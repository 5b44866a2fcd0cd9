//! The bit flags the shaders read from `FrameUniforms`, named once here and once in
//! `shaders/common.glsl` (the layout test compares the two lists). Each word of flags has one
//! home: `counts.w` the forces, `modes.x` the culling tests, `modes.w` how the frame is drawn.

/// `counts.w`: the restoring force toward the rest pose (SPEC §3.2).
pub const FORCE_RECOVERY: u32 = 1 << 0;
/// `counts.w`: environmental and front gravity (SPEC §3.3).
pub const FORCE_GRAVITY: u32 = 1 << 1;
/// `counts.w`: the summed wind fields (SPEC §3.4).
pub const FORCE_WIND: u32 = 1 << 2;
/// `counts.w`: sphere collisions (SPEC §3.7).
pub const FORCE_COLLISIONS: u32 = 1 << 3;

/// `modes.x`: blades seen edge-on are culled (SPEC §4).
pub const CULL_ORIENTATION: u32 = 1 << 0;
/// `modes.x`: blades outside the view frustum are culled.
pub const CULL_FRUSTUM: u32 = 1 << 1;
/// `modes.x`: far blades are thinned by their id.
pub const CULL_DISTANCE: u32 = 1 << 2;
/// `modes.x`: whole tiles outside the view are skipped (host side: the active tile list).
pub const CULL_TILES: u32 = 1 << 3;
/// `modes.x`: blades hidden behind the occluders' depth pyramid are culled.
pub const CULL_OCCLUSION: u32 = 1 << 4;

/// `modes.w`: the sun's shadow map darkens what it hides.
pub const DRAW_SHADOWS: u32 = 1 << 0;
/// `modes.w`: the blades near the eye cast shadows too, into the sun's near cascade (the view-
/// fitted half of the shadow map).
pub const DRAW_BLADE_SHADOWS: u32 = 1 << 1;

/// Every flag with its name, as `common.glsl` spells it.
pub const ALL: [(&str, u32); 11] = [
    ("FORCE_RECOVERY", FORCE_RECOVERY),
    ("FORCE_GRAVITY", FORCE_GRAVITY),
    ("FORCE_WIND", FORCE_WIND),
    ("FORCE_COLLISIONS", FORCE_COLLISIONS),
    ("CULL_ORIENTATION", CULL_ORIENTATION),
    ("CULL_FRUSTUM", CULL_FRUSTUM),
    ("CULL_DISTANCE", CULL_DISTANCE),
    ("CULL_TILES", CULL_TILES),
    ("CULL_OCCLUSION", CULL_OCCLUSION),
    ("DRAW_SHADOWS", DRAW_SHADOWS),
    ("DRAW_BLADE_SHADOWS", DRAW_BLADE_SHADOWS),
];

/// `flag` if `on`, else nothing.
pub const fn when(on: bool, flag: u32) -> u32 {
    if on {
        flag
    } else {
        0
    }
}
