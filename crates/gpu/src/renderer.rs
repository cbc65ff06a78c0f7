//! The renderer: a kernel specialized per scene, dispatched in batches of a few samples per
//! pixel, each batch's per-pixel sums read back and folded into an f64 [`Film`].

mod batch;
mod dispatch;
pub(crate) mod split;

use crate::checks::KernelChecks;
use crate::params::Params;
use crate::shared::{binding, uniform_scene_words, MAX_UNIFORM_SCENE_WORDS};
use crate::specialize::{BvhLayout, Kernel, SceneBinding, Specialization, Traversal};
use crate::upload::bind_group_layout;
use crate::GpuError;
use batch::Batch;
use dispatch::Dispatches;
use split::SampleSplit;
use std::collections::HashMap;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};
use stratapt_film::render::{PeakTwins, Progress};
use stratapt_film::{Film, Render, RenderError, RenderStats};
use stratapt_scene::{FlatScene, RenderSettings};

/// Storage buffers the kernel binds (group 0: the scene's arrays and the accumulator).
const STORAGE_BUFFERS: u32 = binding::SCENE_ARRAYS.len() as u32 + 1;
/// Wall time a dispatch aims at on a hardware GPU: well inside OS watchdogs (Windows resets a
/// GPU busy for 2 s), short enough for progress and Ctrl-C, long enough that readback is a
/// small share.
const DISPATCH_TARGET: Duration = Duration::from_millis(250);
/// The same on a software adapter (lavapipe, llvmpipe), which has no watchdog and pays more per
/// dispatch, so that fewer, longer dispatches render faster (measured:
/// docs/measurements/lavapipe.md#on-mesa-223).
const SOFTWARE_DISPATCH_TARGET: Duration = Duration::from_millis(1000);
/// Most samples per pixel in one slice of a batch (f32 sums of up to this many samples lose
/// < 2⁻¹⁶).
const MAX_BATCH_SPP: u32 = 256;
/// Bytes of accumulator per pixel: sum and sum of squares (rgb), rays, non-finite samples.
const ACCUM_PIXEL_BYTES: u64 = 32;
/// Pixels of the first dispatch of a render, before any time per sample is known.
const FIRST_DISPATCH_PIXELS: u32 = 1 << 16;

/// A GPU path tracer on the caller's device. Kernels are compiled per scene specialization
/// and cached, so rendering several scenes (or one scene many times) compiles each once.
///
/// The BVH layout it traverses and where it reads the scene's arrays from are chosen for the
/// device's adapter ([`BvhLayout::for_adapter`], [`SceneBinding::for_adapter`]);
/// [`Renderer::set_bvh_layout`] and [`Renderer::set_scene_binding`] force one (benchmarks,
/// tests; the images are the same).
/// [`Renderer::set_kernel`] renders with the generic kernel instead (same images).
///
/// The kernel does not render the error estimate's peak twins ([`Film::peak_pixels`]); a
/// renderer given a [`PeakTwins`] ([`Renderer::set_peak_twins`], `stratapt_cpu::render_peak_twins`
/// as the `strata` command and the `stratapt` facade give it) has them rendered after each
/// render, else its films carry none and their error rests on the hashed twins alone.
pub struct Renderer {
    bvh: BvhLayout,
    binding: SceneBinding,
    kernel: Kernel,
    checks: KernelChecks,
    split: SampleSplit,
    /// Most pixels one dispatch covers, beyond what the device's buffers impose.
    max_dispatch_pixels: Option<u32>,
    /// Wall time a dispatch aims at.
    dispatch_target: Duration,
    device: wgpu::Device,
    queue: wgpu::Queue,
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    traversal: Traversal,
    /// The ray-query kernel, compiled at its first use on a device that has ray queries (a
    /// renderer that never traces with them never pays for it), or why it could not be.
    ray_query: OnceLock<Result<RayQueryKernel, String>>,
    pipelines: Mutex<HashMap<Specialization, Compiled>>,
    /// Renders the peak twins after each render (none: the films carry none).
    peak_twins: Option<Arc<PeakTwins>>,
}

/// The kernel's shader module for `device`, compiled with `checks`.
///
/// # Safety
/// The kernel must never need a check `checks` leaves out ([`KernelChecks::AUDITED`] and any
/// set that covers it are proven safe: every loop ends and every integer divisor is nonzero,
/// `docs/design/kernel-checks.md`).
unsafe fn kernel_module(
    device: &wgpu::Device,
    checks: KernelChecks,
) -> Result<wgpu::ShaderModule, GpuError> {
    let source = crate::shader::kernel(uniform_scene_words(&device.limits()))?;
    // SAFETY: the caller's.
    unsafe { trusted_module(device, source, checks) }
}

