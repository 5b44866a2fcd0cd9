//! sward-core: the grass core. Everything about responsive grass that does not need a GPU, and
//! the WGSL both renderers run.
//!
//! It owns the 64-byte [`Blade`], field generation and its tiles ([`tiles`]), mesh colliders
//! packed into spheres ([`bodies`]), the CPU reference of the physical model ([`physics`]) and
//! of per-blade culling ([`cull`]), the [`Camera`] with Vulkan clip conventions, the scene
//! description ([`scene`]), the `#[repr(C)]` structs shared with the shaders ([`gpu`]), what
//! the shaders and the host share, declared once ([`declared`]), and the shaders' WGSL itself
//! ([`wgsl`]). The shaders mirror the maths here; tests compare the two.
//!
//! On its own it runs the paper's model on the CPU: grow a field from a [`Scene`], step it with
//! wind and colliders, and read every blade back.
//!
//! ```
//! use glam::Vec3;
//! use sward_core::{physics, Collider, Scene};
//!
//! let mut scene = Scene::default();
//! scene.field.blades = 500;
//! scene.field.size = glam::Vec2::splat(2.0);
//! let mut field = scene.grow_field().unwrap();
//! // Each blade's collision strength η: how hard it was pressed, decaying as it recovers.
//! let mut etas = vec![0.0; field.blades.len()];
//! let ball = Collider::sphere(Vec3::new(0.0, 0.3, 0.0), 0.8);
//! physics::simulate(&mut field.blades, &mut etas, &scene.simulation, &[ball], &scene.wind, 0.0, 60);
//! assert!(etas.iter().any(|&eta| eta > 0.0), "the ball pressed blades down");
//! assert!(field.blades.iter().all(|b| b.tip().is_finite()));
//! ```
//!
//! `cargo run -p sward-core --example physics` rolls a ball through a field and prints how the
//! trail it leaves recovers.
//!
//! Scene, mesh, height and paint map files are read through [`files`], and only with the
//! `files` feature (on by default; off in a browser build), unless they are given in memory
//! ([`content`]: a game's asset server read them, or they were made in code).

#![warn(missing_docs)]

pub mod billboard;
pub mod blade;
pub mod bodies;
pub mod camera;
pub mod commands;
pub mod content;
pub mod cull;
pub mod declared;
pub mod field;
pub mod files;
pub mod flags;
pub mod frame;
pub mod gpu;
pub mod instanced;
pub mod look;
pub mod memory;
pub mod mesh;
pub mod paint;
pub mod paint_edits;
pub mod physics;
pub mod placement;
pub mod plan;
pub mod quality;
pub mod reference;
pub mod rng;
pub mod sample;
pub mod scene;
pub mod species;
pub mod stream;
pub mod tiles;
pub mod timing;
pub mod trample;
mod validate;
pub use validate::MAX_MAGNITUDE;
pub mod walk;
pub mod wgsl;
pub mod wind;
pub mod words;

pub use blade::Blade;
pub use camera::{Camera, CameraPath};
pub use cull::{BladeOccluders, CullParams, CullVerdict};
pub use field::{Field, FieldDesc};
pub use frame::{FrameCamera, FrameColliders, FrameDesc};
pub use physics::{Collider, SimParams};
pub use scene::{Scene, SceneError};
pub use wind::Wind;
