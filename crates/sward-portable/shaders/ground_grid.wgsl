// The ground's height grid as the portable passes read it (mesh.rs `HeightGrid::height_at`; the
// Vulkan renderer's instanced.glsl `ground_height`): the ground mesh's vertices (position,
// normal), where the ground is a height grid (`instanced_ground_cells`), a placeholder
// otherwise. The trample map stands its texels on it, the streamed tiles their blades. Needs
// frame.wgsl.

@group(0) @binding(7) var<storage, read> ground_points: array<vec4<f32>>;

// The ground at world ground point `xz`: x its height on the grid's triangles, y 1 where `xz`
// lies on the grid (or there is no grid: height 0), 0 off it.
fn ground_at(xz: vec2<f32>) -> vec2<f32> {
    let n = frame.instanced_ground_cells.xy;
    if (n.x == 0u) {
        return vec2<f32>(0.0, 1.0);
    }
    let lo = frame.instanced_ground.xy;
    let hi = frame.instanced_ground.zw;
    let cells = vec2<f32>(n - 1u);
    let q = (xz - lo) / (hi - lo) * cells;
    if (any(q < vec2<f32>(0.0)) || any(q > cells)) {
        return vec2<f32>(0.0);
    }
    let cell = min(floor(q), cells - 1.0);
    let f = q - cell;
    let i = u32(cell.x);
    let j = u32(cell.y);
    let h00 = ground_points[2u * (j * n.x + i)].y;
    let h10 = ground_points[2u * (j * n.x + i + 1u)].y;
    let h01 = ground_points[2u * ((j + 1u) * n.x + i)].y;
    let h11 = ground_points[2u * ((j + 1u) * n.x + i + 1u)].y;
    if (f.x + f.y <= 1.0) {
        return vec2<f32>(h00 + f.x * (h10 - h00) + f.y * (h01 - h00), 1.0);
    }
    return vec2<f32>(h11 + (1.0 - f.x) * (h01 - h11) + (1.0 - f.y) * (h10 - h11), 1.0);
}

// The ground's height at world point `xz`: on the grid, 0 off it or with none.
fn grid_height(xz: vec2<f32>) -> f32 {
    return ground_at(xz).x;
}
