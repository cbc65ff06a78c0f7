//! BSDFs: the interface, the choice of lobe sampling per strategy, and the world-space shading
//! point that guards against light leaks.
//!
//! Local convention: `z` is the shading normal flipped to the side of `wo`, so `wo.z ≥ 0`.
//! `eval` returns `f · |cos θi|`, `pdf` the solid-angle density of `sample` (0 for delta
//! lobes), and `sample` the weight `f · |cos θi| / pdf`.

pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod diffuse_transmission;
pub mod layered;
pub mod mix;
pub mod plastic;
pub mod rough_dielectric;
pub mod thin_dielectric;

use crate::intersect::Hit;
use conductor::{Conductor, Fresnel};
use dielectric::Dielectric;
use diffuse::Diffuse;
use diffuse_transmission::DiffuseTransmission;
use glam::{Vec2, Vec3};
use layered::{Base, Coat, Layered};
use plastic::{Plastic, RoughCoat};
use rough_dielectric::RoughDielectric;
use stratapt_sampling::warp::ggx::Masking;
use stratapt_sampling::{warp, Frame};
use stratapt_scene::coating::TRANSMITTANCE_RES;
use stratapt_scene::records::{material_flag, material_kind, Material, MIRROR_ALPHA};
use stratapt_scene::Strategy;
use thin_dielectric::ThinDielectric;

/// A sampled incident direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    pub wi: Vec3,
    /// `f · |cos θi| / pdf` (for delta lobes: the lobe's weight over its selection probability).
    pub weight: Vec3,
    /// Solid-angle pdf; for delta lobes the discrete probability of the lobe.
    pub pdf: f32,
    pub delta: bool,
    /// Relative index of refraction crossed (`η_t / η_i`), 1 for reflection.
    pub eta: f32,
}

impl BsdfSample {
    /// A reflection into `wi` from a non-delta lobe.
    pub fn reflection(wi: Vec3, weight: Vec3, pdf: f32) -> Self {
        Self {
            wi,
            weight,
            pdf,
            delta: false,
            eta: 1.0,
        }
    }

    /// The mirror reflection of `wo` about the normal, a delta lobe chosen with probability
    /// `pdf`.
    pub fn mirror(wo: Vec3, weight: Vec3, pdf: f32) -> Self {
        Self {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight,
            pdf,
            delta: true,
            eta: 1.0,
        }
    }
}

/// A surface's scattering function in its local frame (borrowing the scene's material tables).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf<'a> {
    Diffuse(Diffuse),
    Conductor(Conductor),
    Dielectric(Dielectric),
    RoughDielectric(RoughDielectric),
    Plastic(Plastic<'a>),
    ThinDielectric(ThinDielectric),
    DiffuseTransmission(DiffuseTransmission),
    Layered(Layered),
}

