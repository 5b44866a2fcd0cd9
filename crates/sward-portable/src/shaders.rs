//! The portable renderer's pipelines: each one's entry points and the core's WESL module it is
//! composed from (sward-core's `wgsl`: its modules and their composition), and which of the
//! frame's blocks each reads.

use sward_core::wgsl::SUBGROUPS;
pub(crate) use sward_core::wgsl::{PipelineSource, ShaderModules, STREAM_SOURCES, TRAMPLE_SOURCE};

use crate::PortableError;

impl From<sward_core::wgsl::ShaderError> for PortableError {
    fn from(error: sward_core::wgsl::ShaderError) -> PortableError {
        PortableError::Shader {
            pipeline: error.pipeline,
            message: error.message,
        }
    }
}

/// The frame's uniform blocks the entry points of `source` read (their bindings, sward-core's
/// `declared::bindings::FRAME_BLOCKS`): what its group binds of the frame's buffer, each block
/// at its place (`declared::frame_blocks`).
pub fn frame_blocks_read(source: &PipelineSource) -> Result<Vec<u32>, PortableError> {
    let entries: Vec<&str> = [Some(source.entry), source.fragment].into_iter().flatten().collect();
    crate::bind::blocks_read(&source.text()?, &entries)
}

/// The simulation.
pub const SIMULATE_SOURCE: PipelineSource = PipelineSource::compute("simulate", "simulate", "simulate");

/// The cull's four passes: count each workgroup's blades per distance bucket, lay the buckets
/// out, scan the workgroups' counts per bucket, place each blade in its bucket's list.
pub const CULL_SOURCES: [PipelineSource; 4] = [
    PipelineSource::compute("count_buckets", "count_buckets", "cull"),
    PipelineSource::compute("lay_out_buckets", "lay_out_buckets", "cull"),
    PipelineSource::compute("scan_buckets", "scan_buckets", "cull"),
    PipelineSource::compute("place_blades", "place_blades", "cull"),
];

/// The feature that keeps the exact-distance sort within WebGPU's default limits (bitonic.wesl:
/// runs of 4,096 blades by 256 invocations in 16 KiB of workgroup memory, where a device that
/// allows it sorts runs of 8,192 by 1,024 in 32 KiB).
pub const NARROW_SORT: &str = "narrow_sort";

/// The exact-distance sort of the blades the strips draw (cull.wesl `sort_drawn`), with the
/// lay-out pass that sizes its dispatch: where the device runs 1,024 invocations a workgroup
/// in 32 KiB, then within WebGPU's default limits (`NARROW_SORT`).
pub const SORT_SOURCES: [[PipelineSource; 2]; 2] = [
    [
        CULL_SOURCES[1],
        PipelineSource::compute("sort_drawn", "sort_drawn", "cull"),
    ],
    [
        PipelineSource {
            name: "lay_out_buckets_narrow",
            features: &[NARROW_SORT],
            ..CULL_SOURCES[1]
        },
        PipelineSource {
            features: &[NARROW_SORT],
            ..PipelineSource::compute("sort_drawn_narrow", "sort_drawn", "cull")
        },
    ],
];

/// A cull pass where the device has subgroups.
const fn with_subgroups(name: &'static str, pass: PipelineSource) -> PipelineSource {
    PipelineSource {
        name,
        features: &[SUBGROUPS],
        ..pass
    }
}

/// The cull's counting, scanning and placing passes where the device has subgroups
/// (`wgpu::Features::SUBGROUP`): the lanes of a subgroup in one bucket are counted with one
/// workgroup atomic. The lay-out is picked with the sort ([`SORT_SOURCES`]).
pub const CULL_SUBGROUP_SOURCES: [PipelineSource; 3] = [
    with_subgroups("count_buckets_subgroups", CULL_SOURCES[0]),
    with_subgroups("scan_buckets_subgroups", CULL_SOURCES[2]),
    with_subgroups("place_blades_subgroups", CULL_SOURCES[3]),
];

