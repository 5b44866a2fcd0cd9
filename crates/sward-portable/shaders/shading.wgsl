// The look and shading of a blade for the portable renderer (SPEC §8), line for line the Vulkan
// renderer's shading.glsl and common.glsl: the paint maps and their noise (paint.rs), the kinds
// of grass and their flowering stalks (species.rs), a blade's look found once at its root, and
// its shading — a root-to-tip gradient varied per blade and per clump, Lambert or Blinn-Phong
// with diffuse transmission, a sky/ground hemisphere ambient, back-scatter into the sun, fake
// ambient occlusion, the lamps and fog. The sun's shadow map is the Vulkan renderer's alone for
// now: here every point is in full sunlight. Needs frame.wgsl, blade.wgsl and noise.wgsl.

// The lighting model (`shading_model.x`; look.rs `ShadingModel`).
const SHADING_BLINN_PHONG: u32 = 1u;

// The paint maps (paint.rs `PaintMap`): per texel the density's byte lowest, then the length's;
// the tint's red, green and blue bytes (128: the scene's own colour); the species' weights.
@group(0) @binding(20) var<storage, read> paint_texels: array<vec4<u32>>;

// ---------------------------------------------------------------- paint (paint.rs)

// What the paint says at a place: how much grass grows and how tall (fractions), what its
// colour is multiplied by, and each species' weight map there.
struct PaintSample {
    amounts: vec2<f32>,
    tint: vec3<f32>,
    species: vec4<f32>,
}

// paint.rs `unpack_texel`: texel t's paint.
fn paint_texel(t: vec2<u32>) -> PaintSample {
    let w = paint_texels[t.y * frame.paint_size.x + t.x];
    let amounts = vec2<f32>(f32(w.x & 0xffu), f32((w.x >> 8u) & 0xffu)) * (1.0 / 255.0);
    let tint = vec3<f32>(f32(w.y & 0xffu), f32((w.y >> 8u) & 0xffu), f32((w.y >> 16u) & 0xffu)) * (1.0 / 128.0);
    let species = vec4<f32>(f32(w.z & 0xffu), f32((w.z >> 8u) & 0xffu), f32((w.z >> 16u) & 0xffu), f32(w.z >> 24u)) * (1.0 / 255.0);
    return PaintSample(amounts, tint, species);
}

fn mix_paint(a: PaintSample, b: PaintSample, t: f32) -> PaintSample {
    return PaintSample(mix(a.amounts, b.amounts, vec2<f32>(t)), mix(a.tint, b.tint, vec3<f32>(t)), mix(a.species, b.species, vec4<f32>(t)));
}

// paint.rs `PaintMap::at`: the four nearest texels blended, the edge carrying on beyond them.
fn paint_map_at(world: vec2<f32>) -> PaintSample {
    let limit = vec2<f32>(frame.paint_size.xy) - 1.0;
    let at = clamp((world - frame.paint_area.xy) * frame.paint_area.zw - 0.5, vec2<f32>(0.0), limit);
    let low = floor(at);
    let f = at - low;
    let low_texel = vec2<u32>(low);
    let high_texel = min(low_texel + 1u, frame.paint_size.xy - 1u);
    let near = mix_paint(paint_texel(low_texel), paint_texel(vec2<u32>(high_texel.x, low_texel.y)), f.x);
    let far = mix_paint(paint_texel(vec2<u32>(low_texel.x, high_texel.y)), paint_texel(high_texel), f.x);
    return mix_paint(near, far, f.y);
}

// paint.rs `noise_patch`: how much of a noise patch (`noise`: x patches per unit, y cover, z
// softness) covers world ground point `world`, the noise shifted by `offset`.
fn noise_patch(world: vec2<f32>, noise: vec4<f32>, offset: vec2<f32>) -> f32 {
    let n = 0.5 + 0.5 * simplex_noise(world * noise.x + offset);
    let threshold = 1.0 - noise.y;
    let soft = noise.z;
    if (soft > 0.0) {
        return smoothstep(threshold - soft, threshold + soft, n);
    }
    return step(threshold, n);
}

// The maps' paint at world ground point `world`, or the full paint where no map is painted.
fn paint_map_or_full(world: vec2<f32>) -> PaintSample {
    if (frame.paint_size.x == 0u) {
        return PaintSample(vec2<f32>(1.0), vec3<f32>(1.0), vec4<f32>(1.0));
    }
    return paint_map_at(world);
}