impl<'a> Bsdf<'a> {
    /// The BSDF of `material`, whose tables (a rough plastic's) are in `tables`
    /// ([`stratapt_scene::FlatScene::tables`]); `entering` says whether `wo` is on the
    /// front (outside) side of the geometric surface, which decides the dielectric's relative
    /// index of refraction.
    pub fn new(material: &Material, tables: &'a [f32], entering: bool) -> Self {
        let color = Vec3::from_array(material.color);
        // A dielectric's η_t / η_i for light crossing from `wo`'s side.
        let relative_ior = || {
            if entering {
                material.ior
            } else {
                1.0 / material.ior
            }
        };
        let masking = if material.has(material_flag::SEPARABLE_MASKING) {
            Masking::Separable
        } else {
            Masking::Correlated
        };
        match material.kind() {
            material_kind::CONDUCTOR => Self::Conductor(
                Conductor::new(Fresnel::Schlick(color), material.alpha_u, material.alpha_v)
                    .with_masking(masking),
            ),
            material_kind::COMPLEX_CONDUCTOR => Self::Conductor(
                Conductor::new(
                    Fresnel::Complex {
                        eta: Vec3::from_array(material.eta),
                        k: Vec3::from_array(material.k),
                        tint: color,
                    },
                    material.alpha_u,
                    material.alpha_v,
                )
                .with_masking(masking),
            ),
            material_kind::DIELECTRIC => Self::Dielectric(Dielectric {
                eta: relative_ior(),
                tint: color,
            }),
            material_kind::ROUGH_DIELECTRIC => {
                // Each α at least the mirror threshold (a GGX pdf with a smaller one overflows).
                let alpha =
                    Vec2::new(material.alpha_u, material.alpha_v).max(Vec2::splat(MIRROR_ALPHA));
                Self::RoughDielectric(RoughDielectric {
                    eta: relative_ior(),
                    tint: color,
                    alpha,
                    masking,
                })
            }
            kind @ (material_kind::PLASTIC | material_kind::ROUGH_PLASTIC) => {
                let rough = (kind == material_kind::ROUGH_PLASTIC).then(|| {
                    let start = material.k[2] as usize;
                    RoughCoat {
                        alpha: material.alpha_u.max(MIRROR_ALPHA),
                        masking,
                        transmittance: &tables[start..start + TRANSMITTANCE_RES],
                    }
                });
                Self::Plastic(Plastic {
                    diffuse: color,
                    specular: Vec3::from_array(material.eta),
                    eta: material.ior,
                    internal: material.k[0],
                    specular_weight: material.k[1],
                    nonlinear: material.has(material_flag::NONLINEAR),
                    rough,
                })
            }
            // Air on both sides of the sheet: the same index seen from either.
            material_kind::THIN_DIELECTRIC => Self::ThinDielectric(ThinDielectric {
                eta: material.ior,
                tint: color,
            }),
            material_kind::DIFFUSE_TRANSMISSION => Self::DiffuseTransmission(DiffuseTransmission {
                reflectance: color,
                transmittance: Vec3::from_array(material.eta),
            }),
            _ => Self::Diffuse(Diffuse { albedo: color }),
        }
    }

    /// A coated material (`material`, [`material_kind::COATED_DIFFUSE`] or
    /// [`material_kind::COATED_CONDUCTOR`]) over `base`, both with their textures resolved: pbrt-v4's
    /// layered BSDF. A conductor base's η and k are relative to the coat, as pbrt divides them.
    pub fn coated(material: &Material, base: &Material) -> Self {
        let eta = material.ior;
        let alpha = Vec2::new(material.alpha_u, material.alpha_v);
        let masking = if material.has(material_flag::SEPARABLE_MASKING) {
            Masking::Separable
        } else {
            Masking::Correlated
        };
        let coat = if alpha.max_element() > MIRROR_ALPHA && eta != 1.0 {
            Coat::Rough(RoughDielectric {
                eta,
                tint: Vec3::ONE,
                alpha,
                masking,
            })
        } else {
            Coat::Smooth { eta }
        };
        let base = match Self::new(base, &[], true) {
            Self::Conductor(c) => Base::Conductor(c.relative_to(eta)),
            Self::Diffuse(d) => Base::Diffuse(d),
            // The loader lets no other base through; drawn as black diffuse if one came.
            _ => Base::Diffuse(Diffuse { albedo: Vec3::ZERO }),
        };
        Self::Layered(Layered {
            thickness: material.eta[0],
            albedo: Vec3::from_array(material.color),
            g: material.eta[1],
            max_depth: material.eta[2] as u32,
            samples: material.k[0] as u32,
            ..Layered::new(coat, base)
        })
    }

    /// Whether every lobe is a Dirac delta (no next-event estimation, no MIS).
    pub fn is_delta(&self) -> bool {
        match self {
            Self::Diffuse(_) => false,
            Self::Conductor(c) => c.is_mirror(),
            Self::Dielectric(_) | Self::ThinDielectric(_) => true,
            Self::RoughDielectric(_)
            | Self::Plastic(_)
            | Self::DiffuseTransmission(_)
            | Self::Layered(_) => false,
        }
    }

