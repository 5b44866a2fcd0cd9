// The billboards as the draws place and cover them (SPEC §7 [B]; the Vulkan renderer's
// billboard.glsl and billboard_coverage.glsl): sward's own draw (billboards.wgsl) and an engine's
// passes both. Their list is generated.wgsl's, from `billboard_meta.x`: three textured quads crossing at 60°, 18
// vertices per instance, the instance pulling its billboard (root, height, half-width, facing,
// hash) from the list generated.wgsl filled; far from the eye one quad turned to it, lit as one
// of the three (its hash picks which). Wind as SPEC §7 [B] has it: the hash picks a fast or a
// slow sway, taller billboards sway slower, the top moves and the base does not, and a second
// hash varies the amplitude; direction and strength are the scene's first wind field's. Near
// the instanced grass's edge (technique landscape) billboards grow in over the cross-fade band,
// they sink into the ground over the last 10 % before the cut-off, and where the trample map
// says so they lie down. The painted grass texture's alpha drives alpha-to-coverage (MSAA edges,
// no shimmering alpha test), its colour lit by the blades' own shading, so billboards match the
// blades they stand beside. Needs frame.wgsl, blade.wgsl, noise.wgsl, shading.wgsl,
// trample_map.wgsl and listed.wgsl.

// The trample map (trample_map.wgsl).
@group(0) @binding(9) var<storage, read> trample_texels: array<vec4<u32>>;
// The painted billboard and its coverage-keeping mip chain (sward-core's
// `shipped_grass_texture`), sampled trilinearly, clamped at its edges.
@group(0) @binding(16) var grass_texture: texture_2d<f32>;
@group(0) @binding(17) var grass_sampler: sampler;

const BILLBOARD_PI: f32 = 3.14159265;
// How many of three crossed quads a line of sight through a billboard crosses, on average over
// the billboard's width: the coverage one quad turned to the eye is drawn with in their place.
const CROSSED_LAYERS: f32 = 2.0;
// Billboards at least this many pixels tall are seen through mip levels 0 to 2 (256 / 4), and
// drawn as the outline their painted blades lie in.
const OUTLINE_PIXELS: f32 = 64.0;
// billboard_coverage.glsl `BILLBOARD_GAIN`: the painted blades' light and dark evened out
// against the instanced grass's.
const BILLBOARD_GAIN: f32 = 1.17;

// A billboard as its list holds it.
struct Billboard {
    root: vec3<f32>,
    // As generated (before it sinks or grows in).
    height: f32,
    half_width: f32,
    facing: f32,
    hash: u32,
}

fn listed_billboard(slot: u32) -> Billboard {
    let a = listed[2u * slot];
    let b = listed[2u * slot + 1u];
    let size = unpack2x16float(a.w);
    return Billboard(bitcast<vec3<f32>>(a.xyz), size.x, size.y, unpack2x16float(b.x).x, b.z);
}

// One quad of a billboard as drawn this frame.
struct BillboardQuad {
    // Unit direction of the quad's width, and the normal it is lit by.
    across: vec3<f32>,
    normal: vec3<f32>,
    // Standing height at this distance, and half-width widened with distance.
    height: f32,
    half_width: f32,
    // The texture layers its coverage stands for.
    layers: f32,
}

// How much of a billboard stands `dist` from the eye: growing in past the inner radius, sinking
// at the edge.
fn standing(dist: f32) -> f32 {
    let inner = frame.billboard_grid.z;
    let fade = frame.billboard_motion.y;
    let radius = frame.billboard_grid.y;
    let grow = select(1.0, smoothstep(inner, inner + fade, dist), inner > 0.0);
    return grow * (1.0 - smoothstep(0.9 * radius, radius, dist));
}

