//! The interface both renderers offer: add samples to a [`Film`] with the same settings,
//! progress callback, cancel flag and [`RenderStats`], so that everything built on films
//! (progressive renders to an error or a time, studies) is written once for either device.

pub mod progressive;

use crate::Film;
use std::sync::atomic::AtomicBool;
use stratapt_scene::{FlatScene, RenderSettings};

/// Renders the peak twins of `film` ([`Film::peak_pixels`]: independent replicas at its
/// noisiest pixels) for all its samples, into `film.peaks`, and returns the non-finite samples it
/// met. The CPU reference renders them with each film; the GPU renderer is handed one
/// (`stratapt_cpu::render_peak_twins`) by whoever builds both, so that neither renderer depends
/// on the other.
pub type PeakTwins = dyn Fn(&FlatScene, &RenderSettings, &mut Film) -> u64 + Send + Sync;

/// Receives the number of samples each step of a render has finished.
pub type Progress<'a> = &'a (dyn Fn(u64) + Sync);

/// An error from a renderer (the device's message; the CPU reference never fails).
pub type RenderError = Box<dyn std::error::Error + Send + Sync>;

/// What a render did besides its image.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Samples taken (pixels × samples per pixel).
    pub samples: u64,
    /// Samples that came out NaN or infinite (a bug; recorded as zero).
    pub non_finite: u64,
    /// Stopped early by the cancel flag: the film holds whole batches only.
    pub cancelled: bool,
    /// Rays traced (path and shadow rays).
    pub rays: u64,
    /// GPU dispatches (a batch is one per band of film rows); 0 on the CPU.
    pub dispatches: u32,
    /// Seconds spent creating the kernel's pipeline (0 when cached, and on the CPU).
    pub compile_seconds: f64,
    /// Seconds of the kernel's first dispatch, on an empty tile: what the driver compiles at
    /// first use (lavapipe compiles its machine code then; 0 when already run, and on the CPU).
    pub first_dispatch_seconds: f64,
    /// Seconds of GPU execution measured by timestamp queries, when the device has them.
    pub gpu_seconds: Option<f64>,
    /// The GPU kernel read the scene's arrays from their uniform copy rather than their storage
    /// buffers (`stratapt_gpu::SceneBinding`; false on the CPU).
    pub uniform_scene: bool,
    /// Most slices a GPU batch split each pixel's samples into, one invocation each
    /// (`stratapt_gpu::SampleSplit`; 1: one invocation per pixel; 0 on the CPU).
    pub slices: u32,
    /// Seconds the GPU renderer spent before its first batch, besides the compile: the
    /// scene's specialization, its upload and the render's buffers (0 on the CPU).
    pub setup_seconds: f64,
    /// Seconds the GPU renderer spent having the CPU reference render the peak twins (0 on
    /// the CPU, which renders them with the film).
    pub peak_twin_seconds: f64,
}

impl RenderStats {
    /// Fold in the stats of a later render into the same film.
    pub fn add(&mut self, other: &RenderStats) {
        self.samples += other.samples;
        self.non_finite += other.non_finite;
        self.cancelled |= other.cancelled;
        self.rays += other.rays;
        self.dispatches += other.dispatches;
        self.compile_seconds += other.compile_seconds;
        self.first_dispatch_seconds += other.first_dispatch_seconds;
        self.gpu_seconds = match (self.gpu_seconds, other.gpu_seconds) {
            (Some(a), Some(b)) => Some(a + b),
            (a, b) => a.or(b),
        };
        self.uniform_scene |= other.uniform_scene;
        self.slices = self.slices.max(other.slices);
        self.setup_seconds += other.setup_seconds;
        self.peak_twin_seconds += other.peak_twin_seconds;
    }
}

/// A renderer: the CPU reference (`stratapt_cpu::CpuRenderer`) or the GPU renderer
/// (`stratapt_gpu::Renderer`).
pub trait Render {
    /// Add samples `k .. k + added_spp`, `k = film.first_sample + film.held_spp()`, of every
    /// pixel of `scene` to `film` (which must have the scene's size, twins when
    /// `settings.twins()`, and the same count in every pixel; its twins get the same samples of
    /// their independent randomization). `settings.pattern_spp` is the size of the sampling
    /// pattern (it sizes the stratified sampler's strata), not the number added. Stops at the
    /// next batch once `cancel` is set; a batch it drops adds nothing, so every pixel keeps the
    /// same count.
    fn render_into(
        &self,
        scene: &FlatScene,
        settings: &RenderSettings,
        film: &mut Film,
        added_spp: u32,
        progress: Progress,
        cancel: Option<&AtomicBool>,
    ) -> Result<RenderStats, RenderError>;

    /// What it renders on, in a few words (e.g. `CPU reference (2 threads)`).
    fn describe(&self) -> String;

    /// Render `settings.pattern_spp` samples per pixel into a new film.
    fn render(
        &self,
        scene: &FlatScene,
        settings: &RenderSettings,
        progress: Progress,
        cancel: Option<&AtomicBool>,
    ) -> Result<(Film, RenderStats), RenderError> {
        let mut film = Film::for_render(scene, settings);
        let stats = self.render_into(
            scene,
            settings,
            &mut film,
            settings.pattern_spp,
            progress,
            cancel,
        )?;
        Ok((film, stats))
    }
}
