#version 460
// The streamed field carried to a new frame origin (stream.rs `frame_origin`): in the frame the
// origin moves, every stored blade's points move by frame.origin.zw (whole multiples of a power
// of two, so the subtraction is exact), before anything else reads them. One row of workgroups
// per tile of the window, an invocation per blade; the host sizes the dispatch (none in the
// frames the origin stays).
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#include "common.glsl"

layout(local_size_x_id = CONSTANT_WORKGROUP) in;

void main() {
    uint per_tile = frame.stream.y * frame.stream.y;
    uint index = gl_GlobalInvocationID.x;
    if (index >= per_tile) {
        return;
    }
    uint id = gl_WorkGroupID.y * per_tile + index;
    vec3 shift = vec3(frame.origin.z, 0.0, frame.origin.w);
    blades[id].v0.xyz -= shift;
    blades[id].v1.xyz -= shift;
    blades[id].v2.xyz -= shift;
}
