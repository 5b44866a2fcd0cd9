//! Where sward meets Bevy's render internals — nowhere else in the crate (a test says so):
//! the render device, the render world's schedules, views, phases and pipelines, and the
//! shaders that import Bevy's. A Bevy upgrade is this module's work; the rest of the crate uses
//! Bevy's public components and the main world only.
//!
//! Each touch point, the app test (`tests/app.rs`) that fails when it breaks, and what an
//! upgrade can change in it:
//!
//! | touch point | where | test | what an upgrade changes |
//! |---|---|---|---|
//! | the render device sward opens, handed to Bevy (`RenderCreation::manual` with `RenderDevice`, `RenderQueue`, `RenderAdapter`, `RenderInstance`) | `device.rs` | `a_headless_bevy_app_draws_the_grass_a_collider_s_trail_and_a_mesh_that_hides_it` | the resources' wrappers and `RenderCreation`'s shape; the wgpu version Bevy builds on |
//! | Bevy's device taken back, or its own used (`RenderAdapter`, `RenderDevice::wgpu_device`, `RenderQueue` at `Plugin::finish`) | `vulkan.rs`, `portable.rs` | `on_bevy_s_own_device_the_portable_passes_draw_the_grass_its_trail_and_the_cube_that_hides_it` | where Bevy keeps its adapter and queue; when the render sub-app has its device |
//! | a starved device said and survived (limits read from `RenderDevice`) | `portable.rs` | `on_a_device_without_what_the_grass_needs_the_app_runs_without_grass_and_says_why` | the limits Bevy asks of an adapter |
//! | the main world read each frame (`ExtractSchedule`, `Extract`: the grass, cameras, lights, colliders, `ViewVisibility`, `RenderLayers`, `NotShadowCaster`) | `extract.rs` | `a_bevy_system_changes_the_grass_while_the_app_runs`, `hidden_grass_and_grass_on_another_layer_are_not_drawn` | the extract schedule's rules; visibility's components |
//! | the cameras' depth made readable by the cull (`Camera3d::depth_texture_usages`) | `mod.rs` | `bevy_s_meshes_hide_the_grass_behind_them_in_the_cull_of_bevy_s_passes` | how a camera's depth texture is described |
//! | compute before Bevy renders (`Render` schedule, `RenderSystems::PrepareBindGroups`) | `vulkan.rs`, `portable.rs` | `a_streamed_field_follows_bevy_s_camera_wherever_it_walks` | the render schedule's sets |
//! | sward's own pass in the main pass (`Core3d`, `Core3dSystems::MainPass` after `main_opaque_pass_3d`, `ViewQuery`, `RenderContext`, `ViewTarget`, `ViewDepthTexture`, `Msaa`, `ExtractedCamera`) | `vulkan.rs` | `bevy_s_sun_lights_the_grass_as_it_lights_a_mesh`, `bevy_s_distance_fog_covers_the_grass_as_it_covers_a_mesh` | the pass systems' names and order (in 0.19 the render graph became these schedules) |
//! | the grass as items of Bevy's opaque phase (`Opaque3d`, its bin and batch-set keys, `ViewBinnedRenderPhases`, `DrawFunctions`, `RenderCommand`) | `phases.rs` | `bevy_s_sun_lights_the_grass_drawn_in_bevy_s_passes_as_it_lights_a_mesh` | the bin keys' fields and `BinnedRenderPhaseType` (reshaped in most releases) |
//! | the prepass and motion vectors (`Opaque3dPrepass`, `PrepassPipeline`, `MotionVectorPrepass`) | `phases.rs` | `the_grass_s_motion_vectors_move_where_the_wind_sways_it_and_the_ground_s_do_not` | the prepass pipeline's layouts and keys |
//! | a deferred camera's G-buffer (`Opaque3dDeferred`) | `phases.rs` | `a_deferred_camera_renders_the_grass_as_the_forward_one` | the deferred phase's item |
//! | the splatted far field resolved in Bevy's phases (a screen-covering item of `Opaque3d`, `Opaque3dPrepass`, `Opaque3dDeferred` writing `frag_depth`, a fragment a sample under MSAA; `position_ndc_to_world`, the prepass's outputs, `deferred_output`) | `phases.rs`, `shaders/splat_cells.wesl`, `shaders/splat_resolve.wesl`, `shaders/splat_prepass.wesl` | `bevy_s_passes_resolve_the_splatted_far_field_as_they_draw_it_as_geometry` | the prepass's output struct and the view's bindings |
//! | the shadow passes (`Shadow`, `LightEntity`, `ViewLightEntities`, `LightKeyCache`), each sun cascade's slice of the view (`ExtractedDirectionalLight`, `CascadeShadowConfig`: its bounds and overlap) | `phases.rs`, `cascades.rs` | `the_grass_drawn_in_bevy_s_passes_casts_its_shadow_on_bevy_s_ground`, `the_far_grass_casts_within_its_shadow_distance_and_joins_a_deferred_camera_s_g_buffer` | the light views' entities and keys; how a cascade's bounds are laid out |
//! | Bevy's mesh pipeline specialised for the grass (`MeshPipeline`, `MeshPipelineKey`, `ViewKeyCache`, `SetMeshViewBindGroup`, `PipelineCache`) | `phases.rs` | `a_bevy_mesh_s_shadow_darkens_the_grass_drawn_in_bevy_s_passes` | the key's bits and the view bind groups |
//! | the shaders' imports of Bevy's (`bevy_pbr::…`, `bevy_render::view::View`: lights, shadows, environment maps, fog) | `shaders/` | `an_environment_map_lights_the_grass_drawn_in_bevy_s_passes_as_it_lights_a_mesh` | the WGSL modules' paths and function signatures |
//! | the shaders added to Bevy's (`Shader::from_wesl` at an `embedded://` path, `AssetServer::add`) | `phases.rs` | `on_sward_s_vulkan_device_bevy_s_passes_draw_instanced_grass` | WESL's import paths of `embedded://` shaders |

