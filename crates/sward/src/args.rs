//! The command line's arguments: what each sub-command takes, parsed by clap. Dispatch lives in
//! `cli.rs`; the sub-commands read these types and never the module that dispatches to them.

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use sward_gpu::{ContextDesc, Validation, Withheld};
use sward_wgpu::portable::ShaderModules;

#[derive(Parser, Debug)]
#[command(name = "sward", version, about = "Responsive real-time grass on Vulkan")]
pub struct Args {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

#[derive(clap::Args, Debug, Clone)]
pub struct GpuArgs {
    /// GPU to use: its index or part of its name (default: the best one)
    #[arg(long, global = true)]
    pub gpu: Option<String>,
    /// Load the Khronos validation layer and fail on any validation message
    #[arg(long, global = true)]
    pub validation: bool,
    /// Use at most this much GPU memory (MiB), as if the GPU had no more
    #[arg(long, global = true, value_name = "MIB", value_parser = clap::value_parser!(u64).range(1..=1 << 30))]
    pub gpu_memory: Option<u64>,
    /// Leave these optional GPU features unused, as if the GPU lacked them (comma separated)
    #[arg(long, global = true, value_enum, value_delimiter = ',', value_name = "FEATURES")]
    pub without: Vec<OptionalFeature>,
    /// Treat the GPU as lost after this many queue submissions (to test how sward ends)
    #[arg(long, global = true, hide = true)]
    pub lose_device_after: Option<u64>,
    /// The portable renderer splats its far field into 32-bit cells (a 16-bit depth key above
    /// a 16-bit colour), as on a device without 64-bit atomics (WebGPU, GL), even where the
    /// device has them: to see and measure that path
    #[arg(long, global = true)]
    pub narrow_splats: bool,
}

/// Optional GPU features sward can do without.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum OptionalFeature {
    /// VK_EXT_mesh_shader: the mesh draw route
    MeshShaders,
    /// 64-bit buffer atomics: the compute route and the splatted far field
    Int64Atomics,
    /// The portable renderer's 32-bit splat cells, its far field where a device lacks 64-bit
    /// atomics (without both it draws the far field as geometry)
    NarrowSplats,
    /// The portable renderer's compute passes handed to wgpu's Vulkan backend as the Vulkan
    /// renderer's SPIR-V (without it, wgpu's own translation of their WGSL)
    SpirvPassthrough,
    /// The portable renderer's subgroup operations (its cull's compaction): without them, the
    /// passes written for WebGPU's core
    Subgroups,
}

/// The `--without` features only the portable renderer has, by name.
const PORTABLE_ONLY: [(OptionalFeature, &str); 3] = [
    (OptionalFeature::NarrowSplats, "narrow-splats"),
    (OptionalFeature::SpirvPassthrough, "spirv-passthrough"),
    (OptionalFeature::Subgroups, "subgroups"),
];

impl GpuArgs {
    pub fn context_desc(&self) -> ContextDesc {
        let validation = if self.validation {
            Validation::Required
        } else {
            ContextDesc::default().validation
        };
        ContextDesc {
            validation,
            gpu: self.gpu.clone(),
            display: None,
            memory_budget: self.gpu_memory.map(|mib| mib << 20),
            withheld: Withheld {
                mesh_shaders: self.without.contains(&OptionalFeature::MeshShaders),
                int64_atomics: self.without.contains(&OptionalFeature::Int64Atomics),
            },
            lose_device_after: self.lose_device_after,
        }
    }

    /// `modules` with the portable renderer's splat cells as asked: 32 bits wide
    /// (`--narrow-splats`), none where the device lacks 64-bit atomics (`--without
    /// narrow-splats`), else as the device allows.
    pub fn splat_modules(&self, modules: ShaderModules) -> anyhow::Result<ShaderModules> {
        self.check_splat_cells(true)?;
        Ok(match self.narrow_splats {
            true => modules.with_narrow_splats(true),
            false if self.without.contains(&OptionalFeature::NarrowSplats) => modules.with_narrow_splats(false),
            false => modules,
        })
    }

