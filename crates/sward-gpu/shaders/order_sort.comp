#version 460
// The ordering pass, part five (a workgroup per run of SORT_RUN entries of the ordered list, up
// to where the compute route's splats begin): each run sorted by the blades' exact distance,
// nearest first. The buckets leave the blades of one bucket in the field's order, and where
// blades are hundreds of pixels tall (an eye down in the grass) one bucket holds thousands that
// overlap on screen; drawn in the field's order, far ones before near ones, their samples pass
// the depth test again and again, and writing those samples is what the draw is bound by.
// A key is the blade's bucket (top bits: no blade leaves its bucket's range, so the strip
// commands, the occluders and the levels of detail stay right), its place within the bucket,
// then its index in the run (so keys are unique and the order is the same every run).
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#include "common.glsl"

layout(local_size_x = 1024) in;

// Entries a workgroup sorts: 32 KiB of keys, what every device gives a workgroup.
const uint SORT_RUN = 8192u;
const uint RUN_BITS = 13u;
const uint FINE_BITS = 32u - 6u - RUN_BITS;
const uint PER_LANE = SORT_RUN / 1024u;

shared uint keys[SORT_RUN];
#define SORT_KEYS keys
#include "bitonic.glsl"

// The bucket holding ordered entry i: the last bucket that starts at or before it (empty buckets
// start where the next one does, so the last is the one that holds it).
uint bucket_of(uint i) {
    uint lo = 0u;
    uint hi = DISTANCE_BUCKETS - 1u;
    while (lo < hi) {
        uint mid = (lo + hi + 1u) / 2u;
        if (draws[COMMAND_BUCKETS + mid].first_instance <= i) {
            lo = mid;
        } else {
            hi = mid - 1u;
        }
    }
    return lo;
}

uint sort_key(uint i, uint run_index) {
    uint bucket = bucket_of(i);
    Blade b = blades[ordered[i]];
    float f = sqrt(distance(b.v0.xyz, frame.camera_position.xyz) / bucket_range()) * float(DISTANCE_BUCKETS);
    // The last bucket reaches past the buckets' range: x / (1 + x) keeps it in order there too.
    float x = max(f - float(bucket), 0.0);
    float within = bucket + 1u < DISTANCE_BUCKETS ? min(x, 1.0) : x / (1.0 + x);
    uint fine = uint(within * float((1u << FINE_BITS) - 1u));
    return (bucket << (32u - 6u)) | (fine << RUN_BITS) | run_index;
}

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint end = draws[COMMAND_SORT_DISPATCH].first_instance;
    uint base = gl_WorkGroupID.x * SORT_RUN;
    uint count = min(end - min(base, end), SORT_RUN);
    // A bitonic network over the next power of two; padding keys sort last.
    uint n = bitonic_size(count);
    for (uint t = lane; t < n; t += 1024u) {
        keys[t] = t < count ? sort_key(base + t, t) : 0xffffffffu;
    }
    barrier();
    bitonic_sort(n);
    // Every lane reads the blades its places get before any lane writes one back.
    uint ids[PER_LANE];
    for (uint s = 0u; s < PER_LANE; s++) {
        uint t = lane + s * 1024u;
        ids[s] = t < count ? ordered[base + (keys[t] & ((1u << RUN_BITS) - 1u))] : 0u;
    }
    memoryBarrierBuffer();
    barrier();
    for (uint s = 0u; s < PER_LANE; s++) {
        uint t = lane + s * 1024u;
        if (t < count) {
            ordered[base + t] = ids[s];
        }
    }
}
