//! The buffers of one render and one dispatch of a batch: scene, params, accumulator,
//! readback, timestamps; and folding a band's sums into the film.

use super::{Renderer, ACCUM_PIXEL_BYTES};
use crate::params::Params;
use crate::readback::take_mapped;
use crate::shared::{binding, WORKGROUP_SIDE};
use crate::specialize::Specialization;
use crate::upload::{entry, SceneBuffers};
use crate::GpuError;
use stratapt_film::Film;
use stratapt_scene::FlatScene;

/// The per-render buffers: scene, params, accumulator, two readback buffers, optional
/// timestamps.
pub(super) struct Batch {
    bind_group: wgpu::BindGroup,
    /// The ray-query kernel's acceleration structure (group 1), when the kernel is it.
    rays: Option<crate::rays::RayStructures>,
    params: wgpu::Buffer,
    accum: wgpu::Buffer,
    /// Two, used in turn: one dispatch's sums are read out of one while the next dispatch runs
    /// and its sums are copied into the other.
    readback: [wgpu::Buffer; 2],
    /// The readback buffer the next dispatch copies into.
    next_slot: usize,
    pub(super) timestamps: Option<Timestamps>,
    /// The tallest band one dispatch may cover, in film rows.
    pub(super) rows: u32,
    /// Rows of film width the accumulator holds: a band's rows times its slices.
    pub(super) capacity_rows: u32,
    _scene: SceneBuffers,
}

pub(super) struct Timestamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    /// One per accumulator readback buffer.
    readback: [wgpu::Buffer; 2],
    period_ns: f64,
}

/// A dispatch on its way: submitted, its sums being copied into a readback buffer that is
/// mapped for reading once the GPU is done ([`Batch::wait`], then [`Batch::read`]).
pub(super) struct Submitted {
    slot: usize,
    /// Bytes of sums to read back.
    len: u64,
    slices: usize,
    index: wgpu::SubmissionIndex,
    /// One message per buffer mapped (the sums, the timestamps).
    mapped: std::sync::mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>,
    maps: usize,
    done: bool,
}

/// One batch's results, as read back.
pub(super) struct BatchResult {
    /// Per slice, then per pixel: `[sum.rgb, rays]`, `[sum_sq.rgb, non_finite]`.
    accum: Vec<f32>,
    /// Slices of the band's samples (tiles of `accum`).
    slices: usize,
    pub(super) gpu_seconds: Option<f64>,
}

