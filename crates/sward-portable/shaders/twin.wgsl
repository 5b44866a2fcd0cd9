// An instanced blade of the grid (instanced.glsl): the blade of a grid cell, from the cell's
// hash, clumps, paint and kinds (`instanced_twin`), and how the frame poses it — settled in the
// gravity and wind, sinking at the cut-off, laid along trails, cut where mown. The generated
// grass lists and draws these blades; the streamed field's Bezier blades are made as them, their
// twins. Needs frame.wgsl, blade.wgsl, noise.wgsl, shading.wgsl, trample_map.wgsl (its
// `trample_texels` bound by the pass), physics.wgsl, ground_grid.wgsl and outline.wgsl.

// stream.rs `STIFFNESS_SALT`, paint.rs `DENSITY_SALT`.
const STIFFNESS_SALT: u32 = 0x3c6ef372u;
const DENSITY_SALT: u32 = 0x2f6b3a91u;
// Steps a twin settles in, and steps toward the curve's length within each (instanced.glsl
// `SETTLE_STEPS`, `CHORD_STEPS`).
const SETTLE_STEPS: i32 = 6;
const CHORD_STEPS: i32 = 2;

// An instanced blade (instanced.glsl `InstancedBlade`).
struct Twin {
    root: vec3<f32>,
    facing: f32,
    height: f32,
    width: f32,
    bend: f32,
    hash: u32,
    species: u32,
    outline: u32,
    tip: vec3<f32>,
}

// paint.rs `painted_height`: the height a blade with hash `hash` grows to where the paint says
// `paint` — none unless its draw falls under the density, else scaled by the length.
fn painted_height(hash: u32, height: f32, paint: vec2<f32>) -> f32 {
    return select(0.0, height * paint.y, hash_unit(hash ^ DENSITY_SALT) < paint.x);
}

// The outline a blade of species `k` is drawn with: a flowering stalk with the species' head
// where `flowering`, else a leaf of the scene's shape.
fn outline_of(k: u32, flowering: bool) -> u32 {
    let head = select(0u, u32(round(frame.seed_heads[2u * k].y * 255.0)), flowering);
    return u32(frame.blade_style.x) | (head << 8u);
}

// A grid of generated grass (instanced.rs `InstancedParams`): the instanced grass's or the
// billboards'.
struct Grid {
    spacing: f32,
    clump_scale: f32,
    // Height min, max; half-width min, max.
    shape: vec4<f32>,
    bend: f32,
    seed: u32,
    // The billboards' grid: a billboard is of a kind by its colour only (see `grid_blade`).
    billboards: bool,
}

fn instanced_grid() -> Grid {
    let g = frame.instanced_grid;
    return Grid(g.x, g.w, frame.instanced_shape, frame.instanced_motion.x, frame.instanced_meta.x, false);
}

fn billboard_grid() -> Grid {
    let g = frame.billboard_grid;
    return Grid(g.x, g.w, frame.billboard_shape, 0.0, frame.billboard_meta.w, true);
}

// The blade of cell `cell` of grid `grid` (instanced.rs `blade_at`, instanced.glsl
// `instanced_blade_of`): jittered position, clumped height and width, facing, bend, all from the
// cell's hash and simplex noise of its position, of its kind where the scene lists kinds; on the
// ground's height grid, and of no height off it. Uncut.
fn grid_blade(cell: vec2<i32>, grid: Grid) -> Twin {
    var shape = grid.shape;
    var bend = grid.bend;
    let h = cell_hash(cell, grid.seed);
    let h1 = hash_word(h);
    let h2 = hash_word(h ^ 0x68e31da4u);
    let h3 = hash_word(h ^ 0xb5297a4du);
    let h4 = hash_word(h ^ 0x1b56c4e9u);
    let h5 = hash_word(h ^ 0x7f4a7c15u);
    let xz = (vec2<f32>(cell) + vec2<f32>(hash_unit(h1), hash_unit(h2))) * grid.spacing;
    // The paint there (read once), and its kind of grass where the scene lists kinds: their
    // shape ranges and lean.
    let paint = paint_map_or_full(xz);
    let species = species_drawn(h, paint.species);
    if (species_count() > 0u && !grid.billboards) {
        shape = frame.species[4u * species];
        bend = frame.species[4u * species + 1u].z;
    } else if (species_count() > 0u) {
        // A billboard is of a kind too (its colour, by its hash): the tallest kind's billboards
        // stand as tall as the scene's billboards, the others as much shorter as their blades
        // are (so the billboards' bounds hold).
        var tallest = 0.0;
        for (var k = 0u; k < species_count(); k++) {
            tallest = max(tallest, dot(frame.species[4u * k].xy, vec2<f32>(1.0)));
        }
        let kind = dot(frame.species[4u * species].xy, vec2<f32>(1.0));
        shape = vec4<f32>(shape.xy * (kind / max(tallest, 1e-6)), shape.zw);
    }
    let ground = ground_at(xz);
    let clump = 0.5 + 0.5 * simplex_noise(xz * grid.clump_scale);
    let tall = clamp(clump + 0.25 * (hash_unit(h3) - 0.5), 0.0, 1.0);
    let at = frame_xz(xz);
    var b: Twin;
    b.root = vec3<f32>(at.x, ground.x, at.y);
    b.facing = hash_unit(h4) * 6.2831855;
    // As the paint says (paint.rs): a blade whose draw falls above the density does not grow.
    let painted = vec2<f32>(painted_density(paint, xz), paint.amounts.y);
    b.height = select(0.0, painted_height(h, shape.x + (shape.y - shape.x) * tall, painted), ground.y > 0.0);
    b.width = shape.z + (shape.w - shape.z) * (0.5 * tall + 0.5 * hash_unit(h5));
    b.bend = bend * (0.5 + hash_unit(h5));
    b.hash = h;
    b.species = select(species, 0u, grid.billboards);
    // A flowering stalk where its kind has them and its hash says, as its Bezier twin is drawn.
    b.outline = outline_of(species, !grid.billboards && seed_head_drawn(h, species));
    b.tip = b.root;
    return b;
}

