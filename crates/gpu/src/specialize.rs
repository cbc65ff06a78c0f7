//! Per-scene specialization: the scene's [`Effects`] and [`DimLayout`], and the BVH layout the
//! renderer traverses and where it reads the scene's arrays from, as the `override` constants of `shaders/scene.wgsl`, so a kernel never
//! pays for an effect its scene lacks nor holds the traversal it does not use.

mod size;

pub use size::KernelSize;

use crate::shared::effect_bit;
use crate::GpuError;
use stratapt_scene::effects::{kind_names, LIGHT_KIND_NAMES, MATERIAL_KIND_NAMES};
use stratapt_scene::records::NONE;
use stratapt_scene::{DimLayout, Effects, FlatScene, RenderSettings};

/// How the BVH is laid out for the GPU (both are built from the scene's obvhs BVH2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BvhLayout {
    /// The BVH2 itself, two children per node (`shaders/bvh.wgsl`).
    Bvh2,
    /// A compressed wide BVH, eight children per node with quantized boxes
    /// (`shaders/cwbvh.wgsl`; Ylitie, Karras & Laine 2017). What [`BvhLayout::for_adapter`]
    /// picks for every adapter type today.
    #[default]
    Cwbvh,
}

impl BvhLayout {
    /// Both layouts.
    pub const ALL: [BvhLayout; 2] = [BvhLayout::Bvh2, BvhLayout::Cwbvh];

    /// The layout a [`crate::Renderer`] traverses on an adapter of this type unless told
    /// otherwise: the faster one where it has been measured, else the literature's choice.
    pub fn for_adapter(device_type: wgpu::DeviceType) -> Self {
        // The CWBVH everywhere. On lavapipe it is faster than the BVH2 on the bundled scenes
        // (one to fifteen wide nodes each) except the two with the shallowest trees (measured:
        // docs/measurements/performance.md#the-bundled-scenes). On hardware GPUs it is the
        // layout designed for them (Ylitie et al. 2017, on NVIDIA GPUs), not compared here: the
        // H200 runs (docs/measurements/h200.md) used this default.
        let _ = device_type;
        BvhLayout::Cwbvh
    }
}

impl std::fmt::Display for BvhLayout {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            BvhLayout::Bvh2 => "bvh2",
            BvhLayout::Cwbvh => "cwbvh",
        })
    }
}

/// How the kernel finds what a ray hits: its own traversal of the BVH, or the adapter's ray
/// queries (wgpu's `EXPERIMENTAL_RAY_QUERY`) over an acceleration structure of the scene's
/// triangles. The ray-query kernel serves scenes of static triangles without alpha (procedural
/// spheres, disks and motion are not built); others take the BVH.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Traversal {
    /// The kernel's own BVH traversal (`shaders/accel.wgsl`), bit for bit the CPU's.
    #[default]
    Bvh,
    /// The adapter's ray queries (`shaders/accel_ray_query.wgsl`) where the device has them
    /// and the scene is served, else the BVH.
    RayQuery,
}

impl Traversal {
    /// The traversal a [`crate::Renderer`] uses unless told otherwise: the BVH everywhere.
    /// On lavapipe ray queries measured slower (docs/measurements/ray-queries.md); on hardware
    /// GPUs they have not been measured yet.
    pub fn for_adapter(device_type: wgpu::DeviceType) -> Self {
        let _ = device_type;
        Traversal::Bvh
    }

    /// Whether the ray-query kernel can render `scene`: static triangles only, no alpha.
    pub fn serves(scene: &FlatScene) -> bool {
        let geometry = &scene.geometry;
        (0..geometry.len() as u32).all(|id| geometry.is_static_triangle(id))
            && !scene.geometry.is_empty()
            && !scene.motions.iter().any(|m| m.is_moving())
            && !geometry
                .surfaces
                .iter()
                .any(|s| s.flags & stratapt_scene::records::surface_flag::ALPHA != 0)
    }
}

impl std::fmt::Display for Traversal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Traversal::Bvh => "bvh",
            Traversal::RayQuery => "ray-query",
        })
    }
}

