//! The portable renderer without a window: a device on the wgpu backend asked for, an offscreen
//! target (8-bit sRGB colour, multisampled as the scene's quality asks, resolved), a scene's
//! field on it, and frames read back as RGBA bytes — what `sward render --renderer wgpu`
//! writes and what the picture tests compare with the Vulkan renderer's. What waits on the GPU
//! (reading frames and counts back) is built only with the `blocking` feature; the rest records
//! frames a caller submits and awaits itself (a browser page).

use std::sync::{Arc, Mutex};

use glam::Vec2;
use sward_core::{Field, FrameDesc, Scene};

use crate::{
    PortableError, PortableField, PortablePasses, PortableRenderer, PortableTarget, PortableViews, ShaderModules,
};

/// The colour format of the offscreen target (as the Vulkan renderer's `OFFSCREEN_FORMAT`).
pub const PORTABLE_COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Fixed steps of simulation recorded in one submission: each submission writes the frame's
/// uniforms once.
const STEPS_PER_SUBMIT: u32 = 120;
/// Steps per submission where the trample map runs and colliders move over it: a submission
/// stamps them once, where its first step finds them (the Vulkan renderer's headless frames
/// step as many, so both leave the same trails).
const STEPS_PER_TRAMPLE: u32 = 8;

/// The portable renderer drawing a field into an offscreen target of its own.
pub struct PortableHeadless {
    /// The adapter the device is of.
    pub adapter: wgpu::Adapter,
    /// The device everything is made on.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The renderer, made for the offscreen target.
    pub renderer: PortableRenderer,
    field: Option<PortableField>,
    size: [u32; 2],
    color: wgpu::Texture,
    resolve: Option<wgpu::Texture>,
    depth: wgpu::Texture,
    /// What the device reported outside an error scope (validation errors, a lost device).
    faults: Arc<Mutex<Vec<String>>>,
}

impl PortableHeadless {
    /// A `width` × `height` target of `samples` per pixel on the device, and the renderer.
    pub fn new(
        device: (wgpu::Adapter, wgpu::Device, wgpu::Queue),
        size: [u32; 2],
        samples: u32,
    ) -> Result<PortableHeadless, PortableError> {
        PortableHeadless::made_of(device, size, samples, ShaderModules::built_in())
    }

    /// The same, the renderer's pipelines composed of `modules`
    /// ([`PortableRenderer::made_of`]).
    pub fn made_of(
        (adapter, device, queue): (wgpu::Adapter, wgpu::Device, wgpu::Queue),
        [width, height]: [u32; 2],
        samples: u32,
        modules: ShaderModules,
    ) -> Result<PortableHeadless, PortableError> {
        let largest = device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > largest || height > largest {
            return Err(PortableError::TargetSize { width, height, largest });
        }
        let target = PortableTarget {
            color: PORTABLE_COLOR,
            depth: DEPTH,
            samples,
        };
        let faults = watch_faults(&device);
        let renderer = PortableRenderer::made_of(&adapter, &device, Some(&target), modules)?;
        let texture = |label, format, samples, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let read = attachment | wgpu::TextureUsages::COPY_SRC;
        let (color, resolve) = match samples {
            1 => (texture("sward colour", PORTABLE_COLOR, 1, read), None),
            n => (
                texture("sward colour", PORTABLE_COLOR, n, attachment),
                Some(texture("sward resolved colour", PORTABLE_COLOR, 1, read)),
            ),
        };
        let depth = texture("sward depth", DEPTH, samples, attachment);
        Ok(PortableHeadless {
            adapter,
            device,
            queue,
            renderer,
            field: None,
            size: [width, height],
            color,
            resolve,
            depth,
            faults,
        })
    }

    /// Bytes of GPU memory allocated on the headless device: what wgpu's allocator says (on
    /// Vulkan and DX12 the allocator the Vulkan renderer allocates with, every buffer and image
    /// at its allocation's size, so `sward bench` counts both renderers alike), else the sum of
    /// the field's and the renderer's buffers and the target.
    pub fn memory_bytes(&self) -> u64 {
        match self.device.generate_allocator_report() {
            Some(report) => report.total_allocated_bytes,
            None => self.buffers_and_target_bytes(),
        }
    }

    /// The `count` largest allocations on the headless device, by name (each buffer's and
    /// image's label), largest first: where the memory goes; none where wgpu gives no report.
    pub fn largest_allocations(&self, count: usize) -> Vec<(String, u64)> {
        let Some(report) = self.device.generate_allocator_report() else {
            return Vec::new();
        };
        let all = report.allocations.into_iter().map(|a| (a.name, a.size)).collect();
        sward_core::memory::largest(all, count)
    }

