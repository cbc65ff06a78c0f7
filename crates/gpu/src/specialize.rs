//! Per-scene specialization: the scene's [`Effects`] and [`DimLayout`] as the `override`
//! constants of `shaders/scene.wgsl`, so a kernel never pays for an effect its scene lacks.

use stratapt_scene::{DimLayout, Effects};

/// The key a compiled kernel is cached under, and its override constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Specialization {
    pub effects: Effects,
    pub layout: DimLayout,
    /// Some primitive or light moves (object motion; camera motion is in `effects.time`).
    pub motion: bool,
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
            ("HAS_PATH", flag(e.path)),
            ("HAS_LOBE", flag(e.lobe)),
            ("HAS_ROULETTE", flag(e.roulette)),
            ("HAS_MOTION", flag(self.motion)),
            ("HAS_SKY", flag(e.has_sky())),
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