// The sideways push of the billboard's top at time `time`.
fn sway(root: vec3<f32>, height: f32, hash: u32, time: f32) -> vec3<f32> {
    var direction = vec3<f32>(1.0, 0.0, 0.0);
    var strength = 4.0;
    if (frame.modes.y > 0u) {
        direction = normalize_or_zero(vec3<f32>(frame.winds[0].x, 0.0, frame.winds[0].z));
        strength = frame.winds[0].w;
    }
    let fast = (hash & 1u) != 0u;
    let frequency = select(1.3, 2.6, fast) / (0.6 + height);
    let world = world_xz(root.xz);
    let phase = hash_unit(hash) * 2.0 * BILLBOARD_PI + 0.3 * (world.x + world.y);
    var amplitude = frame.billboard_motion.x * height * (0.6 + 0.8 * hash_unit(hash ^ 0x51ed27u));
    amplitude *= clamp(strength / 4.0, 0.0, 2.0);
    return direction * amplitude * cos(frequency * time + phase);
}

// Whether a billboard `dist` from the eye is drawn as one quad turned to the eye.
fn one_quad(dist: f32) -> bool {
    return dist > frame.billboard_far.x;
}

// Quad `quad` (0 to 2) of billboard `t`, `dist` from the eye; where the billboard is `single`,
// the one quad turned to the eye, lit as one of the three, so far billboards keep the mix of lit
// and shaded sides the crossed quads show.
fn billboard_quad(t: Billboard, quad: u32, dist: f32, single: bool) -> BillboardQuad {
    let angle = t.facing + f32(quad) * BILLBOARD_PI / 3.0;
    var across = vec3<f32>(cos(angle), 0.0, -sin(angle));
    var lit_across = across;
    var layers = 1.0;
    if (single) {
        let lit_angle = t.facing + f32(t.hash % 3u) * BILLBOARD_PI / 3.0;
        lit_across = vec3<f32>(cos(lit_angle), 0.0, -sin(lit_angle));
        let to_eye = frame.camera_position.xz - t.root.xz;
        across = normalize_or_zero(vec3<f32>(-to_eye.y, 0.0, to_eye.x));
        layers = CROSSED_LAYERS;
    }
    // Lit as grass, not as a flat card: the quad's normal leaning up.
    let normal = normalize(cross(lit_across, vec3<f32>(0.0, 1.0, 0.0)) + vec3<f32>(0.0, 0.25, 0.0));
    // Wider with distance, as the instanced blades, so far billboards keep their coverage.
    let widen = 1.0 + 1.5 * smoothstep(0.05 * frame.billboard_grid.y, frame.billboard_grid.y, dist);
    return BillboardQuad(across, normal, t.height * standing(dist), t.half_width * widen, layers);
}

// The point of quad `q` of billboard `t` at `place` (x across from 0 to 1, y up from 0 to 1):
// swayed by the wind at the top, laid along the trample map's push where trampled.
fn billboard_point(t: Billboard, q: BillboardQuad, place: vec2<f32>) -> vec3<f32> {
    let x = 2.0 * place.x - 1.0;
    let y = place.y;
    var p = t.root + q.across * (x * q.half_width) + vec3<f32>(0.0, y * q.height, 0.0);
    p += sway(t.root, q.height, t.hash, frame.camera_position.w) * (y * y);
    let push = trample_push(t.root.xz);
    let flat_by = min(length(push), 1.0);
    if (flat_by > 0.0) {
        let along = vec3<f32>(push.x, 0.0, push.y) / length(push);
        p += (along * 0.9 - vec3<f32>(0.0, 0.75, 0.0)) * (q.height * flat_by * y);
    }
    return p;
}

// How many pixels of the image a billboard of `height` standing at `root` spans (0 where the eye
// is below or behind it).
fn pixels_tall(root: vec3<f32>, height: f32) -> f32 {
    let foot = frame.view_proj * vec4<f32>(root, 1.0);
    let top = frame.view_proj * vec4<f32>(root + vec3<f32>(0.0, height, 0.0), 1.0);
    // Behind the eye (either end's w not above 0) it spans nothing.
    let seen = foot.w > 0.0 && top.w > 0.0;
    let span = (top.xy / max(top.w, 1e-20) - foot.xy / max(foot.w, 1e-20)) * 0.5 * frame.viewport.xy;
    return select(0.0, length(span), seen);
}

