// The physical model of SPEC §3 for one blade, in WGSL for the portable renderer: recovery,
// gravity (environmental, toward a point, and the front gravity that bends a blade over its
// face), the summed wind fields, state validation, sphere collisions with a decaying strength.
// Line for line the Vulkan renderer's (shaders/physics.glsl and common.glsl) and sward-core's
// physics.rs, the CPU reference both are tested against. Needs frame.wgsl, blade.wgsl,
// noise.wgsl and trample_map.wgsl (with `trample_texels` bound).

// The forces that act (`counts.w`; sward-core flags.rs).
const FORCE_RECOVERY: u32 = 1u;
const FORCE_GRAVITY: u32 = 2u;
const FORCE_WIND: u32 = 4u;
const FORCE_COLLISIONS: u32 = 8u;

// A wind field's kind (the third vector's w; sward-core flags.rs).
const WIND_NONE: u32 = 0u;
const WIND_WAVES: u32 = 1u;
const WIND_NOISE: u32 = 2u;
const WIND_ANALYTIC: u32 = 3u;
const WIND_RADIAL: u32 = 4u;
const WIND_WHIRL: u32 = 5u;

// ---------------------------------------------------------------- wind (wind.rs)

fn wind_attenuation(dist: f32) -> f32 {
    return max(1.0 - log2(0.2 * dist + 1.0) / 4.0, 0.0);
}

fn wind_field_at(field: u32, p: vec3<f32>, t: f32) -> vec3<f32> {
    let direction = frame.winds[3u * field];
    let params = frame.winds[3u * field + 1u];
    let center = frame.winds[3u * field + 2u];
    let dir = direction.xyz;
    let strength = direction.w;
    let kind = u32(center.w);
    if (kind == WIND_WAVES) {
        let sum = cos((p.x + p.z) * 0.75 + t) + sin((p.x + p.y) * 0.5 + t) + sin((p.y + p.z) * 0.25 + t);
        let shape = 1.0 - max(sum / 3.0, 0.0);
        let gust = 1.0 + params.x * sin(params.y * t);
        return dir * (strength * shape * gust);
    }
    if (kind == WIND_NOISE) {
        let scale = params.z;
        let q = vec2<f32>(p.x, p.z) * scale - vec2<f32>(dir.x, dir.z) * (params.w * scale * t);
        let n = 0.65 * value_noise(q) + 0.35 * value_noise(q * 2.03 + vec2<f32>(17.1));
        return dir * (strength * n);
    }
    if (kind == WIND_ANALYTIC) {
        let s = 1.0 + sin(0.4 * t + 0.06 * p.x + 0.05 * p.z) + 0.4 * cos(1.7 * t + 0.4 * p.x) + 0.2 * sin(3.0 * t + 0.5 * p.z);
        return dir * (strength * s);
    }
    if (kind == WIND_RADIAL) {
        let d = p - center.xyz;
        let dist = length(d);
        let wave = 1.0 - max(sin(0.4 * dist - 4.0 * t), 0.0);
        return normalize_or_zero(d) * (strength * wind_attenuation(dist) * wave);
    }
    if (kind == WIND_WHIRL) {
        let d = vec3<f32>(p.x - center.x, 0.0, p.z - center.z);
        let radial = normalize_or_zero(d);
        let tangent = cross(vec3<f32>(0.0, 1.0, 0.0), radial);
        return (tangent - 0.25 * radial) * (strength * wind_attenuation(length(d)));
    }
    return vec3<f32>(0.0);
}

// The sum of the scene's wind fields at frame point `p` (wind.rs `sum_at`).
fn wind_at(p: vec3<f32>, t: f32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    let world = world_point(p);
    for (var i = 0u; i < frame.modes.y; i++) {
        sum += wind_field_at(i, world, t);
    }
    return sum;
}

// The wind's push on a blade: strongest on a blade standing across it and upright.
fn wind_force(wind: vec3<f32>, root: vec3<f32>, tip: vec3<f32>, up: vec3<f32>, height: f32) -> vec3<f32> {
    let alignment = 1.0 - abs(dot(normalize_or_zero(wind), normalize_or_zero(tip - root)));
    let height_ratio = dot(tip - root, up) / height;
    return wind * (alignment * height_ratio);
}

// Gravity on a blade with its tip at `tip`, its face toward `front`: the environment's gravity
// or a pull toward a point, and the forward part that bends a blade over its face.
fn gravity_force(tip: vec3<f32>, front: vec3<f32>) -> vec3<f32> {
    let environmental = frame.gravity.xyz * frame.gravity.w;
    let toward_point = normalize_or_zero(frame.point_gravity.xyz - tip) * frame.point_gravity.w;
    let g_e = mix(environmental, toward_point, frame.simulation.z);
    return g_e + 0.25 * length(g_e) * front;
}

// ---------------------------------------------------------------- collisions (validation: blade.wgsl)

// How far `p` must move to leave `sphere` (xyz centre, w radius): zero outside it.
fn push_out(sphere: vec4<f32>, p: vec3<f32>) -> vec3<f32> {
    let to_center = sphere.xyz - p;
    return min(length(to_center) - sphere.w, 0.0) * normalize_or_zero(to_center);
}

