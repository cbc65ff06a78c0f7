//! Test support (not part of the stable API): the software device, shader composition, and
//! "probes" — small kernels that call one shader routine per invocation and write its result,
//! so tests can compare WGSL routines with their Rust counterparts value by value.

pub use crate::params::{KernelParams, Params, UniformSceneOffsets};
pub use crate::shader::{
    compose as compose_modules, kernel_modules, ray_query_kernel, validate, ShaderModule, MODULES,
    REPLACEMENTS,
};
pub use crate::shared::{binding, MAX_BVH_DEPTH};
use crate::specialize::BvhLayout;
use crate::upload::{bind_group_layout, SceneBuffers};
use crate::GpuError;
use stratapt_scene::{FlatScene, RenderSettings};
use wgpu::util::DeviceExt;

/// The environment variable that lets the GPU tests run on Mesa's GL llvmpipe when there is no
/// software Vulkan adapter (`STRATA_TESTS_ALLOW_GL=1`); without it they refuse GL.
pub const ALLOW_GL: &str = "STRATA_TESTS_ALLOW_GL";

/// The environment variable that runs the GPU tests on another adapter than lavapipe: the
/// first whose name contains its text (`STRATA_TESTS_ADAPTER=h200`). The tests' tolerances
/// and bit-close floors were set on lavapipe; another driver may round differently.
pub const TESTS_ADAPTER: &str = "STRATA_TESTS_ADAPTER";

/// The adapter [`TESTS_ADAPTER`] names, if any: the tests run on it instead of lavapipe.
pub fn tests_adapter() -> Option<String> {
    std::env::var(TESTS_ADAPTER)
        .ok()
        .filter(|name| !name.is_empty())
}

/// Whether the device [`software_device`] opened is a software adapter (lavapipe, llvmpipe),
/// whose arithmetic the agreement tests' bit-level criteria were set on; true until it has
/// opened one.
pub fn tests_on_software() -> bool {
    *ON_SOFTWARE.get().unwrap_or(&true)
}

static ON_SOFTWARE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();

/// lavapipe (software Vulkan): the adapter the tests run on, on purpose, unless
/// [`TESTS_ADAPTER`] names another. Says which adapter and backend it opened (once per test
/// binary). Err with what to install when there is no software adapter, or when the only one
/// is GL llvmpipe and [`ALLOW_GL`] is not set: the tests must not pass quietly on another
/// backend than the one CI means to test.
pub fn software_device() -> Result<(wgpu::Device, wgpu::Queue), String> {
    let choice = match tests_adapter() {
        Some(name) => crate::adapter::AdapterChoice::Named(name),
        None => crate::adapter::AdapterChoice::Software,
    };
    let gpu = crate::adapter::open(&choice).map_err(|e| match tests_adapter() {
        Some(name) => format!("{e}\n{TESTS_ADAPTER}={name} names no adapter here"),
        None => format!(
            "{e}\nthe GPU tests need Mesa's software Vulkan: apt-get install mesa-vulkan-drivers"
        ),
    })?;
    let _ = ON_SOFTWARE.set(gpu.adapter.get_info().device_type == wgpu::DeviceType::Cpu);
    let backend = gpu.adapter.get_info().backend;
    if backend != wgpu::Backend::Vulkan && std::env::var_os(ALLOW_GL).is_none() {
        return Err(format!(
            "the GPU tests found {} but no software Vulkan adapter: install lavapipe \
             (apt-get install mesa-vulkan-drivers), or set {ALLOW_GL}=1 to test on it",
            gpu.describe()
        ));
    }
    static SAID: std::sync::Once = std::sync::Once::new();
    SAID.call_once(|| eprintln!("GPU tests on {}", gpu.describe()));
    Ok((gpu.device, gpu.queue))
}

/// `scene.wgsl` + `modules` + `extra`, validated by naga.
pub fn compose(modules: &[&str], extra: &str) -> Result<String, String> {
    crate::shader::compose(modules, extra).map_err(|e| e.to_string())
}

const PROBE_MAIN: &str = r#"
@group(1) @binding(0) var<storage, read> probe_in: array<u32>;
@group(1) @binding(1) var<storage, read_write> probe_out: array<u32>;
struct ProbeCount { count: u32, _p0: u32, _p1: u32, _p2: u32 }
@group(1) @binding(2) var<uniform> probe_count: ProbeCount;

@compute @workgroup_size(64)
fn probe_main(@builtin(global_invocation_id) id: vec3u) {
    let i = id.x + id.y * 65535u * 64u;
    if (i < probe_count.count) {
        probe(i);
    }
}
"#;

