//! sward's portable renderer in a browser page: the shipped scenes grown in the page, drawn on
//! the browser's WebGPU into an offscreen target, and timed or read back — what a web build
//! of sward runs, and how the far field's routes on a browser's device (splatted into 32-bit
//! cells, or drawn as geometry) are measured against each other. Built for
//! `wasm32-unknown-unknown` with wasm-bindgen (`scripts/browser-bench.sh`); on other targets
//! only its cases build (`cases`), with no device and no wasm-bindgen.

mod cases;
#[cfg(target_arch = "wasm32")]
mod page;

pub use cases::{case_names, case_scene, far_field_modules};
