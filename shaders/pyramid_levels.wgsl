// Where the depth pyramid's levels lie in its buffer (pyramid.wgsl): one after another from
// level 0, each row by row, level k `side >> k` texels square. Stands alone.

// The first texel of level `level` of a pyramid whose level 0 is `side` texels square.
fn pyramid_start(side: u32, level: u32) -> u32 {
    var start = 0u;
    for (var k = 0u; k < level; k++) {
        let s = max(side >> k, 1u);
        start += s * s;
    }
    return start;
}

// The levels of a pyramid whose level 0 is `side` texels square (a power of two).
fn pyramid_levels(side: u32) -> u32 {
    return firstLeadingBit(side) + 1u;
}