// A vertex of a billboard's draw: whether it is drawn (not past a full list, not a far
// billboard's second or third quad), where it is (in the frame's coordinates), the normal it is
// lit by, the texture's coordinates (row 0 holds the tips), its billboard's root and hash, and
// the texture layers its coverage stands for.
struct BillboardCorner {
    drawn: bool,
    position: vec3<f32>,
    normal: vec3<f32>,
    uv: vec2<f32>,
    root: vec3<f32>,
    hash: u32,
    layers: f32,
}

// The corner (0 bottom left, 1 bottom right, 2 top left, 3 top right) of vertex `i` of a
// quad's six: bottom left, bottom right, top left; top left, bottom right, top right.
fn quad_corner(i: u32) -> u32 {
    return select(select(select(3u, 1u, i == 4u), 2u, i == 3u), i, i < 3u);
}

// Where corner `corner` of a billboard's painted blades lies in its quad (billboard.rs
// BILLBOARD_OUTLINE): blades lean outward from roots crowded in the middle and the top 5 %
// holds no tip. Drawn as this trapezoid, a near billboard rasterizes a fifth fewer fragments.
fn painted_outline(corner: u32) -> vec2<f32> {
    let right = (corner & 1u) == 1u;
    let top = corner >= 2u;
    let x = select(select(0.22, 0.89, right), select(0.02, 0.99, right), top);
    return vec2<f32>(x, select(0.0, 0.95, top));
}

// Vertex `vertex_index` (18 an instance: three quads of two triangles) of instance `instance`
// of the billboards' draw.
fn billboard_corner(vertex_index: u32, instance: u32) -> BillboardCorner {
    // Without an early return: a vertex past a full list reads the first slot, and is not
    // drawn; a far billboard's second and third quads are placed, and not drawn. (Written so
    // while a lavapipe crash in Bevy's prepass was sought, which was the bind groups':
    // sward-bevy phases.rs `depth_group_one`. The early returns drew the H200's billboards
    // 0.8 % faster; they were not tried against that crash again.)
    let listed = instance < frame.billboard_meta.y;
    let t = listed_billboard(select(0u, frame.billboard_meta.x + instance, listed));
    let quad = vertex_index / 6u;
    let corner = quad_corner(vertex_index % 6u);
    let dist = distance(t.root, frame.camera_position.xyz);
    // Far off: one quad, turned square to the eye.
    let single = one_quad(dist);
    let q = billboard_quad(t, quad, dist, single);
    let square = vec2<f32>(f32(corner & 1u), f32(corner >> 1u));
    let place = select(square, painted_outline(corner), pixels_tall(t.root, t.height) >= OUTLINE_PIXELS);
    var out: BillboardCorner;
    out.drawn = listed && !(single && quad > 0u);
    out.position = billboard_point(t, q, place);
    out.normal = q.normal;
    out.uv = vec2<f32>(place.x, 1.0 - place.y);
    out.root = t.root;
    out.hash = t.hash;
    out.layers = q.layers;
    return out;
}

// The share of a billboard's quad at a texel of coverage `alpha` seen through mip `level`
// covered by its painted blades, as `layers` quads crossing it would cover it
// (billboard_coverage.glsl).
fn billboard_coverage_at(alpha: f32, level: f32, layers: f32) -> f32 {
    let overlap = mix(layers, 1.0, smoothstep(3.8, 5.7, level));
    return 1.0 - pow(1.0 - alpha, overlap);
}

// How the painted blades' own light and dark modulate a billboard's shaded colour.
fn painted_detail(painted: vec4<f32>) -> f32 {
    return clamp(painted.g / 0.55, 0.6, 1.4) * BILLBOARD_GAIN;
}

// The painted texture at `uv` where a fragment's quad stands for `layers` quads: its colour,
// and as alpha the share of the fragment its painted blades cover.
fn billboard_painted(uv: vec2<f32>, layers: f32) -> vec4<f32> {
    var painted = textureSample(grass_texture, grass_sampler, uv);
    // The mip level the sample was taken from (GLSL's textureQueryLod).
    let texels = uv * vec2<f32>(textureDimensions(grass_texture));
    let level = log2(max(max(length(dpdx(texels)), length(dpdy(texels))), 1e-8));
    painted.a = billboard_coverage_at(painted.a, level, layers);
    return painted;
}
