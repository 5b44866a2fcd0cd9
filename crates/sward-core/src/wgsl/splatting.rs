//! The generated far field's passes as both renderers run them where the device has 64-bit
//! atomic min/max (wgpu's `SHADER_INT64_ATOMIC_MIN_MAX`): both grids' patches kept
//! (`patch_cull.wesl`), each grid counted with its far blades splatted, its counts scanned, its
//! listed blades placed (`generate_grid.wesl`, `generated_scan.wesl`), the near far blades and
//! billboards rasterized by compute (`instanced_raster.wesl`, `billboard_raster.wesl`) between
//! the splat tiles' farthest depths (`splat_tiles.wesl`), the far Bezier blades splatted
//! (`splat_blades.wesl`), and the splat cells resolved into the frame (`splat_resolve.wesl`). Which grid, chunk or pass a pipeline is is set by its
//! overrides (`declared::constants`) as it is made.

use super::PipelineSource;

/// Both generated grids' patch lists and dispatch sizes (`patch_cull.wesl`), composed with
/// `features` (the Vulkan renderer's depth pyramid is an image: `pyramid_image`).
pub const fn patch_cull(features: &'static [&'static str]) -> PipelineSource {
    PipelineSource {
        features,
        ..PipelineSource::compute("patch_cull", "cull_patches", "patch_cull")
    }
}

/// One of a generated grid's two passes (`generate_grid.wesl`; which grid by
/// `constants::BILLBOARDS`): counting, or placing.
const fn generate_grid(features: &'static [&'static str]) -> PipelineSource {
    PipelineSource {
        features,
        ..PipelineSource::compute("generate_grid", "generate_grid", "generate_grid")
    }
}

/// A generated grid's counting pass on a device with 64-bit atomics, its far blades splatted:
/// the instanced grass's (`[0]`, its workgroups queueing their splats), the billboards' (`[1]`).
pub const GENERATE_SPLATS: [PipelineSource; 2] = [
    generate_grid(&["splats", "queue", "shadow_map"]),
    generate_grid(&["splats", "shadow_map"]),
];
/// The same for the portable renderer, whose shadow map holds its cascades as layers
/// (`shadow_layers`).
pub const GENERATE_SPLATS_LAYERED: [PipelineSource; 2] = [
    generate_grid(&["splats", "queue", "shadow_map", "shadow_layers"]),
    generate_grid(&["splats", "shadow_map", "shadow_layers"]),
];
/// A generated grid's counting pass on a device without 64-bit atomics: nothing is splatted.
pub const GENERATE_DRAWN: PipelineSource = generate_grid(&[]);
/// A generated grid's placing pass.
pub const GENERATE_PLACE: PipelineSource = generate_grid(&["place"]);

/// A generated grid's counts scanned, and the compute rasterizers' dispatch sizes
/// (`generated_scan.wesl`; the grid by `constants::BILLBOARDS`).
pub const GENERATED_SCAN: PipelineSource =
    PipelineSource::compute("generated_scan", "scan_generated", "generated_scan");

/// The instanced grass's blades rasterized by compute, chunk by chunk of their list
/// (`instanced_raster.wesl`; the chunk by `constants::CHUNK`), lit with the shadow map.
pub const INSTANCED_RASTER: PipelineSource = PipelineSource {
    features: &["shadow_map"],
    ..PipelineSource::compute("instanced_raster", "raster_instanced", "instanced_raster")
};

/// The instanced grass's compute rasterizer for the portable renderer's layered shadow map.
pub const INSTANCED_RASTER_LAYERED: PipelineSource = PipelineSource {
    features: &["shadow_map", "shadow_layers"],
    ..INSTANCED_RASTER
};

/// The billboards rasterized by compute (`billboard_raster.wesl`), lit with the shadow map.
pub const BILLBOARD_RASTER: PipelineSource = PipelineSource {
    features: &["shadow_map"],
    ..PipelineSource::compute("billboard_raster", "raster_billboards", "billboard_raster")
};

/// The billboards' compute rasterizer for the portable renderer's layered shadow map.
pub const BILLBOARD_RASTER_LAYERED: PipelineSource = PipelineSource {
    features: &["shadow_map", "shadow_layers"],
    ..BILLBOARD_RASTER
};

/// The far Bezier blades splatted (`splat_blades.wesl`, a blade an invocation), lit with the
/// shadow map: over the Vulkan renderer's ordered list, from the range its ordering wrote.
pub const SPLAT_BLADES: PipelineSource = PipelineSource {
    features: &["shadow_map"],
    ..PipelineSource::compute("splat_blades", "splat_blades", "splat_blades")
};

