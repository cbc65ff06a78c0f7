//! Per-scene specialization: the scene's [`Effects`] and [`DimLayout`], and the BVH layout the
//! renderer traverses, as the `override` constants of `shaders/scene.wgsl`, so a kernel never
//! pays for an effect its scene lacks nor holds the traversal it does not use.

use stratapt_scene::{DimLayout, Effects};

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
        // The CWBVH everywhere. Measured on lavapipe (`strata bench --spp 16 --bvh both`, 512²,
        // depth 8, 2 cores): 1.02–1.45× the BVH2's paths/s on the bundled scenes (one to
        // fifteen wide nodes each). On hardware GPUs it is the layout designed for them (Ylitie
        // et al. 2017, on NVIDIA GPUs), not measured here: strata has not run on one yet.
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

/// The key a compiled kernel is cached under, and its override constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Specialization {
    pub effects: Effects,
    pub layout: DimLayout,
    /// Some primitive or light moves (object motion; camera motion is in `effects.time`).
    pub motion: bool,
    /// The BVH layout the kernel traverses (`BVH_WIDE`).
    pub bvh: BvhLayout,
}

impl Specialization {
    /// `(name, value)` pairs for `PipelineCompilationOptions::constants`.
    pub fn constants(&self) -> Vec<(&'static str, f64)> {
        let e = &self.effects;
        let l = &self.layout;
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        // An absent domain's offset is never read; NONE makes a stray read obvious.
        let dim = |d: Option<u32>| d.unwrap_or(u32::MAX) as f64;
        vec![
            ("HAS_LENS", flag(e.lens)),
            ("HAS_TIME", flag(e.time)),
            ("HAS_NEE", flag(e.nee)),
            ("HAS_LOBE", flag(e.lobe)),
            ("HAS_ROULETTE", flag(e.roulette)),
            ("HAS_MOTION", flag(self.motion)),
            ("HAS_SKY", flag(e.has_sky())),
            ("BVH_WIDE", flag(self.bvh == BvhLayout::Cwbvh)),
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
        ]
    }
}
