// A Bezier blade in WGSL for the portable renderer (sward-core blade.rs): its layout, its
// frame, its state validation, the frame point's world point, and the hash every pass draws
// numbers from. Needs frame.wgsl.

// How the frame is drawn (`modes.w`; sward-core flags.rs).
const DRAW_SHADOWS: u32 = 1u;
const DRAW_BLADE_SHADOWS: u32 = 2u;
const DRAW_BLADE_RIDGE: u32 = 4u;

// A Bezier blade (sward-core blade.rs, named as its v0, v1, v2): root and w its orientation,
// guide and w its height, tip and w its half-width, up its up vector and w its stiffness. (No
// name of an engine's shader library ends in a digit: naga_oil's rule for composable modules.)
struct Blade {
    root: vec4<f32>,
    guide: vec4<f32>,
    tip: vec4<f32>,
    up: vec4<f32>,
}

fn hash_word(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let len = length(v);
    if (len > 0.0) {
        return v / len;
    }
    return vec3<f32>(0.0);
}

// The world point of frame point `p` (the frame is held around a moving origin where the field
// streams).
fn world_point(p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(p.x + frame.origin.x, p.y, p.z + frame.origin.y);
}

// The world ground point of frame ground point `xz`, and back.
fn world_xz(xz: vec2<f32>) -> vec2<f32> {
    return xz + frame.origin.xy;
}

fn frame_xz(xz: vec2<f32>) -> vec2<f32> {
    return xz - frame.origin.xy;
}

// Where an engine's world has frame point `p`, this frame and the last (`FrameUniforms::placed`:
// the field's own space turned, scaled and moved; the identity in sward's own passes), a
// direction there, and a length there.
fn placed_point(p: vec3<f32>) -> vec3<f32> {
    return (frame.placed * vec4<f32>(world_point(p), 1.0)).xyz;
}

fn placed_before_point(p: vec3<f32>) -> vec3<f32> {
    return (frame.placed_before * vec4<f32>(world_point(p), 1.0)).xyz;
}

fn placed_normal(n: vec3<f32>) -> vec3<f32> {
    return normalize((frame.placed * vec4<f32>(n, 0.0)).xyz);
}

fn placed_length(d: f32) -> f32 {
    return d * length(frame.placed[0].xyz);
}

// A point of sward's clip space (the frame's matrices: y down, as Vulkan's) in wgpu's (y up):
// what the vertex stages write.
fn target_clip(clip: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(clip.x, -clip.y, clip.z, clip.w);
}

// ---------------------------------------------------------------- blade frame (blade.rs)

// The blade's width direction for orientation `orientation` about `up`: the surface's tangent
// frame (a branchless orthonormal basis of `up`) turned by it.
fn width_direction(up: vec3<f32>, orientation: f32) -> vec3<f32> {
    let s = select(-1.0, 1.0, up.z >= 0.0);
    let a = -1.0 / (s + up.z);
    let c = up.x * up.y * a;
    let t = vec3<f32>(1.0 + s * up.x * up.x * a, s * c, -s * up.x);
    let b = vec3<f32>(c, s + up.y * up.y * a, -up.y);
    return normalize_or_zero(t * cos(orientation) + b * sin(orientation));
}

// ---------------------------------------------------------------- validation (blade.rs)

// How far from its root, in heights, a listed blade's stored tip may lie (instanced.glsl
// `LEAN_RANGE`): a settled tip is stored before validation, which may lie past the length.
const LEAN_RANGE: f32 = 4.0;

// Validation's guide for a blade rooted at `v0` along `up`, `h` long, its tip at `v2` (above the
// ground), placed by how far the tip leans, and (w) the length of the curve through them, which
// validation brings back to `h` by scaling the curve about its root (common.glsl
// `guided_length`).
fn guided_length(v0: vec3<f32>, up: vec3<f32>, h: f32, v2: vec3<f32>) -> vec4<f32> {
    let rel = v2 - v0;
    let l_proj = length(rel - up * dot(rel, up));
    let v1 = v0 + up * (h * max(1.0 - l_proj / h, 0.05 * max(l_proj / h, 1.0)));
    let l0 = length(v2 - v0);
    let l1 = length(v1 - v0) + length(v2 - v1);
    return vec4<f32>(v1, (2.0 * l0 + l1) / 3.0);
}

// State validation a–c (paper §5.2) of blade `b` whose tip would move to `v2`: the tip kept
// above the ground, the guide placed by how far the tip leans, the curve brought back to its
// length.
fn validate(b: ptr<function, Blade>, tip: vec3<f32>) {
    let v0 = (*b).root.xyz;
    let up = (*b).up.xyz;
    let h = (*b).guide.w;
    let v2 = tip - up * min(dot(up, tip - v0), 0.0);
    let guided = guided_length(v0, up, h, v2);
    let v1 = guided.xyz;
    let len = guided.w;
    let ratio = select(1.0, h / len, len > 1e-12);
    let v1_new = v0 + (v1 - v0) * ratio;
    (*b).guide = vec4<f32>(v1_new, (*b).guide.w);
    (*b).tip = vec4<f32>(v1_new + (v2 - v1) * ratio, (*b).tip.w);
}

// A curve rooted at `root`, `h` long, whose tip would move to `tip`, validated (physics.wgsl
// `validate`): its guide (xyz) and tip.
fn validated(root: vec3<f32>, h: f32, tip: vec3<f32>) -> Blade {
    var b = Blade(vec4<f32>(root, 0.0), vec4<f32>(root, h), vec4<f32>(tip, 0.0), vec4<f32>(0.0, 1.0, 0.0, 0.0));
    validate(&b, tip);
    return b;
}

// Invocations per workgroup of the passes that take a blade each.
const WORKGROUP: u32 = 64u;

// The blade an invocation takes: a row of workgroups first, then as many rows as it takes
// where one row of the device's dispatch does not hold the field.
fn blade_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * WORKGROUP;
}
