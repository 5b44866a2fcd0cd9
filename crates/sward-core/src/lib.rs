//! sward-core: everything about responsive grass that does not need a GPU.
//!
//! It owns the 64-byte [`Blade`], field generation and its tiles ([`tiles`]), mesh colliders
//! packed into spheres ([`bodies`]), the CPU reference of the physical model
//! ([`physics`]) and of per-blade culling ([`cull`]), the [`Camera`] with Vulkan clip conventions,
//! the scene description ([`scene`]) and the `#[repr(C)]` structs shared with the shaders ([`gpu`]).
//! The GPU back end (`sward-gpu`) mirrors the maths here; tests compare the two.

pub mod billboard;
pub mod blade;
pub mod bodies;
pub mod camera;
pub mod cull;
pub mod field;
pub mod flags;
pub mod gpu;
pub mod instanced;
pub mod look;
pub mod mesh;
pub mod physics;
pub mod quality;
pub mod rng;
pub mod scene;
pub mod tiles;
pub mod wind;

pub use blade::Blade;
pub use camera::Camera;
pub use cull::{CullParams, CullVerdict};
pub use field::{Field, FieldDesc};
pub use physics::{Collider, SimParams};
pub use scene::{Scene, SceneError};
pub use wind::Wind;
