//! Render settings: how many samples, which sampler and which estimator.

use stratapt_sampling::SamplerKind;

/// The estimator (importance-sampling strategy).
///
/// Lights that no sampled direction can ever hit — point lights, line lights and distant lights
/// with a zero angular diameter — are always reached by next-event estimation, whatever the
/// strategy, so every strategy estimates the same integral; the strategy decides how the
/// hittable emitters (surfaces, suns with a cone, the sky) are estimated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Strategy {
    /// Uniform hemisphere directions; hittable emission found only by hitting it.
    Uniform,
    /// Cosine-weighted hemisphere directions; emission found only by hitting it.
    Cosine,
    /// BSDF importance sampling (GGX: visible normals); emission found only by hitting it.
    Bsdf,
    /// Next-event estimation only: emission reached by light sampling, never by hitting it
    /// (except directly from the camera or through perfectly specular chains).
    Light,
    /// BSDF and light sampling combined by the power heuristic (Veach 1995).
    #[default]
    Mis,
}

impl Strategy {
    pub const ALL: [Strategy; 5] = [
        Self::Uniform,
        Self::Cosine,
        Self::Bsdf,
        Self::Light,
        Self::Mis,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Uniform => "uniform",
            Self::Cosine => "cosine",
            Self::Bsdf => "bsdf",
            Self::Light => "light",
            Self::Mis => "mis",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Whether hittable emitters are sampled by next-event estimation.
    pub fn samples_lights(self) -> bool {
        matches!(self, Self::Light | Self::Mis)
    }

    /// Whether emission found by a scattered ray counts (fully or MIS-weighted).
    pub fn counts_hit_emission(self) -> bool {
        !matches!(self, Self::Light)
    }

    /// The WGSL `override` constant value (index in [`Strategy::ALL`]).
    pub fn id(self) -> u32 {
        self as u32
    }
}

impl std::fmt::Display for Strategy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Everything about a render that is not the scene itself. Scene files give defaults in their
/// `[render]` table; the command line overrides them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderSettings {
    /// Samples per pixel the sampling pattern is laid out for (the stratified sampler's strata,
    /// the samples a Sobol pattern spans): all that `Render::render` (`stratapt-film`) takes of
    /// each pixel. A progressive render to an error or a time keeps it at a fixed pattern
    /// (`progressive::OPEN_ENDED_STRATA`) and adds patterns until it stops, so the samples a
    /// film holds (`Film::held_spp`) may be many times this. Not the samples a `render_into`
    /// adds (its `added_spp`).
    pub pattern_spp: u32,
    /// Maximum number of path vertices after the camera (1 = direct lighting only).
    pub max_depth: u32,
    pub sampler: SamplerKind,
    pub strategy: Strategy,
    pub seed: u32,
    /// Render the film's twin pixels (an independent randomization of 1 pixel in 16, see
    /// `stratapt_film::twin`) to calibrate the error estimate of the stratified and Sobol
    /// samplers. Off, their error estimate is the per-sample variance, which overstates it.
    pub calibrate: bool,
}

impl RenderSettings {
    /// Whether the render samples twin pixels: when calibrating a sampler whose per-sample
    /// variance is not already its error (all but the independent one).
    pub fn twins(&self) -> bool {
        self.calibrate && self.sampler != SamplerKind::Independent
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            pattern_spp: 64,
            max_depth: 8,
            sampler: SamplerKind::Sobol,
            strategy: Strategy::Mis,
            seed: 0,
            calibrate: true,
        }
    }
}

pub use crate::shared::ROULETTE_START;
