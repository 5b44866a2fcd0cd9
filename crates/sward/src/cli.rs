//! Command-line arguments and dispatch to the sub-commands.

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use sward_gpu::{ContextDesc, Validation};

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
}

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
        }
    }
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Open the interactive viewer (the default when a display is available)
    View(ViewArgs),
    /// Simulate a scene for some fixed steps and write one frame to a PNG
    Render(RenderArgs),
    /// Print the GPU sward would use and its driver
    Info,
}

#[derive(clap::Args, Debug, Clone)]
pub struct RenderArgs {
    /// A shipped scene's name (meadow) or a path to a scene file
    #[arg(long, default_value = "meadow")]
    pub scene: String,
    /// Image width in pixels
    #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub width: u32,
    /// Image height in pixels
    #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub height: u32,
    /// Fixed simulation steps before the frame is drawn
    #[arg(long, default_value_t = 240, value_parser = clap::value_parser!(u32).range(0..=1_000_000))]
    pub frames: u32,
    /// Where to write the PNG
    #[arg(long, default_value = "meadow.png")]
    pub out: PathBuf,
    /// Patches per indirect draw command (0: one command; default: per driver)
    #[arg(long)]
    pub patches_per_draw: Option<u32>,
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
    /// A shipped scene's name (meadow) or a path to a scene file
    #[arg(long, default_value = "meadow")]
    pub scene: String,
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
    /// Resize the window after FRAME frames to W×H pixels, written FRAME:WxH (for tests)
    #[arg(long, value_parser = parse_resize)]
    pub resize_at: Option<(u32, [u32; 2])>,
}

impl Default for ViewArgs {
    fn default() -> Self {
        match Args::parse_from(["sward", "view"]).command {
            Some(Command::View(args)) => args,
            _ => unreachable!("'sward view' parses as the view command"),
        }
    }
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

impl Default for RenderArgs {
    fn default() -> Self {
        match Args::parse_from(["sward", "render"]).command {
            Some(Command::Render(args)) => args,
            _ => unreachable!("'sward render' parses as the render command"),
        }
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    match args.command {
        Some(Command::Render(render)) => crate::render::render(&render, &args.gpu),
        Some(Command::Info) => crate::render::info(&args.gpu),
        Some(Command::View(view)) => crate::viewer::run(&view, &args.gpu),
        None if crate::viewer::display_available() => crate::viewer::run(&ViewArgs::default(), &args.gpu),
        None => {
            let render = RenderArgs::default();
            println!(
                "no display found; rendering the {} scene to {} instead",
                render.scene,
                render.out.display()
            );
            crate::render::render(&render, &args.gpu)
        }
    }
}