pub(crate) mod cascades;
#[cfg(feature = "vulkan")]
mod device;
pub(crate) mod extract;
pub(crate) mod frames;
mod phases;
pub(crate) mod portable;
#[cfg(feature = "vulkan")]
pub(crate) mod vulkan;

use bevy::app::{App, PostUpdate};
use bevy::camera::{Camera3d, Camera3dDepthTextureUsage};
use bevy::ecs::prelude::*;
use bevy::render::render_resource::TextureUsages;
use bevy::render::RenderApp;
#[cfg(feature = "vulkan")]
pub use device::{render_plugin, render_plugin_with};
pub use portable::{GrassRoute, GrassSplats};
#[cfg(feature = "vulkan")]
pub use vulkan::SwardContext;

use crate::GrassTimings;

/// The plugin's build: every 3D camera's depth made readable (main world), and the render
/// world's extraction and phases, the far field reaching them as `splats` says.
pub(crate) fn build(app: &mut App, splats: GrassSplats) {
    app.add_systems(PostUpdate, let_the_cull_read_depth.in_set(crate::GrassSystems));
    if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
        render_app.insert_resource(splats);
        extract::build(render_app);
        phases::build(render_app);
    }
}

/// The plugin's finish, once Bevy's render device exists: sward's route on it (the Vulkan
/// renderer on the device `render_plugin` opened, else the portable passes), in the render
/// world and returned with sward's context where it is the Vulkan renderer's. None without a
/// render world.
#[cfg(feature = "vulkan")]
pub(crate) fn finish(
    app: &mut App,
    context: &sward_gpu::ContextDesc,
    timings: Option<GrassTimings>,
) -> Option<(GrassRoute, Option<SwardContext>)> {
    let render_app = app.get_sub_app_mut(RenderApp)?;
    let (route, context) = vulkan::finish(render_app, context, timings);
    render_app.insert_resource(route.clone());
    Some((route, context))
}

/// The plugin's finish, once Bevy's render device exists: the portable passes on it, in the
/// render world and returned. None without a render world.
#[cfg(not(feature = "vulkan"))]
pub(crate) fn finish(app: &mut App, timings: Option<GrassTimings>) -> Option<GrassRoute> {
    let render_app = app.get_sub_app_mut(RenderApp)?;
    let route = portable::finish(render_app, timings);
    render_app.insert_resource(route.clone());
    Some(route)
}

/// Add `TEXTURE_BINDING` to a new 3D camera's depth texture usage, so sward's cull can test the
/// grass against what Bevy's meshes hide.
fn let_the_cull_read_depth(mut cameras: Query<&mut Camera3d, Added<Camera3d>>) {
    for mut camera in &mut cameras {
        let usage = TextureUsages::from(camera.depth_texture_usages);
        if !usage.contains(TextureUsages::TEXTURE_BINDING) {
            camera.depth_texture_usages = Camera3dDepthTextureUsage::from(usage | TextureUsages::TEXTURE_BINDING);
        }
    }
}