// paint.rs `GroundPaint::at`: how much grass grows at world ground point `world`.
fn painted_density(p: PaintSample, world: vec2<f32>) -> f32 {
    var density = p.amounts.x;
    if (frame.paint_noise.x > 0.0) {
        density *= noise_patch(world, frame.paint_noise, vec2<f32>(57.3, -131.9));
    }
    return density;
}

// paint.rs `GroundPaint::at`: what the grass's colour is multiplied by at `world`.
fn painted_tint(p: PaintSample, world: vec2<f32>) -> vec3<f32> {
    var tint = p.tint;
    if (frame.paint_tint_noise.x > 0.0) {
        let amount = noise_patch(world, frame.paint_tint_noise, vec2<f32>(-211.7, 93.1));
        tint *= mix(vec3<f32>(1.0), frame.paint_tint_color.rgb, vec3<f32>(amount));
    }
    return tint;
}

// ---------------------------------------------------------------- species (species.rs)

fn species_count() -> u32 {
    return frame.species_meta.x;
}

fn species_weight(k: u32, maps: vec4<f32>) -> f32 {
    return frame.species[4u * k + 1u].w * maps[k];
}

// species.rs `species_of`: the species of the blade with hash `hash` where the weight maps read
// `maps`.
const SPECIES_SALT: u32 = 0x5bd1e995u;
fn species_drawn(hash: u32, maps: vec4<f32>) -> u32 {
    let n = species_count();
    if (n <= 1u) {
        return 0u;
    }
    var total = 0.0;
    for (var k = 0u; k < n; k++) {
        total += species_weight(k, maps);
    }
    if (total <= 0.0) {
        return 0u;
    }
    var draw = hash_unit(hash ^ SPECIES_SALT) * total;
    for (var k = 0u; k < n; k++) {
        let w = species_weight(k, maps);
        if (draw < w) {
            return k;
        }
        draw -= w;
    }
    return n - 1u;
}

// species.rs `seed_head_drawn`: whether the blade with hash `key`, of species `k`, flowers.
const SEED_HEAD_SALT: u32 = 0x27d4eb2fu;
fn seed_head_drawn(key: u32, k: u32) -> bool {
    return frame.species_meta.y != 0u && hash_unit(key ^ SEED_HEAD_SALT) < frame.seed_heads[2u * k].x;
}

// What a blade's colour comes from, found once at its root: x its species (low byte) and whether
// it is tinted or flowers, y its tint (a quarter of it, packed).
const LOOK_TINTED: u32 = 0x80000000u;
const LOOK_SEED_HEAD: u32 = 0x40000000u;
fn blade_look(key: u32, world_root: vec2<f32>) -> vec2<u32> {
    if (frame.paint_size.x == 0u && frame.paint_tint_noise.x <= 0.0 && species_count() == 0u) {
        return vec2<u32>(0u);
    }
    let p = paint_map_or_full(world_root);
    let tint = painted_tint(p, world_root);
    let k = species_drawn(key, p.species);
    let head = select(0u, LOOK_SEED_HEAD, seed_head_drawn(key, k));
    return vec2<u32>(k | head | LOOK_TINTED, pack4x8unorm(vec4<f32>(0.25 * tint, 0.0)));
}

// Whether the blade with hash `key` may be a flowering stalk, whatever its kind: found without
// the paint, for the passes that only need to know it is surely a leaf (occluders).
fn may_flower(key: u32) -> bool {
    if (frame.species_meta.y == 0u) {
        return false;
    }
    var most = 0.0;
    for (var k = 0u; k < species_count(); k++) {
        most = max(most, frame.seed_heads[2u * k].x);
    }
    return hash_unit(key ^ SEED_HEAD_SALT) < most;
}

fn seed_head_length(look: vec2<u32>) -> f32 {
    return select(0.0, frame.seed_heads[2u * (look.x & 0xffu)].y, (look.x & LOOK_SEED_HEAD) != 0u);
}

// The outline a blade of look `look` is drawn with: a flowering stalk with its species' head, or
// a leaf of the scene's shape (`blade_style.x`).
fn blade_outline(look: vec2<u32>) -> u32 {
    let k = look.x & 0xffu;
    let head = select(0u, u32(round(frame.seed_heads[2u * k].y * 255.0)), (look.x & LOOK_SEED_HEAD) != 0u);
    return u32(frame.blade_style.x) | (head << 8u);
}

