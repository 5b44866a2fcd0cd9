#version 460
// Memory bandwidth probe for `sward bench`: copy vec4s from binding 1 to binding 2, the access
// pattern of the grass passes (coalesced 16-byte loads and stores), one element per invocation.

layout(local_size_x = 256) in;
layout(set = 0, binding = 1, std430) readonly buffer Source { vec4 source[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Destination { vec4 destination[]; };
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < uint(destination.length())) {
        destination[i] = source[i];
    }
}
