//! The `strata` command: `render` a scene to EXR/PNG (whole, or a part of its samples),
//! `merge` parts, print what a scene calls for (`info`), time the renderers (`bench`), list GPU
//! adapters (`adapters`), write a pbrt-v4 scene as strata's own (`convert`). Every command that
//! reads a scene takes strata's TOML or a pbrt-v4 file.
//!
//! Owns: argument parsing (the commands themselves are in the crate's library, `src/lib.rs`).

use clap::{Parser, Subcommand};
use std::process::ExitCode;
use stratapt_cli::{bench, convert, device, info, merge, render, study};

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
    /// Render a scene to EXR (linear + variance) and/or PNG (sRGB), whole or one part of it
    /// (`--part K/N`) for `merge`.
    Render(render::RenderArgs),
    /// Sum render parts into the whole render, exactly (parts rendered anywhere, e.g. as a
    /// Slurm or Kubernetes job array; see docs/guide/many-machines.md).
    Merge(merge::MergeArgs),
    /// Measure error against time for every sampler × strategy, against a reference: CSV,
    /// plots and a ranked report.
    Study(study::StudyArgs),
    /// Print a scene's effects, sample-dimension layout and sizes, without rendering.
    Info(info::InfoArgs),
    /// Time the GPU renderer and the CPU reference on scenes: paths/s, rays/s, ms per spp.
    Bench(bench::BenchArgs),
    /// List the GPU adapters wgpu finds, best first (the one `--device gpu` takes).
    Adapters,
    /// Write a pbrt-v4 scene as strata's own (.toml), or any scene as Mitsuba 3's (.xml).
    Convert(convert::ConvertArgs),
}

fn main() -> ExitCode {
    quiet_device_select();
    quiet_obj_parser_panics();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Study(args) => study::run(args),
        Command::Info(args) => info::run(args).map(|()| ExitCode::SUCCESS),
        Command::Bench(args) => bench::run(args).map(|()| ExitCode::SUCCESS),
        Command::Adapters => device::list_adapters().map(|()| ExitCode::SUCCESS),
        Command::Convert(args) => convert::run(args).map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(code) => code,
        Err(err) if is_broken_pipe(&err) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}

/// The OBJ parser (tobj) panics on some malformed files (indices that overflow, found by the
/// mutation corpus); the scene loader catches that and reports the file as malformed, so the
/// panic's own message would only be noise before the real error. Every other panic is
/// reported as usual.
fn quiet_obj_parser_panics() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let in_tobj = info.location().is_some_and(|l| {
            let file = l.file().replace('\\', "/");
            file.contains("/tobj-") || file.contains("/tobj/")
        });
        if !in_tobj {
            default(info);
        }
    }));
}

fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|e| {
        e.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Mesa's implicit Vulkan layer `VK_LAYER_MESA_device_select` only reorders devices (strata
/// ranks adapters itself), and on a machine without a display it prints "XDG_RUNTIME_DIR is
/// invalid" twice per instance. Turn it off unless the user set the variable themselves. Runs
/// first in `main`, before any thread exists.
fn quiet_device_select() {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}
