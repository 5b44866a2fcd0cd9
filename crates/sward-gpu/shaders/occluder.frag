#version 460
// The occluders' depth, written as colour into level 0 of the depth pyramid (Hi-Z).
layout(location = 0) out float out_depth;

void main() {
    out_depth = gl_FragCoord.z;
}
