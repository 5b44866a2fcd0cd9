// The portable renderer's Bezier blades drawn as triangle strips, as the Vulkan renderer's
// strip route draws them (blade_strip.vert, blade.frag): each visible blade one instance of its
// distance bucket's command, its vertices where strip_surface.wgsl puts them, its fragments
// shaded by shading.wgsl; and the nearest blades as occluders of the depth pyramid. Needs
// frame.wgsl, blade.wgsl, noise.wgsl, buckets.wgsl, shading.wgsl, strip_surface.wgsl and
// blade_fragment.wgsl.

// ---------------------------------------------------------------- the strips

@vertex
fn strip_vertex(@builtin(vertex_index) vertex_index: u32, @builtin(instance_index) instance: u32) -> BladeVertex {
    let at = strip_place(vertex_index, instance);
    let b = blades[at.id];
    let key = blade_colour_key(at.id);
    let look = blade_look(key, world_xz(b.root.xz));
    let point = blade_point(b, blade_outline(look), at.u, at.v);
    var out: BladeVertex;
    out.clip = target_clip(frame.view_proj * vec4<f32>(point.position, 1.0));
    out.normal = point.normal;
    out.position = point.position;
    out.uv = vec2<f32>(at.u, at.v);
    out.look = look;
    out.vary = albedo_variation(point.position, key, look);
    return out;
}

// ---------------------------------------------------------------- blade occluders

// A blade as an occluder of the depth pyramid (blade_strip.vert `occluder_point`): shortened by
// a pyramid texel and narrowed on each side by a texel and a tenth of its width, so a texel it
// covers at its centre is wholly behind it and the sway before the next cull does not uncover
// what it hides; nothing of a thin blade, and none for one that may be a flowering stalk.
fn occluder_point(b: Blade, u: f32, v_in: f32, none: bool) -> vec3<f32> {
    let outline = u32(frame.blade_style.x);
    let texel = max(frame.viewport.x, frame.viewport.y) / f32(frame.occlusion.y);
    let tip = to_pixels(blade_point(b, outline, 0.5, 1.0).position);
    let tall = length(tip - to_pixels(blade_point(b, outline, 0.5, 0.0).position));
    let v = v_in * max(0.0, 1.0 - texel / max(tall, 1e-3));
    let one = to_pixels(blade_point(b, outline, 1.0, v).position);
    let across = length(one - to_pixels(blade_point(b, outline, 0.0, v).position));
    let keep = select(max(0.0, 1.0 - 2.0 * (texel + 0.1 * across) / max(across, 1e-3)), 0.0, none);
    let p = blade_point(b, outline, 0.5 + (u - 0.5) * keep, v).position;
    // Drawn flat: set back along the view by the most the ridge's fold bulges.
    return p + normalize(p - frame.camera_position.xyz) * 0.5 * b.tip.w;
}

// The nearest blades the last frame listed (the list is nearest bucket first), each a flat
// strip of OCCLUDER_SEGMENTS rows.
@vertex
fn occluder_vertex(@builtin(vertex_index) i: u32, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    let id = visible[instance];
    let u = f32(i & 1u);
    let v = f32(i >> 1u) / f32(OCCLUDER_SEGMENTS);
    let p = occluder_point(blades[id], u, v, may_flower(blade_colour_key(id)));
    return target_clip(frame.view_proj * vec4<f32>(p, 1.0));
}