    /// `f(wo, wi) · |cos θi|` (0 for delta lobes).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self {
            Self::Diffuse(b) => b.eval(wo, wi),
            Self::Conductor(b) => b.eval(wo, wi),
            Self::Dielectric(_) | Self::ThinDielectric(_) => Vec3::ZERO,
            Self::RoughDielectric(b) => b.eval(wo, wi),
            Self::Plastic(b) => b.eval(wo, wi),
            Self::DiffuseTransmission(b) => b.eval(wo, wi),
            Self::Layered(b) => b.eval(wo, wi),
        }
    }

    /// Solid-angle density with which [`Bsdf::sample`] picks `wi` under `strategy`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, strategy: Strategy) -> f32 {
        match self {
            Self::Diffuse(b) => b.pdf(wo, wi, Lobe::of(strategy)),
            Self::Conductor(b) => b.pdf(wo, wi, Lobe::of(strategy)),
            Self::Dielectric(_) | Self::ThinDielectric(_) => 0.0,
            Self::RoughDielectric(b) => b.pdf(wo, wi, Lobe::of(strategy)),
            Self::Plastic(b) => b.pdf(wo, wi, Lobe::of(strategy)),
            Self::DiffuseTransmission(b) => b.pdf(wo, wi, Lobe::of(strategy)),
            Self::Layered(b) => b.pdf(wo, wi, Lobe::of(strategy)),
        }
    }

    /// Sample `wi` with the direction dimensions `u` and the lobe dimension `u_lobe`.
    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, strategy: Strategy) -> Option<BsdfSample> {
        match self {
            Self::Diffuse(b) => b.sample(wo, u, Lobe::of(strategy)),
            Self::Conductor(b) => b.sample(wo, u, Lobe::of(strategy)),
            Self::Dielectric(b) => b.sample(wo, u_lobe),
            Self::RoughDielectric(b) => b.sample(wo, u, u_lobe, Lobe::of(strategy)),
            Self::Plastic(b) => b.sample(wo, u, u_lobe, Lobe::of(strategy)),
            Self::ThinDielectric(b) => b.sample(wo, u_lobe),
            Self::DiffuseTransmission(b) => b.sample(wo, u, u_lobe, Lobe::of(strategy)),
            Self::Layered(b) => b.sample(wo, u, u_lobe, Lobe::of(strategy)),
        }
    }
}

/// How a non-delta lobe picks directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    /// Uniform over the hemisphere (strategy `uniform`).
    Uniform,
    /// Cosine-weighted hemisphere (strategy `cosine`).
    Cosine,
    /// The BSDF's own importance sampling (diffuse: cosine; GGX: visible normals).
    Bsdf,
}

impl Lobe {
    pub fn of(strategy: Strategy) -> Self {
        match strategy {
            Strategy::Uniform => Self::Uniform,
            Strategy::Cosine => Self::Cosine,
            Strategy::Bsdf | Strategy::Light | Strategy::Mis => Self::Bsdf,
        }
    }
}

/// Hemisphere direction for the uniform / cosine lobes, with its pdf.
pub(crate) fn sample_hemisphere(u: Vec2, uniform: bool) -> (Vec3, f32) {
    if uniform {
        (warp::uniform_hemisphere(u), warp::uniform_hemisphere_pdf())
    } else {
        let wi = warp::cosine_hemisphere(u);
        (wi, warp::cosine_hemisphere_pdf(wi.z))
    }
}

/// Density of [`sample_hemisphere`] (0 below the horizon).
pub(crate) fn hemisphere_pdf(wi: Vec3, uniform: bool) -> f32 {
    if wi.z <= 0.0 {
        0.0
    } else if uniform {
        warp::uniform_hemisphere_pdf()
    } else {
        warp::cosine_hemisphere_pdf(wi.z)
    }
}

// ---------------------------------------------------------------------------------------------
// Shading point: the BSDF placed on a hit, in world space.
// ---------------------------------------------------------------------------------------------

/// A BSDF at a surface point, with its shading frame and the leak guard.
#[derive(Clone, Copy, Debug)]
pub struct ShadingPoint<'a> {
    pub p: Vec3,
    /// Bound on the rounding error of `p`'s coordinates ([`Hit::err`]).
    pub err: Vec3,
    /// Unit geometric normal flipped to the side of `wo`.
    pub ng: Vec3,
    /// Shading frame; `n` is the shading normal flipped to the side of `wo`.
    pub frame: Frame,
    pub bsdf: Bsdf<'a>,
}

