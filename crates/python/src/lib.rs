//! strata from Python: the extension module `strata._strata`, which the `strata` package
//! (`python/strata/__init__.py`) wraps with the documented API (`load`, `render`, `study`,
//! `merge`, `adapters`).
//!
//! Owns: conversions between Python and strata's types, running work off the interpreter's lock
//! with Ctrl-C and progress handled from the interpreter's thread, the devices (and so the
//! compiled kernels) kept for the process.
//! Must not know: how scenes load, devices are chosen or films are written: the `strata`
//! command's library does that, so that a script and the command say the same.

mod error;
mod film;
mod render;
mod scene;
mod session;
mod study;

use pyo3::prelude::*;

#[pymodule]
fn _strata(m: &Bound<'_, PyModule>) -> PyResult<()> {
    quiet_device_select();
    m.add("SceneError", m.py().get_type::<error::SceneError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<film::Film>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(study::study, m)?)?;
    m.add_function(wrap_pyfunction!(film::merge, m)?)?;
    m.add_function(wrap_pyfunction!(session::adapters, m)?)?;
    Ok(())
}

/// Mesa's implicit layer `VK_LAYER_MESA_device_select` only reorders devices (strata ranks
/// adapters itself) and, without a display, prints "XDG_RUNTIME_DIR is invalid" on every
/// instance; off unless the user set the variable (as the `strata` command does), set when the
/// module is imported, before it opens any instance.
fn quiet_device_select() {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}
