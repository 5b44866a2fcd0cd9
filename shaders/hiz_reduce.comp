#version 460
// One level of the depth pyramid (Hi-Z): each texel keeps the farthest depth of the texels it
// covers one level down, so a test against it is conservative. Odd sizes fold the last row and
// column into the texel beside them.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D finer;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D coarser;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(coarser);
    if (any(greaterThanEqual(texel, size))) {
        return;
    }
    ivec2 finer_size = imageSize(finer);
    ivec2 start = texel * 2;
    // The last texel also covers a leftover odd row or column.
    ivec2 stop = min(start + 1 + ivec2(equal(texel, size - 1)) * (finer_size - 2 * size), finer_size - 1);
    float farthest = 0.0;
    for (int y = start.y; y <= stop.y; y++) {
        for (int x = start.x; x <= stop.x; x++) {
            farthest = max(farthest, imageLoad(finer, ivec2(x, y)).r);
        }
    }
    imageStore(coarser, texel, vec4(farthest));
}
