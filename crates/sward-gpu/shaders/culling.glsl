// Per-blade culling of SPEC §4 (orientation → frustum → distance → occlusion) and compaction into the visible
// list and draw commands (SPEC §5). Mirrors sward-core's cull.rs. Included by cull.comp and
// simulate_cull.comp, which declare USE_SUBGROUPS.

#include "hiz.glsl"

bool seen_edge_on(Blade b, vec3 eye) {
    vec3 view_dir = normalize_or_zero(b.v0.xyz - eye);
    return abs(dot(view_dir, width_direction(b.up.xyz, b.v0.w))) > frame.cull.x;
}

// Where blades cast shadows (the sun's near cascade, shading_extra.w around the eye), whether
// the shadow of the blade's tip on the ground through its root lies in view: such a blade is
// kept though it is off screen, so it casts into the view (cull.rs `ShadowCasting`).
bool shadow_in_view(Blade b, float t) {
    float reach = frame.shading_extra.w;
    if ((frame.modes.w & DRAW_BLADE_SHADOWS) == 0u || distance(b.v0.xyz, frame.camera_position.xyz) >= reach) {
        return false;
    }
    vec3 sun = frame.light_direction.xyz; // a unit vector already (gpu.rs)
    float height = dot(b.v2.xyz - b.v0.xyz, b.up.xyz);
    vec3 shadow = b.v2.xyz - sun * (height / max(dot(sun, b.up.xyz), 0.2));
    return inside_clip(frame.view_proj * vec4(shadow, 1.0), t);
}

bool outside_frustum(Blade b) {
    vec3 mid = 0.25 * b.v0.xyz + 0.5 * b.v1.xyz + 0.25 * b.v2.xyz;
    float t = frame.cull.y;
    return !inside_clip(frame.view_proj * vec4(b.v0.xyz, 1.0), t)
        && !inside_clip(frame.view_proj * vec4(mid, 1.0), t)
        && !inside_clip(frame.view_proj * vec4(b.v2.xyz, 1.0), t)
        && !shadow_in_view(b, t);
}

bool thinned_by_distance(Blade b, uint id, vec3 eye) {
    vec3 up = b.up.xyz;
    vec3 rel = b.v0.xyz - eye;
    float d_proj = length(rel - up * dot(rel, up));
    uint n = max(uint(frame.cull.w), 1u);
    float kept = ceil(float(n) * (1.0 - d_proj / frame.cull.z));
    return float(id % n) >= kept;
}

// Level of the depth pyramid the occlusion test reads: texels of 2 × 2 occluder pixels, and the
// test takes the farthest of the 2 × 2 texels around a point, so an occluder's edge rasterised a
// pixel off never hides what is beside it.
const int HIZ_LEVEL = 1;


// Whether point p lies behind the occluders by more than the tolerance. Points off screen or
// behind the eye are never hidden.
bool hidden(vec3 p) {
    vec4 clip = frame.view_proj * vec4(p, 1.0);
    if (clip.w <= 0.0) {
        return false;
    }
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0))) || ndc.z < 0.0 || ndc.z > 1.0) {
        return false;
    }
    ivec2 size = textureSize(hiz, HIZ_LEVEL);
    ivec2 corner = clamp(ivec2(floor((ndc.xy * 0.5 + 0.5) * vec2(size) - 0.5)), ivec2(0), size - 2);
    float farthest = max(
        max(texelFetch(hiz, corner, HIZ_LEVEL).r, texelFetch(hiz, corner + ivec2(1, 0), HIZ_LEVEL).r),
        max(texelFetch(hiz, corner + ivec2(0, 1), HIZ_LEVEL).r, texelFetch(hiz, corner + ivec2(1, 1), HIZ_LEVEL).r));
    return view_depth(ndc.z) > view_depth(farthest) + frame.coarse_cull.y;
}

// Pieces of the curve blade_hidden tests one by one: a bent blade's one box would hold much
// that the blade does not cover. Measured on the H100 (cis565 2^20): 8 pieces culled a few per
// cent more blades than 4, and cost more in the cull than they saved in the draw.
const int BLADE_PIECES = 4;

// Whether a ball of radius r swept along the segment a–b lies wholly behind what the depth
// pyramid holds. The ball's screen box and nearest view depth are bounded from the
// view-projection's rows (clip x, y and w change by at most a row's length per unit moved).
bool capsule_hidden(vec3 a, vec3 b, float r) {
    mat4 m = frame.view_proj;
    vec3 pad = r * vec3(length(vec3(m[0][0], m[1][0], m[2][0])), length(vec3(m[0][1], m[1][1], m[2][1])),
                        length(vec3(m[0][3], m[1][3], m[2][3])));
    vec2 lo = vec2(1e30);
    vec2 hi = vec2(-1e30);
    float nearest = 1e30;
    vec4 ends[2] = vec4[](m * vec4(a, 1.0), m * vec4(b, 1.0));
    for (int i = 0; i < 2; i++) {
        vec4 clip = ends[i];
        float w_near = clip.w - pad.z;
        if (w_near <= frame.coarse_cull.z) {
            return false; // reaches the near plane
        }
        float w_far = clip.w + pad.z;
        vec4 corners = vec4(clip.xy - pad.xy, clip.xy + pad.xy);
        lo = min(lo, min(corners.xy / w_near, corners.xy / w_far));
        hi = max(hi, max(corners.zw / w_near, corners.zw / w_far));
        nearest = min(nearest, w_near);
    }
    return screen_box_hidden(lo, hi, nearest);
}

