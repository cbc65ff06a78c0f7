//! strata's errors as Python exceptions, with the messages the `strata` command prints.

use pyo3::create_exception;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyRuntimeError, PyValueError};
use pyo3::PyErr;
use std::path::Path;

create_exception!(
    strata,
    SceneError,
    PyValueError,
    "A scene file strata cannot use: the message names the file, line and column, as the \
     `strata` command's does."
);

/// The error of loading the scene at `path`: `FileNotFoundError` when there is no such file,
/// else [`SceneError`], with the command's message (`{error:#}`).
pub fn scene(path: &Path, error: &anyhow::Error) -> PyErr {
    let message = format!("{error:#}");
    if !path.exists() {
        PyFileNotFoundError::new_err(message)
    } else {
        SceneError::new_err(message)
    }
}

/// An argument out of range or of an unknown name: `ValueError` naming the argument.
pub fn argument(name: &str, message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{name}: {message}"))
}

/// A file that cannot be read: `FileNotFoundError` when there is none at `path`, else
/// `OSError`.
pub fn reading(path: &Path, error: &anyhow::Error) -> PyErr {
    let message = format!("{error:#}");
    if !path.exists() {
        PyFileNotFoundError::new_err(message)
    } else {
        PyOSError::new_err(message)
    }
}

/// An image that cannot be written at `path`: `ValueError` for a name that is not .exr or
/// .png, `FileNotFoundError` when its folder is missing, else `OSError`.
pub fn writing(path: &Path, error: &anyhow::Error) -> PyErr {
    let message = format!("{error:#}");
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let folder = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !matches!(ext.as_deref(), Some("exr" | "png")) {
        PyValueError::new_err(message)
    } else if !folder.is_dir() {
        PyFileNotFoundError::new_err(message)
    } else {
        PyOSError::new_err(message)
    }
}

/// A render or device failure.
pub fn runtime(error: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(error.to_string())
}
