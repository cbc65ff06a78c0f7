//! Errors of the GPU renderer.

use thiserror::Error;

/// Why the GPU renderer could not compile, upload or render: the one error type of
/// [`Renderer`](crate::Renderer), its message meant for the user (it names the limit or the
/// WGSL line).
#[derive(Debug, Error)]
pub enum GpuError {
    /// A WGSL module failed to parse or validate (a bug in `shaders/`, or a naga limitation).
    #[error("shader: {0}")]
    Shader(String),
    /// The device lacks a feature or limit the renderer needs.
    #[error("the GPU device cannot run strata: {0}")]
    Unsupported(String),
    /// The scene does not fit in the device's buffers.
    #[error("the scene does not fit on this GPU: {0}")]
    TooLarge(String),
    /// No adapter matched the request.
    #[error("{0}")]
    NoAdapter(String),
    /// The device reported an error (validation, out of memory, device lost).
    #[error("GPU device error: {0}")]
    Device(String),
}
