//! Dispatch: runs the sub-command the arguments (`args.rs`) name, or the default job — the viewer
//! where there is a display, else a render of the default scene to an image.

use crate::args::{Args, Command, RenderArgs, ViewArgs};

pub fn run(args: Args) -> anyhow::Result<()> {
    match args.command {
        Some(Command::Render(render)) => crate::render::render(&render, &args.gpu),
        Some(Command::Info) => crate::render::info(&args.gpu),
        Some(Command::Soak(soak)) => {
            args.gpu.check_splat_cells(false)?;
            crate::soak::soak(&soak, &args.gpu)
        }
        Some(Command::Bench(bench)) => crate::bench::run(&bench, &args.gpu),
        Some(Command::View(view)) => {
            args.gpu.check_splat_cells(false)?;
            crate::viewer::run(&view, &args.gpu)
        }
        Some(Command::Scene(what)) => crate::scenes::print_reference(what.markdown),
        Some(Command::Shaders(shaders)) => crate::shaders::write_wgsl(&shaders.out),
        None if crate::viewer::display_available() => crate::viewer::run(&ViewArgs::default(), &args.gpu),
        None => {
            let render = RenderArgs::default();
            println!(
                "no display found; rendering the {} scene to {} instead",
                render.scene.name,
                render.out_path().display()
            );
            crate::render::render(&render, &args.gpu)
        }
    }
}