/// The generated grass's passes, after the depth pyramid: both grids' patches kept, then per
/// grid (the instanced grass's, the billboards') each workgroup's blades per list counted, the
/// counts scanned, the blades placed in their lists.
pub const GENERATED_SOURCES: [PipelineSource; 7] = [
    PipelineSource::compute("cull_patches", "cull_patches", "generated"),
    PipelineSource::compute("count_generated", "count_generated", "generated"),
    PipelineSource::compute("scan_generated", "scan_generated", "generated"),
    PipelineSource::compute("place_generated", "place_generated", "generated"),
    PipelineSource::compute("count_billboards", "count_billboards", "generated"),
    PipelineSource::compute("scan_billboards", "scan_billboards", "generated"),
    PipelineSource::compute("place_billboards", "place_billboards", "generated"),
];

/// A draw shaded in the sun's light, the shadow map's included (`shadow_map`: where the frame
/// draws none, the shading reads it as all light), its cascades as layers (`shadow_layers`).
const fn lit(pass: PipelineSource) -> PipelineSource {
    PipelineSource {
        features: &["shadow_map", "shadow_layers"],
        ..pass
    }
}

/// The draws: the blades' strips, the ground, the collider spheres, the sky, the generated
/// grass's strips, the billboards.
pub const DRAW_SOURCES: [PipelineSource; 6] = [
    lit(PipelineSource::draw(
        "strips",
        "strip_vertex",
        "strip_fragment",
        "strips",
    )),
    lit(PipelineSource::draw(
        "ground",
        "ground_vertex",
        "ground_fragment",
        "scenery",
    )),
    lit(PipelineSource::draw(
        "colliders",
        "collider_vertex",
        "collider_fragment",
        "scenery",
    )),
    PipelineSource::draw("sky", "sky_vertex", "sky_fragment", "scenery"),
    lit(PipelineSource::draw(
        "generated_strips",
        "generated_vertex",
        "strip_fragment",
        "generated_strips",
    )),
    lit(PipelineSource::draw(
        "billboards",
        "left_billboard_vertex",
        "billboard_fragment",
        "billboards",
    )),
];

/// The sun's shadow map's casters, drawn depth only (a vertex stage alone) through the sun's
/// eyes (`pass_view.wesl`'s `VIEW`, set as each pipeline is made): the ground and the colliders
/// into the field cascade, the near Bezier blades and the instanced grass's near levels into
/// the near cascade.
pub const SHADOW_SOURCES: [PipelineSource; 4] = [
    PipelineSource::compute("shadow_ground", "ground_vertex", "scenery"),
    PipelineSource::compute("shadow_colliders", "collider_vertex", "scenery"),
    PipelineSource::compute("shadow_blades", "strip_vertex", "strips"),
    PipelineSource::compute("shadow_generated", "generated_vertex", "generated_strips"),
];

/// The depth pyramid: the blades, the ground (within its field where fields share the pyramid,
/// else whole) and the colliders drawn as the bits of their depth (into an `r32uint` target:
/// pipelines named `occluder_*`), and a level of the pyramid's buffer copied from them or
/// reduced from the one below.
pub const PYRAMID_SOURCES: [PipelineSource; 5] = [
    PipelineSource::draw("occluder_blades", "occluder_vertex", "occluder_depth", "strips"),
    PipelineSource::draw("occluder_ground", "occluder_ground_vertex", "occluder_depth", "scenery"),
    PipelineSource::draw("occluder_colliders", "collider_vertex", "occluder_depth", "scenery"),
    PipelineSource::compute("reduce_pyramid", "reduce_level", "pyramid"),
    PipelineSource::draw("occluder_ground_whole", "ground_vertex", "occluder_depth", "scenery"),
];

