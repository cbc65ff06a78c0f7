//! The `strata` command: `render` a scene to EXR/PNG, or print what a scene calls for (`info`).
//!
//! Owns: argument parsing, device choice, progress display, Ctrl-C handling, output naming.
//! Must not know: how rendering works (it calls the library crates).

mod device;
mod info;
mod render;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "strata",
    version,
    about = "A Monte Carlo path tracer with a CPU reference"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to EXR (linear + variance) and/or PNG (sRGB).
    Render(render::RenderArgs),
    /// Print a scene's effects, sample-dimension layout and sizes, without rendering.
    Info(info::InfoArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(args),
        Command::Info(args) => info::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
