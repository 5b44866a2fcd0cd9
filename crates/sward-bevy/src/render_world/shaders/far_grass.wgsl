#define_import_path sward::far_grass

// sward's far grass as Bevy's passes draw it on any device Bevy opened: the generated grass's
// levels (each instance of a level's draw command one listed blade, a strip of that level's
// rows, geomorphed near the level's boundaries) and the billboards (three crossed quads, one
// turned to the eye far off), placed by the portable renderer's own WGSL (sward::portable:
// generated_blades.wgsl, billboard_quads.wgsl) from the lists its generating passes filled for
// the camera this frame. Their blades are made again each frame, so their motion vectors are
// the camera's alone (the sway between two frames is not kept).

#import sward::portable::{
    frame, placed_point, placed_normal, placed_length, world_xz, blade_look, hash_unit, generated_point, billboard_corner,
}

// A point of the far grass, in Bevy's world.
struct FarPoint {
    // False past a full list, and for a far billboard's second and third quads.
    drawn: bool,
    world_position: vec3<f32>,
    normal: vec3<f32>,
    // A generated blade's u across and v from root to tip; a billboard's texture coordinates
    // (row 0 holds the tips).
    uv: vec2<f32>,
    // What its colour comes from: its hash (x) and its look (y, z).
    colour: vec3<u32>,
    // A billboard's texture layers its coverage stands for.
    layers: f32,
    // How far its root is from the camera whose lists it is in.
    distance: f32,
}

// What the colour of the blade or billboard of `hash` rooted at `root` comes from, where the
// pass shades it (a prepass of depth and motion vectors alone does not).
fn far_colour(hash: u32, root: vec3<f32>) -> vec3<u32> {
    var look = vec2(0u);
#ifdef PREPASS_PIPELINE
#ifdef NORMAL_PREPASS_OR_DEFERRED_PREPASS
    look = blade_look(hash, world_xz(root.xz));
#endif
#else
    look = blade_look(hash, world_xz(root.xz));
#endif
    return vec3(hash, look);
}

// Vertex `vertex` of instance `instance` of a level's (or the billboards') draw command.
fn far_vertex(instance: u32, vertex: u32) -> FarPoint {
    var out: FarPoint;
#ifdef GRASS_BILLBOARDS
    let b = billboard_corner(vertex, instance);
    out.drawn = b.drawn;
    out.world_position = placed_point(b.position);
    out.normal = placed_normal(b.normal);
    out.uv = b.uv;
    out.colour = far_colour(b.hash, b.root);
    out.layers = b.layers;
    out.distance = placed_length(distance(b.root, frame.camera_position.xyz));
#else
    let g = generated_point(vertex, instance);
    out.drawn = g.drawn;
    out.world_position = placed_point(g.point.position);
    out.normal = placed_normal(g.point.normal);
    out.uv = g.point.uv;
    out.colour = far_colour(g.hash, g.root);
    out.layers = 1.0;
    out.distance = placed_length(distance(g.root, frame.camera_position.xyz));
#endif
    return out;
}

// Whether the far grass's point `p` casts into Bevy's shadow maps: within the grass's shadow
// distance (GRASS_SHADOW_CENTIMETRES) of the camera, thinned blade by blade over its last
// fifth, so the edge of the cast shadows is a fading band, not a line that follows the eye.
#ifdef GRASS_SHADOW_CENTIMETRES
fn casts(p: FarPoint) -> bool {
    let reach = f32(#{GRASS_SHADOW_CENTIMETRES}) * 0.01;
    return p.drawn && p.distance <= reach * (0.8 + 0.2 * hash_unit(p.colour.x));
}
#endif

// A clip position outside the clip volume (Bevy's depth runs 0 to 1): a triangle not drawn.
fn not_drawn() -> vec4<f32> {
    return vec4(0.0, 0.0, -1.0, 1.0);
}