// The pushing spheres (the first `counts.z` colliders) move the tip out of them, by the tip's
// and the curve's middle's way out; the collision strength η grows by how far. True where any
// moved it.
fn collide(b: ptr<function, Blade>, eta: ptr<function, f32>) -> bool {
    var moved = false;
    for (var i = 0u; i < frame.counts.z; i++) {
        let sphere = frame.colliders[i];
        if (length((*b).root.xyz - sphere.xyz) - sphere.w >= (*b).guide.w) {
            continue;
        }
        let mid = 0.25 * (*b).root.xyz + 0.5 * (*b).guide.xyz + 0.25 * (*b).tip.xyz;
        let d_tip = push_out(sphere, (*b).tip.xyz);
        let d_mid = 4.0 * push_out(sphere, mid);
        let d = d_tip + d_mid;
        if (any(d != vec3<f32>(0.0))) {
            (*b).tip = vec4<f32>((*b).tip.xyz + d, (*b).tip.w);
            *eta += dot(d_tip, d_tip) + dot(d_mid, d_mid);
            moved = true;
        }
    }
    return moved;
}

// SPEC §11: the trample map remembers where colliders pressed the ground — also while a
// blade was not simulated, or before it was made. A blade standing higher than the map lays
// the grass there is held down to it, as the generated grass beside it is (from upright
// towards lying along the push, by the pressing), and its collision strength is at least the
// pressing, so a trail recovers at one rate in every kind of grass. True where it held the tip.
fn press_by_map(b: ptr<function, Blade>, eta: ptr<function, f32>) -> bool {
    let push = trample_push((*b).root.xz);
    let pressed = min(length(push), 1.0);
    if (pressed <= 0.0) {
        return false;
    }
    let root = (*b).root.xyz;
    let up = (*b).up.xyz;
    let flat_push = vec3<f32>(push.x, 0.0, push.y);
    let along = normalize_or_zero(flat_push - up * dot(flat_push, up));
    let lying = root + (*b).guide.w * (0.95 * along + 0.1 * up);
    let held = mix(root + (*b).guide.w * up, lying, pressed);
    *eta = max(*eta, pressed);
    if (dot((*b).tip.xyz - root, up) <= dot(held - root, up)) {
        return false;
    }
    (*b).tip = vec4<f32>(held, (*b).tip.w);
    return true;
}

// One fixed step of blade `b` at time `t` (SPEC §3.1–3.7, in order); `outer`: how strongly
// gravity and wind act, 1 but on a mown blade (simulate_blade).
fn step_blade(b: ptr<function, Blade>, eta: ptr<function, f32>, t: f32, outer: f32) {
    let forces = frame.counts.w;
    let dt = frame.simulation.x;
    *eta = max(*eta - frame.simulation.y * dt, 0.0);

    let v0 = (*b).root.xyz;
    let up = (*b).up.xyz;
    var v2 = (*b).tip.xyz;
    var delta = vec3<f32>(0.0);
    if ((forces & FORCE_RECOVERY) != 0u) {
        let rest_tip = v0 + up * (*b).guide.w;
        delta += (rest_tip - v2) * (*b).up.w * max(1.0 - *eta, 0.1);
    }
    if ((forces & FORCE_GRAVITY) != 0u) {
        let front = normalize_or_zero(cross(up, width_direction(up, (*b).root.w)));
        delta += gravity_force(v2, front) * outer;
    }
    if ((forces & FORCE_WIND) != 0u) {
        delta += wind_force(wind_at(v0, t), v0, v2, up, (*b).guide.w) * outer;
    }
    v2 += delta * dt;
    validate(b, v2);

    if ((forces & FORCE_COLLISIONS) != 0u && collide(b, eta)) {
        validate(b, (*b).tip.xyz);
    }
    if ((forces & FORCE_COLLISIONS) != 0u && frame.trample.x > 0u && press_by_map(b, eta)) {
        validate(b, (*b).tip.xyz);
    }
}

// `counts.y` fixed steps from the frame's start time (`camera_position.w`). Where the trample
// map says the grass was mown, the blade steps as a blade no taller than the cut — recovery,
// validation and collisions all keep it that long — and keeps its own height to grow back to
// as the cut grows back. Gravity and wind act on a mown blade by the square of the share of it
// left (less blade to weigh and catch the wind, a stiffer stub: physics.rs `step_mown_blade`).
fn simulate_blade(b: ptr<function, Blade>, eta: ptr<function, f32>) {
    let height = (*b).guide.w;
    var outer = 1.0;
    if (frame.trample.x > 0u) {
        (*b).guide.w = min(height, trample_cut((*b).root.xz));
        let left = (*b).guide.w / max(height, 1e-6);
        outer = left * left;
    }
    for (var k = 0u; k < frame.counts.y; k++) {
        step_blade(b, eta, frame.camera_position.w + f32(k) * frame.simulation.x, outer);
    }
    (*b).guide.w = height;
}
