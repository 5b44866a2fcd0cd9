// Per-blade culling of SPEC §4 (orientation → frustum → distance) and compaction into the visible
// list and draw commands (SPEC §5). Mirrors sward-core's cull.rs. Included by cull.comp and
// simulate_cull.comp, which declare USE_SUBGROUPS.

bool seen_edge_on(Blade b, vec3 eye) {
    vec3 view_dir = normalize_or_zero(b.v0.xyz - eye);
    return abs(dot(view_dir, width_direction(b.up.xyz, b.v0.w))) > frame.cull.x;
}

bool outside_frustum(Blade b) {
    vec3 mid = 0.25 * b.v0.xyz + 0.5 * b.v1.xyz + 0.25 * b.v2.xyz;
    float t = frame.cull.y;
    return !inside_clip(frame.view_proj * vec4(b.v0.xyz, 1.0), t)
        && !inside_clip(frame.view_proj * vec4(mid, 1.0), t)
        && !inside_clip(frame.view_proj * vec4(b.v2.xyz, 1.0), t);
}

bool thinned_by_distance(Blade b, uint id, vec3 eye) {
    vec3 up = b.up.xyz;
    vec3 rel = b.v0.xyz - eye;
    float d_proj = length(rel - up * dot(rel, up));
    uint n = max(uint(frame.cull.w), 1u);
    float kept = ceil(float(n) * (1.0 - d_proj / frame.cull.z));
    return float(id % n) >= kept;
}

bool is_visible(Blade b, uint id) {
    vec3 eye = frame.camera_position.xyz;
    uint tests = frame.modes.x;
    if ((tests & 1u) != 0u && seen_edge_on(b, eye)) return false;
    if ((tests & 2u) != 0u && outside_frustum(b)) return false;
    if ((tests & 4u) != 0u && thinned_by_distance(b, id, eye)) return false;
    return true;
}

// One atomic per subgroup instead of one per visible blade.
uint append_slot(bool keep) {
    if (!USE_SUBGROUPS) {
        return keep ? atomicAdd(draws[0].vertex_count, 1u) : 0u;
    }
    uvec4 ballot = subgroupBallot(keep);
    uint total = subgroupBallotBitCount(ballot);
    uint base = 0u;
    if (subgroupElect() && total > 0u) {
        base = atomicAdd(draws[0].vertex_count, total);
    }
    return subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(ballot);
}

// Append blade `id` (whose state is `b`) to the visible list if `keep`; every invocation of the
// subgroup must call this.
void append_visible(bool keep, uint id, Blade b) {
    uint slot = append_slot(keep);
    if (!keep) {
        return;
    }
    if (COPY_BLADES) {
        culled[slot] = b;
    } else {
        visible[slot] = id;
    }
    uint per_draw = frame.modes.z;
    if (per_draw != 0u) {
        uint k = slot / per_draw;
        atomicMax(draws[1u + k].vertex_count, slot - k * per_draw + 1u);
        if (slot == k * per_draw) {
            draws[1u + k].instance_count = 1u;
            draws[1u + k].first_vertex = k * per_draw;
        }
    }
}
