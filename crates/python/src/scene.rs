//! `strata.load` and the `Scene` it returns.

use crate::error;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;
use stratapt_cli::scene::{load as load_scene, warning_lines, ImportArgs};
use stratapt_scene::{Effects, FlatScene};

/// A loaded scene: strata's TOML or a pbrt-v4 file, validated, with its BVH built.
#[pyclass(module = "strata", name = "Scene", frozen)]
pub struct Scene {
    pub scene: Arc<FlatScene>,
    warnings: Vec<String>,
}

/// Load the scene file at `path` (strata's TOML, or pbrt-v4: .pbrt, .pbrt.gz); `strict` refuses
/// a pbrt-v4 scene whose import has warnings, as `--strict` does.
#[pyfunction]
#[pyo3(signature = (path, *, strict = false))]
pub fn load(py: Python<'_>, path: PathBuf, strict: bool) -> PyResult<Scene> {
    let loaded = py.detach(|| load_scene(&path, ImportArgs { strict }, false));
    let scene = loaded.map_err(|e| error::scene(&path, &e))?;
    Ok(Scene {
        warnings: warning_lines(scene.import.as_ref()),
        scene: Arc::new(scene),
    })
}

#[pymethods]
impl Scene {
    /// The scene file.
    #[getter]
    fn path(&self) -> PathBuf {
        self.scene.path.clone()
    }

    /// Film width and height in pixels, as `(width, height)`.
    #[getter]
    fn size(&self) -> (u32, u32) {
        (self.scene.camera.width, self.scene.camera.height)
    }

    /// The scene's render settings: spp, max_depth, sampler, strategy, seed, calibrate.
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::film::settings_dict(py, &self.scene.settings)
    }

    /// What the scene calls for under its own settings, in the words of `strata info`, e.g.
    /// `pinhole, static, rectangle lights, diffuse, NEE, roulette`.
    #[getter]
    fn effects(&self) -> String {
        Effects::of(&self.scene, &self.scene.settings).summary()
    }

    /// How much there is: primitives, points, materials, lights, textures, texture_bytes.
    #[getter]
    fn counts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.scene;
        let counts = PyDict::new(py);
        counts.set_item("primitives", s.geometry.len())?;
        counts.set_item("points", s.geometry.points.len())?;
        counts.set_item("materials", s.materials.len())?;
        counts.set_item("lights", s.lights.len())?;
        counts.set_item("textures", s.textures)?;
        counts.set_item("texture_bytes", s.texture_bytes)?;
        Ok(counts)
    }

    /// A pbrt-v4 import's warnings, one per line (`file:line:column: what strata does
    /// instead`); empty for strata's own TOML.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    fn __repr__(&self) -> String {
        let (w, h) = self.size();
        format!(
            "<strata.Scene {} {w}×{h}, {} primitives, {} warnings>",
            self.scene.path.display(),
            self.scene.geometry.len(),
            self.warnings.len()
        )
    }
}