vec3 curve_point(Blade b, float t) {
    float s = 1.0 - t;
    return s * s * b.v0.xyz + 2.0 * s * t * b.v1.xyz + t * t * b.v2.xyz;
}

// Whether the whole blade lies behind what the depth pyramid holds — with blade occluders
// (occlusion.x > 0) the nearest blades the last frame drew, whose gaps a test of three points
// would see through. The curve is cut into pieces; each piece's chord carries a ball of 1.2 w
// (the half width, and the ridge's bulge) plus how far the curve strays from the chord
// (|v0 − 2 v1 + v2| Δt² / 4 for a quadratic Bezier), so the blade lies within the capsules.
bool blade_hidden(Blade b) {
    float dt = 1.0 / float(BLADE_PIECES);
    float r = 1.2 * b.v2.w + length(b.v0.xyz - 2.0 * b.v1.xyz + b.v2.xyz) * dt * dt * 0.25;
    vec3 a = b.v0.xyz;
    for (int i = 1; i <= BLADE_PIECES; i++) {
        vec3 next = curve_point(b, float(i) * dt);
        if (!capsule_hidden(a, next, r)) {
            return false;
        }
        a = next;
    }
    return true;
}

// SPEC §4 occlusion: culled only if the curve points at t = 0.1, 0.5 and 1 are all hidden —
// or, where blades occlude too, only if the whole blade is (blade_hidden). A blade that casts
// into the near shadow cascade is kept though hidden: its shadow may fall where it is seen.
bool occluded(Blade b) {
    if (frame.occlusion.x > 0u) {
        bool casts = (frame.modes.w & DRAW_BLADE_SHADOWS) != 0u
            && distance(b.v0.xyz, frame.camera_position.xyz) < frame.shading_extra.w;
        return !casts && blade_hidden(b);
    }
    return hidden(curve_point(b, 0.1)) && hidden(curve_point(b, 0.5)) && hidden(curve_point(b, 1.0));
}

bool is_visible(Blade b, uint id) {
    vec3 eye = frame.camera_position.xyz;
    uint tests = frame.modes.x;
    if ((tests & CULL_ORIENTATION) != 0u && seen_edge_on(b, eye)) return false;
    if ((tests & CULL_FRUSTUM) != 0u && outside_frustum(b)) return false;
    if (streamed()) {
        // The streamed field hands over cell for cell: no thinning, every blade nearer than
        // the hand-over drawn, the instanced twin of every other (instanced_pass.glsl).
        if (b.v1.w <= 0.0 || distance(b.v0.xyz, eye) >= frame.stream_reach.x) return false;
    } else if ((tests & CULL_DISTANCE) != 0u && thinned_by_distance(b, id, eye)) {
        return false;
    }
    if ((tests & CULL_OCCLUSION) != 0u && occluded(b)) return false;
    return true;
}

// One atomic per subgroup instead of one per visible blade.
uint append_slot(bool keep) {
    if (!USE_SUBGROUPS) {
        return keep ? atomicAdd(draws[COMMAND_ALL].vertex_count, 1u) : 0u;
    }
    uvec4 ballot = subgroupBallot(keep);
    uint total = subgroupBallotBitCount(ballot);
    uint base = 0u;
    if (subgroupElect() && total > 0u) {
        base = atomicAdd(draws[COMMAND_ALL].vertex_count, total);
    }
    return subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(ballot);
}

// Count a kept blade in its distance bucket's draw command: one atomic per bucket the subgroup's
// blades fall in (neighbouring blades share buckets, so that is one or two).
void count_in_bucket(bool keep, uint bucket) {
    if (!USE_SUBGROUPS) {
        if (keep) {
            atomicAdd(draws[COMMAND_BUCKETS + bucket].instance_count, 1u);
        }
        return;
    }
    bool pending = keep;
    while (subgroupAny(pending)) {
        if (pending) {
            uint first = subgroupBroadcastFirst(bucket);
            if (bucket == first) {
                uint n = subgroupBallotBitCount(subgroupBallot(true));
                if (subgroupElect()) {
                    atomicAdd(draws[COMMAND_BUCKETS + bucket].instance_count, n);
                }
                pending = false;
            }
        }
    }
}

// Append blade `id` (whose state is `b`) to the visible list if `keep`, with its distance
// bucket; every invocation of the subgroup must call this. order_blades.comp then puts the list
// in draw order.
// The counts are sums, the same whatever order the workgroups ran in; the verdict goes to this
// invocation's own slot (CULL_SLOT), so the list the ordering passes read does not depend on that
// order either, and neither does the picture (SPEC §5: a draw order that changes from run to run
// breaks depth ties differently). The bench's copy variant appends whole blades instead.
void append_visible(bool keep, uint id, Blade b) {
    uint slot = append_slot(keep);
    uint bucket = distance_bucket(distance(b.v0.xyz, frame.camera_position.xyz));
    count_in_bucket(keep, bucket);
    if (COPY_BLADES) {
        if (keep) {
            culled[slot] = b;
        }
    } else {
        visible[CULL_SLOT()] = keep ? id | (bucket << BUCKET_SHIFT) : NOT_VISIBLE;
    }
}
