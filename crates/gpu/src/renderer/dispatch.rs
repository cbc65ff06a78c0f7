//! One render's dispatches: batches of samples, each dispatched as bands of rows, one band
//! running on the GPU while the host reads back and adds up the one before it (the GPU idles
//! only between a dispatch's end and the next one's submission).
//!
//! A batch adds `slices · n` samples to every pixel, dispatched as bands of rows that the
//! accumulator holds, each pixel's samples in `slices` slices of `n` (one when the band alone
//! fills the device); the batch's samples and the band height aim each dispatch at the
//! renderer's target from the time per sample measured so far. The first dispatch, unmeasured,
//! is kept small. A band's sums wait until its batch is whole: a cancelled batch adds nothing,
//! so every pixel keeps the same sample count.

use super::batch::{Batch, BatchResult, Submitted};
use super::{split, Renderer, FIRST_DISPATCH_PIXELS, MAX_BATCH_SPP};
use crate::params::Params;
use crate::GpuError;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use stratapt_film::render::Progress;
use stratapt_film::{Film, RenderStats};

/// A dispatch the GPU has run, whose sums are still to be read back ([`Batch::read`]).
struct InFlight {
    submitted: Submitted,
    /// Its band's first row.
    row: u32,
    /// Samples per pixel in each of its slices.
    spp: u32,
    /// Whether it is its batch's last band.
    completes_batch: bool,
}

/// The dispatch loop of one render, on a compiled kernel and the render's buffers.
pub(super) struct Dispatches<'a> {
    renderer: &'a Renderer,
    pipeline: &'a wgpu::ComputePipeline,
    batch: &'a mut Batch,
    /// The parameters every batch shares.
    base: Params,
    /// Most slices a batch splits its samples into (as many as the accumulator holds).
    most_slices: u32,
    /// The adapter's type, for the sample split.
    device_type: wgpu::DeviceType,
    width: u32,
    height: u32,
    /// The film's rows, then its twins' virtual rows.
    rows_total: u32,
    /// The band the GPU has run last, not yet read back.
    pending: Option<InFlight>,
    /// The bands of the unfinished batch, read back, with their first rows.
    bands: Vec<(u32, BatchResult)>,
    /// GPU time of the bands read back (none: the device has no timestamps).
    gpu_seconds: Option<f64>,
}

impl<'a> Dispatches<'a> {
    /// Dispatches of `pipeline` into `batch` with parameters `base`, in up to `most_slices` slices.
    pub(super) fn new(
        renderer: &'a Renderer,
        pipeline: &'a wgpu::ComputePipeline,
        batch: &'a mut Batch,
        base: Params,
        most_slices: u32,
    ) -> Self {
        Self {
            renderer,
            pipeline,
            gpu_seconds: batch.timestamps.as_ref().map(|_| 0.0),
            batch,
            base,
            most_slices,
            device_type: renderer.device.adapter_info().device_type,
            width: base.camera.width,
            height: base.camera.height,
            rows_total: base.rows_with_twins(),
            pending: None,
            bands: Vec::new(),
        }
    }

    /// Add samples `first..end` of every pixel to `film`, batch by batch; returns how many.
    ///
    /// Once `cancel` is set (after the first batch) it stops before the next band, keeping whole
    /// batches only.
    pub(super) fn run(
        mut self,
        film: &mut Film,
        stats: &mut RenderStats,
        (first, end): (u32, u32),
        progress: Progress,
        cancel: Option<&AtomicBool>,
    ) -> Result<u32, GpuError> {
        let mut done = first;
        let mut batch_spp = 1;
        let first_rows = FIRST_DISPATCH_PIXELS.div_ceil(self.width);
        let mut band_rows = self.batch.rows.min(first_rows).max(1);
        while done < end {
            // Split the batch's samples into slices the accumulator holds for this band height.
            let band_pixels = band_rows * self.width;
            let (slices, n) = split::plan(
                batch_spp.min(end - done),
                self.renderer.split.slices(self.device_type, band_pixels),
                band_pixels,
                self.batch.capacity_rows * self.width,
            );
            let params = Params {
                sample_base: done,
                batch_spp: n,
                split: slices,
                ..self.base
            };
            stats.slices = stats.slices.max(slices);
            let start = Instant::now();
            // The call's first batch always finishes (a Ctrl-C during the kernel's compile
            // still leaves one sample per pixel to write).
            let cancel = cancel.filter(|_| done > first);
            if !self.dispatch_batch(film, stats, params, band_rows, progress, cancel)? {
                stats.cancelled = true;
                break;
            }
            let added = slices * n;
            done += added;
            (batch_spp, band_rows) = self.pace(start.elapsed(), added);
        }
        // The last dispatch waited for (on Ctrl-C, it adds its batch only if it completed it).
        if let Some(band) = self.pending.take() {
            self.settle(film, stats, band)?;
        }
        stats.gpu_seconds = self.gpu_seconds;
        Ok(done - first)
    }