impl<'a> ShadingPoint<'a> {
    /// Place `material` (with the scene's material `tables`, its textures looked up at the
    /// hit's `(u, v)`) at `hit`, seen from direction `wo` (pointing away from the surface).
    pub fn new(hit: &Hit, material: &Material, tables: &'a [f32], wo: Vec3) -> Self {
        Self::with_base(hit, material, None, tables, wo)
    }

    /// [`ShadingPoint::new`] for a material that may be coated: `base` is the record of a
    /// coated material's base (its `k[1]`), `None` for any other material.
    pub fn with_base(
        hit: &Hit,
        material: &Material,
        base: Option<&Material>,
        tables: &'a [f32],
        wo: Vec3,
    ) -> Self {
        let uv = hit.uv.to_array();
        let resolve = |m: &Material| match m.tag & material_flag::TEXTURES {
            0 => *m,
            _ => stratapt_scene::texture::resolve(m, tables, uv),
        };
        let material = &resolve(material);
        let entering = hit.ng.dot(wo) > 0.0;
        let ng = if entering { hit.ng } else { -hit.ng };
        let ns = if hit.ns.dot(wo) < 0.0 {
            -hit.ns
        } else {
            hit.ns
        };
        Self {
            p: hit.p,
            err: hit.err,
            ng,
            frame: Frame::from_normal(ns),
            bsdf: match base {
                Some(base) => Bsdf::coated(material, &resolve(base)),
                None => Bsdf::new(material, tables, entering),
            },
        }
    }

    /// `f · |cos θi|` for world directions; zero when the shading frame and the geometric
    /// surface disagree on the side of `wi` (a shading normal must not let light leak through,
    /// nor turn a reflection into a transmission).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let local = self.frame.to_local(wi);
        let above = self.ng.dot(wi);
        if above == 0.0 || (above > 0.0) != (local.z > 0.0) {
            return Vec3::ZERO;
        }
        self.bsdf.eval(self.frame.to_local(wo), local)
    }

    /// Solid-angle pdf of [`ShadingPoint::sample`] for world directions.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, strategy: Strategy) -> f32 {
        self.bsdf
            .pdf(self.frame.to_local(wo), self.frame.to_local(wi), strategy)
    }

    /// Sample a world direction; `None` when the lobe's side (reflection / transmission) and the
    /// geometric side of `wi` disagree.
    pub fn sample(&self, wo: Vec3, u: Vec2, u_lobe: f32, strategy: Strategy) -> Option<BsdfSample> {
        let s = self
            .bsdf
            .sample(self.frame.to_local(wo), u, u_lobe, strategy)?;
        let wi = self.frame.to_world(s.wi);
        let reflected = s.wi.z > 0.0;
        let above = self.ng.dot(wi) > 0.0;
        (reflected == above).then_some(BsdfSample { wi, ..s })
    }
}

#[cfg(test)]
pub(crate) mod test_util {
    //! Shared checks for the BSDF variants.

    use super::*;
    use stratapt_sampling::testing::TestRng;

    /// A direction in the upper hemisphere, avoiding exact grazing.
    pub fn random_upper(rng: &mut TestRng) -> Vec3 {
        let v = warp::uniform_hemisphere(rng.u2());
        Vec3::new(v.x, v.y, v.z.max(1e-3)).normalize()
    }

    /// Mean and standard error of the sampling weight over `n` samples (lobe dim random).
    pub fn weight_mean(
        bsdf: &Bsdf,
        wo: Vec3,
        strategy: Strategy,
        n: usize,
        seed: u64,
    ) -> (Vec3, Vec3) {
        let mut rng = TestRng(seed);
        let (mut sum, mut sum_sq) = (Vec3::ZERO.as_dvec3(), Vec3::ZERO.as_dvec3());
        for _ in 0..n {
            let u = rng.u2();
            if let Some(bs) = bsdf.sample(wo, u, rng.f32(), strategy) {
                assert!(
                    bs.weight.is_finite() && bs.weight.min_element() >= 0.0,
                    "{bs:?}"
                );
                let w = bs.weight.as_dvec3();
                sum += w;
                sum_sq += w * w;
            }
        }
        let mean = sum / n as f64;
        let var = (sum_sq / n as f64 - mean * mean).max(glam::DVec3::ZERO);
        (mean.as_vec3(), (var / n as f64).sqrt().as_vec3())
    }