// The instanced grass's blade of grid cell `cell` (the streamed field's twin of a Bezier blade).
fn instanced_twin(cell: vec2<i32>) -> Twin {
    return grid_blade(cell, instanced_grid());
}

// The stiffness of the blade of a cell with hash `hash`, of species `species` (stream.rs
// `blade_of_cell`).
fn grid_stiffness(hash: u32, species: u32) -> f32 {
    var range = frame.stream_reach.zw;
    if (species_count() > 0u) {
        range = frame.species[4u * species + 1u].xy;
    }
    return mix(range.x, range.y, hash_unit(hash ^ STIFFNESS_SALT));
}

// Where a blade rooted at `root`, `h` long, its face toward `front`, `k` stiff, leaning `bend`
// at rest, comes to rest in the frame's gravity and wind (instanced.glsl `settle`, which says
// how): its tip before the physics step's validation, which drawing it applies.
fn settle(root: vec3<f32>, h: f32, front: vec3<f32>, k: f32, bend: f32) -> vec3<f32> {
    let up = vec3<f32>(0.0, 1.0, 0.0);
    let rest = root + h * normalize(up + bend * front);
    let forces = frame.counts.w;
    // Nothing holds a blade up without recovery: it lies down.
    let stiffness = select(1e-3, max(k, 1e-3), (forces & FORCE_RECOVERY) != 0u);
    let share = min(stiffness * frame.simulation.x, 1.0);
    var wind = vec3<f32>(0.0);
    if ((forces & FORCE_WIND) != 0u) {
        wind = wind_at(root, frame.camera_position.w);
    }
    let gravity = (forces & FORCE_GRAVITY) != 0u;
    let toward_point = frame.simulation.z != 0.0;
    var steady_gravity = vec3<f32>(0.0);
    if (gravity && !toward_point) {
        steady_gravity = gravity_force(root, front);
    }
    var tip = rest;
    var way = up;
    var balance_reach = h;
    var chord = h;
    for (var i = 0; i < SETTLE_STEPS; i++) {
        var force = wind_force(wind, root, tip, up, h) + steady_gravity;
        if (gravity && toward_point) {
            force += gravity_force(tip, front);
        }
        var balance = rest + force / stiffness;
        balance -= up * min(dot(up, balance - root), 0.0);
        balance_reach = length(balance - root);
        way = select(up, (balance - root) / balance_reach, balance_reach > 1e-9);
        for (var j = 0; j < CHORD_STEPS; j++) {
            let reach = mix(chord, balance_reach, share);
            chord = reach * h / max(guided_length(root, up, h, root + way * reach).w, 1e-12);
        }
        // Damped (instanced.glsl `settle`).
        tip = mix(tip, root + way * chord, vec3<f32>(0.7));
    }
    return root + way * min(mix(chord, balance_reach, share), LEAN_RANGE * h);
}

// Twin `twin` posed `dist` from the eye (instanced.glsl `posed`): sinking into the ground over
// the last 15 % before the cut-off, its tip where it settles in the frame's gravity and wind,
// laid along a trail where the trample map says it was walked on.
fn posed(twin: Twin, dist: f32) -> Twin {
    var b = twin;
    let radius = frame.instanced_grid.y;
    b.height = b.height * (1.0 - smoothstep(0.85 * radius, radius, dist));
    let front = normalize_or_zero(cross(vec3<f32>(0.0, 1.0, 0.0), blade_across(b.facing)));
    b.tip = settle(b.root, max(b.height, 1e-4), front, grid_stiffness(b.hash, b.species), b.bend);
    // Trampled (trample.rs): laid along the push, down to lying flat at full strength.
    let push = trample_push(b.root.xz);
    let flat_by = min(length(push), 1.0);
    if (flat_by > 0.0) {
        let along = vec3<f32>(push.x, 0.0, push.y) / length(push);
        b.tip = mix(b.tip, b.root + b.height * (along + vec3<f32>(0.0, 0.08, 0.0)), vec3<f32>(flat_by));
    }
    return b;
}

// Twin `twin` no taller than the trample map's cut where it stands (mown grass).
fn cut(twin: Twin) -> Twin {
    var b = twin;
    b.height = min(b.height, trample_cut(b.root.xz));
    return b;
}

// Twin `twin` as the frame shows it `dist` from the eye (instanced.glsl `twin_shape`): cut,
// posed; its guide and tip as validation makes the curve of its root, height and tip.
fn twin_shape(twin: Twin, dist: f32) -> Blade {
    let b = posed(cut(twin), dist);
    return validated(b.root, max(b.height, 1e-4), b.tip);
}