/// Run `probe_src` (defining `fn probe(i: u32)`, reading `probe_in`, writing `probe_out`) for
/// `i` in `0..count`, with group 0 bound to `scene` and `settings` (batch = all of
/// `settings.pattern_spp` from sample 0) and every override at its default (the BVH in the
/// default [`BvhLayout`]).
/// Returns `probe_out`. Panics on errors: this is for tests.
#[allow(clippy::too_many_arguments)]
pub fn run_probe(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &FlatScene,
    settings: &RenderSettings,
    modules: &[&str],
    probe_src: &str,
    input: &[u32],
    output_words: usize,
    count: u32,
) -> Vec<u32> {
    run_probe_with_bvh(
        device,
        queue,
        scene,
        settings,
        BvhLayout::default(),
        modules,
        probe_src,
        input,
        output_words,
        count,
    )
}

/// [`run_probe`] with the scene's BVH uploaded in layout `bvh` and `BVH_WIDE` set to match.
#[allow(clippy::too_many_arguments)]
pub fn run_probe_with_bvh(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &FlatScene,
    settings: &RenderSettings,
    bvh: BvhLayout,
    modules: &[&str],
    probe_src: &str,
    input: &[u32],
    output_words: usize,
    count: u32,
) -> Vec<u32> {
    try_run_probe(
        device,
        queue,
        scene,
        settings,
        bvh,
        modules,
        probe_src,
        input,
        output_words,
        count,
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

#[allow(clippy::too_many_arguments)]
fn try_run_probe(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &FlatScene,
    settings: &RenderSettings,
    bvh: BvhLayout,
    modules: &[&str],
    probe_src: &str,
    input: &[u32],
    output_words: usize,
    count: u32,
) -> Result<Vec<u32>, GpuError> {
    let source = crate::shader::compose(modules, &format!("{probe_src}\n{PROBE_MAIN}"))?;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("probe"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let group0 = bind_group_layout(device);
    let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let group1 = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("probe io"),
        entries: &[
            storage(0, true),
            storage(1, false),
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("probe"),
        bind_group_layouts: &[Some(&group0), Some(&group1)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("probe"),
        layout: Some(&layout),
        module: &module,
        entry_point: Some("probe_main"),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &[("BVH_WIDE", if bvh == BvhLayout::Cwbvh { 1.0 } else { 0.0 })],
            ..Default::default()
        },
        cache: None,
    });

    // ---- Buffers --------------------------------------------------------------------------
    let buffers = SceneBuffers::new(device, scene, bvh, false)?;
    let params = Params::new(scene, settings, 0, settings.pattern_spp);
    let uniform = |label, bytes: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        })
    };
    let params_buffer = uniform("params", bytemuck::bytes_of(&params));
    let accum = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("accum (unused)"),
        size: 32,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let input_words: Vec<u32> = if input.is_empty() {
        vec![0]
    } else {
        input.to_vec()
    };
    let probe_in = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("probe_in"),
        contents: bytemuck::cast_slice(&input_words),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let out_size = (output_words.max(1) * 4) as u64;
    let probe_out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe_out"),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe readback"),
        size: out_size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let count_buffer = uniform("probe count", bytemuck::bytes_of(&[count, 0, 0, 0]));

    let mut entries = vec![wgpu::BindGroupEntry {
        binding: 0,
        resource: params_buffer.as_entire_binding(),
    }];
    entries.extend(buffers.entries());
    entries.push(wgpu::BindGroupEntry {
        binding: crate::shared::binding::ACCUM,
        resource: accum.as_entire_binding(),
    });
    let bind0 = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("scene"),
        layout: &group0,
        entries: &entries,
    });
    let bind1 = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("probe io"),
        layout: &group1,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: probe_in.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: probe_out.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: count_buffer.as_entire_binding(),
            },
        ],
    });

    // ---- Dispatch and read back -------------------------------------------------------------
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind0, &[]);
        pass.set_bind_group(1, &bind1, &[]);
        let groups = count.div_ceil(64).max(1);
        pass.dispatch_workgroups(groups.min(65535), groups.div_ceil(65535), 1);
    }
    encoder.copy_buffer_to_buffer(&probe_out, 0, &readback, 0, out_size);
    queue.submit([encoder.finish()]);
    if let Some(error) = pollster::block_on(scope.pop()) {
        return Err(GpuError::Device(error.to_string()));
    }
    crate::readback::read_u32(device, &readback).map(|mut v| {
        v.truncate(output_words);
        v
    })
}