/// Where the kernel reads the scene's arrays from (`UNIFORM_SCENE` in `shaders/scene.wgsl`):
/// primitives, points, shading normals, surfaces, materials, lights, their alias tables,
/// motions and the BVH nodes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SceneBinding {
    /// Their storage buffers, whatever the scene's size.
    #[default]
    Storage,
    /// A copy of them all in one uniform buffer as large as the device binds, 16 KiB (WebGPU's
    /// downlevel limit) to 64 KiB ([`crate::shared::uniform_scene_words`]), when they fit it, as
    /// every bundled scene does even in 16 KiB; their storage buffers otherwise.
    Uniform,
}

impl SceneBinding {
    /// Both bindings.
    pub const ALL: [SceneBinding; 2] = [SceneBinding::Storage, SceneBinding::Uniform];

    /// The binding a [`crate::Renderer`] reads the scene through on an adapter of this type
    /// unless told otherwise.
    pub fn for_adapter(device_type: wgpu::DeviceType) -> Self {
        match device_type {
            // Software Vulkan (lavapipe) loads a storage buffer's elements lane by lane, each
            // with a bounds check and a branch, but a uniform buffer's with one branch-free
            // gather, so the bundled scenes render faster from the uniform scene (measured:
            // docs/measurements/lavapipe.md#on-mesa-25).
            wgpu::DeviceType::Cpu => SceneBinding::Uniform,
            // Hardware GPUs serve uniform reads from a constant cache that serializes the
            // different addresses of one warp; traversal's reads differ per lane. Not compared:
            // the H200 runs (docs/measurements/h200.md) used this default.
            _ => SceneBinding::Storage,
        }
    }
}

impl std::fmt::Display for SceneBinding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SceneBinding::Storage => "storage",
            SceneBinding::Uniform => "uniform",
        })
    }
}

/// What a kernel decides at run time, from the scene's specialization passed as data in the
/// render parameters, instead of having it compiled in: an effect whose bit is set is compiled
/// in whether or not the scene calls for it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Runtime {
    /// [`effect_bit`]s.
    pub effects: u32,
    /// Bit `1 << k` per light kind `k`.
    pub light_kinds: u32,
    /// Bit `1 << k` per material kind `k`.
    pub material_kinds: u32,
    /// The sample-dimension layout.
    pub dims: bool,
}

impl Runtime {
    /// Nothing at run time: the specialized kernel.
    pub const NONE: Runtime = Runtime {
        effects: 0,
        light_kinds: 0,
        material_kinds: 0,
        dims: false,
    };
    /// Everything at run time: the generic kernel.
    pub const ALL: Runtime = Runtime {
        effects: (1 << effect_bit::ALL.len()) - 1,
        light_kinds: (1 << LIGHT_KIND_NAMES.len()) - 1,
        material_kinds: (1 << MATERIAL_KIND_NAMES.len()) - 1,
        dims: true,
    };
}

/// Which kernel renders a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Kernel {
    /// Compiled for the scene: only the effects it calls for, its dimension layout as
    /// constants (`Specialization::of`). One compile per distinct specialization.
    #[default]
    Specialized,
    /// One kernel for every scene: every effect compiled in, each decided at run time from the
    /// scene's specialization passed as data. Same sample dimensions in the same order, so
    /// the same image up to float rounding.
    Generic,
    /// The specialized kernel with what `Runtime` names compiled in and decided at run time:
    /// what carrying an effect the scene does not use costs (`strata bench --kernel effects`).
    Carrying(Runtime),
}

impl Kernel {
    /// `specialized` or `generic` (a carrying kernel names what it carries).
    pub fn name(&self) -> String {
        match self {
            Kernel::Specialized => "specialized".into(),
            Kernel::Generic => "generic".into(),
            Kernel::Carrying(r) => format!("specialized + {}", r.describe()),
        }
    }
}

