// What the portable renderer draws around the grass, as the Vulkan renderer does (ground.vert,
// ground.frag, collider.vert, collider.frag, sky.vert, sky.frag): the ground — a plane (around
// the eye under a streamed field), a sphere, or the scene's mesh — lit as the blades are, mottled,
// tinted toward the grass as densely as the paint lets it grow; the collider spheres as weathered
// stone; and the sky's gradient with a glow around the sun. Needs frame.wgsl, blade.wgsl,
// noise.wgsl and shading.wgsl.

// The ground's shape (`instanced_ground_cells.z`; frame.rs `GroundShape`).
const GROUND_PLANE: u32 = 0u;
const GROUND_SPHERE: u32 = 1u;
const GROUND_MESH: u32 = 2u;
// The techniques (`instanced_meta.y`; instanced.rs `Technique::index`).
const TECHNIQUE_BEZIER: u32 = 0u;
const TECHNIQUE_BILLBOARD: u32 = 3u;
const TECHNIQUE_LANDSCAPE: u32 = 4u;
// The sphere ground's quads (ground.vert; the renderer draws 6 vertices each).
const SPHERE_RINGS: u32 = 96u;
const SPHERE_SEGMENTS: u32 = 192u;
// The collider spheres' quads (collider.vert).
const COLLIDER_RINGS: u32 = 16u;
const COLLIDER_SEGMENTS: u32 = 32u;

// A vertex of the ground mesh: a position and a normal.
struct GroundVertex {
    position: vec4<f32>,
    normal: vec4<f32>,
}

@group(0) @binding(7) var<storage, read> ground_vertices: array<GroundVertex>;

struct LitVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

fn quad_corner(vertex: u32) -> vec2<f32> {
    // Two triangles: (0,0) (1,0) (1,1), (0,0) (1,1) (0,1).
    let c = array<vec2<f32>, 6>(vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0));
    return c[vertex % 6u];
}

// The unit normal of a UV sphere of `rings` × `segments` quads at vertex `vertex`.
fn sphere_normal(vertex: u32, rings: u32, segments: u32) -> vec3<f32> {
    let quad = vertex / 6u;
    let grid = (vec2<f32>(f32(quad % segments), f32(quad / segments)) + quad_corner(vertex)) / vec2<f32>(f32(segments), f32(rings));
    let phi = 3.14159265 * grid.y;
    let theta = 6.28318531 * grid.x;
    return vec3<f32>(sin(phi) * cos(theta), cos(phi), sin(phi) * sin(theta));
}

fn ground_kind() -> u32 {
    return frame.instanced_ground_cells.z;
}

@vertex
fn ground_vertex(@builtin(vertex_index) vertex: u32) -> LitVertex {
    return ground_at(vertex, frame.ground_extent.xy);
}

// The ground as an occluder of the depth pyramid: a plane no wider than its own field (but
// under a streamed field, which has no edge). Beyond its field a plane hides none of its own
// grass, which stands on it, but it would hide other fields' grass placed lower than it where
// the fields of a view share one pyramid.
@vertex
fn occluder_ground_vertex(@builtin(vertex_index) vertex: u32) -> LitVertex {
    let own = min(frame.ground_extent.xy, frame.ground_extent.zw);
    return ground_at(vertex, select(own, frame.ground_extent.xy, frame.stream.x > 0u));
}

// Vertex `vertex` of the ground: its mesh, its sphere, or a plane reaching `plane_extent`
// (half its width and depth) around the field's middle.
fn ground_at(vertex: u32, plane_extent: vec2<f32>) -> LitVertex {
    var out: LitVertex;
    if (ground_kind() == GROUND_MESH) {
        let v = ground_vertices[vertex];
        out.normal = v.normal.xyz;
        // A hair below the triangles the blades stand on, so roots never float.
        let world = v.position.xyz - v.normal.xyz * 0.002;
        let xz = frame_xz(world.xz);
        out.position = vec3<f32>(xz.x, world.y, xz.y);
    } else if (ground_kind() == GROUND_SPHERE) {
        out.normal = sphere_normal(vertex, SPHERE_RINGS, SPHERE_SEGMENTS);
        // Slightly inside the facets the blades stand on.
        out.position = frame.surface.xyz + out.normal * frame.surface.w * 0.999;
    } else {
        // Under a streamed field the plane goes where the eye goes.
        let middle = select(vec2<f32>(0.0), frame.camera_position.xz, frame.stream.x > 0u);
        let xz = middle + (quad_corner(vertex) * 2.0 - 1.0) * plane_extent;
        out.normal = vec3<f32>(0.0, 1.0, 0.0);
        out.position = vec3<f32>(xz.x, 0.0, xz.y);
    }
    out.clip = target_clip(frame.view_proj * vec4<f32>(out.position, 1.0));
    return out;
}

