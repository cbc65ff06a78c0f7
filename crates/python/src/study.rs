//! `strata.study`: `strata study` from Python, with the command's options and checks.

use crate::error;
use crate::session;
use clap::Parser;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use std::path::PathBuf;
use stratapt_cli::study::{study_with, Studied, StudyArgs};

/// `strata study`'s options, parsed from the words the `strata` package makes of its keyword
/// arguments, so that they mean and are checked as on the command line.
#[derive(Parser)]
#[command(name = "strata.study", no_binary_name = true, disable_help_flag = true)]
struct StudyCommand {
    #[command(flatten)]
    args: StudyArgs,
}

/// Run the study `words` asks for (`strata study`'s arguments, scene first); `command` is how
/// its report names the call. Returns the folder its files were written in. Ctrl-C stops it:
/// the files then hold what was measured, and `KeyboardInterrupt` is raised.
#[pyfunction]
pub fn study(py: Python<'_>, words: Vec<String>, command: String) -> PyResult<PathBuf> {
    let mut parsed = StudyCommand::try_parse_from(&words)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.render().to_string()))?;
    parsed.args.command = Some(command);
    let scene = PathBuf::from(words.first().cloned().unwrap_or_default());
    let args = &parsed.args;
    // On the devices this process opened, whose kernels the study then shares with renders.
    let studied = session::interruptible(py, None, |watch| {
        study_with(args, &watch.cancel, &mut session::open)
    })?;
    match studied {
        Ok(Studied::Measured {
            out,
            cancelled: false,
        }) => Ok(out),
        Ok(
            Studied::Measured {
                cancelled: true, ..
            }
            | Studied::NothingMeasured,
        ) => Err(PyKeyboardInterrupt::new_err("study interrupted")),
        Err(e) if !scene.exists() => Err(error::scene(&scene, &e)),
        Err(e) => Err(error::runtime(format!("{e:#}"))),
    }
}