/// The caller's depth folded into the depth pyramid's level 0: from a single-sampled depth
/// texture, from a multisampled one.
pub const CALLER_DEPTH_SOURCES: [PipelineSource; 2] = [
    PipelineSource::compute("fold_caller_depth", "fold_caller_depth", "caller_depth"),
    PipelineSource::compute("fold_caller_depth_samples", "fold_caller_depth_samples", "caller_depth"),
];

/// Whether pipeline `source` is a vertex stage alone (a shadow map's caster), not a compute
/// pipeline: both have no fragment stage.
pub fn vertex_only(source: &PipelineSource) -> bool {
    SHADOW_SOURCES.iter().any(|s| s.name == source.name)
}

/// Every portable pipeline's shader.
pub const PIPELINES: &[PipelineSource] = &[
    STREAM_SOURCES[0],
    STREAM_SOURCES[1],
    TRAMPLE_SOURCE,
    SIMULATE_SOURCE,
    CULL_SOURCES[0],
    CULL_SOURCES[1],
    CULL_SOURCES[2],
    CULL_SOURCES[3],
    CULL_SUBGROUP_SOURCES[0],
    CULL_SUBGROUP_SOURCES[1],
    CULL_SUBGROUP_SOURCES[2],
    SORT_SOURCES[1][0],
    SORT_SOURCES[1][1],
    DRAW_SOURCES[0],
    DRAW_SOURCES[1],
    DRAW_SOURCES[2],
    DRAW_SOURCES[3],
    DRAW_SOURCES[4],
    DRAW_SOURCES[5],
    SHADOW_SOURCES[0],
    SHADOW_SOURCES[1],
    SHADOW_SOURCES[2],
    SHADOW_SOURCES[3],
    GENERATED_SOURCES[0],
    GENERATED_SOURCES[1],
    GENERATED_SOURCES[2],
    GENERATED_SOURCES[3],
    GENERATED_SOURCES[4],
    GENERATED_SOURCES[5],
    GENERATED_SOURCES[6],
    PYRAMID_SOURCES[0],
    PYRAMID_SOURCES[1],
    PYRAMID_SOURCES[2],
    PYRAMID_SOURCES[3],
    PYRAMID_SOURCES[4],
    CALLER_DEPTH_SOURCES[0],
    CALLER_DEPTH_SOURCES[1],
];

#[cfg(test)]
mod tests {
    use crate::PIPELINES;

    /// Each pipeline's text, composed.
    fn texts() -> Vec<(sward_core::wgsl::PipelineSource, String)> {
        PIPELINES
            .iter()
            .map(|p| (*p, p.text().unwrap_or_else(|e| panic!("{e}"))))
            .collect()
    }

    #[test]
    fn every_pipeline_composes_with_its_entry_points() {
        for (pipeline, text) in texts() {
            for entry in [Some(pipeline.entry), pipeline.fragment].into_iter().flatten() {
                assert!(
                    text.contains(&format!("fn {entry}(")),
                    "{} lacks {entry}",
                    pipeline.name
                );
            }
        }
    }

    #[test]
    fn only_the_subgroup_pipelines_hold_subgroup_operations() {
        for (pipeline, text) in texts() {
            assert_eq!(
                text.contains("subgroupAdd("),
                pipeline.uses_subgroups(),
                "{}: its subgroup operations and its features disagree",
                pipeline.name
            );
        }
    }

    #[test]
    fn only_the_trample_pass_writes_the_trample_map() {
        let writers: Vec<&str> = texts()
            .into_iter()
            .filter(|(_, text)| {
                text.lines()
                    .any(|line| line.starts_with("var<storage, read_write>") && line.contains("trample_texels"))
            })
            .map(|(pipeline, _)| pipeline.name)
            .collect();
        assert_eq!(writers, ["trample"]);
        let readers = texts()
            .into_iter()
            .filter(|(_, text)| text.contains("trample_texels"))
            .count();
        assert!(readers > 4, "the trample map is read by {readers} pipelines");
    }
}