    /// The splat-cell flags refused in one sentence where they contradict each other, or where
    /// the Vulkan renderer draws (`portable` false), which splats into 64-bit cells only.
    pub fn check_splat_cells(&self, portable: bool) -> anyhow::Result<()> {
        let without = self.without.contains(&OptionalFeature::NarrowSplats);
        if self.narrow_splats && without {
            anyhow::bail!("--narrow-splats asks for the 32-bit splat cells that --without narrow-splats leaves out: give one of them");
        }
        if !portable && (self.narrow_splats || without) {
            anyhow::bail!("--narrow-splats and --without narrow-splats choose the portable renderer's splat cells (--renderer wgpu); the Vulkan renderer splats into 64-bit cells, or with --without int64-atomics not at all");
        }
        let portable_only = PORTABLE_ONLY.iter().find(|(f, _)| self.without.contains(f));
        if let (false, Some((_, name))) = (portable, portable_only) {
            anyhow::bail!("--without {name} leaves out what only the portable renderer uses (--renderer wgpu); the Vulkan renderer can do without mesh-shaders or int64-atomics");
        }
        Ok(())
    }

    /// The optional features the portable renderer uses on `adapter`, less those `--without`
    /// withholds (64-bit atomics: its far field then drawn or in 32-bit cells, not in 64-bit
    /// ones; the SPIR-V pass-through; subgroups).
    pub fn portable_features(&self, adapter: &sward_wgpu::wgpu::Adapter) -> sward_wgpu::wgpu::Features {
        use sward_wgpu::wgpu::Features;
        let withheld = [
            (OptionalFeature::Int64Atomics, sward_wgpu::portable::SPLAT_FEATURES),
            (OptionalFeature::SpirvPassthrough, Features::PASSTHROUGH_SHADERS),
            (OptionalFeature::Subgroups, Features::SUBGROUP),
        ];
        withheld
            .into_iter()
            .filter(|(named, _)| self.without.contains(named))
            .fold(
                sward_wgpu::portable::portable_features(adapter),
                |features, (_, left_out)| features - left_out,
            )
    }
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Open the interactive viewer (the default when a display is available)
    View(ViewArgs),
    /// Simulate a scene for some fixed steps and write one frame to a PNG
    Render(RenderArgs),
    /// Time every pass over blade counts × culling modes × presets; tables, CSV and plots
    Bench(BenchArgs),
    /// Print the GPU sward would use and its driver, then every Vulkan device with its index,
    /// driver and draw routes
    Info,
    /// Simulate a scene for a long time on the GPU, checking every blade as it goes
    Soak(SoakArgs),
    /// Print every key a scene file takes, with what it means and takes and its default, as a
    /// commented scene file (or, with --markdown, the reference page)
    Scene(SceneReferenceArgs),
    /// Write the WGSL of every pipeline of the portable renderer as the device gets it (its
    /// modules joined), one file each, so any WGSL tool can check it
    Shaders(ShadersArgs),
}

#[derive(clap::Args, Debug, Clone)]
pub struct ShadersArgs {
    /// The folder to write them to (made if missing)
    #[arg(long)]
    pub out: std::path::PathBuf,
}

#[derive(clap::Args, Debug, Clone)]
pub struct SceneReferenceArgs {
    /// Print the reference as Markdown (docs/scene-reference.md) instead of a scene file
    #[arg(long)]
    pub markdown: bool,
}

#[derive(clap::Args, Debug, Clone)]
pub struct SoakArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Fixed simulation steps in all
    #[arg(long, default_value_t = 100_000, value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
    pub steps: u64,
    /// Read every blade back and check it after this many steps
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub check_every: u32,
    /// Stiffness at both ends of its range, every wind at strength 100, colliders along the ground
    #[arg(long)]
    pub extreme: bool,
    /// Walk the camera along the scene's camera path at this many units per second (a streamed
    /// field's window follows it) [default: the path's own speed; a scene without a path stands]
    #[arg(long, value_parser = parse_speed)]
    pub speed: Option<f32>,
}

