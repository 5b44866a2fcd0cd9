// The tiles a frame runs (sward-core tiles.rs `ActiveTile`: first blade, blades, whether drawn),
// nearest first, as the host decided them for the view; the pass that binds `active_tiles`
// declares it. Where the field has tiles (`tiles.y`: the workgroups of a tile's row), a pass
// takes a row of workgroups per tile; else a blade per invocation over the whole field. Needs
// frame.wgsl and blade.wgsl.

// The blade an invocation takes: its index, whether there is one, whether its tile is drawn
// (false: a tile just outside the view, simulated so the grass entering it is settled).
struct TiledBlade {
    index: u32,
    taken: bool,
    drawn: bool,
}

fn tiled_blade(id: vec3<u32>, groups: vec3<u32>) -> TiledBlade {
    if (frame.tiles.y == 0u) {
        let i = blade_index(id, groups);
        return TiledBlade(i, i < frame.counts.x, true);
    }
    let tile = active_tiles[id.y];
    return TiledBlade(tile.x + id.x, id.x < tile.y, tile.z != 0u);
}
