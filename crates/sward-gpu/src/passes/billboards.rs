//! Billboards (SPEC §7 [B]): their pipelines — generated and culled over their own grid by the
//! instanced blades' passes (`generated.rs`, which keeps both grids' lists in one set of
//! buffers), drawn as three crossed quads of the painted grass texture in one pass or behind a
//! depth pre-pass, and rasterized by compute where the device splats.

use ash::vk;

use crate::error::Result;
use crate::pipelines::{Builder, Depth, GraphicsDesc, Pipeline, Stage::Fragment, Stage::Vertex};
use crate::shaders;

/// The billboards' pipelines.
pub struct BillboardPipelines {
    /// Generated and culled by generate_grid.wesl over their grid: count, scan, place.
    pub cull: [Pipeline; 3],
    /// Their draws.
    pub draws: BillboardDraws,
    /// Rasterized by compute (billboard_raster.wesl), where the device has 64-bit atomics.
    pub raster: Option<Pipeline>,
}

impl BillboardPipelines {
    pub(crate) fn new(b: &Builder) -> Result<BillboardPipelines> {
        Ok(BillboardPipelines {
            cull: crate::passes::generated::generate_passes(b, true)?,
            draws: BillboardDraws::new(b)?,
            raster: match b.ctx.info.int64_atomics {
                true => Some(b.compute_wgsl(&shaders::BILLBOARD_RASTER)?),
                false => None,
            },
        })
    }
}

/// The ways to draw the billboards: in one pass (every overlapping quad shaded where it
/// covers), or a depth pre-pass of their texture's coverage and then the shading of only the
/// nearest billboard at each sample (`billboard.depth_prepass`).
pub struct BillboardDraws {
    pub one_pass: Pipeline,
    pub depth: Pipeline,
    pub nearest: Pipeline,
}

impl BillboardDraws {
    fn new(b: &Builder) -> Result<BillboardDraws> {
        let billboards = GraphicsDesc {
            alpha_to_coverage: true,
            ..b.opaque()
        };
        let depth = GraphicsDesc {
            writes_color: false,
            ..billboards
        };
        let nearest = GraphicsDesc {
            depth: Depth::SameSurface,
            ..billboards
        };
        let [one_pass, prepass, shaded] = &shaders::BILLBOARD_DRAWS;
        Ok(BillboardDraws {
            one_pass: b.draw(&billboards, &[Vertex(one_pass), Fragment(one_pass)])?,
            depth: b.draw(&depth, &[Vertex(prepass), Fragment(prepass)])?,
            nearest: b.draw(&nearest, &[Vertex(shaded), Fragment(shaded)])?,
        })
    }

    /// The passes a frame draws the billboards with, in order (the second is null in one pass).
    pub(crate) fn passes(&self, depth_prepass: bool) -> [vk::Pipeline; 2] {
        match depth_prepass {
            true => [self.depth.raw, self.nearest.raw],
            false => [self.one_pass.raw, vk::Pipeline::null()],
        }
    }
}