    /// The field's and the renderer's buffers and the target's images, as sized.
    fn buffers_and_target_bytes(&self) -> u64 {
        let [width, height] = self.size;
        let pixel = 4 * width as u64 * height as u64;
        let samples = self.color.sample_count() as u64;
        let resolve = self.resolve.as_ref().map_or(0, |_| pixel);
        let field = self.field.as_ref().map_or(0, PortableField::bytes);
        field + self.renderer.bytes() + 2 * pixel * samples + resolve
    }

    /// The blades the last culled frame made visible (listed, or splatted or rasterized by
    /// compute), once the work submitted so far has finished.
    #[cfg(feature = "blocking")]
    pub fn visible_count(&self) -> Result<u32, PortableError> {
        let field = self.field.as_ref().ok_or(PortableError::NoField)?;
        let [generated, _] = self.renderer.generated_count(&self.device, &self.queue, 0)?;
        Ok(field.visible_count(&self.device, &self.queue)? + generated)
    }

    /// Of [`PortableHeadless::visible_count`], the generated blades and billboards splatted or
    /// rasterized by compute.
    #[cfg(feature = "blocking")]
    pub fn splatted_count(&self) -> Result<u32, PortableError> {
        let [_, splatted] = self.renderer.generated_count(&self.device, &self.queue, 0)?;
        Ok(splatted)
    }

    /// The Bezier blades the last culled frame listed, in draw order, and its draw command per
    /// distance bucket ([`PortableField::read_visible`]), once the work submitted so far has
    /// finished.
    #[cfg(feature = "blocking")]
    pub fn read_visible(&self) -> Result<(Vec<u32>, Vec<sward_core::gpu::DrawCommand>), PortableError> {
        let field = self.field.as_ref().ok_or(PortableError::NoField)?;
        field.read_visible(&self.device, &self.queue, 0)
    }

    /// The blades the last frame ran (those of the tiles it ran; every blade where the field
    /// has no tiles).
    pub fn blades_run(&self) -> Result<u32, PortableError> {
        let field = self.field.as_ref().ok_or(PortableError::NoField)?;
        Ok(field.blades_run(0))
    }

    /// The first fault the device reported since the last call, if any.
    pub fn take_fault(&self) -> Result<(), PortableError> {
        let first = {
            let mut faults = self.faults.lock().unwrap_or_else(|e| e.into_inner());
            std::mem::take(&mut *faults).into_iter().next()
        };
        first.map_or(Ok(()), |fault| Err(PortableError::Device(fault)))
    }

    /// Put `field`'s blades (or, where it streams, its window), its ground mesh and its paint
    /// on the GPU.
    pub fn upload(&mut self, field: &Field) -> Result<(), PortableError> {
        self.field = Some(match field.stream {
            Some(window) => PortableField::streamed(&self.device, window)?,
            None => PortableField::with_tiles(&self.device, &field.blades, field.tiles.clone())?,
        });
        self.renderer.upload_ground(&self.device, field.ground.as_ref());
        self.renderer.upload_paint(&self.device, field.paint.as_ref());
        self.renderer.forget_generated(&self.device);
        Ok(())
    }

    /// The frame of `scene` over a field `field_size` wide at simulated time `clock.0` running
    /// `clock.1` steps, on this target.
    pub fn frame(&self, scene: &Scene, field_size: Vec2, clock: (f32, u32)) -> FrameDesc {
        FrameDesc::of_scene(scene, field_size, clock, self.size)
    }

    /// Simulate `steps` fixed steps of `scene` from the field's current state, then cull and
    /// draw one frame and read it back: RGBA, row by row from the top.
    #[cfg(feature = "blocking")]
    pub fn render_scene(&mut self, scene: &Scene, field_size: Vec2, steps: u32) -> Result<Vec<u8>, PortableError> {
        let encoder = self.submit_scene(scene, field_size, steps)?;
        self.read_image(encoder)
    }

    /// The first part of [`PortableHeadless::render_scene`], which waits on nothing: `steps`
    /// fixed steps of `scene` submitted, and an encoder holding the frame's cull and draw, for
    /// the caller to finish (with [`PortableHeadless::record_image_copy`]) and submit.
    pub fn submit_scene(
        &mut self,
        scene: &Scene,
        field_size: Vec2,
        steps: u32,
    ) -> Result<wgpu::CommandEncoder, PortableError> {
        let trampling = scene.tramples() && !scene.colliders_at(0.0).is_empty();
        let per_submit = if trampling { STEPS_PER_TRAMPLE } else { STEPS_PER_SUBMIT };
        let mut done = 0;
        while done < steps {
            let chunk = (steps - done).min(per_submit);
            let desc = self.frame(scene, field_size, (done as f32 * scene.simulation.step, chunk));
            let mut encoder = self.device.create_command_encoder(&Default::default());
            self.record(&mut encoder, &desc, PortablePasses::SIMULATE)?;
            self.queue.submit([encoder.finish()]);
            done += chunk;
        }
        let desc = self.frame(scene, field_size, (steps as f32 * scene.simulation.step, 0));
        let mut encoder = self.device.create_command_encoder(&Default::default());
        self.record(&mut encoder, &desc, PortablePasses::CULL)?;
        self.record_draw(&mut encoder)?;
        Ok(encoder)
    }

