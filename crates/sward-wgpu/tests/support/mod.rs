//! What the tests and examples of sward-wgpu share.

pub mod cube;