    /// `weight == eval / pdf` and `pdf(wo, wi) == sampled pdf` for non-delta samples.
    pub fn check_sample_consistency(bsdf: &Bsdf, strategy: Strategy, seed: u64) {
        let mut rng = TestRng(seed);
        let mut checked = 0;
        for _ in 0..2000 {
            let wo = random_upper(&mut rng);
            let u = rng.u2();
            let Some(bs) = bsdf.sample(wo, u, rng.f32(), strategy) else {
                continue;
            };
            if bs.delta {
                continue;
            }
            let pdf = bsdf.pdf(wo, bs.wi, strategy);
            let f = bsdf.eval(wo, bs.wi);
            assert!(
                rel_close(pdf, bs.pdf, 1e-3),
                "pdf {pdf} vs sampled {}: {bs:?}",
                bs.pdf
            );
            let expected = f / pdf;
            for c in 0..3 {
                assert!(
                    rel_close(expected[c], bs.weight[c], 2e-3),
                    "eval/pdf {expected} vs weight {}",
                    bs.weight
                );
            }
            checked += 1;
        }
        assert!(checked > 1000, "only {checked} samples were valid");
    }

    /// f(wo, wi) / cos θi == f(wi, wo) / cos θo.
    pub fn check_reciprocity(bsdf: &Bsdf, seed: u64) {
        let mut rng = TestRng(seed);
        for _ in 0..1000 {
            let (wo, wi) = (random_upper(&mut rng), random_upper(&mut rng));
            let a = bsdf.eval(wo, wi) / wi.z;
            let b = bsdf.eval(wi, wo) / wo.z;
            for c in 0..3 {
                assert!(
                    rel_close(a[c], b[c], 1e-3),
                    "f(wo,wi) {a} vs f(wi,wo) {b}, wo {wo} wi {wi}"
                );
            }
        }
    }

    pub fn rel_close(a: f32, b: f32, tol: f32) -> bool {
        (a - b).abs() <= tol * a.abs().max(b.abs()) + 1e-6
    }
}

#[cfg(test)]
mod guards {
    //! Every BSDF at its numerical edges: grazing and below-horizon `wo` (down to 10⁻³⁰), the
    //! random numbers 0 and 1 − 2⁻²⁴, GGX alphas around the mirror threshold and far beyond 1,
    //! index-matched and inverted dielectrics, smooth and rough. A sample is refused or finite
    //! with a positive pdf; eval and pdf are finite and non-negative: no zero pdf is ever divided
    //! by.
    use super::*;
    use stratapt_sampling::testing::TestRng;
    use stratapt_scene::coating::{fresnel_diffuse_reflectance, RoughCoating};
    use stratapt_scene::records::MIRROR_ALPHA;