#[derive(clap::Args, Debug, Clone)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image width in pixels
    #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub width: u32,
    /// Image height in pixels
    #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub height: u32,
    /// Fixed simulation steps before the frame is drawn
    #[arg(long, default_value_t = 240, value_parser = clap::value_parser!(u32).range(0..=1_000_000))]
    pub steps: u32,
    /// Not render's: --frames counts drawn frames (view, bench); render counts steps (--steps)
    #[arg(long = "frames", hide = true)]
    pub frames: Option<String>,
    /// Where to write the PNG [default: the scene's name, e.g. prairie.png]
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Patches per indirect draw command (0: one command; default: per driver)
    #[arg(long)]
    pub patches_per_draw: Option<u32>,
    /// Write an animation of this many frames (an animated PNG at --out) after the --steps
    /// steps, instead of one still
    #[arg(long, value_name = "FRAMES", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub animation: Option<u32>,
    /// Frames per second of the animation: each frame advances the simulation by 1/FPS seconds
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=240))]
    pub fps: u32,
    /// With --animation: also write each frame as its own PNG, OUT-0001.png, OUT-0002.png, …
    #[arg(long, requires = "animation")]
    pub sequence: bool,
    /// With --animation: turn the camera about its target by this many degrees per second
    #[arg(long, value_name = "DEGREES", requires = "animation", allow_negative_numbers = true, value_parser = parse_degrees)]
    pub orbit: Option<f32>,
    /// Compile the shaders from this folder instead of those built in (any of the core's WESL
    /// modules the folder holds in place of the built-in one, on either renderer; the Vulkan
    /// renderer's GLSL stages too): see a shader change's picture with the binary that measures
    /// it (bench --shaders)
    #[arg(long, value_name = "DIR")]
    pub shaders: Option<PathBuf>,
    #[command(flatten)]
    pub renderer: RendererArgs,
}

/// Which renderer draws, and on which wgpu backend the portable one runs.
#[derive(clap::Args, Debug, Clone)]
pub struct RendererArgs {
    /// Which renderer draws: vulkan (sward's own: every technique, route and shadow), wgpu (the
    /// portable renderer on any wgpu backend: Bezier blades, the generated grass, ground and sky)
    /// or auto (Vulkan where a Vulkan device has what sward needs, else wgpu, and says so)
    #[arg(long, value_enum, default_value_t = RendererArg::Auto)]
    pub renderer: RendererArg,
    /// The wgpu backend the portable renderer runs on [default: the first that has an adapter]
    #[arg(long, value_enum)]
    pub wgpu_backend: Option<WgpuBackendArg>,
}

/// The renderers `--renderer` names.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum RendererArg {
    /// Vulkan where a device has what sward needs, else the portable renderer
    Auto,
    /// sward's Vulkan renderer
    Vulkan,
    /// The portable renderer, through wgpu
    Wgpu,
}

/// The wgpu backends `--wgpu-backend` names.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum WgpuBackendArg {
    Vulkan,
    /// OpenGL 4.3 or GL ES 3.1 (EGL on Linux)
    Gl,
    /// Metal (macOS, iOS)
    Metal,
    /// DirectX 12 (Windows)
    Dx12,
}

impl RendererArgs {
    /// The wgpu backends the portable renderer may take.
    pub fn wgpu_backends(&self) -> sward_wgpu::wgpu::Backends {
        use sward_wgpu::wgpu;
        match self.wgpu_backend {
            None => wgpu::Backends::all(),
            Some(WgpuBackendArg::Vulkan) => wgpu::Backends::VULKAN,
            Some(WgpuBackendArg::Gl) => wgpu::Backends::GL,
            Some(WgpuBackendArg::Metal) => wgpu::Backends::METAL,
            Some(WgpuBackendArg::Dx12) => wgpu::Backends::DX12,
        }
    }
}