/// `source` compiled on `device` with `checks`.
///
/// # Safety
/// As [`kernel_module`]'s.
unsafe fn trusted_module(
    device: &wgpu::Device,
    source: String,
    checks: KernelChecks,
) -> Result<wgpu::ShaderModule, GpuError> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let descriptor = wgpu::ShaderModuleDescriptor {
        label: Some("strata kernel"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    };
    // SAFETY: the caller's.
    let module =
        unsafe { device.create_shader_module_trusted(descriptor, checks.runtime_checks()) };
    match pollster::block_on(scope.pop()) {
        Some(error) => Err(GpuError::Shader(error.to_string())),
        None => Ok(module),
    }
}

/// The ray-query kernel's module, its group 1 (the acceleration structure) and its layout.
pub(super) struct RayQueryKernel {
    module: wgpu::ShaderModule,
    pub(super) layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
}

impl RayQueryKernel {
    /// The ray-query kernel on `device` with `checks` (`group0`: the scene's group), or why
    /// not: the device has no ray queries, or its compiler refuses the kernel.
    ///
    /// # Safety
    /// As [`kernel_module`]'s.
    unsafe fn new(
        device: &wgpu::Device,
        checks: KernelChecks,
        group0: &wgpu::BindGroupLayout,
    ) -> Result<Self, GpuError> {
        if !device
            .features()
            .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY)
        {
            return Err(GpuError::Unsupported(
                "the device has no ray queries".into(),
            ));
        }
        let source = crate::shader::ray_query_kernel(uniform_scene_words(&device.limits()))?;
        // SAFETY: the caller's.
        let module = unsafe { trusted_module(device, source, checks)? };
        let layout = crate::rays::bind_group_layout(device);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("strata ray-query kernel"),
            bind_group_layouts: &[Some(group0), Some(&layout)],
            immediate_size: 0,
        });
        Ok(Self {
            module,
            layout,
            pipeline_layout,
        })
    }
}

/// A compiled kernel, and whether the driver has run it yet (lavapipe compiles a kernel's
/// machine code at its first dispatch, not at pipeline creation).
struct Compiled {
    pipeline: wgpu::ComputePipeline,
    dispatched: bool,
}

