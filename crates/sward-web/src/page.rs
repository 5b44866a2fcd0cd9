//! The page's calls (wasm-bindgen): the browser's WebGPU adapter described, a case or a scene
//! file grown on its device, drawn into an offscreen target, timed or read back. Built for
//! `wasm32-unknown-unknown` only.

use futures_channel::oneshot;
use sward_core::{Field, FrameDesc, Scene};
use sward_portable::{
    adapter_sentence, portable_features, portable_limits, PortableError, PortableHeadless, PortablePasses,
};
use wasm_bindgen::prelude::*;

use crate::cases::{case_names, case_scene, far_field_modules};

/// The cases a page can measure (`cases::case_names`), to the page's JavaScript.
#[wasm_bindgen(js_name = case_names)]
pub fn case_names_for_the_page() -> Vec<String> {
    case_names()
}

/// A scene grown on the browser's device, drawn into an offscreen target.
struct Page {
    headless: PortableHeadless,
    scene: Scene,
    field: Field,
    size: [u32; 2],
}

/// What the page's JavaScript sees of a failure: one sentence.
fn said(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

/// The browser's WebGPU adapter, as the portable renderer sees it (one sentence).
#[wasm_bindgen]
pub async fn describe() -> Result<String, JsError> {
    Ok(adapter_sentence(&adapter().await?))
}

async fn adapter() -> Result<wgpu::Adapter, JsError> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::BROWSER_WEBGPU,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    instance
        .request_adapter(&wgpu::RequestAdapterOptions::default())
        .await
        .map_err(|e| said(format!("this browser gives no WebGPU adapter: {e}")))
}

impl Page {
    /// `scene` grown on a device of the browser's adapter, `width` × `height`, its far field as
    /// `far_field` says.
    async fn open(scene: Scene, far_field: &str, [width, height]: [u32; 2]) -> Result<Page, JsError> {
        let modules = far_field_modules(far_field).map_err(said)?;
        let adapter = adapter().await?;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("sward web"),
                required_features: portable_features(&adapter),
                required_limits: portable_limits(&adapter),
                ..Default::default()
            })
            .await
            .map_err(|e| said(PortableError::NoDevice(adapter.get_info().name, e.to_string())))?;
        let samples = scene.quality.preset.msaa_samples();
        let mut headless =
            PortableHeadless::made_of((adapter, device, queue), [width, height], samples, modules).map_err(said)?;
        let field = scene.grow_field().map_err(said)?;
        headless.upload(&field).map_err(said)?;
        Ok(Page {
            headless,
            scene,
            field,
            size: [width, height],
        })
    }

    /// Record frame `frame` (one fixed step, then the cull and the draw, as `sward bench`
    /// records a frame), submit it and wait for the GPU to finish it.
    async fn frame(&mut self, frame: u32) -> Result<(), JsError> {
        let clock = (frame as f32 * self.scene.simulation.step, 1);
        let desc = FrameDesc::of_scene(&self.scene, self.field.size, clock, self.size);
        let mut encoder = self.headless.device.create_command_encoder(&Default::default());
        self.record(&mut encoder, &desc)?;
        self.headless.queue.submit([encoder.finish()]);
        self.finished().await
    }

    fn record(&mut self, encoder: &mut wgpu::CommandEncoder, desc: &FrameDesc) -> Result<(), JsError> {
        let occluders = PortablePasses {
            occluders: true,
            ..Default::default()
        };
        let cull = PortablePasses {
            cull: true,
            ..Default::default()
        };
        for passes in [occluders, PortablePasses::SIMULATE, cull] {
            self.headless.record(encoder, desc, passes).map_err(said)?;
        }
        self.headless.record_draw(encoder).map_err(said)
    }

    /// Wait for the work submitted so far, and say the first fault the device reported.
    async fn finished(&self) -> Result<(), JsError> {
        let (done, finished) = oneshot::channel();
        self.headless.queue.on_submitted_work_done(move || {
            let _ = done.send(());
        });
        finished
            .await
            .map_err(|_| said("the browser's GPU device was dropped before the frame finished"))?;
        self.headless.take_fault().map_err(said)
    }

    /// The scene after `steps` fixed steps, culled and drawn as `sward render` draws it
    /// ([`PortableHeadless::submit_scene`]): RGBA, row by row from the top.
    async fn render(&mut self, steps: u32) -> Result<Vec<u8>, JsError> {
        let mut encoder = self
            .headless
            .submit_scene(&self.scene, self.field.size, steps)
            .map_err(said)?;
        let staging = self.headless.record_image_copy(&mut encoder);
        self.headless.queue.submit([encoder.finish()]);
        let (mapped, on_mapped) = oneshot::channel();
        staging.slice(..).map_async(wgpu::MapMode::Read, move |result| {
            let _ = mapped.send(result);
        });
        on_mapped
            .await
            .map_err(|_| said("the browser's GPU device was dropped before the image was read"))?
            .map_err(|e| said(format!("the image could not be read back: {e}")))?;
        self.headless.take_fault().map_err(said)?;
        let copied = staging
            .slice(..)
            .get_mapped_range()
            .map_err(|e| said(format!("the image could not be read back: {e}")))?;
        Ok(self.headless.image_rows(&copied))
    }
}

/// Time the case `name` on the browser's WebGPU at `width` × `height`, its far field as
/// `far_field` says (`splatted` or `drawn`): `warmup` frames, then `frames` frames, each the
/// milliseconds from its submission to the GPU's end of it (wall clock: a browser's WebGPU
/// gives no timestamps inside a command encoder).
#[wasm_bindgen]
pub async fn bench(
    name: String,
    far_field: String,
    width: u32,
    height: u32,
    warmup: u32,
    frames: u32,
) -> Result<Vec<f64>, JsError> {
    let scene = case_scene(&name).map_err(said)?;
    let mut page = Page::open(scene, &far_field, [width, height]).await?;
    let performance = web_sys::window()
        .and_then(|w| w.performance())
        .ok_or_else(|| said("the page has no performance clock"))?;
    let mut times = Vec::with_capacity(frames as usize);
    for frame in 0..warmup + frames {
        let start = performance.now();
        page.frame(frame).await?;
        if frame >= warmup {
            times.push(performance.now() - start);
        }
    }
    Ok(times)
}

/// The case `name` after `steps` fixed steps on the browser's WebGPU at `width` × `height`,
/// its far field as `far_field` says, as `sward render --renderer wgpu` draws it: RGBA (8-bit
/// sRGB), row by row from the top.
#[wasm_bindgen]
pub async fn render(name: String, far_field: String, width: u32, height: u32, steps: u32) -> Result<Vec<u8>, JsError> {
    let scene = case_scene(&name).map_err(said)?;
    Page::open(scene, &far_field, [width, height])
        .await?
        .render(steps)
        .await
}

/// [`render`] of the scene file `toml` (what a test hands the page to draw what it draws
/// itself).
#[wasm_bindgen]
pub async fn render_toml(
    toml: String,
    far_field: String,
    width: u32,
    height: u32,
    steps: u32,
) -> Result<Vec<u8>, JsError> {
    let scene = Scene::from_toml(&toml, "the page's scene").map_err(said)?;
    Page::open(scene, &far_field, [width, height])
        .await?
        .render(steps)
        .await
}