#[derive(clap::Args, Debug, Clone)]
pub struct BenchArgs {
    #[command(flatten)]
    pub renderer: RendererArgs,
    /// Blade counts, comma separated; each a number or 2^N [default: 2^10,2^12,…,2^24; quick: 2^10,2^12].
    /// Above 2^26 only with --technique instanced or billboard, where a count sets the density
    #[arg(long, value_delimiter = ',', value_parser = parse_count)]
    pub counts: Vec<u32>,
    /// Override one value of every preset's scene, e.g. --set instanced.splat_distance=60
    /// (repeatable; blade counts and densities still come from --counts)
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_set)]
    pub set: Vec<(String, String)>,
    /// Culling modes to sweep [default: all five]
    #[arg(long, value_enum, value_delimiter = ',')]
    pub modes: Vec<CullMode>,
    /// Scene presets to sweep [default: cis565,meadow]; prairie is the scale preset
    #[arg(long, value_enum, value_delimiter = ',')]
    pub presets: Vec<Preset>,
    /// Image width [default: 1920; quick: 320]
    #[arg(long, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub width: Option<u32>,
    /// Image height [default: 1080; quick: 240]
    #[arg(long, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub height: Option<u32>,
    /// Frames run before timing starts [default: 30; quick: 3]
    #[arg(long)]
    pub warmup: Option<u32>,
    /// Timed frames per case [default: 200; quick: 10]
    #[arg(long)]
    pub frames: Option<u32>,
    /// Stop timing a case after this many seconds (keeping at least 20 frames)
    #[arg(long, default_value_t = 4.0)]
    pub max_seconds: f32,
    /// A small sweep that finishes in under a minute on a CPU driver
    #[arg(long)]
    pub quick: bool,
    /// Folder for results.md, summary.csv, frames.csv and the plots
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Patches per indirect draw command (0: one command; default: per driver)
    #[arg(long)]
    pub patches_per_draw: Option<u32>,
    /// Compute workgroup size of simulate and cull
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(32..=1024))]
    pub workgroup: u32,
    /// Compute workgroup size of the instanced grass's generating passes: 32, 64, 128, 256, 512 or
    /// 1024 (a patch's cells; the device's limits permitting, else --workgroup)
    #[arg(long, default_value_t = sward_core::instanced::PATCH_BLADES, value_parser = parse_patch_divisor)]
    pub instanced_workgroup: u32,
    /// One atomic per visible blade instead of one per subgroup
    #[arg(long)]
    pub no_subgroup_atomics: bool,
    /// Simulate and cull as two dispatches instead of one fused pass
    #[arg(long)]
    pub separate: bool,
    /// Cull copies whole blades for the draw instead of 4-byte indices (to measure what indices save)
    #[arg(long)]
    pub copy_blades: bool,
    /// The passes compiled with the runtime checks WebGPU asks of untrusted shaders (bounds
    /// checks, loop bounds, zeroed workgroup memory), on either renderer (to measure what they
    /// cost; a browser's WebGPU always adds them)
    #[arg(long)]
    pub wgsl_checks: bool,
    /// Record every frame's passes anew instead of replaying the last frame's recording while
    /// nothing that shapes them changed (to measure what keeping them saves the host)
    #[arg(long)]
    pub record_every_frame: bool,
    /// Override the presets' highest tessellation level (level of detail up close)
    #[arg(long)]
    pub lod_max: Option<f32>,
    /// Which blades to draw; with `instanced` (or `billboard`), a count is the number of candidate
    /// blades (billboards) within the cut-off radius (it sets the density)
    #[arg(long, value_enum)]
    pub technique: Option<TechniqueArg>,
    /// Draw routes of the Bezier blades to sweep, comma separated [default: auto]
    #[arg(long, value_enum, value_delimiter = ',')]
    pub draw_route: Vec<RouteArg>,
    /// Quality presets to sweep, comma separated [default: high]
    #[arg(long, value_enum, value_delimiter = ',')]
    pub quality: Vec<QualityArg>,
    /// Camera speeds to sweep, units (metres) per second, comma separated: the camera moves along
    /// the scene's camera path (straight ahead where it has none) at each; 0 stands still
    /// [default: 0]. A moving case's table reports frame pacing (p99, worst, hitches)
    #[arg(long, value_delimiter = ',', value_parser = parse_speed)]
    pub speeds: Vec<f32>,
    /// Measure only the raster floor: blades and triangles per second of each route, fragments
    /// per second at each sample count, blades per second of the compute rasterizer (a full run,
    /// without --quick, measures it after its sweep)
    #[arg(long)]
    pub floor: bool,
    /// Run the regression set instead of a sweep: the named cases where cost grows with scale
    /// (generated grass at 2^24 and 2^26, the landscape chain, the prairie, cis565, billboards, the
    /// open world walked, run and flown); compare two runs' folders with --compare
    #[arg(long, conflicts_with_all = ["counts", "presets", "technique", "speeds", "modes", "shipped"])]
    pub regression_set: bool,
    /// Run every shipped scene as it ships (and the meadow with each technique) instead of a
    /// sweep: the table of what to expect (expect.md in the output folder)
    #[arg(long, conflicts_with_all = ["counts", "presets", "technique", "speeds", "modes"])]
    pub shipped: bool,
    /// Measure this scene (a shipped scene's name or a scene file) as it is — its own blades,
    /// technique, camera and paint, every culling test on — instead of a sweep, one row of the
    /// table of what to expect (expect.md) each; repeatable, and after the shipped set with
    /// --shipped
    #[arg(long = "scene", value_name = "NAME_OR_FILE", conflicts_with_all = ["counts", "presets", "technique", "speeds", "modes", "regression_set"])]
    pub scenes: Vec<String>,
    /// Compare two result folders case by case (the ratio of each case's median GPU frame) and
    /// exit non-zero when a case in NEW is more than --tolerance slower than in OLD; runs nothing
    #[arg(long, num_args = 2, value_names = ["OLD", "NEW"])]
    pub compare: Vec<PathBuf>,
    /// With --compare: how much slower a case may be, per cent
    #[arg(long, default_value_t = 3.0, value_parser = parse_tolerance)]
    pub tolerance: f64,
    /// Compile the shaders from this folder instead of those built in (any of
    /// crates/sward-core/shaders' WESL modules in place of the built-in ones, on either
    /// renderer; for the Vulkan renderer a copy of crates/sward-gpu/shaders' GLSL beside them):
    /// measure a shader change before and after with one binary
    #[arg(long, value_name = "DIR")]
    pub shaders: Option<PathBuf>,
}

