//! Headless Chromium for the tests that run a page on a browser's WebGPU (SwiftShader, no GPU
//! needed): where Chromium is, and a page's folder run through `run.mjs`. Shared by the portable
//! renderer's browser tests and sward-bevy's web example test.

use std::path::Path;

/// Chromium: where SWARD_CHROMIUM says, else Debian's or Ubuntu's.
pub fn chromium() -> Option<String> {
    let named = std::env::var("SWARD_CHROMIUM").ok();
    let usual = ["/usr/bin/chromium", "/usr/bin/chromium-browser"].map(String::from);
    named.into_iter().chain(usual).find(|p| Path::new(p).exists())
}

/// Run the page fixture folder `dir` holds (or run.mjs's own) in `chromium` through `run.mjs`;
/// what it posts back lands in `dir` as `out-NAME`. A page that `presents` frames to a canvas
/// gets Chromium started for it, and five minutes. `needs` says what to install when node is
/// missing.
pub fn run_page(dir: &Path, chromium: &str, needs: &str, presents: bool) {
    let runner = concat!(env!("CARGO_MANIFEST_DIR"), "/../sward-wgpu/tests/browser/run.mjs");
    let mut node = std::process::Command::new("node");
    node.arg(runner).arg(dir).arg(chromium);
    if presents {
        node.env("SWARD_PAGE_PRESENTS", "1").env("SWARD_PAGE_TIMEOUT_S", "300");
    }
    let out = node
        .output()
        .unwrap_or_else(|e| panic!("{needs}: node does not run ({e})"));
    assert!(
        out.status.success(),
        "the browser run failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}