impl Runtime {
    /// What is decided at run time, in words (e.g. `lens`, `line lights`).
    pub fn describe(&self) -> String {
        let mut parts: Vec<String> = effect_bit::ALL
            .iter()
            .filter(|(_, bit)| self.effects & bit != 0)
            .map(|(name, _)| name.to_lowercase())
            .collect();
        if self.light_kinds != 0 {
            parts.push(format!(
                "{} lights",
                kind_names(self.light_kinds, &LIGHT_KIND_NAMES, "+")
            ));
        }
        if self.material_kinds != 0 {
            parts.push(kind_names(self.material_kinds, &MATERIAL_KIND_NAMES, "+"));
        }
        if self.dims {
            parts.push("dimension layout".into());
        }
        if parts.is_empty() {
            "nothing".into()
        } else {
            parts.join(", ")
        }
    }
}

/// The key a compiled kernel is cached under, and its override constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Specialization {
    pub effects: Effects,
    pub layout: DimLayout,
    /// Some primitive or light has a motion (object motion; camera motion is in
    /// `effects.time`).
    pub motion: bool,
    /// The BVH layout the kernel traverses (`BVH_WIDE`).
    pub bvh: BvhLayout,
    /// The first primitive in the second primitives binding, or 0 when the first holds them all
    /// (`PRIMS_SPLIT`; `upload::prims_split`): a device's binding limit, not the scene,
    /// so only scenes too large for one binding compile a kernel that chooses between two.
    pub prims_split: u32,
    /// The first word of the tables in the second tables binding, or 0 when the first holds
    /// them all (`TABLES_SPLIT`; `upload::tables_split`), as `prims_split`.
    pub tables_split: u32,
    /// The kernel reads the scene's arrays from the uniform scene (`UNIFORM_SCENE`;
    /// [`SceneBinding::Uniform`] on a scene that fits it): like the BVH layout, a matter of the
    /// device and the scene's size, not an effect.
    pub uniform_scene: bool,
    /// What the kernel decides at run time instead ([`Runtime::NONE`] when specialized).
    pub runtime: Runtime,
    /// The kernel traces with the adapter's ray queries ([`Traversal::RayQuery`] on a scene it
    /// serves): another shader module and a second bind group.
    pub ray_query: bool,
}

impl Specialization {
    /// What `scene` rendered with `settings` calls for, fully specialized, in the default
    /// [`BvhLayout`].
    pub fn of(scene: &FlatScene, settings: &RenderSettings) -> Self {
        let effects = Effects::of(scene, settings);
        Self {
            layout: DimLayout::new(&effects),
            effects,
            motion: scene.motions.iter().any(|m| m.is_moving()),
            bvh: BvhLayout::default(),
            prims_split: 0,
            tables_split: 0,
            uniform_scene: false,
            runtime: Runtime::NONE,
            ray_query: false,
        }
    }

    /// Every effect, light kind and material kind compiled in and the dimension layout that
    /// holds them all, nothing decided at run time, in the default [`BvhLayout`], the scene's
    /// arrays from their storage buffers, one primitives binding: what the `override` constants
    /// of `shaders/scene.wgsl` default to (a test holds them to it), and what the generic kernel
    /// compiles in.
    pub fn everything() -> Self {
        let effects = Effects::everything();
        Self {
            layout: DimLayout::new(&effects),
            effects,
            motion: true,
            bvh: BvhLayout::default(),
            prims_split: 0,
            tables_split: 0,
            uniform_scene: false,
            runtime: Runtime::NONE,
            ray_query: false,
        }
    }

    /// The kernel `kernel` compiles this specialization to: itself, the one generic kernel (the
    /// same for every scene, so its key holds no scene), or itself carrying what it names.
    pub fn for_kernel(self, kernel: Kernel) -> Self {
        match kernel {
            Kernel::Specialized => Self {
                runtime: Runtime::NONE,
                ..self
            },
            Kernel::Generic => Self {
                bvh: self.bvh,
                prims_split: self.prims_split,
                tables_split: self.tables_split,
                uniform_scene: self.uniform_scene,
                runtime: Runtime::ALL,
                ray_query: self.ray_query,
                ..Self::everything()
            },
            Kernel::Carrying(runtime) => Self { runtime, ..self },
        }
    }

    /// The kernel this is: specialized, generic, or carrying something.
    pub fn kernel(&self) -> Kernel {
        match self.runtime {
            Runtime::NONE => Kernel::Specialized,
            Runtime::ALL => Kernel::Generic,
            r => Kernel::Carrying(r),
        }
    }