/// The largest bench count: candidates of a generated field, which sets its density (a Bezier
/// field holds at most `MAX_BLADES`, which `bench_scene` checks).
pub const MAX_BENCH_COUNT: u32 = 1 << 28;

fn parse_count(text: &str) -> Result<u32, String> {
    let text = text.trim();
    let value = match text.strip_prefix("2^") {
        Some(exp) => exp.parse::<u32>().ok().filter(|e| *e <= 28).map(|e| 1u32 << e),
        None => text.parse::<u32>().ok(),
    };
    value.filter(|v| (1..=MAX_BENCH_COUNT).contains(v)).ok_or_else(|| {
        format!("'{text}' is not a blade count: use a number from 1 to {MAX_BENCH_COUNT} or 2^N with N ≤ 28")
    })
}

/// A workgroup size that divides a patch's cells: a power of two from 32 to 1024.
fn parse_patch_divisor(text: &str) -> Result<u32, String> {
    let patch = sward_core::instanced::PATCH_BLADES;
    match text.trim().parse::<u32>() {
        Ok(v) if v >= 32 && v <= patch && patch.is_multiple_of(v) => Ok(v),
        _ => Err(format!(
            "{text} does not divide a patch's {patch} cells: use 32, 64, 128, 256, 512 or 1024"
        )),
    }
}

/// A per-cent tolerance: a finite number from 0 to 100.
fn parse_tolerance(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if (0.0..=100.0).contains(&v) => Ok(v),
        _ => Err(format!("{s} is not a tolerance: give a per cent from 0 to 100, e.g. 3")),
    }
}

/// How finished frames reach the screen.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum PresentMode {
    /// Vsync on
    Fifo,
    /// Vsync off, no tearing (falls back to fifo where unsupported)
    Mailbox,
    /// Vsync off (falls back to fifo where unsupported)
    Immediate,
}