    /// Dispatch one batch as bands of `band_rows` rows; false if `cancel` stopped it.
    ///
    /// Each band is submitted before the band before it is read back ([`Dispatches::settle`]).
    fn dispatch_batch(
        &mut self,
        film: &mut Film,
        stats: &mut RenderStats,
        params: Params,
        band_rows: u32,
        progress: Progress,
        cancel: Option<&AtomicBool>,
    ) -> Result<bool, GpuError> {
        let mut row = 0;
        while row < self.rows_total {
            if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return Ok(false);
            }
            let rows = band_rows.min(self.rows_total - row);
            // Progress counts the film's samples (not the twins').
            let film_rows = rows.min(self.height.saturating_sub(row));
            let tile = params.rows(row, rows);
            let mut submitted = self.batch.submit(self.renderer, self.pipeline, tile)?;
            stats.dispatches += 1;
            // The band before runs no more: read it while this one runs.
            if let Some(band) = self.pending.take() {
                self.settle(film, stats, band)?;
            }
            self.batch.wait(self.renderer, &mut submitted)?;
            self.pending = Some(InFlight {
                submitted,
                row,
                spp: params.batch_spp,
                completes_batch: row + rows >= self.rows_total,
            });
            row += rows;
            let samples = (params.split * params.batch_spp) as u64;
            progress(samples * self.width as u64 * film_rows as u64);
        }
        Ok(true)
    }

    /// Read `band` back, and add its batch's bands to `film` once `band` completes it.
    fn settle(
        &mut self,
        film: &mut Film,
        stats: &mut RenderStats,
        band: InFlight,
    ) -> Result<(), GpuError> {
        let result = self.batch.read(band.submitted)?;
        if let (Some(total), Some(seconds)) = (self.gpu_seconds.as_mut(), result.gpu_seconds) {
            *total += seconds;
        }
        self.bands.push((band.row, result));
        if band.completes_batch {
            for (row, result) in self.bands.drain(..) {
                let (non_finite, rays) = result.fold_into(film, row, band.spp);
                stats.non_finite += non_finite;
                stats.rays += rays;
            }
        }
        Ok(())
    }

    /// Pace the next batch: its samples per pixel and band height, from the last batch's time.
    ///
    /// `elapsed` is the time the last batch, of `added` samples per pixel, took.
    fn pace(&self, elapsed: Duration, added: u32) -> (u32, u32) {
        let (width, height) = (self.width, self.height);
        // Aim the next batch at the target per dispatch: more samples while the whole
        // film fits in one dispatch's time, else one sample in bands of fewer rows.
        let per_sample = elapsed.as_secs_f64() / (added as f64 * width as f64 * height as f64);
        let target = self.renderer.dispatch_target.as_secs_f64() / per_sample.max(1e-12);
        let film_pixels = width as f64 * height as f64;
        let want = (target / film_pixels).min(u32::MAX as f64) as u32;
        // At most what the slices the film asks for can hold: more would only shorten the
        // bands below what the batch renders.
        let batch_spp = want
            .clamp(1, MAX_BATCH_SPP * self.most_slices)
            .min(added.saturating_mul(4));
        let rows = (target / (batch_spp as f64 * width as f64)) as u32;
        (batch_spp, rows.clamp(1, self.batch.rows))
    }
}
