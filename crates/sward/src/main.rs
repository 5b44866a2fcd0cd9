//! The `sward` command: view responsive grass in a window (`view`), render it to images (`render`)
//! benchmark it (`bench`), run its simulation long and check it (`soak`) and describe the GPU
//! (`info`).

mod animation;
mod args;
mod bench;
mod cli;
mod logging;
mod portable;
mod render;
mod scenes;
mod shaders;
mod soak;
mod viewer;

use clap::Parser;

fn main() {
    logging::init();
    let args = args::Args::parse();
    if let Err(error) = cli::run(args) {
        eprintln!("sward: {}", one_sentence(&error));
        std::process::exit(1);
    }
}

/// The error and its causes on one line, outermost first, without repeating a cause that the
/// context already quotes.
fn one_sentence(error: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in error.chain() {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&cause);
        }
    }
    text
}