#[derive(clap::Args, Debug, Clone)]
pub struct ViewArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Window width in pixels
    #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(64..=16384))]
    pub width: u32,
    /// Window height in pixels
    #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(64..=16384))]
    pub height: u32,
    /// Presentation: fifo (vsync on), mailbox or immediate (vsync off)
    #[arg(long, value_enum, default_value_t = PresentMode::Fifo)]
    pub present_mode: PresentMode,
    /// Draw this many frames, then exit
    #[arg(long)]
    pub frames: Option<u32>,
    /// With --frames: save the last frame to this PNG
    #[arg(long, requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// Start on foot: walk mode (WASD at a person's pace, shift to run), where the scene's camera
    /// stands
    #[arg(long)]
    pub walk: bool,
    /// Show the trample map in the panel from the start (trails yellow, mown grass brown)
    #[arg(long)]
    pub show_trample_map: bool,
    /// Resize the window after FRAME frames to W×H pixels, written FRAME:WxH (for tests)
    #[arg(long, value_parser = parse_resize)]
    pub resize_at: Option<(u32, [u32; 2])>,
    /// Switch to quality PRESET after FRAME frames, written FRAME:PRESET (for tests)
    #[arg(long, value_parser = parse_quality_at)]
    pub quality_at: Option<(u32, QualityArg)>,
    /// After FRAME frames drag the paint brush (density 0, radius 2) along the ground from
    /// (X0, Z0) to (X1, Z1), written FRAME:X0,Z0,X1,Z1, as a person painting a path would (for
    /// tests)
    #[arg(long, value_parser = parse_brush_at)]
    pub brush_at: Option<(u32, [f32; 4])>,
    /// With --frames: act as a restless user, seeded by SEED — random resizes (to nothing and
    /// 16384 wide too), minimising, and panel edits of blade count, technique, route and
    /// quality — twice over, reporting GPU memory in use after each (for tests)
    #[arg(long, value_name = "SEED", requires = "frames")]
    pub stress: Option<u64>,
}

impl Default for ViewArgs {
    fn default() -> Self {
        match Args::parse_from(["sward", "view"]).command {
            Some(Command::View(args)) => args,
            _ => unreachable!("'sward view' parses as the view command"),
        }
    }
}

/// The scene `render` and `view` show: `--scene`, its `--set` overrides and `--technique`.
#[derive(clap::Args, Debug, Clone)]
pub struct SceneArgs {
    /// A shipped scene's name (meadow) or a path to a scene file
    #[arg(long = "scene", default_value = "meadow")]
    pub name: String,
    /// Override one scene value, e.g. --set wind.strength=3 --set field.blades=20000 or
    /// --set wind.1.type=whirl (repeatable)
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_set)]
    pub set: Vec<(String, String)>,
    /// Which blades to draw: bezier (physics), instanced (the GPU-generated field) or both
    /// (Bezier near the camera, instanced beyond), billboard (crossed textured quads) or landscape
    /// (Bezier → instanced → billboards → tinted ground); overrides the scene's `technique`
    #[arg(long, value_enum)]
    pub technique: Option<TechniqueArg>,
    /// Quality preset: low (1 sample, half the blade segments), medium, high (4× MSAA, the
    /// reference picture) or ultra; overrides the scene's `[quality]` preset
    #[arg(long, value_enum)]
    pub quality: Option<QualityArg>,
    /// How the Bezier blades reach the rasterizer (see docs/program.md); overrides the scene's
    /// `[quality] route`
    #[arg(long, value_enum)]
    pub draw_route: Option<RouteArg>,
}

impl SceneArgs {
    /// The scene with its overrides applied and validated.
    pub fn load(&self) -> anyhow::Result<sward_core::Scene> {
        let mut scene = crate::scenes::load_with(&self.name, &self.set)?;
        if let Some(technique) = self.technique {
            scene.technique = technique.into();
        }
        if let Some(quality) = self.quality {
            scene.quality.preset = quality.into();
        }
        if let Some(route) = self.draw_route {
            scene.quality.route = route.into();
        }
        Ok(scene)
    }
}

