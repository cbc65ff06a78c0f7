//! The `Film` a render or a merge returns: the image and its calibrated error as numpy arrays,
//! and what the render took.

use crate::error;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use stratapt_cli::render::check_outputs;
use stratapt_film::part;
use stratapt_film::{RelativeError, RenderStats};
use stratapt_scene::RenderSettings;

/// What produced a film: how long it took, where, with which settings and why it stopped.
pub struct About {
    pub seconds: f64,
    pub device: String,
    pub device_reason: Option<String>,
    /// `spp`, `target-error`, `time-limit` or `merged`.
    pub stopped: &'static str,
    pub settings: RenderSettings,
    pub stats: Option<RenderStats>,
}

/// A render's estimate: per pixel the mean of its samples and the calibrated variance of that
/// mean, and what the render took. `np.asarray(film)` is `film.image`.
#[pyclass(module = "strata", name = "Film", frozen)]
pub struct Film {
    film: stratapt_film::Film,
    about: About,
}

impl Film {
    pub fn new(film: stratapt_film::Film, about: About) -> Self {
        Self { film, about }
    }

    /// `values` (one per pixel, row by row) as an H × W × 3 float32 array.
    fn rgb<'py>(
        &self,
        py: Python<'py>,
        values: impl Iterator<Item = [f64; 3]>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let flat: Vec<f32> = values.flat_map(|v| v.map(|c| c as f32)).collect();
        let (w, h) = (self.film.width as usize, self.film.height as usize);
        Ok(PyArray1::from_vec(py, flat).reshape([h, w, 3])?.into_any())
    }

    fn error(&self) -> RelativeError {
        self.film.relative_error()
    }
}

