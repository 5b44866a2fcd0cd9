//! The bit flags and the codes the shaders read from `FrameUniforms`, named once here and written
//! into the shaders from `declared.rs`. Each word of flags has one
//! home: `counts.w` the forces, `modes.x` the culling tests, `modes.w` how the frame is drawn;
//! each code says which of a kind a number stands for (the technique, a wind field's kind, the
//! blade's silhouette, the lighting model, the ground's shape, whose eyes a pipeline draws
//! through).

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

/// `modes.w`: the Bezier blades have a ridge down the middle (`blades.ridge`).
pub const DRAW_BLADE_RIDGE: u32 = 1 << 2;

/// `instanced_meta.y`: the technique (`Technique::index`).
pub const TECHNIQUE_BEZIER: u32 = 0;
/// The instanced grass alone.
pub const TECHNIQUE_INSTANCED: u32 = 1;
/// Bezier blades near the eye, the instanced grass beyond.
pub const TECHNIQUE_BOTH: u32 = 2;
/// Billboards alone.
pub const TECHNIQUE_BILLBOARD: u32 = 3;
/// The whole chain: Bezier, instanced, billboards, the tinted ground.
pub const TECHNIQUE_LANDSCAPE: u32 = 4;

/// `winds[3k + 2].w`: a wind field's kind (`WindKind::code`).
pub const WIND_NONE: u32 = 0;
/// Waves.
pub const WIND_WAVES: u32 = 1;
/// Value noise drifting along the direction.
pub const WIND_NOISE: u32 = 2;
/// The analytic field.
pub const WIND_ANALYTIC: u32 = 3;
/// Outward from a centre.
pub const WIND_RADIAL: u32 = 4;
/// Around a centre.
pub const WIND_WHIRL: u32 = 5;

/// `blade_style.x`: the Bezier blade's silhouette (`BladeShape::code`).
pub const BLADE_QUAD: u32 = 0;
/// Narrowing linearly to a point.
pub const BLADE_TRIANGLE: u32 = 1;
/// Narrowing along a parabola.
pub const BLADE_QUADRATIC: u32 = 2;
/// Full width, then a triangular tip.
pub const BLADE_TRIANGLE_TIP: u32 = 3;

/// `shading_model.x`: diffuse only (`ShadingModel::code`).
pub const SHADING_LAMBERT: u32 = 0;
/// Diffuse and a specular highlight.
pub const SHADING_BLINN_PHONG: u32 = 1;

/// `instanced_ground_cells.z`: the plane y = 0 (`GroundShape::code`).
pub const GROUND_PLANE: u32 = 0;
/// A sphere (`surface`: centre and radius).
pub const GROUND_SPHERE: u32 = 1;
/// The uploaded ground mesh.
pub const GROUND_MESH: u32 = 2;

/// The `VIEW` specialisation constant: the camera.
pub const VIEW_CAMERA: u32 = 0;
/// The sun over the whole field (the shadow map's field cascade).
pub const VIEW_SUN_FIELD: u32 = 1;
/// The sun over the ball around the eye (the shadow map's near cascade).
pub const VIEW_SUN_NEAR: u32 = 2;
/// The camera, drawing blades as occluders into the depth pyramid.
pub const VIEW_OCCLUDERS: u32 = 3;

/// Every flag with its name, as the shaders spell it.
pub const ALL: [(&str, u32); 12] = [
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
    ("DRAW_BLADE_RIDGE", DRAW_BLADE_RIDGE),
];

/// Every code with its name, as the shaders spell it.
pub const CODES: [(&str, u32); 24] = [
    ("TECHNIQUE_BEZIER", TECHNIQUE_BEZIER),
    ("TECHNIQUE_INSTANCED", TECHNIQUE_INSTANCED),
    ("TECHNIQUE_BOTH", TECHNIQUE_BOTH),
    ("TECHNIQUE_BILLBOARD", TECHNIQUE_BILLBOARD),
    ("TECHNIQUE_LANDSCAPE", TECHNIQUE_LANDSCAPE),
    ("WIND_NONE", WIND_NONE),
    ("WIND_WAVES", WIND_WAVES),
    ("WIND_NOISE", WIND_NOISE),
    ("WIND_ANALYTIC", WIND_ANALYTIC),
    ("WIND_RADIAL", WIND_RADIAL),
    ("WIND_WHIRL", WIND_WHIRL),
    ("BLADE_QUAD", BLADE_QUAD),
    ("BLADE_TRIANGLE", BLADE_TRIANGLE),
    ("BLADE_QUADRATIC", BLADE_QUADRATIC),
    ("BLADE_TRIANGLE_TIP", BLADE_TRIANGLE_TIP),
    ("SHADING_LAMBERT", SHADING_LAMBERT),
    ("SHADING_BLINN_PHONG", SHADING_BLINN_PHONG),
    ("GROUND_PLANE", GROUND_PLANE),
    ("GROUND_SPHERE", GROUND_SPHERE),
    ("GROUND_MESH", GROUND_MESH),
    ("VIEW_CAMERA", VIEW_CAMERA),
    ("VIEW_SUN_FIELD", VIEW_SUN_FIELD),
    ("VIEW_SUN_NEAR", VIEW_SUN_NEAR),
    ("VIEW_OCCLUDERS", VIEW_OCCLUDERS),
];

/// `flag` if `on`, else nothing.
pub const fn when(on: bool, flag: u32) -> u32 {
    if on {
        flag
    } else {
        0
    }
}