/// The techniques `--technique` names (the scene file's `technique` values).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum TechniqueArg {
    Bezier,
    Instanced,
    Both,
    Billboard,
    Landscape,
}

impl From<TechniqueArg> for sward_core::instanced::Technique {
    fn from(t: TechniqueArg) -> Self {
        match t {
            TechniqueArg::Bezier => Self::Bezier,
            TechniqueArg::Instanced => Self::Instanced,
            TechniqueArg::Both => Self::Both,
            TechniqueArg::Billboard => Self::Billboard,
            TechniqueArg::Landscape => Self::Landscape,
        }
    }
}

/// The routes `--draw-route` names.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum RouteArg {
    /// The fastest route of this device
    Auto,
    /// One tessellated patch per blade (the reference picture)
    Tessellation,
    /// One vertex-pulled triangle strip per blade, no tessellator
    Strips,
    /// Strips up to the scene's lod.splat_distance, splatted by compute beyond it (with lod.compute_raster, blades from lod.strip_distance on rasterized by compute)
    Compute,
    /// Mesh shaders, where the GPU has them (VK_EXT_mesh_shader)
    Mesh,
}

impl From<RouteArg> for sward_gpu::DrawRoute {
    fn from(r: RouteArg) -> Self {
        match r {
            RouteArg::Auto => Self::Auto,
            RouteArg::Tessellation => Self::Tessellation,
            RouteArg::Strips => Self::Strips,
            RouteArg::Compute => Self::Compute,
            RouteArg::Mesh => Self::Mesh,
        }
    }
}

/// The presets `--quality` names (the scene file's `[quality] preset` values).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum QualityArg {
    Low,
    Medium,
    High,
    Ultra,
}

impl From<QualityArg> for sward_core::quality::QualityPreset {
    fn from(q: QualityArg) -> Self {
        match q {
            QualityArg::Low => Self::Low,
            QualityArg::Medium => Self::Medium,
            QualityArg::High => Self::High,
            QualityArg::Ultra => Self::Ultra,
        }
    }
}

fn parse_set(text: &str) -> Result<(String, String), String> {
    let (key, value) = text
        .split_once('=')
        .ok_or_else(|| format!("'{text}' is not KEY=VALUE, e.g. wind.strength=3"))?;
    Ok((key.trim().to_string(), value.trim().to_string()))
}

fn parse_quality_at(text: &str) -> Result<(u32, QualityArg), String> {
    use clap::ValueEnum;
    let bad = || format!("'{text}' is not FRAME:PRESET, e.g. 30:low (presets: low, medium, high, ultra)");
    let (frame, preset) = text.split_once(':').ok_or_else(bad)?;
    let frame = frame.trim().parse::<u32>().map_err(|_| bad())?;
    Ok((frame, QualityArg::from_str(preset.trim(), true).map_err(|_| bad())?))
}

/// Degrees per second: a finite number within ±100,000.
fn parse_degrees(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(d) if d.is_finite() && d.abs() <= 1e5 => Ok(d),
        _ => Err(format!(
            "'{text}' is not a number of degrees per second between -100000 and 100000"
        )),
    }
}

