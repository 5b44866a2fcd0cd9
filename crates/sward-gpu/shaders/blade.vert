#version 460
// The tessellation route (SPEC §6): one patch per visible blade, its blade's index from the
// ordered list (or, in the bench's copy variant, the copy's own index). The stages are glue: what
// they compute is the core's WGSL (tessellation.wesl), written as GLSL into tessellation.glsl.
#extension GL_GOOGLE_include_directive : require
#include "declared.glsl"
#include "tessellation.glsl"

layout(constant_id = CONSTANT_COPY_BLADES) const bool COPY_BLADES = false;
layout(location = 0) out uint out_blade;

void main() {
    out_blade = patch_blade(uint(gl_VertexIndex), COPY_BLADES);
}