    /// Record the frame `desc` describes into `encoder`: its `passes` over the uploaded field
    /// (the frame's uniforms are written once per submission: record one frame per encoder).
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        desc: &FrameDesc,
        passes: PortablePasses,
    ) -> Result<(), PortableError> {
        let field = self.field.as_mut().ok_or(PortableError::NoField)?;
        self.renderer
            .record(&self.device, &self.queue, encoder, desc, field, passes);
        Ok(())
    }

    /// Record the draw of the frame last recorded into the offscreen target: its shadow map,
    /// then what the camera sees.
    pub fn record_draw(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), PortableError> {
        self.record_shadow_map(encoder)?;
        self.record_lit_draw(encoder)
    }

    /// The first part of [`PortableHeadless::record_draw`]: the sun's shadow map, where the
    /// frame has shadows.
    pub fn record_shadow_map(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), PortableError> {
        let field = self.field.as_ref().ok_or(PortableError::NoField)?;
        self.renderer.draw_shadow_map(&self.device, encoder, field);
        Ok(())
    }

    /// The rest of [`PortableHeadless::record_draw`], after its shadow map.
    pub fn record_lit_draw(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), PortableError> {
        let field = self.field.as_ref().ok_or(PortableError::NoField)?;
        let color = self.color.create_view(&Default::default());
        let resolve = self.resolve.as_ref().map(|t| t.create_view(&Default::default()));
        let depth = self.depth.create_view(&Default::default());
        let views = PortableViews {
            color: &color,
            resolve: resolve.as_ref(),
            depth: &depth,
        };
        self.renderer.draw_lit(&self.device, encoder, field, &views);
        Ok(())
    }

    /// The target's colour as the frame leaves it: resolved where it is multisampled
    /// ([`PORTABLE_COLOR`], one sample a pixel; what a caller copies a frame from).
    pub fn resolved_color(&self) -> &wgpu::Texture {
        self.resolve.as_ref().unwrap_or(&self.color)
    }

    /// Finish `encoder` with a copy of the resolved colour, submit it and read the pixels.
    #[cfg(feature = "blocking")]
    fn read_image(&self, mut encoder: wgpu::CommandEncoder) -> Result<Vec<u8>, PortableError> {
        let staging = self.record_image_copy(&mut encoder);
        self.queue.submit([encoder.finish()]);
        let bytes = crate::field::map_read(&self.device, &staging);
        self.take_fault()?;
        Ok(self.image_rows(&bytes?))
    }

    /// Record a copy of the frame's resolved colour into a new buffer for mapping, and return
    /// it: its rows padded to wgpu's copy alignment ([`PortableHeadless::image_rows`] takes the
    /// padding out).
    pub fn record_image_copy(&self, encoder: &mut wgpu::CommandEncoder) -> wgpu::Buffer {
        let [width, height] = self.size;
        let row = padded_row(width);
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward image read-back"),
            size: row as u64 * height as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        encoder.copy_texture_to_buffer(
            self.resolved_color().as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        staging
    }

    /// The image in a mapped copy ([`PortableHeadless::record_image_copy`]) as RGBA, row by row
    /// from the top, without the rows' padding.
    pub fn image_rows(&self, copied: &[u8]) -> Vec<u8> {
        let width = self.size[0] as usize;
        copied
            .chunks(padded_row(self.size[0]) as usize)
            .flat_map(|r| &r[..width * 4])
            .copied()
            .collect()
    }
}

/// Bytes a row of an RGBA image of `width` pixels takes in a buffer a texture is copied into.
fn padded_row(width: u32) -> u32 {
    (width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
}

/// Collect what `device` reports outside an error scope — a validation error, the device lost —
/// as one line each, instead of wgpu's default handler, which panics.
fn watch_faults(device: &wgpu::Device) -> Arc<Mutex<Vec<String>>> {
    let faults = Arc::new(Mutex::new(Vec::new()));
    let one_line = |text: &str| text.split_whitespace().collect::<Vec<_>>().join(" ");
    let errors = faults.clone();
    device.on_uncaptured_error(Arc::new(move |error: wgpu::Error| {
        errors
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(one_line(&error.to_string()));
    }));
    let lost = faults.clone();
    device.set_device_lost_callback(move |reason, message| {
        let line = format!("the GPU device was lost ({reason:?}: {})", one_line(&message));
        lost.lock().unwrap_or_else(|e| e.into_inner()).push(line);
    });
    faults
}