#[pymethods]
impl Film {
    /// The image: H × W × 3 float32, linear RGB, each pixel the mean of its samples (the
    /// values the EXR's R, G, B channels hold).
    #[getter]
    fn image<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.rgb(py, (0..self.film.sum.len()).map(|i| self.film.mean(i)))
    }

    /// The calibrated variance of each pixel's mean: H × W × 3 float32 (the EXR's var.R,
    /// var.G, var.B).
    #[getter]
    fn variance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.rgb(py, self.film.variances().into_iter())
    }

    /// The calibrated relative standard error of the image mean (channel-averaged): the
    /// figure `strata render` prints as `error:`.
    #[getter(error)]
    fn image_error(&self) -> f64 {
        self.error().image_mean
    }

    /// The 95th-percentile pixel's relative standard error.
    #[getter]
    fn error_p95(&self) -> f64 {
        self.error().pixel_p95
    }

    /// Each pixel's calibrated relative standard error, √Var(mean) / max(mean, 0.01)
    /// channel-averaged: H × W float64.
    #[getter]
    fn pixel_error<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (w, h) = (self.film.width as usize, self.film.height as usize);
        Ok(PyArray1::from_vec(py, self.film.pixel_errors())
            .reshape([h, w])?
            .into_any())
    }

    /// The image mean per channel, (r, g, b).
    #[getter]
    fn mean(&self) -> (f64, f64, f64) {
        let [r, g, b] = self.film.image_mean().0;
        (r, g, b)
    }

    /// The calibrated standard error of the image mean per channel, (r, g, b).
    #[getter]
    fn mean_error(&self) -> (f64, f64, f64) {
        let [r, g, b] = self.film.image_mean().1;
        (r, g, b)
    }

    /// Samples per pixel held.
    #[getter]
    fn spp(&self) -> u32 {
        self.film.held_spp()
    }

    /// `(width, height)` in pixels.
    #[getter]
    fn size(&self) -> (u32, u32) {
        (self.film.width, self.film.height)
    }

    /// Wall-clock seconds of the render (0 for a merge).
    #[getter]
    fn seconds(&self) -> f64 {
        self.about.seconds
    }

    /// Where it rendered, as `strata render`'s `device:` line names it.
    #[getter]
    fn device(&self) -> String {
        self.about.device.clone()
    }

    /// Why `device="auto"` chose that device (None when it was asked for).
    #[getter]
    fn device_reason(&self) -> Option<String> {
        self.about.device_reason.clone()
    }

    /// Why the render stopped: `spp` (its samples were taken), `target-error`, `time-limit`;
    /// `merged` for a merge.
    #[getter]
    fn stopped(&self) -> &'static str {
        self.about.stopped
    }

    /// The settings it rendered with: spp (the sample pattern's), max_depth, sampler,
    /// strategy, seed, calibrate.
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        settings_dict(py, &self.about.settings)
    }

    /// What the render did: samples, rays, non_finite (samples replaced by zero), dispatches,
    /// compile_seconds (0 when the kernel was already compiled in this process),
    /// first_dispatch_seconds, gpu_seconds (None where the adapter has no timestamps).
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let Some(s) = &self.about.stats else {
            return Ok(d);
        };
        d.set_item("samples", s.samples)?;
        d.set_item("rays", s.rays)?;
        d.set_item("non_finite", s.non_finite)?;
        d.set_item("dispatches", s.dispatches)?;
        d.set_item("compile_seconds", s.compile_seconds)?;
        d.set_item("first_dispatch_seconds", s.first_dispatch_seconds)?;
        d.set_item("gpu_seconds", s.gpu_seconds)?;
        Ok(d)
    }

    /// Write the film by extension, as `strata render -o` does: `.exr` (linear RGB and the
    /// variance channels) or `.png` (sRGB). The file is written beside its place and renamed
    /// into it, so it is never seen torn.
    fn write(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let written = check_outputs(std::slice::from_ref(&path)).and_then(|()| {
            py.detach(|| self.film.write(&path))
                .map_err(anyhow::Error::from)
        });
        written.map_err(|e| error::writing(&path, &e))
    }

    /// `np.asarray(film)`: the image (converted to `dtype` if given).
    #[pyo3(signature = (dtype = None, copy = None))]
    fn __array__<'py>(
        &self,
        py: Python<'py>,
        dtype: Option<Bound<'py, PyAny>>,
        copy: Option<bool>,
    ) -> PyResult<Bound<'py, PyAny>> {
        // Every call makes a new array, so `copy` is honoured whatever it asks.
        let _ = copy;
        let image = self.image(py)?;
        match dtype {
            Some(dtype) => image.call_method1("astype", (dtype,)),
            None => Ok(image),
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "<strata.Film {}×{}, {} spp, error {:.3} %, {:.2} s on {}>",
            self.film.width,
            self.film.height,
            self.film.held_spp(),
            100.0 * self.error().image_mean,
            self.about.seconds,
            self.about.device
        )
    }
}

/// Render settings as a dict: spp, max_depth, sampler, strategy, seed, calibrate.
pub fn settings_dict<'py>(py: Python<'py>, s: &RenderSettings) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("spp", s.pattern_spp)?;
    d.set_item("max_depth", s.max_depth)?;
    d.set_item("sampler", s.sampler.to_string())?;
    d.set_item("strategy", s.strategy.to_string())?;
    d.set_item("seed", s.seed)?;
    d.set_item("calibrate", s.calibrate)?;
    Ok(d)
}

/// Sum render parts (EXRs written by `strata render --part`, in any order) into the whole
/// render, exactly, as `strata merge` does.
#[pyfunction]
#[pyo3(signature = (paths, *, allow_partial = false))]
pub fn merge(py: Python<'_>, paths: Vec<PathBuf>, allow_partial: bool) -> PyResult<Film> {
    let mut parts = Vec::with_capacity(paths.len());
    for path in &paths {
        let (film, info) = py
            .detach(|| part::read(path))
            .map_err(|e| error::reading(path, &e.into()))?;
        parts.push((path.clone(), film, info));
    }
    let merged = part::merge(parts, allow_partial)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    let about = About {
        seconds: 0.0,
        device: "merge".into(),
        device_reason: None,
        stopped: "merged",
        settings: merged.info.settings,
        stats: None,
    };
    Ok(Film::new(merged.film, about))
}