@fragment
fn ground_fragment(in: LitVertex) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    var xz = world_xz(in.position.xz);
    if (ground_kind() == GROUND_SPHERE) {
        xz = vec2<f32>(in.position.x + in.position.y, in.position.z);
    }
    let mottle = 0.6 * value_noise(xz * 0.9) + 0.4 * value_noise(xz * 4.1 + vec2<f32>(3.7));
    let outside = max(abs(xz) - frame.ground_extent.zw, vec2<f32>(0.0));
    var in_field = select(1.0 - smoothstep(0.0, 2.0, length(outside)), 1.0, ground_kind() != GROUND_PLANE);
    let technique = frame.instanced_meta.y;
    if (technique != TECHNIQUE_BEZIER) {
        in_field = 1.0; // generated grass covers the ground far beyond the grown field
    }
    // A path painted bare shows its soil at every distance.
    let paint = paint_map_or_full(xz);
    let density = painted_density(paint, xz);
    in_field *= density;
    let tint = painted_tint(paint, xz);
    let grass = ground_grass_colours(paint.species);
    var albedo = frame.ground_color.rgb * (0.7 + 0.6 * mottle);
    albedo = mix(albedo, grass.root * tint * (0.8 + 0.4 * mottle), vec3<f32>(0.6 * in_field));
    let dist = distance(frame.camera_position.xyz, in.position);
    if (technique == TECHNIQUE_BILLBOARD || technique == TECHNIQUE_LANDSCAPE) {
        // Past the billboards' reach the ground wears the grass's colour to the horizon.
        let radius = frame.billboard_grid.y;
        let turf = mix(grass.root, grass.tip, vec3<f32>(0.45)) * tint * (0.9 + 0.2 * mottle);
        albedo = mix(albedo, turf, vec3<f32>(density * smoothstep(0.75 * radius, radius, dist)));
    }
    let lambert = max(dot(n, frame.light_direction.xyz), 0.0) * sunlight(in.position);
    var color = albedo * (frame.light_color.rgb * lambert + frame.sky_zenith.rgb * frame.light_direction.w * 2.0);
    for (var k = 0u; k < frame.lamp_meta.x; k++) {
        let lamp = lamp_light(k, in.position);
        color += albedo * lamp.light * max(dot(n, lamp.toward), 0.0);
    }
    return guard_color(apply_fog(color, dist));
}

@vertex
fn collider_vertex(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> LitVertex {
    let sphere = frame.colliders[instance];
    var out: LitVertex;
    out.normal = sphere_normal(vertex, COLLIDER_RINGS, COLLIDER_SEGMENTS);
    out.position = sphere.xyz + out.normal * sphere.w;
    out.clip = target_clip(frame.view_proj * vec4<f32>(out.position, 1.0));
    return out;
}

@fragment
fn collider_fragment(in: LitVertex) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let mottle = 0.7 + 0.3 * value_noise(vec2<f32>(in.position.x + in.position.y, in.position.z) * 3.0);
    let albedo = vec3<f32>(0.32, 0.29, 0.25) * mottle;
    let lambert = max(dot(n, frame.light_direction.xyz), 0.0);
    let sky = frame.light_direction.w * (0.6 + 0.4 * n.y);
    let color = albedo * (frame.light_color.rgb * lambert + frame.sky_zenith.rgb * sky * 2.0);
    return guard_color(apply_fog(color, distance(frame.camera_position.xyz, in.position)));
}

struct SkyVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

// One triangle covering the screen at the far plane.
@vertex
fn sky_vertex(@builtin(vertex_index) vertex: u32) -> SkyVertex {
    let ndc = vec2<f32>(f32((vertex << 1u) & 2u), f32(vertex & 2u)) * 2.0 - 1.0;
    return SkyVertex(vec4<f32>(ndc, 1.0, 1.0), ndc);
}

@fragment
fn sky_fragment(in: SkyVertex) -> @location(0) vec4<f32> {
    // The frame's matrices are sward's, whose y runs down.
    let far_point = frame.inv_view_proj * vec4<f32>(in.ndc.x, -in.ndc.y, 1.0, 1.0);
    let ray = normalize(far_point.xyz / far_point.w - frame.camera_position.xyz);
    let elevation = clamp(ray.y, 0.0, 1.0);
    var color = mix(frame.sky_horizon.rgb, frame.sky_zenith.rgb, vec3<f32>(pow(elevation, 0.6)));
    let sun = max(dot(ray, frame.light_direction.xyz), 0.0);
    color += frame.light_color.rgb * (0.25 * pow(sun, 8.0) + 0.6 * pow(sun, 256.0));
    return guard_color(color);
}
