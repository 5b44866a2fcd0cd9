// Where the depth pyramid's levels lie in its buffer (pyramid.wgsl): one after another from
// level 0, each row by row, level k `side >> k` texels square. Stands alone.

// The first texel of level `level` of a pyramid whose level 0 is `side` texels square (a power
// of two, `level` at most its last): the levels before it, side² (1 + 1/4 + … ) texels, in
// closed form — the cull reads the pyramid in its innermost loop (a loop over the levels here
// cost cis565 2^20 0.23 ms on the H100).
fn pyramid_start(side: u32, level: u32) -> u32 {
    let at = side >> level;
    return (4u * (side * side - at * at)) / 3u;
}

// The levels of a pyramid whose level 0 is `side` texels square (a power of two).
fn pyramid_levels(side: u32) -> u32 {
    return firstLeadingBit(side) + 1u;
}