/// The same over the portable renderer's cull list (`portable_lists`: the range from its
/// bucket counters and its splat dispatch's last word), lit with its layered shadow map.
pub const SPLAT_LISTED_BLADES: PipelineSource = PipelineSource {
    name: "splat_listed_blades",
    features: &["shadow_map", "shadow_layers", "portable_lists"],
    ..SPLAT_BLADES
};

/// Each splat tile's farthest depth (`splat_tiles.wesl`; which pass by `constants::SECOND_PASS`
/// and `constants::GENERATED`).
pub const SPLAT_TILES: PipelineSource = PipelineSource::compute("splat_tiles", "splat_tiles", "splat_tiles");

/// Every word of the splat buffer set to all ones — cells empty, tiles hiding nothing — before
/// a frame splats (`splat_tiles.wesl` `clear_splats`): the portable renderer's fill, where wgpu
/// fills a buffer only with zeros.
pub const SPLAT_CLEAR: PipelineSource = PipelineSource::compute("splat_clear", "clear_splats", "splat_tiles");

/// The splatted far field resolved into the frame (`splat_resolve.wesl`): a fragment stage
/// alone, over the sky's triangle, covering each pixel's samples whose cells hold a blade.
pub const SPLAT_RESOLVE: PipelineSource =
    PipelineSource::draw("splat_resolve", "resolve_splats", "resolve_splats", "splat_resolve");

/// The same over its own screen-covering triangle (`resolve_vertex`), for a renderer that
/// draws it from this module alone (the portable renderer on Metal, DX12 and Vulkan).
pub const SPLAT_RESOLVE_MASKED: PipelineSource = PipelineSource::draw(
    "splat_resolve_masked",
    "resolve_vertex",
    "resolve_splats",
    "splat_resolve",
);

/// The same a sample at a time, with its own screen-covering triangle: each sample takes its
/// own cell, so no sample mask is written (wgpu's SPIR-V writes one as Vulkan refuses it,
/// gfx-rs/wgpu#7311); the MSAA resolve averages the same colours.
pub const SPLAT_RESOLVE_SAMPLES: PipelineSource = PipelineSource::draw(
    "splat_resolve_samples",
    "resolve_vertex",
    "resolve_splat_samples",
    "splat_resolve",
);

/// The splatting pipelines the portable renderer makes (passes/splats.rs), with the resolve a
/// sample at a time it draws where it cannot hand over the pixel-rate one (a browser's WebGPU,
/// GL): the set a browser compiles with 32-bit cells (`narrow_splats`).
/// Each under a name of its own (the generating passes share one module).
pub const PORTABLE_SPLATTING: [PipelineSource; 11] = [
    patch_cull(&[]),
    PipelineSource {
        name: "generate_instanced_splats",
        ..GENERATE_SPLATS_LAYERED[0]
    },
    PipelineSource {
        name: "generate_billboard_splats",
        ..GENERATE_SPLATS_LAYERED[1]
    },
    GENERATED_SCAN,
    PipelineSource {
        name: "place_generated",
        ..GENERATE_PLACE
    },
    INSTANCED_RASTER_LAYERED,
    SPLAT_TILES,
    BILLBOARD_RASTER_LAYERED,
    SPLAT_LISTED_BLADES,
    SPLAT_CLEAR,
    SPLAT_RESOLVE_SAMPLES,
];

/// Every pipeline here, each once (the grids, chunks and passes are overrides of these).
pub const SPLATTING: [PipelineSource; 19] = [
    patch_cull(&[]),
    GENERATE_SPLATS[0],
    GENERATE_SPLATS[1],
    GENERATE_SPLATS_LAYERED[0],
    GENERATE_SPLATS_LAYERED[1],
    GENERATE_DRAWN,
    GENERATE_PLACE,
    GENERATED_SCAN,
    INSTANCED_RASTER,
    INSTANCED_RASTER_LAYERED,
    BILLBOARD_RASTER,
    BILLBOARD_RASTER_LAYERED,
    SPLAT_BLADES,
    SPLAT_LISTED_BLADES,
    SPLAT_TILES,
    SPLAT_CLEAR,
    SPLAT_RESOLVE,
    SPLAT_RESOLVE_MASKED,
    SPLAT_RESOLVE_SAMPLES,
];