// The root and tip colours of the grass as the ground wears it, where the species' maps read
// `maps` (the scene's where it has none).
struct GrassColours {
    root: vec3<f32>,
    tip: vec3<f32>,
}

fn ground_grass_colours(maps: vec4<f32>) -> GrassColours {
    var out = GrassColours(frame.root_color.rgb, frame.tip_color.rgb);
    let n = species_count();
    var total = 0.0;
    var r = vec3<f32>(0.0);
    var t = vec3<f32>(0.0);
    for (var k = 0u; k < n; k++) {
        let w = species_weight(k, maps);
        r += w * frame.species[4u * k + 2u].rgb;
        let heads = frame.seed_heads[2u * k];
        let seeds = heads.x * min(2.0 * heads.y, 1.0);
        t += w * mix(frame.species[4u * k + 3u].rgb, frame.seed_heads[2u * k + 1u].rgb, vec3<f32>(seeds));
        total += w;
    }
    if (total > 0.0) {
        out = GrassColours(r / total, t / total);
    }
    return out;
}

// ---------------------------------------------------------------- shading (shading.glsl)

// What blade `blade` of look `look` at `position` multiplies its kind's colours by.
fn albedo_variation(position: vec3<f32>, blade: u32, look: vec2<u32>) -> vec3<f32> {
    let jitter = frame.root_color.w;
    let variation = frame.shading_extra.y;
    let xz = world_xz(position.xz) * frame.shading_extra.z;
    let clump = value_noise(xz) - 0.5;
    let clump_hue = value_noise(xz * 0.7 + vec2<f32>(31.7)) - 0.5;
    let shade = (hash_unit(blade) - 0.5) * jitter + clump * variation;
    let hue = (hash_unit(blade ^ 0x9e3779b9u) - 0.5) * jitter + clump_hue * 2.0 * variation;
    var vary = vec3<f32>(1.0 + shade);
    vary.r *= 1.0 + 1.5 * hue;
    if ((look.x & LOOK_TINTED) != 0u) {
        vary *= 4.0 * unpack4x8unorm(look.y).rgb;
    }
    return vary;
}

fn root_albedo(look: vec2<u32>) -> vec3<f32> {
    return select(frame.root_color.rgb, frame.species[4u * (look.x & 0xffu) + 2u].rgb, species_count() > 0u);
}

fn tip_albedo(look: vec2<u32>) -> vec3<f32> {
    return select(frame.tip_color.rgb, frame.species[4u * (look.x & 0xffu) + 3u].rgb, species_count() > 0u);
}

// The colour at height v: a root-to-tip gradient; a flowering stalk's head in its own colour,
// with rows of spikelets.
fn blade_albedo(v: f32, look: vec2<u32>, vary: vec3<f32>) -> vec3<f32> {
    var base = mix(root_albedo(look), tip_albedo(look), vec3<f32>(v));
    let head = seed_head_length(look);
    if (head > 0.0) {
        var seeds = frame.seed_heads[2u * (look.x & 0xffu) + 1u].rgb;
        let rows = sin(6.2831853 * v / head * 8.0);
        seeds *= 0.85 + 0.2 * rows;
        base = mix(base, seeds, vec3<f32>(smoothstep(1.0 - head - 0.02, 1.0 - head + 0.06, v)));
    }
    return max(base * vary, vec3<f32>(0.0));
}

// Fake ambient occlusion: dark at the root where blades crowd, a faint groove along the midrib.
fn occlusion(uv: vec2<f32>) -> f32 {
    let strength = frame.shading_extra.x;
    let root = mix(1.0 - strength, 1.0, smoothstep(0.0, 0.7, uv.y));
    // Squared by a product: pow of a negative base is undefined in WGSL, as in GLSL.
    let off_rib = (uv.x - 0.5) / 0.06;
    let midrib = 1.0 - 0.35 * strength * exp(-off_rib * off_rib);
    return root * midrib;
}

// Sunlight on a thin blade seen from the side whose normal is `n`: reflected, or transmitted
// through the blade toward the thin tip.
fn sun_on_side(n: vec3<f32>, l: vec3<f32>, v: f32) -> f32 {
    let n_dot_l = dot(n, l);
    let transmission = frame.shading_model.w * (0.5 + v);
    return select(-n_dot_l * transmission, n_dot_l, n_dot_l >= 0.0);
}