impl Batch {
    /// Buffers for a batch of kernel `spec` over `height` rows (the film's, then its twins'),
    /// split into up to `slices` slices where the accumulator fits them.
    pub(super) fn new(
        renderer: &Renderer,
        scene: &FlatScene,
        spec: &Specialization,
        height: u32,
        slices: u32,
    ) -> Result<Self, GpuError> {
        let device = &renderer.device;
        let width = scene.camera.width;
        let scene_buffers = SceneBuffers::new(device, scene, spec.bvh, spec.uniform_scene)?;
        // The accumulator holds as many whole rows as the device binds, and no more than the
        // film or the renderer's dispatch cap asks for.
        let limits = device.limits();
        let bytes = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let row_bytes = width as u64 * ACCUM_PIXEL_BYTES;
        let fit = (bytes / row_bytes).min(height as u64) as u32;
        let capped = renderer
            .max_dispatch_pixels
            .map_or(fit, |p| fit.min((p / width).max(1)));
        if fit == 0 {
            return Err(GpuError::TooLarge(format!(
                "one {width}-pixel row of the film needs a {} KiB accumulator; this device \
                 binds at most {} KiB (render a narrower film)",
                row_bytes >> 10,
                bytes >> 10
            )));
        }
        // The kernel indexes the accumulator's vec4s with a u32.
        let index_rows = (u32::MAX / 2 / width.max(1)).max(1);
        let rows = capped.min(index_rows);
        // Room for every slice of the tallest band, but for no more pixels than the film or
        // 2¹⁸ per slice (a forced split of a large film has no use for more), as far as the
        // device binds and the kernel's u32 accumulator index reaches.
        let (width64, slices64) = (width as u64, slices.max(1) as u64);
        let most_pixels = (height as u64 * width64).max(slices64 << 18);
        let capacity_rows = (rows as u64 * slices64)
            .min(most_pixels.div_ceil(width64))
            .max(rows as u64)
            .min(bytes / row_bytes)
            .min(index_rows as u64) as u32;
        let accum_size = capacity_rows as u64 * row_bytes;
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: std::mem::size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let accum = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("accum"),
            size: accum_size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = [0, 1].map(|_| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("accum readback"),
                size: accum_size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let mut entries = vec![entry(0, &params)];
        entries.extend(scene_buffers.entries());
        entries.push(entry(binding::ACCUM, &accum));
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("strata scene"),
            layout: &renderer.layout,
            entries: &entries,
        });
        let rays = match spec.ray_query {
            true => Some(crate::rays::RayStructures::new(
                device,
                &renderer.queue,
                scene,
                &renderer.ray_query_kernel()?.layout,
            )?),
            false => None,
        };
        Ok(Self {
            bind_group,
            rays,
            params,
            accum,
            readback,
            next_slot: 0,
            timestamps: Timestamps::new(renderer),
            rows,
            capacity_rows,
            _scene: scene_buffers,
        })
    }

    /// Dispatch one band of a batch (`params.tile_*`, in `params.split` slices), wait for it
    /// and read its sums back.
    pub(super) fn run(
        &mut self,
        renderer: &Renderer,
        pipeline: &wgpu::ComputePipeline,
        params: Params,
    ) -> Result<BatchResult, GpuError> {
        let mut submitted = self.submit(renderer, pipeline, params)?;
        self.wait(renderer, &mut submitted)?;
        self.read(submitted)
    }

    /// Dispatch one band of a batch and have its sums copied into the next readback buffer,
    /// which is mapped once the GPU is done. The dispatch before it must have been read
    /// ([`Batch::read`]) or dropped, or be in the other buffer: two may be on their way at once.
    pub(super) fn submit(
        &mut self,
        renderer: &Renderer,
        pipeline: &wgpu::ComputePipeline,
        params: Params,
    ) -> Result<Submitted, GpuError> {
        let (device, queue) = (&renderer.device, &renderer.queue);
        let slot = self.next_slot;
        self.next_slot = 1 - slot;
        // Ordered after every dispatch submitted before, which has read its params already.
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let timestamp_writes =
                self.timestamps
                    .as_ref()
                    .map(|t| wgpu::ComputePassTimestampWrites {
                        query_set: &t.queries,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: Some(1),
                    });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("strata render"),
                timestamp_writes,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            if let Some(rays) = &self.rays {
                pass.set_bind_group(1, &rays.bind_group, &[]);
            }
            // An empty tile still dispatches one workgroup (whose invocations all return): the
            // renderer's first, compile-timing dispatch.
            let [w, h] = params.tile_size;
            pass.dispatch_workgroups(
                w.div_ceil(WORKGROUP_SIDE).max(1),
                h.div_ceil(WORKGROUP_SIDE).max(1),
                params.split,
            );
        }
        let [w, h] = params.tile_size;
        let len = params.split as u64 * w as u64 * h as u64 * ACCUM_PIXEL_BYTES;
        let readback = &self.readback[slot];
        if len > 0 {
            encoder.copy_buffer_to_buffer(&self.accum, 0, readback, 0, len);
        }
        if let Some(t) = &self.timestamps {
            encoder.resolve_query_set(&t.queries, 0..2, &t.resolve, 0);
            encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readback[slot], 0, 16);
        }
        let index = queue.submit([encoder.finish()]);
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device(error.to_string()));
        }
        let (tx, mapped) = std::sync::mpsc::channel();
        let mut maps = 0;
        let mut map = |buffer: &wgpu::Buffer, len: u64| {
            let tx = tx.clone();
            buffer.map_async(wgpu::MapMode::Read, ..len, move |result| {
                let _ = tx.send(result);
            });
            maps += 1;
        };
        if len > 0 {
            map(readback, len);
        }
        if let Some(t) = &self.timestamps {
            map(&t.readback[slot], 16);
        }
        Ok(Submitted {
            slot,
            len,
            slices: params.split as usize,
            index,
            mapped,
            maps,
            done: false,
        })
    }

    /// Wait until the GPU has run `submitted` and its readback buffers are mapped. The
    /// dispatches submitted after it may still be running.
    pub(super) fn wait(
        &self,
        renderer: &Renderer,
        submitted: &mut Submitted,
    ) -> Result<(), GpuError> {
        if submitted.done {
            return Ok(());
        }
        renderer
            .device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(submitted.index.clone()),
                timeout: None,
            })
            .map_err(|e| GpuError::Device(e.to_string()))?;
        for _ in 0..submitted.maps {
            submitted
                .mapped
                .recv()
                .map_err(|e| GpuError::Device(e.to_string()))?
                .map_err(|e| GpuError::Device(e.to_string()))?;
        }
        submitted.done = true;
        Ok(())
    }

    /// The sums (and GPU time) of a dispatch [`Batch::wait`] has waited for, copied out of
    /// its readback buffers, which are then free for the next dispatch but one.
    pub(super) fn read(&self, submitted: Submitted) -> Result<BatchResult, GpuError> {
        debug_assert!(submitted.done, "read before wait");
        // Straight into f32s: one copy of up to 2¹⁸ pixels' 32 bytes.
        let accum = if submitted.len > 0 {
            take_mapped(&self.readback[submitted.slot], submitted.len)?
        } else {
            Vec::new()
        };
        let gpu_seconds = match &self.timestamps {
            Some(t) => {
                let ticks: Vec<u8> = take_mapped(&t.readback[submitted.slot], 16)?;
                let at = |i: usize| u64::from_le_bytes(ticks[i * 8..i * 8 + 8].try_into().unwrap());
                Some(at(1).saturating_sub(at(0)) as f64 * t.period_ns * 1e-9)
            }
            None => None,
        };
        Ok(BatchResult {
            accum,
            slices: submitted.slices,
            gpu_seconds,
        })
    }
}

