#version 460
// The streamed field's tiles entering the window this frame (stream.rs), made before the frame
// steps them: one row of workgroups per entering tile, an invocation per blade. Each blade is
// the instanced grass's blade of its cell (instanced.glsl `instanced_twin`: root, height,
// half-width, facing), standing as that twin stands this frame — bent, swaying, laid down where
// the trample map says the grass there was walked on —, with a stiffness from its cell's hash;
// physics takes it from there (and presses it, and cuts it, by the map as it does every blade).
// The host lists the entering tiles after the frame's tile list and boxes (renderer
// `StreamState`): a dispatch command, then per tile its slot and world tile.
#extension GL_GOOGLE_include_directive : require
#define SWARD_WRITE
#include "common.glsl"
#include "instanced.glsl"

layout(local_size_x_id = CONSTANT_WORKGROUP) in;

void main() {
    uint tiles = frame.stream.x * frame.stream.x;
    // After the tile list (one entry per slot) and the boxes (two per slot): the dispatch
    // command, then the entering tiles.
    ActiveTile entering = active_tiles[3u * tiles + 1u + gl_WorkGroupID.y];
    uint cells = frame.stream.y;
    uint index = gl_GlobalInvocationID.x;
    if (index >= cells * cells) {
        return;
    }
    InstancedBlade twin = instanced_twin(tile_cell(ivec2(int(entering.count), int(entering.drawn)), index));
    float stiffness = grid_stiffness(twin.hash, twin.species);
    float dist = distance(twin.root, frame.camera_position.xyz);
    Blade b;
    b.v0 = vec4(twin.root, twin.facing);
    b.up = vec4(0.0, 1.0, 0.0, stiffness);
    if (twin.height > 0.0) {
        Shape shape = twin_shape(twin, dist);
        b.v1 = vec4(shape.p1, twin.height);
        b.v2 = vec4(shape.p2, twin.width);
    } else {
        // Off the ground's height grid: a blade of no height, never drawn.
        b.v1 = vec4(twin.root, 0.0);
        b.v2 = vec4(twin.root, twin.width);
    }
    uint id = entering.first * cells * cells + index;
    blades[id] = b;
    etas[id] = 0.0;
}