    /// The effect bits of `KernelParams::effects` (what the scene calls for, as data).
    pub fn effect_bits(&self) -> u32 {
        let e = &self.effects;
        [
            (e.lens, effect_bit::LENS),
            (e.time, effect_bit::TIME),
            (e.nee, effect_bit::NEE),
            (e.lobe, effect_bit::LOBE),
            (e.roulette, effect_bit::ROULETTE),
            (self.motion, effect_bit::MOTION),
            (e.textures, effect_bit::TEXTURES),
            (e.alpha, effect_bit::ALPHA),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .fold(0, |acc, (_, bit)| acc | bit)
    }

    /// The code this kernel leaves for the driver to compile ([`KernelSize`]), from naga's IR
    /// with the overrides applied; no device needed.
    pub fn kernel_size(&self) -> Result<KernelSize, GpuError> {
        let source = crate::shader::source(&crate::shader::kernel_modules(), "")?;
        let (module, info) = crate::shader::parse(&source)?;
        let mut constants = naga::back::PipelineConstants::default();
        for (name, value) in self.constants() {
            constants.insert(name.to_string(), value);
        }
        let entry = Some((naga::ShaderStage::Compute, "render"));
        let (module, info) =
            naga::back::pipeline_constants::process_overrides(&module, &info, entry, &constants)
                .map_err(|e| GpuError::Shader(format!("overrides: {e}")))?;
        let pipeline = naga::back::spv::PipelineOptions {
            shader_stage: naga::ShaderStage::Compute,
            entry_point: "render".into(),
        };
        let words = naga::back::spv::write_vec(
            &module,
            &info,
            &naga::back::spv::Options::default(),
            Some(&pipeline),
        )
        .map_err(|e| GpuError::Shader(format!("SPIR-V: {e}")))?
        .len();
        size::measure(&module, "render", words)
            .ok_or_else(|| GpuError::Shader("no `render` entry point".into()))
    }

    /// `(name, value)` pairs for `PipelineCompilationOptions::constants`.
    pub fn constants(&self) -> Vec<(&'static str, f64)> {
        let e = &self.effects;
        let l = &self.layout;
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        // An absent domain's offset is never read; NONE makes a stray read obvious.
        let dim = |d: Option<u32>| d.unwrap_or(NONE) as f64;
        vec![
            ("HAS_LENS", flag(e.lens)),
            ("HAS_TIME", flag(e.time)),
            ("HAS_NEE", flag(e.nee)),
            ("HAS_LOBE", flag(e.lobe)),
            ("HAS_ROULETTE", flag(e.roulette)),
            ("HAS_MOTION", flag(self.motion)),
            ("HAS_TEXTURES", flag(e.textures)),
            ("HAS_ALPHA", flag(e.alpha)),
            ("BVH_WIDE", flag(self.bvh == BvhLayout::Cwbvh)),
            ("PRIMS_SPLIT", self.prims_split as f64),
            ("TABLES_SPLIT", self.tables_split as f64),
            ("UNIFORM_SCENE", flag(self.uniform_scene)),
            ("LIGHT_KINDS", e.light_kinds as f64),
            ("MATERIAL_KINDS", e.material_kinds as f64),
            ("DIM_PIXEL", l.pixel as f64),
            ("DIM_LENS", dim(l.lens)),
            ("DIM_TIME", dim(l.time)),
            ("DIM_FIRST_VERTEX", l.first_vertex as f64),
            ("DIM_PER_VERTEX", l.per_vertex as f64),
            ("DIM_LIGHT_SELECT", dim(l.light_select)),
            ("DIM_LIGHT_POINT", dim(l.light_point)),
            ("DIM_DIRECTION", l.direction as f64),
            ("DIM_LOBE", dim(l.lobe)),
            ("DIM_ROULETTE", dim(l.roulette)),
            ("RUNTIME_EFFECTS", self.runtime.effects as f64),
            ("RUNTIME_LIGHT_KINDS", self.runtime.light_kinds as f64),
            ("RUNTIME_MATERIAL_KINDS", self.runtime.material_kinds as f64),
            ("RUNTIME_DIMS", flag(self.runtime.dims)),
        ]
    }
}
