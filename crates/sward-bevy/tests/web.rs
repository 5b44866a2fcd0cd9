//! The web example in a browser: built for `wasm32-unknown-unknown` and bound by wasm-bindgen
//! (`scripts/web-example.sh`), served from a local folder and run in headless Chromium's WebGPU
//! (SwiftShader, no GPU needed) in a page of 480×270 pixels, which asks the example for its
//! window's pictures (`?shots`) until one is a tenth grass. The page must log no error (Bevy logs
//! a WebGPU validation error, a lost device, a panic as one) and sward no warning, and the
//! picture must show the meadow, the ball and the sky.

// A native test: it writes and reads its folders on disk.
#![allow(clippy::disallowed_methods)]

#[path = "../../sward-wgpu/tests/browser/runner.rs"]
mod runner;

use std::path::{Path, PathBuf};
use std::process::Command;

const NEEDS: &str = "this test needs node, Chromium and the wasm32-unknown-unknown target \
     (scripts/setup.sh --xvfb installs them)";

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The example built for the browser into `dir`, the watching page beside it.
fn build_page(dir: &Path) {
    let built = Command::new("bash")
        .arg(workspace().join("scripts/web-example.sh"))
        .arg(dir)
        .output()
        .unwrap_or_else(|e| panic!("{NEEDS}: bash does not run ({e})"));
    assert!(
        built.status.success(),
        "the web example did not build for the browser: {}",
        String::from_utf8_lossy(&built.stderr)
    );
    let page = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/web/page.html");
    std::fs::copy(page, dir.join("page.html")).unwrap();
}

/// The share of `pixels` (RGBA) passing `test`.
fn share(pixels: &[u8], test: impl Fn(u8, u8, u8) -> bool) -> f32 {
    let count = pixels
        .as_chunks::<4>()
        .0
        .iter()
        .filter(|p| test(p[0], p[1], p[2]))
        .count();
    count as f32 / (pixels.len() / 4).max(1) as f32
}

#[test]
fn the_web_example_draws_the_meadow_in_headless_chromium_s_webgpu() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("web-example");
    build_page(&dir);
    let chromium =
        runner::chromium().unwrap_or_else(|| panic!("{NEEDS}: no Chromium found (SWARD_CHROMIUM names one)"));
    runner::run_page(&dir, &chromium, NEEDS, true);
    let said = std::fs::read_to_string(dir.join("out-said")).expect("the page says what it saw");
    eprintln!("the page said:\n{said}");
    let errors: Vec<&str> = said.lines().filter(|l| l.starts_with("error:")).collect();
    assert!(errors.is_empty(), "the page logged errors:\n{}", errors.join("\n"));
    let sward_warned: Vec<&str> = said
        .lines()
        .filter(|l| l.starts_with("warning:") && l.contains("sward"))
        .collect();
    assert!(sward_warned.is_empty(), "sward warned:\n{}", sward_warned.join("\n"));

    let size: Vec<u32> = said
        .lines()
        .next()
        .and_then(|l| l.strip_prefix("size "))
        .map(|s| s.split(' ').filter_map(|v| v.parse().ok()).collect())
        .unwrap_or_default();
    let [width, height] = size[..] else {
        panic!("the page gave no picture size: {said}");
    };
    assert!(
        width >= 480 && height >= 270,
        "the canvas is {width}×{height}, not the page's 480×270"
    );
    let pixels = std::fs::read(dir.join("out-shot.rgba")).expect("the page posts its picture");
    let picture = image::RgbaImage::from_raw(width, height, pixels).expect("a whole picture");
    let kept = dir.join("web-example.png");
    picture.save(&kept).unwrap();

    let grass = share(picture.as_raw(), |r, g, b| {
        g > 30 && g as u32 * 10 > r as u32 * 11 && g as u32 * 10 > b as u32 * 11
    });
    assert!(
        grass > 0.1,
        "the page's picture ({}) is {:.1} % grass",
        kept.display(),
        grass * 100.0
    );
    // The ball (red) rolls in the grass, and the sky (the clear colour, blue) is above it.
    let ball = share(picture.as_raw(), |r, g, b| {
        r > 120 && r as u32 > g as u32 + 50 && r as u32 > b as u32 + 50
    });
    assert!(ball > 0.0005, "no ball in the page's picture ({})", kept.display());
    let sky = share(picture.as_raw(), |r, g, b| b > 150 && b > g && g > r);
    assert!(sky > 0.05, "no sky in the page's picture ({})", kept.display());
}
