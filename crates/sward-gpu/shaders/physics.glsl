// The physical model of SPEC §3 for one blade: forces, state validation, sphere collisions. Mirrors
// sward-core's physics.rs step by step. Included by simulate.comp and simulate_cull.comp.

// State validation a–c (paper §5.2, common.glsl `validate_tip`); writes b.v1 and b.v2.
void validate(inout Blade b, vec3 v2) {
    vec3 v1_new, v2_new;
    validate_tip(b.v0.xyz, b.up.xyz, b.v1.w, v2, v1_new, v2_new);
    b.v1.xyz = v1_new;
    b.v2.xyz = v2_new;
}

vec3 push_out(vec4 sphere, vec3 p) {
    vec3 to_center = sphere.xyz - p;
    return min(length(to_center) - sphere.w, 0.0) * normalize_or_zero(to_center);
}

bool collide(inout Blade b, inout float eta) {
    bool moved = false;
    for (uint i = 0u; i < frame.counts.z; ++i) {
        vec4 sphere = frame.colliders[i];
        if (length(b.v0.xyz - sphere.xyz) - sphere.w >= b.v1.w) {
            continue;
        }
        vec3 mid = 0.25 * b.v0.xyz + 0.5 * b.v1.xyz + 0.25 * b.v2.xyz;
        vec3 d_tip = push_out(sphere, b.v2.xyz);
        vec3 d_mid = 4.0 * push_out(sphere, mid);
        vec3 d = d_tip + d_mid;
        if (d != vec3(0.0)) {
            b.v2.xyz += d;
            eta += dot(d_tip, d_tip) + dot(d_mid, d_mid);
            moved = true;
        }
    }
    return moved;
}

// SPEC §11: the trample map remembers where colliders pressed the ground — also while a blade's
// tile was out of view and not simulated, or before the blade was made. A blade standing
// higher than the map lays the grass there is held down to it, as the generated grass beside
// it is (instanced.glsl: from upright towards lying along the push, by the pressing), and its
// collision strength is at least the pressing, so a trail crosses the hand-over to the
// generated grass without a seam and recovers at one rate on both sides. The map is on only
// where generated grass is drawn; Bezier-only scenes never read it.
bool press_by_map(inout Blade b, inout float eta) {
    vec2 push = trample_push(b.v0.xz);
    float pressed = min(length(push), 1.0);
    if (pressed <= 0.0) {
        return false;
    }
    vec3 up = b.up.xyz;
    vec3 flat_push = vec3(push.x, 0.0, push.y);
    vec3 along = normalize_or_zero(flat_push - up * dot(flat_push, up));
    vec3 lying = b.v0.xyz + b.v1.w * (0.95 * along + 0.1 * up);
    vec3 held = mix(b.v0.xyz + b.v1.w * up, lying, pressed);
    eta = max(eta, pressed);
    if (dot(b.v2.xyz - b.v0.xyz, up) <= dot(held - b.v0.xyz, up)) {
        return false;
    }
    b.v2.xyz = held;
    return true;
}

// `outer`: how strongly gravity and wind act, 1 but on a mown blade (simulate_blade).
void step_blade(inout Blade b, inout float eta, float t, float outer) {
    uint forces = frame.counts.w;
    float dt = frame.simulation.x;
    eta = max(eta - frame.simulation.y * dt, 0.0);

    vec3 v0 = b.v0.xyz;
    vec3 up = b.up.xyz;
    vec3 v2 = b.v2.xyz;
    vec3 delta = vec3(0.0);
    if ((forces & FORCE_RECOVERY) != 0u) {
        vec3 rest_tip = v0 + up * b.v1.w;
        delta += (rest_tip - v2) * b.up.w * max(1.0 - eta, 0.1);
    }
    if ((forces & FORCE_GRAVITY) != 0u) {
        vec3 front = normalize_or_zero(cross(up, width_direction(up, b.v0.w)));
        delta += gravity_force(v2, front) * outer;
    }
    if ((forces & FORCE_WIND) != 0u) {
        delta += wind_force(wind_at(v0, t), v0, v2, up, b.v1.w) * outer;
    }
    v2 += delta * dt;
    validate(b, v2);

    if ((forces & FORCE_COLLISIONS) != 0u && collide(b, eta)) {
        validate(b, b.v2.xyz);
    }
    if ((forces & FORCE_COLLISIONS) != 0u && frame.trample.x > 0u && press_by_map(b, eta)) {
        validate(b, b.v2.xyz);
    }
}

// `counts.y` fixed steps from the frame's start time. Where the trample map says the grass was
// mown (a cutter passed, trample.comp), the blade steps as a blade no taller than the cut —
// recovery, validation and collisions all keep it that long — and keeps its own height to
// grow back to as the cut grows back. Gravity and wind act on a mown blade by the square of
// the share of it left (less blade to weigh and catch the wind, a stiffer stub): with the full
// forces a stub bent flat, since recovery pulls by the tip's distance from rest, which a short
// blade keeps small, while gravity pulls the same on every blade.
void simulate_blade(inout Blade b, inout float eta) {
    float height = b.v1.w;
    float outer = 1.0;
    if (frame.trample.x > 0u) {
        b.v1.w = min(height, trample_cut(b.v0.xz));
        float left = b.v1.w / max(height, 1e-6);
        outer = left * left;
    }
    for (uint k = 0u; k < frame.counts.y; ++k) {
        step_blade(b, eta, frame.camera_position.w + float(k) * frame.simulation.x, outer);
    }
    b.v1.w = height;
}

// The streamed field's hand-over (stream.rs): over the last band before the hand-over radius
// a Bezier blade eases into the shape its instanced twin — the instanced blade of its cell —
// has there (bent, swaying, trampled, mown, widened as the twin is), all the way at the
// radius, where the twin takes over; walking back, physics takes the blade back as gently.
// Only the guide, the tip and the width move; the state stays the blade's own, so the easing
// is as continuous as the physics.
void ease_into_twin(inout Blade b, uint id) {
    float s = twin_ease(b.v0.xyz);
    if (s <= 0.0) {
        return;
    }
    float dist = distance(b.v0.xyz, frame.camera_position.xyz);
    InstancedBlade twin = instanced_twin(stream_cell(id));
    Shape shape = twin_shape(twin, dist);
    b.v1.xyz = mix(b.v1.xyz, shape.p1, s);
    b.v2.xyz = mix(b.v2.xyz, shape.p2, s);
    b.v2.w = mix(twin.width, shape.width, s);
}