    #[test]
    fn bsdfs_at_their_edges_give_no_sample_or_a_finite_one() {
        let below_one = f32::from_bits(1.0f32.to_bits() - 1);
        let plain = |tag, color: f32| Material {
            color: [color; 3],
            tag,
            ..Material::default()
        };
        let mut materials = vec![
            plain(material_kind::DIFFUSE, 1.0),
            plain(material_kind::DIFFUSE, 0.0),
        ];
        // Diffuse transmission: all reflected, all transmitted, half each, nothing.
        for (r, t) in [(1.0, 0.0), (0.0, 1.0), (0.5, 0.5), (0.0, 0.0)] {
            materials.push(Material {
                eta: [t; 3],
                ..plain(material_kind::DIFFUSE_TRANSMISSION, r)
            });
        }
        let alphas = [
            0.0,
            1e-4,
            MIRROR_ALPHA,
            MIRROR_ALPHA * 1.0001,
            0.05,
            1.0,
            1e3,
        ];
        for alpha_u in alphas {
            for alpha_v in [alpha_u, 0.0, 0.3] {
                materials.push(Material {
                    alpha_u,
                    alpha_v,
                    ..plain(material_kind::CONDUCTOR, 1.0)
                });
                for (eta, k) in [(0.2, 3.0), (1.0, 0.0), (1.5, 0.0), (1e-3, 1e3)] {
                    materials.push(Material {
                        alpha_u,
                        alpha_v,
                        eta: [eta; 3],
                        k: [k; 3],
                        ..plain(material_kind::COMPLEX_CONDUCTOR, 1.0)
                    });
                }
            }
        }
        for ior in [1.5, 1.0 / 1.5, 1.0, 1.0001, 1e3] {
            materials.push(Material {
                ior,
                ..plain(material_kind::DIELECTRIC, 1.0)
            });
            materials.push(Material {
                ior,
                ..plain(material_kind::THIN_DIELECTRIC, 0.5)
            });
            for alpha_u in alphas {
                for alpha_v in [alpha_u, 0.3] {
                    materials.push(Material {
                        ior,
                        alpha_u,
                        alpha_v,
                        ..plain(material_kind::ROUGH_DIELECTRIC, 1.0)
                    });
                }
            }
        }
        // Plastics, smooth and rough, from nearly index-matched to extreme coatings, with
        // sampling weights from all-coating to all-base.
        let mut tables = Vec::new();
        for ior in [1.0001f32, 1.49, 3.0, 0.7] {
            for (diffuse, weight) in [(0.0, 1.0), (0.5, 0.67), (1.0, 0.0)] {
                for (alpha, nonlinear) in [(0.0, false), (1e-4, true), (0.05, false), (1.0, true)] {
                    let rough = alpha > MIRROR_ALPHA;
                    let (kind, internal, table) = if rough {
                        let coating = RoughCoating::new(ior, alpha, Masking::Separable);
                        tables.extend_from_slice(&coating.transmittance);
                        let start = (tables.len() - TRANSMITTANCE_RES) as f32;
                        (
                            material_kind::ROUGH_PLASTIC,
                            coating.internal_reflectance,
                            start,
                        )
                    } else {
                        let fdr = fresnel_diffuse_reflectance(1.0 / ior);
                        (material_kind::PLASTIC, fdr, 0.0)
                    };
                    let flags = if nonlinear {
                        material_flag::NONLINEAR
                    } else {
                        0
                    };
                    materials.push(Material {
                        ior,
                        eta: [1.0; 3],
                        alpha_u: alpha,
                        alpha_v: alpha,
                        k: [internal, weight, table],
                        ..plain(kind | flags | material_flag::SEPARABLE_MASKING, diffuse)
                    });
                }
            }
        }
        let mut rng = TestRng(3);
        let (mut samples, mut refused) = (0, 0);
        for material in materials {
            for entering in [true, false] {
                let bsdf = Bsdf::new(&material, &tables, entering);
                for cos in [1.0, 0.5, 1e-3, 1e-7, 1e-30, 0.0, -1e-7, -0.5] {
                    let sin = (1.0f32 - cos * cos).max(0.0).sqrt();
                    let wo = Vec3::new(sin, 0.0, cos);
                    let us = [0.0, 0.5, below_one];
                    for strategy in Strategy::ALL {
                        for ux in us {
                            for uy in us {
                                for u_lobe in [0.0, rng.f32(), below_one] {
                                    samples += 1;
                                    let Some(bs) =
                                        bsdf.sample(wo, Vec2::new(ux, uy), u_lobe, strategy)
                                    else {
                                        refused += 1;
                                        continue;
                                    };
                                    assert!(
                                        bs.pdf > 0.0
                                            && !bs.pdf.is_nan()
                                            && (bs.delta || bs.pdf.is_finite())
                                            && bs.weight.is_finite()
                                            && bs.weight.min_element() >= 0.0
                                            && bs.wi.is_finite()
                                            && (bs.wi.length() - 1.0).abs() < 1e-3,
                                        "{material:?} wo {wo} u {ux},{uy},{u_lobe}: {bs:?}"
                                    );
                                    let (f, pdf) =
                                        (bsdf.eval(wo, bs.wi), bsdf.pdf(wo, bs.wi, strategy));
                                    assert!(
                                        f.is_finite()
                                            && f.min_element() >= 0.0
                                            && pdf.is_finite()
                                            && pdf >= 0.0,
                                        "{material:?} wo {wo}: eval {f} pdf {pdf}"
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
        println!("{refused} of {samples} edge samples refused");
        assert!(refused > 0 && refused < samples, "{refused} of {samples}");
    }
}
