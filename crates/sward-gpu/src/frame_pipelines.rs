//! Every pipeline of the frame together: each pass's set (built by the pass's own module with
//! `pipelines.rs`'s builder), the splat resolve and the frame layout they share — built as one
//! so the viewer's hot reload swaps them as one. Above the passes; only the renderer holds it.

use std::sync::Arc;

use ash::vk;

use crate::context::Context;
use crate::error::Result;
use crate::pipelines::{Builder, ComputeOptions, FrameLayout, Pipeline, TargetFormat};
use crate::shaders::ShaderSet;

/// Every pipeline of the frame, each set owned by the pass that records with it; built together
/// so the viewer's hot reload swaps them as one.
pub struct Pipelines {
    /// The Bezier field's simulate, cull and ordering passes.
    pub field: crate::passes::bezier::FieldPipelines,
    /// The draw routes' pipelines.
    pub routes: crate::passes::routes::RoutePipelines,
    /// Sky, ground and colliders.
    pub scene: crate::passes::ground::ScenePipelines,
    /// Depth pyramid and shadow map.
    pub occluders: crate::passes::occluders::OccluderPipelines,
    /// The instanced blades.
    pub generated: crate::passes::generated::GeneratedPipelines,
    /// The billboards.
    pub billboards: crate::passes::billboards::BillboardPipelines,
    /// The trample map's step.
    pub trample: Pipeline,
    /// The listed blades for a renderer that draws them itself.
    pub drawn_blades: Pipeline,
    /// The splat target's resolve into the frame and its tiles' depths.
    pub splats: crate::passes::splats::SplatPipelines,
    /// The options the compute pipelines were built with.
    pub options: ComputeOptions,
    /// What the graphics pipelines render into.
    pub target: TargetFormat,
    /// Declared last: dropped after every pipeline made with it. Shared with pipelines rebuilt
    /// from other shaders (`rebuilt`), so the descriptor sets allocated with its set layout stay
    /// valid across a hot reload.
    pub frame: Arc<FrameLayout>,
}

impl Pipelines {
    /// Pipelines from the SPIR-V built into sward.
    pub fn new(ctx: &Arc<Context>, target: TargetFormat, options: ComputeOptions) -> Result<Pipelines> {
        Self::with_shaders(ctx, target, options, &ShaderSet::embedded())
    }

    /// Pipelines from the given SPIR-V, with a frame layout of their own. On error, whatever was
    /// built so far is dropped, which destroys it.
    pub fn with_shaders(
        ctx: &Arc<Context>,
        target: TargetFormat,
        options: ComputeOptions,
        shaders: &ShaderSet,
    ) -> Result<Pipelines> {
        Self::on_layout(ctx, Arc::new(FrameLayout::new(ctx)?), target, options, shaders)
    }

    /// These pipelines built again from other SPIR-V (the viewer's hot reload, `--shaders`): the
    /// same target, options and frame layout, so a renderer's descriptor sets bind them.
    pub fn rebuilt(&self, ctx: &Arc<Context>, shaders: &ShaderSet) -> Result<Pipelines> {
        Self::on_layout(ctx, self.frame.clone(), self.target, self.options, shaders)
    }

    fn on_layout(
        ctx: &Arc<Context>,
        frame: Arc<FrameLayout>,
        target: TargetFormat,
        options: ComputeOptions,
        shaders: &ShaderSet,
    ) -> Result<Pipelines> {
        let b = Builder {
            ctx,
            layout: frame.layout,
            target,
            options,
            shaders,
        };
        Ok(Pipelines {
            field: crate::passes::bezier::FieldPipelines::new(&b)?,
            routes: crate::passes::routes::RoutePipelines::new(&b)?,
            scene: crate::passes::ground::ScenePipelines::new(&b)?,
            occluders: crate::passes::occluders::OccluderPipelines::new(&b)?,
            generated: crate::passes::generated::GeneratedPipelines::new(&b)?,
            billboards: crate::passes::billboards::BillboardPipelines::new(&b)?,
            trample: crate::passes::trample::TrampleTexels::pipeline(&b)?,
            drawn_blades: crate::passes::drawn_blades::DrawnBlades::pipeline(&b)?,
            splats: crate::passes::splats::SplatPipelines::new(&b)?,
            options,
            target,
            frame,
        })
    }

    /// The pipeline layout every pass binds its set with.
    pub fn layout(&self) -> vk::PipelineLayout {
        self.frame.layout
    }
}
