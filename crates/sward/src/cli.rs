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
        None => crate::render::render(&RenderArgs::default(), &args.gpu),
    }
}