fn parse_brush_at(text: &str) -> Result<(u32, [f32; 4]), String> {
    let bad = || format!("'{text}' is not FRAME:X0,Z0,X1,Z1, e.g. 10:-5,-4,5,-4");
    let (frame, line) = text.split_once(':').ok_or_else(bad)?;
    let numbers: Vec<f32> = line
        .split(',')
        .map(|v| v.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    let line: [f32; 4] = numbers.try_into().map_err(|_| bad())?;
    if !line.iter().all(|v| v.is_finite()) {
        return Err(bad());
    }
    Ok((frame.trim().parse::<u32>().map_err(|_| bad())?, line))
}

fn parse_resize(text: &str) -> Result<(u32, [u32; 2]), String> {
    let bad = || format!("'{text}' is not FRAME:WxH, e.g. 30:400x300");
    let (frame, size) = text.split_once(':').ok_or_else(bad)?;
    let (w, h) = size.split_once('x').ok_or_else(bad)?;
    let number = |s: &str| s.trim().parse::<u32>().map_err(|_| bad());
    let (w, h) = (number(w)?, number(h)?);
    if w == 0 || h == 0 {
        return Err(format!("'{text}': width and height must be at least 1"));
    }
    Ok((number(frame)?, [w, h]))
}

impl RenderArgs {
    /// Where the image goes: `--out`, else `SCENE.png` in the working directory, named after
    /// `--scene` (a shipped scene's name, or a scene file's stem: `my/hill.toml` → `hill.png`),
    /// kept to letters, digits, `-` and `_`.
    pub fn out_path(&self) -> PathBuf {
        if let Some(out) = &self.out {
            return out.clone();
        }
        let scene = std::path::Path::new(&self.scene.name);
        let stem = scene
            .file_stem()
            .map_or(self.scene.name.clone(), |s| s.to_string_lossy().into_owned());
        let name: String = stem
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '-'
                }
            })
            .collect();
        let name = if name.trim_matches('-').is_empty() {
            "scene".to_string()
        } else {
            name
        };
        PathBuf::from(format!("{name}.png"))
    }
}

impl Default for RenderArgs {
    fn default() -> Self {
        match Args::parse_from(["sward", "render"]).command {
            Some(Command::Render(args)) => args,
            _ => unreachable!("'sward render' parses as the render command"),
        }
    }
}

/// The scene set-ups a sweep runs.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// The CIS 565 course set-up: 15×15 plane, its blade attributes, 45° lens at distance 10.
    Cis565,
    /// The shipped meadow at constant density: the field grows with the count; eye-height camera.
    Meadow,
    /// The shipped hills: terrain that hides much of its grass from the low camera (occlusion).
    Hills,
    /// The shipped prairie (2^24 blades, 16 spheres, rolling terrain) at the count's blades over
    /// the same terrain.
    Prairie,
    /// The shipped trample scene (64 rolling spheres seen from above) at the count's blades over
    /// the same field: what colliders cost.
    Trample,
    /// The shipped open world (a streamed field over kilometres of terrain, the whole chain), the
    /// count its streaming budget; with --speeds, its camera path walked, run and flown.
    Openworld,
    /// The shipped landscape (Bezier blades near, generated grass, billboards, tinted ground) at
    /// the count's Bezier blades.
    Landscape,
    /// The shipped park (paths, lawns and three kinds of grass painted, the whole chain).
    Park,
    /// The shipped planet: grass over a whole sphere.
    Planet,
    /// The shipped trail (a mower cutting through the landscape chain).
    Trail,
}

/// Which culling tests are on.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum CullMode {
    None,
    Orientation,
    Frustum,
    Distance,
    /// Whole tiles outside the view skipped (simulation and culling).
    Tiles,
    /// Blades behind occluders culled with the depth pyramid.
    Occlusion,
    All,
}

/// A camera speed: a finite number of units per second from 0 to 1000.
fn parse_speed(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if (0.0..=1000.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "{s} is not a camera speed: give units per second from 0 to 1000, e.g. 1.5,10,100"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn render(args: &[&str]) -> RenderArgs {
        let args = ["sward", "render"].iter().chain(args);
        match Args::parse_from(args).command {
            Some(Command::Render(render)) => render,
            _ => unreachable!("parsed as the render command"),
        }
    }

    #[test]
    fn a_render_is_written_after_its_scene_unless_told_where() {
        assert_eq!(render(&[]).out_path(), PathBuf::from("meadow.png"));
        assert_eq!(render(&["--scene", "prairie"]).out_path(), PathBuf::from("prairie.png"));
        assert_eq!(
            render(&["--scene", "my/hill side.toml"]).out_path(),
            PathBuf::from("hill-side.png")
        );
        assert_eq!(
            render(&["--scene", "prairie", "--out", "x/y.png"]).out_path(),
            PathBuf::from("x/y.png")
        );
    }
}