impl Renderer {
    /// A renderer on `device`. Fails, naming the limit, if the device cannot bind the kernel's
    /// buffers (it needs 14 storage buffers per stage: request the device with
    /// [`Renderer::required_limits`], or the adapter's limits, rather than WebGPU's defaults).
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Self, GpuError> {
        let limits = device.limits();
        if limits.max_storage_buffers_per_shader_stage < STORAGE_BUFFERS {
            return Err(GpuError::Unsupported(format!(
                "the kernel binds {STORAGE_BUFFERS} storage buffers but the device allows {} \
                 per shader stage (request the device with `required_limits: Renderer::required_limits(&adapter)?` or \
                 `adapter.limits()`)",
                limits.max_storage_buffers_per_shader_stage
            )));
        }
        let checks = KernelChecks::DEFAULT;
        // SAFETY: the default checks cover the audited ones, which leave out only what the
        // kernel never needs.
        let module = unsafe { kernel_module(device, checks)? };
        let layout = bind_group_layout(device);
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("strata kernel"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(error.to_string()));
        }
        Ok(Self {
            traversal: Traversal::for_adapter(device.adapter_info().device_type),
            ray_query: OnceLock::new(),
            bvh: BvhLayout::for_adapter(device.adapter_info().device_type),
            binding: SceneBinding::for_adapter(device.adapter_info().device_type),
            kernel: Kernel::default(),
            checks,
            split: SampleSplit::Auto,
            device: device.clone(),
            queue: queue.clone(),
            module,
            layout,
            pipeline_layout,
            pipelines: Mutex::new(HashMap::new()),
            peak_twins: None,
            max_dispatch_pixels: None,
            dispatch_target: match device.adapter_info().device_type {
                wgpu::DeviceType::Cpu => SOFTWARE_DISPATCH_TARGET,
                _ => DISPATCH_TARGET,
            },
        })
    }

    /// The limits to request a device with for this renderer on `adapter`: WebGPU's downlevel
    /// defaults, raised to the storage buffers the kernel binds, to the adapter's largest
    /// buffers (so that large scenes and films fit) and to its uniform bindings up to 64 KiB
    /// (a small scene's uniform scene). Fails, naming the limit, when the adapter cannot
    /// bind the kernel.
    pub fn required_limits(adapter: &wgpu::Adapter) -> Result<wgpu::Limits, GpuError> {
        let have = adapter.limits();
        if have.max_storage_buffers_per_shader_stage < STORAGE_BUFFERS {
            return Err(GpuError::Unsupported(format!(
                "the kernel binds {STORAGE_BUFFERS} storage buffers but {} allows {} per \
                 shader stage",
                adapter.get_info().name,
                have.max_storage_buffers_per_shader_stage
            )));
        }
        Ok(wgpu::Limits {
            max_storage_buffers_per_shader_stage: STORAGE_BUFFERS,
            // the uniform scene grows with it, up to 64 KiB.
            max_uniform_buffer_binding_size: have
                .max_uniform_buffer_binding_size
                .min(MAX_UNIFORM_SCENE_WORDS as u64 * 16),
            max_storage_buffer_binding_size: have.max_storage_buffer_binding_size,
            max_buffer_size: have.max_buffer_size,
            ..wgpu::Limits::downlevel_defaults()
        })
    }

    /// The BVH layout this renderer traverses.
    pub fn bvh_layout(&self) -> BvhLayout {
        self.bvh
    }

    /// How the kernel finds hits ([`Traversal`]): the adapter's default unless set.
    pub fn traversal(&self) -> Traversal {
        self.traversal
    }

    /// Find hits by `traversal` from now on (ray queries only where the device has them and
    /// the scene is one the ray-query kernel serves: [`Traversal::serves`]).
    pub fn set_traversal(&mut self, traversal: Traversal) {
        self.traversal = traversal;
    }

    /// Whether a render of `scene` traces with the adapter's ray queries: asked for
    /// ([`Renderer::set_traversal`]), the device has them, and the scene is one they serve.
    pub fn uses_ray_queries(&self, scene: &FlatScene) -> bool {
        self.traversal == Traversal::RayQuery && self.has_ray_queries() && Traversal::serves(scene)
    }

    /// Whether this renderer's device has ray queries.
    pub fn has_ray_queries(&self) -> bool {
        self.device
            .features()
            .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY)
    }

    /// The ray-query kernel, compiled now if this is its first use.
    pub(super) fn ray_query_kernel(&self) -> Result<&RayQueryKernel, GpuError> {
        self.ray_query
            .get_or_init(|| {
                // SAFETY: as the kernel's: the checks are this renderer's.
                unsafe { RayQueryKernel::new(&self.device, self.checks, &self.layout) }
                    .map_err(|e| e.to_string())
            })
            .as_ref()
            .map_err(|e| GpuError::Unsupported(format!("the ray-query kernel: {e}")))
    }

    /// Traverse `bvh` from now on, whatever the adapter (to measure or test either layout).
    pub fn set_bvh_layout(&mut self, bvh: BvhLayout) {
        self.bvh = bvh;
    }

    /// Where this renderer reads the scene's arrays from (a scene too large for the uniform scene
    /// is read from storage whatever this says; [`Specialization::uniform_scene`] tells).
    pub fn scene_binding(&self) -> SceneBinding {
        self.binding
    }

    /// 16-byte words of the uniform scene on this renderer's device (16 KiB to
    /// 64 KiB, as its uniform bindings allow): the scenes that fit it read it.
    pub fn uniform_scene_words(&self) -> u32 {
        uniform_scene_words(&self.device.limits())
    }

    /// Read the scene's arrays through `binding` from now on, whatever the adapter (to measure
    /// or test either binding).
    pub fn set_scene_binding(&mut self, binding: SceneBinding) {
        self.binding = binding;
    }

    /// [`Renderer::set_bvh_layout`], builder style.
    pub fn with_bvh_layout(mut self, bvh: BvhLayout) -> Self {
        self.bvh = bvh;
        self
    }

    /// Cover at most `pixels` pixels (whole film rows, at least one) per dispatch, on top of the
    /// device's buffer limits and the renderer's timing; `None` lifts the cap. For devices
    /// whose watchdog is stricter than the 250 ms a dispatch aims at, and for tests.
    pub fn set_max_dispatch_pixels(&mut self, pixels: Option<u32>) {
        self.max_dispatch_pixels = pixels;
    }

    /// Bytes of device memory a render of `scene` with `settings` takes, estimated without a
    /// device: `(scene, film)`, the scene's arrays in layout `bvh` ([`crate::scene_bytes`])
    /// and the accumulator with its two readback copies for the whole film and its twins (a
    /// device whose buffers are smaller dispatches fewer rows at a time, and takes less; a GPU
    /// that splits a small image's samples ([`SampleSplit`]) holds up to 2¹⁸ pixels' worth,
    /// 24 MiB, whatever the image).
    pub fn device_bytes(
        scene: &FlatScene,
        settings: &RenderSettings,
        bvh: BvhLayout,
    ) -> Result<(u64, u64), GpuError> {
        let arrays: u64 = crate::upload::scene_bytes(scene, bvh)?
            .iter()
            .map(|(_, b)| b)
            .sum();
        let rows = Params::new(scene, settings, 0, 0).rows_with_twins() as u64;
        let film = 3 * rows * scene.camera.width as u64 * ACCUM_PIXEL_BYTES;
        Ok((arrays, film))
    }

    /// Have `peak_twins` render each film's peak twins after its samples (none by default: the
    /// kernel places its twins by a hash, not by a list of pixels).
    pub fn set_peak_twins(&mut self, peak_twins: Option<Arc<PeakTwins>>) {
        self.peak_twins = peak_twins;
    }

    /// [`Renderer::set_peak_twins`], builder style.
    pub fn with_peak_twins(mut self, peak_twins: Arc<PeakTwins>) -> Self {
        self.peak_twins = Some(peak_twins);
        self
    }

    /// Render with `kernel` from now on (the specialized kernel by default).
    pub fn set_kernel(&mut self, kernel: Kernel) {
        self.kernel = kernel;
    }

    /// [`Renderer::set_kernel`], builder style.
    pub fn with_kernel(mut self, kernel: Kernel) -> Self {
        self.kernel = kernel;
        self
    }

    /// The kernel this renderer renders with.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// Compile the kernel with `checks` from now on ([`KernelChecks::DEFAULT`] until then;
    /// [`KernelChecks::ALL`] is wgpu's fully checked kernel, [`KernelChecks::AUDITED`] the
    /// fewest allowed). Drops the kernels compiled so far.
    /// Fails for checks that leave out one the audit keeps ([`Renderer::set_checks_unaudited`]
    /// takes those).
    pub fn set_checks(&mut self, checks: KernelChecks) -> Result<(), GpuError> {
        if !checks.covers(KernelChecks::AUDITED) {
            return Err(GpuError::Unsupported(format!(
                "kernel checks `{checks}` leave out one the kernel is not proven to do without \
                 (the audited set is `{}`)",
                KernelChecks::AUDITED
            )));
        }
        // SAFETY: every check left out is one the audit shows the kernel never needs.
        unsafe { self.set_checks_unaudited(checks) }
    }

    /// [`Renderer::set_checks`] for any checks, to measure what each costs.
    ///
    /// # Safety
    /// Without the bounds checks, an index out of range reads or writes outside its array (and,
    /// on a driver without robust buffer access, outside its buffer); the kernel has not been
    /// proven free of that ([`KernelChecks::AUDITED`]).
    pub unsafe fn set_checks_unaudited(&mut self, checks: KernelChecks) -> Result<(), GpuError> {
        if checks != self.checks {
            // SAFETY: the caller's (above), and the audit's for the rest.
            self.module = unsafe { kernel_module(&self.device, checks)? };
            // The ray-query kernel is compiled again, with these checks, at its next use.
            self.ray_query = OnceLock::new();
            self.checks = checks;
            self.pipelines
                .lock()
                .expect("pipeline cache poisoned")
                .clear();
        }
        Ok(())
    }

    /// [`Renderer::set_checks`], builder style.
    pub fn with_checks(mut self, checks: KernelChecks) -> Result<Self, GpuError> {
        self.set_checks(checks)?;
        Ok(self)
    }

    /// Split each pixel's samples over invocations as `split` says from now on
    /// ([`SampleSplit::Auto`] by default: enough to fill a large GPU, none on a CPU adapter).
    pub fn set_sample_split(&mut self, split: SampleSplit) {
        self.split = split;
    }

    /// How this renderer splits each pixel's samples over invocations.
    pub fn sample_split(&self) -> SampleSplit {
        self.split
    }

    /// The runtime checks this renderer's kernel is compiled with.
    pub fn checks(&self) -> KernelChecks {
        self.checks
    }

    /// The specialization `scene` rendered with `settings` compiles to with the default
    /// [`BvhLayout`], fully specialized; [`Renderer::specialize`] gives this renderer's.
    pub fn specialization(scene: &FlatScene, settings: &RenderSettings) -> Specialization {
        Specialization::of(scene, settings)
    }

    /// The kernel this renderer compiles `scene` rendered with `settings` to (the one to
    /// [`Renderer::prepare`] ahead of a render): its specialization in this renderer's BVH
    /// layout, or the generic kernel.
    pub fn specialize(&self, scene: &FlatScene, settings: &RenderSettings) -> Specialization {
        self.kernel_for(scene, Specialization::of(scene, settings))
    }

    /// The kernel this renderer compiles `scene`, of specialization `spec`, to.
    fn kernel_for(&self, scene: &FlatScene, spec: Specialization) -> Specialization {
        let limit = self.device.limits().max_storage_buffer_binding_size;
        Specialization {
            bvh: self.bvh,
            prims_split: crate::upload::prims_split(scene.geometry.len(), limit),
            tables_split: crate::upload::tables_split(scene.tables.len(), limit),
            uniform_scene: self.binding == SceneBinding::Uniform
                && crate::upload::uniform_scene_fits(scene, self.bvh, self.uniform_scene_words()),
            ray_query: self.uses_ray_queries(scene),
            ..spec
        }
        .for_kernel(self.kernel)
    }

    /// Create the pipeline for `spec` (or find it in the cache); returns the seconds spent.
    /// The driver may compile more at the kernel's first dispatch (lavapipe compiles it
    /// then): a render measures that too ([`RenderStats::first_dispatch_seconds`]).
    pub fn prepare(&self, spec: &Specialization) -> Result<f64, GpuError> {
        let mut pipelines = self.pipelines.lock().expect("pipeline cache poisoned");
        if pipelines.contains_key(spec) {
            return Ok(0.0);
        }
        let start = Instant::now();
        let constants = spec.constants();
        // The ray-query kernel is compiled at its first use (its own error scope).
        let ray_query = match spec.ray_query {
            true => Some(self.ray_query_kernel()?),
            false => None,
        };
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let (module, layout) = match ray_query {
            Some(rq) => (&rq.module, &rq.pipeline_layout),
            None => (&self.module, &self.pipeline_layout),
        };
        let pipeline = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("strata render"),
                layout: Some(layout),
                module,
                entry_point: Some("render"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    zero_initialize_workgroup_memory: false,
                },
                cache: None,
            });
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader(error.to_string()));
        }
        pipelines.insert(
            *spec,
            Compiled {
                pipeline,
                dispatched: false,
            },
        );
        Ok(start.elapsed().as_secs_f64())
    }

    /// Add `added_spp` samples of every pixel to `film`, from index
    /// `film.first_sample + film.held_spp()`: [`Render::render_into`], with the device's error.
    fn add_samples(
        &self,
        scene: &FlatScene,
        settings: &RenderSettings,
        film: &mut Film,
        added_spp: u32,
        progress: Progress,
        cancel: Option<&AtomicBool>,
    ) -> Result<RenderStats, GpuError> {
        let (width, height) = (scene.camera.width, scene.camera.height);
        let mut stats = RenderStats::default();
        if width == 0 || height == 0 || added_spp == 0 {
            return Ok(stats);
        }
        check_film(film, settings, width, height)?;
        let setup = Instant::now();
        // Specialize the kernel and compile it (the compile timed apart from the setup).
        let (spec, base) = self.specialize_render(scene, settings);
        let compile = Instant::now();
        stats.compile_seconds = self.prepare(&spec)?;
        let compiled_at = compile.elapsed();
        stats.uniform_scene = spec.uniform_scene;
        // The render's buffers, with room for the slices the sample split asks for.
        let (mut batch, most_slices) = self.batch_for(scene, &spec, base.rows_with_twins())?;
        // Time what the driver compiles at the kernel's first dispatch.
        let mut pipelines = self.pipelines.lock().expect("pipeline cache poisoned");
        let compiled = pipelines.get_mut(&spec).expect("prepared above");
        stats.first_dispatch_seconds = self.first_dispatch(&mut batch, compiled, base)?;
        stats.setup_seconds =
            (setup.elapsed() - compiled_at).as_secs_f64() - stats.first_dispatch_seconds;
        // Batches of samples until `added_spp` are added or Ctrl-C stops them (whole batches
        // only).
        let first = film.first_sample.saturating_add(film.held_spp());
        let samples = (first, first.saturating_add(added_spp));
        let dispatches = Dispatches::new(self, &compiled.pipeline, &mut batch, base, most_slices);
        let added = dispatches.run(film, &mut stats, samples, progress, cancel)?;
        stats.samples = added as u64 * width as u64 * height as u64;
        // The peak twins, with the pipeline cache free again.
        drop(pipelines);
        self.render_peak_twins(scene, settings, film, &mut stats);
        Ok(stats)
    }

    /// Specialize: the kernel a render dispatches and the parameters all its batches share.
    ///
    /// The scene's specialization (it walks every primitive) is computed once, for both.
    fn specialize_render(
        &self,
        scene: &FlatScene,
        settings: &RenderSettings,
    ) -> (Specialization, Params) {
        let scene_spec = Specialization::of(scene, settings);
        let base = Params::for_spec(scene, settings, &scene_spec, 0, 0);
        (self.kernel_for(scene, scene_spec), base)
    }

    /// Plan the split and make the buffers: the render's batch and the most slices it takes.
    ///
    /// The batch covers `rows_total` rows (the film's, then its twins'); its slices are as many
    /// as the sample split asks for the whole film and the accumulator holds for its tallest band.
    fn batch_for(
        &self,
        scene: &FlatScene,
        spec: &Specialization,
        rows_total: u32,
    ) -> Result<(Batch, u32), GpuError> {
        let device_type = self.device.adapter_info().device_type;
        let width = scene.camera.width;
        let most_slices = self
            .split
            .slices(device_type, rows_total.saturating_mul(width));
        let batch = Batch::new(self, scene, spec, rows_total, most_slices)?;
        let most_slices = most_slices.min(batch.capacity_rows / batch.rows).max(1);
        Ok((batch, most_slices))
    }

    /// Time the driver's compile by the kernel's first dispatch, on an empty tile (0 s if done).
    fn first_dispatch(
        &self,
        batch: &mut Batch,
        compiled: &mut Compiled,
        base: Params,
    ) -> Result<f64, GpuError> {
        if compiled.dispatched {
            return Ok(0.0);
        }
        let start = Instant::now();
        batch.run(self, &compiled.pipeline, base.rows(0, 0))?;
        let seconds = start.elapsed().as_secs_f64();
        compiled.dispatched = true;
        Ok(seconds)
    }

    /// Render the peak twins for all the film's samples, unless the render was cancelled.
    ///
    /// At most 64 pixels, rendered by the renderer given for them (the CPU reference, which
    /// computes the same samples as the kernel: the agreement tests). The kernel does not render
    /// them: its twins are placed by a hash, not by a list.
    fn render_peak_twins(
        &self,
        scene: &FlatScene,
        settings: &RenderSettings,
        film: &mut Film,
        stats: &mut RenderStats,
    ) {
        film.peaks.clear();
        if let (false, Some(peak_twins)) = (stats.cancelled, &self.peak_twins) {
            let start = Instant::now();
            stats.non_finite += peak_twins(scene, settings, film);
            stats.peak_twin_seconds = start.elapsed().as_secs_f64();
        }
    }
}

/// Check the film: fail unless it has the size and twins of a `width`×`height` render.
fn check_film(
    film: &Film,
    settings: &RenderSettings,
    width: u32,
    height: u32,
) -> Result<(), GpuError> {
    if (film.width, film.height, film.has_twins()) == (width, height, settings.twins()) {
        return Ok(());
    }
    Err(GpuError::Unsupported(format!(
        "the film is {}×{} (twins: {}); the render is {width}×{height} (twins: {})",
        film.width,
        film.height,
        film.has_twins(),
        settings.twins()
    )))
}

impl Render for Renderer {
    fn render_into(
        &self,
        scene: &FlatScene,
        settings: &RenderSettings,
        film: &mut Film,
        added_spp: u32,
        progress: Progress,
        cancel: Option<&AtomicBool>,
    ) -> Result<RenderStats, RenderError> {
        Ok(self.add_samples(scene, settings, film, added_spp, progress, cancel)?)
    }

    fn describe(&self) -> String {
        let info = self.device.adapter_info();
        format!("GPU {} ({:?})", info.name, info.backend)
    }
}
