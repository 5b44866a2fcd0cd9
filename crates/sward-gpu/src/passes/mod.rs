//! The passes of the grass frame, one module each, each owning its pipelines, buffers and
//! descriptor writes; the renderer (`renderer.rs`) calls them in order:
//!
//! - `depth_pyramid.rs`: the depth pyramid the culls test against (ground, colliders, the
//!   nearest blades, the caller's depth);
//! - `shadows.rs`: the sun's shadow map (its field and near cascades);
//! - `occluders.rs`: what those two share — the pipelines that draw the occluders into them;
//! - `trample.rs`: the trample map, stepped with the simulation;
//! - `bezier.rs`: the Bezier field — tile cull, simulate, cull, order into distance buckets —
//!   and the compute route's splat and rasterizer passes over it;
//! - `stream.rs`: the streamed field's window — the tiles entering it each frame;
//! - `generated.rs`: the instanced blades and the billboards generated each frame around the eye
//!   (patch lists, count, scan, place) and their draws;
//! - `billboards.rs`: the billboards' pipelines (their lists are the generated grass's);
//! - `routes.rs`: the ways the Bezier blades reach the screen (tessellation, strips, mesh,
//!   compute) and their draws;
//! - `splats.rs`: the splat target the compute passes write, its tiles and its resolve;
//! - `ground.rs`: the ground, the sky and the colliders;
//! - `grass_texture.rs`: the billboards' painted grass texture;
//! - `paint.rs`: the paint maps over the ground (where grass grows, how tall);
//! - `drawn_blades.rs`: the listed blades for a renderer that draws them itself.

pub(crate) mod bezier;
pub(crate) mod billboards;
pub mod depth_pyramid;
pub mod drawn_blades;
pub(crate) mod generated;
pub(crate) mod grass_texture;
pub(crate) mod ground;
pub mod occluders;
pub(crate) mod paint;
pub mod routes;
pub mod shadows;
pub(crate) mod splats;
pub(crate) mod stream;
pub(crate) mod trample;