fn hemisphere_ambient(n: vec3<f32>) -> vec3<f32> {
    let sky = frame.sky_zenith.rgb * frame.light_direction.w * 2.0;
    let bounce = frame.ground_color.rgb * (frame.light_color.rgb * max(frame.light_direction.y, 0.0) + sky);
    return mix(bounce, sky, vec3<f32>(0.5 + 0.5 * n.y));
}

fn light_on_side(n: vec3<f32>, l: vec3<f32>, sun: vec3<f32>, uv: vec2<f32>, ao: f32) -> vec3<f32> {
    return hemisphere_ambient(n) * ao + sun * sun_on_side(n, l, uv.y);
}

// Lamp k's light at `p` and the direction toward it: Bevy's falloff, within a spot's cone.
struct LampLight {
    light: vec3<f32>,
    toward: vec3<f32>,
}

fn lamp_light(k: u32, p: vec3<f32>) -> LampLight {
    let at = frame.lamps[3u * k];
    let light = frame.lamps[3u * k + 1u];
    let spot = frame.lamps[3u * k + 2u];
    let to = at.xyz - p;
    let dist_sq = max(dot(to, to), 1e-4);
    let l = to * inverseSqrt(dist_sq);
    let reach = dist_sq / max(at.w * at.w, 1e-8);
    let window = clamp(1.0 - reach * reach, 0.0, 1.0);
    var cone = 1.0;
    if (light.w > -1.5) {
        let t = clamp((dot(-l, spot.xyz) - light.w) / max(spot.w - light.w, 1e-4), 0.0, 1.0);
        cone = t * t;
    }
    return LampLight(light.rgb * (window * window * cone / dist_sq), l);
}

fn apply_fog(color: vec3<f32>, dist: f32) -> vec3<f32> {
    let fog = 1.0 - exp(-frame.sky_horizon.w * dist);
    return mix(color, frame.sky_horizon.rgb, vec3<f32>(fog));
}

// Share of sunlight reaching `p`: the shadow map is not drawn by the portable renderer yet.
fn sunlight(p: vec3<f32>) -> f32 {
    return 1.0;
}

// The colour at `position` with (either side's) normal `normal` and blade coordinates `uv` of a
// blade of look `look` whose colour varies by `vary`, in `sunlit` of the sunlight, fogged.
fn shade_blade_lit(normal: vec3<f32>, position: vec3<f32>, uv: vec2<f32>, look: vec2<u32>, vary: vec3<f32>, sunlit: f32) -> vec3<f32> {
    let to_eye = frame.camera_position.xyz - position;
    let dist = length(to_eye);
    let view = to_eye / max(dist, 1e-6);
    let n = normalize_or_zero(normal);
    // The side the eye sees, blended over a narrow band of angles (shading.glsl says why).
    let front = smoothstep(-0.2, 0.2, dot(n, view));
    let l = frame.light_direction.xyz;
    let sun = frame.light_color.rgb * sunlit;
    let albedo = blade_albedo(uv.y, look, vary);
    let ao = occlusion(uv);
    var color = albedo * mix(light_on_side(-n, l, sun, uv, ao), light_on_side(n, l, sun, uv, ao), vec3<f32>(front));
    for (var k = 0u; k < frame.lamp_meta.x; k++) {
        let lamp = lamp_light(k, position);
        color += albedo * lamp.light * mix(sun_on_side(-n, lamp.toward, uv.y), sun_on_side(n, lamp.toward, uv.y), front);
    }
    if (u32(frame.shading_model.x) == SHADING_BLINN_PHONG) {
        let h = normalize(l + view);
        let tip = uv.y * uv.y;
        let highlight = mix(pow(max(dot(-n, h), 0.0), frame.shading_model.z), pow(max(dot(n, h), 0.0), frame.shading_model.z), front);
        color += sun * frame.shading_model.y * tip * highlight;
    }
    let into_sun = pow(max(dot(-view, l), 0.0), 4.0);
    color += albedo * sun * frame.shading_model.w * into_sun * (0.3 + 0.7 * uv.y) * 1.5;
    return apply_fog(color, dist);
}

// Broken maths made visible: NaN or infinity becomes magenta, which the picture tests look for.
fn guard_color(color: vec3<f32>) -> vec4<f32> {
    let bad = any(color != color) || any(abs(color) > vec3<f32>(3.0e38));
    return select(vec4<f32>(color, 1.0), vec4<f32>(1.0, 0.0, 1.0, 1.0), bad);
}