impl Timestamps {
    fn new(renderer: &Renderer) -> Option<Self> {
        let device = &renderer.device;
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 16,
                usage,
                mapped_at_creation: false,
            })
        };
        Some(Self {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("batch time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: buffer(
                "timestamps",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: [0, 1].map(|_| {
                buffer(
                    "timestamps readback",
                    wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                )
            }),
            period_ns: renderer.queue.get_timestamp_period() as f64,
        })
    }
}

impl BatchResult {
    /// Add this band's slices of `spp` samples per pixel to `film`, slice by slice, from film
    /// row `first_row`; returns the number of non-finite samples and of rays traced.
    pub(super) fn fold_into(&self, film: &mut Film, first_row: u32, spp: u32) -> (u64, u64) {
        let mut non_finite = 0;
        let mut rays = 0;
        let width = film.width as usize;
        let pixels = film.sum.len();
        let offset = first_row as usize * width;
        let tile = self.accum.len() / self.slices.max(1);
        // In slice order: the film a batch of k slices of n samples makes is the one k batches
        // of n samples make.
        for slice in self.accum.chunks_exact(tile.max(8)) {
            for (k, px) in slice.chunks_exact(8).enumerate() {
                let i = offset + k;
                let sum = [px[0], px[1], px[2]].map(f64::from);
                let sum_sq = [px[4], px[5], px[6]].map(f64::from);
                // Film pixels, then twins (virtual rows past the film; the last row's tail
                // unused).
                let (sums, squares) = if i < pixels {
                    film.count[i] += spp;
                    (&mut film.sum[i], &mut film.sum_sq[i])
                } else if i - pixels < film.twin_sum.len() {
                    (
                        &mut film.twin_sum[i - pixels],
                        &mut film.twin_sum_sq[i - pixels],
                    )
                } else {
                    continue;
                };
                for c in 0..3 {
                    sums[c] += sum[c];
                    squares[c] += sum_sq[c];
                }
                rays += px[3] as u64;
                non_finite += px[7] as u64;
            }
        }
        (non_finite, rays)
    }
}
