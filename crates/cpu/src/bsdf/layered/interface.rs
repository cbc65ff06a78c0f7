//! The two interfaces of [`Layered`](super::Layered) as its walks call them: the coat (smooth
//! or rough) and the base, from either side, sampling restricted to reflection or transmission
//! as pbrt's `BxDFReflTransFlags`.

use super::*;

// ---------------------------------------------------------------------------------------------
// The two interfaces as the walk calls them: from either side, sampling restricted to
// reflection or transmission as pbrt's `BxDFReflTransFlags`.
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, PartialEq)]
pub(super) enum Only {
    All,
    Reflection,
    Transmission,
}

/// An interface's sample: `weight` is `f · |cos| / pdf` (radiance).
#[derive(Clone, Copy)]
pub(super) struct Scatter {
    pub(super) wi: Vec3,
    pub(super) weight: Vec3,
    pub(super) pdf: f32,
    pub(super) delta: bool,
}

impl Scatter {
    /// pbrt's test of a usable sample: a density, a direction off the plane, some throughput.
    pub(super) fn usable(self) -> Option<Self> {
        let ok = self.pdf > 0.0 && self.wi.z != 0.0 && self.weight != Vec3::ZERO;
        ok.then_some(self)
    }
}

#[derive(Clone, Copy)]
pub(super) enum Top {
    Smooth(Dielectric),
    Rough(RoughDielectric),
}

impl Top {
    pub(super) fn eta(self) -> f32 {
        match self {
            Self::Smooth(d) => d.eta,
            Self::Rough(r) => r.eta,
        }
    }

    pub(super) fn specular(self) -> bool {
        matches!(self, Self::Smooth(_))
    }

    /// The interface seen from `wo`'s side, and the sign that takes directions there (from
    /// inside, the relative index is 1/η and directions are mirrored through the origin).
    pub(super) fn facing(self, wo: Vec3) -> (Self, f32) {
        if wo.z >= 0.0 {
            return (self, 1.0);
        }
        let top = match self {
            Self::Smooth(d) => Self::Smooth(Dielectric {
                eta: 1.0 / d.eta,
                ..d
            }),
            Self::Rough(r) => Self::Rough(RoughDielectric {
                eta: 1.0 / r.eta,
                ..r
            }),
        };
        (top, -1.0)
    }

    pub(super) fn eval(self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self.facing(wo) {
            (Self::Rough(r), s) => r.eval(s * wo, s * wi),
            (Self::Smooth(_), _) => Vec3::ZERO,
        }
    }

    pub(super) fn pdf(self, wo: Vec3, wi: Vec3, only: Only) -> f32 {
        let (Self::Rough(r), s) = self.facing(wo) else {
            return 0.0;
        };
        let (wo, wi) = (s * wo, s * wi);
        let full = r.pdf(wo, wi, Lobe::Bsdf);
        let reflect = wi.z > 0.0;
        match (only, reflect) {
            (Only::All, _) => return full,
            (Only::Reflection, false) | (Only::Transmission, true) => return 0.0,
            _ => {}
        }
        // The lobe's probability F or 1 − F at the half vector, divided out.
        let h = if reflect { wo + wi } else { wo + r.eta * wi };
        let h = h.normalize_or_zero();
        let h = if h.z < 0.0 { -h } else { h };
        let f = fresnel(wo.dot(h), r.eta);
        let prob = if reflect { f } else { 1.0 - f };
        let pdf = full / prob;
        if full > 0.0 && pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }

    pub(super) fn sample(self, wo: Vec3, uc: f32, u: Vec2, only: Only) -> Option<Scatter> {
        let (top, s) = self.facing(wo);
        let wo = s * wo;
        if wo.z.is_nan() || wo.z <= 0.0 {
            return None;
        }
        let out = match top {
            Self::Smooth(d) => sample_smooth(d, wo, uc, only)?,
            Self::Rough(r) => sample_rough(r, wo, uc, u, only)?,
        };
        Scatter {
            wi: s * out.wi,
            ..out
        }
        .usable()
    }
}

/// A smooth interface's sample from above: both lobes by F (as [`Dielectric::sample`]), or one.
pub(super) fn sample_smooth(d: Dielectric, wo: Vec3, uc: f32, only: Only) -> Option<Scatter> {
    let f = fresnel(wo.z, d.eta);
    let (wi, weight, pdf) = match only {
        Only::All => {
            let b = d.sample(wo, uc)?;
            (b.wi, b.weight, b.pdf)
        }
        Only::Reflection if f > 0.0 => (Vec3::new(-wo.x, -wo.y, wo.z), Vec3::splat(f), 1.0),
        // The refraction (lobe dimension 1 ≥ F < 1), its weight times its probability 1 − F.
        Only::Transmission if f < 1.0 => {
            let b = d.sample(wo, 1.0)?;
            (b.wi, b.weight * (1.0 - f), 1.0)
        }
        _ => return None,
    };
    Some(Scatter {
        wi,
        weight,
        pdf,
        delta: true,
    })
}

/// A GGX interface's sample from above: both lobes by F at the visible normal (as
/// [`RoughDielectric::sample`]), or one, with the lobe's probability moved from the pdf into the
/// weight.
pub(super) fn sample_rough(
    r: RoughDielectric,
    wo: Vec3,
    uc: f32,
    u: Vec2,
    only: Only,
) -> Option<Scatter> {
    let (prob, u_lobe) = match only {
        Only::All => (1.0, uc),
        _ => {
            // The normal RoughDielectric::sample draws with `u`, and its F.
            let f = fresnel(wo.dot(ggx::sample_vndf(wo, r.alpha, u)), r.eta);
            match only {
                Only::Reflection => (f, 0.0),
                _ => (1.0 - f, 1.0),
            }
        }
    };
    if prob.is_nan() || prob <= 0.0 {
        return None;
    }
    let b = r.sample(wo, u, u_lobe, Lobe::Bsdf)?;
    Some(Scatter {
        wi: b.wi,
        weight: b.weight * prob,
        pdf: b.pdf / prob,
        delta: false,
    })
}

impl Base {
    pub(super) fn specular(&self) -> bool {
        match self {
            Self::Diffuse(_) => false,
            Self::Conductor(c) => c.is_mirror(),
        }
    }

    pub(super) fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self {
            Self::Diffuse(b) => b.eval(wo, wi),
            Self::Conductor(b) => b.eval(wo, wi),
        }
    }

    pub(super) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Self::Diffuse(b) => b.pdf(wo, wi, Lobe::Bsdf),
            Self::Conductor(b) => b.pdf(wo, wi, Lobe::Bsdf),
        }
    }

    /// The base's own sampling (`_uc`: pbrt draws a lobe dimension it does not use).
    pub(super) fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<Scatter> {
        let b = match self {
            Self::Diffuse(b) => b.sample(wo, u, Lobe::Bsdf)?,
            Self::Conductor(b) => b.sample(wo, u, Lobe::Bsdf)?,
        };
        Scatter {
            wi: b.wi,
            weight: b.weight,
            pdf: b.pdf,
            delta: b.delta,
        }
        .usable()
    }
}
