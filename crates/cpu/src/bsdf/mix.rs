//! pbrt-v4's `MixMaterial`: at each path vertex one of two materials, the second with
//! probability `amount`, chosen by a hash of the path and the mix ([`mix_choice`], which says
//! why not of the point as pbrt does), so that the choice is the same for every estimate made
//! there (next-event estimation, BSDF sampling, MIS) and on the CPU and the GPU alike. In
//! expectation it is the blend `(1 − amount) f₀ + amount f₁`.

use crate::detail::{self, Tangents};
use crate::intersect::Hit;
use stratapt_scene::records::{
    material_flag, material_kind, mix_choice, Material, MAX_RESOLVE_STEPS,
};
use stratapt_scene::texture;

/// Which path vertex a mix chooses at: the pixel's sampler key, the sample and the depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Vertex {
    pub key: u32,
    pub sample: u32,
    pub depth: u32,
}

/// The material drawn at `hit` (its texture coordinates read a textured amount or map) for
/// material `index` at path vertex `at`: itself unless it is a mix or a map, else the material
/// its mixes choose, with `hit.ns` tilted by the bump and normal maps met on the way
/// ([`crate::detail`], the shading geometry's derivatives from `tangents`, asked only there);
/// at most [`MAX_RESOLVE_STEPS`] steps, as the loader guarantees.
pub fn resolve<'m>(
    materials: &'m [Material],
    tables: &[f32],
    index: u32,
    hit: &mut Hit,
    at: Vertex,
    tangents: impl Fn(&Hit) -> Tangents,
) -> &'m Material {
    let mut i = index;
    for _ in 0..MAX_RESOLVE_STEPS {
        let m = &materials[i as usize];
        i = match m.kind() {
            material_kind::MIX => choose(m, i, tables, hit.uv.to_array(), at),
            material_kind::BUMP => {
                hit.ns = detail::bump(m, tables, &tangents(hit), hit.ns, hit.uv);
                m.k[0] as u32
            }
            material_kind::NORMAL_MAP => {
                hit.ns = detail::normal_map(m, tables, &tangents(hit), hit.ns, hit.uv);
                m.k[0] as u32
            }
            _ => break,
        };
    }
    &materials[i as usize]
}

/// Which of mix `m`'s (record `i`'s) two materials vertex `at` draws where the texture
/// coordinates are `uv`.
fn choose(m: &Material, i: u32, tables: &[f32], uv: [f32; 2], at: Vertex) -> u32 {
    let amount = match m.has(material_flag::ALPHA_TEXTURE) {
        true => texture::eval_scalar(tables, m.alpha_u as u32, uv),
        false => m.alpha_u,
    };
    // pbrt-v4: the first where amount ≤ 0, the second where ≥ 1, else the second when
    // u < amount.
    let second = if amount <= 0.0 {
        false
    } else if amount >= 1.0 {
        true
    } else {
        mix_choice(i, at.key, at.sample, at.depth) < amount
    };
    m.k[usize::from(second)] as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    fn no_tangents(_: &Hit) -> Tangents {
        unreachable!("no bump or normal maps here")
    }

    fn hit() -> Hit {
        Hit {
            t: 1.0,
            prim: 0,
            p: Vec3::ZERO,
            err: Vec3::ZERO,
            ng: Vec3::Z,
            ns: Vec3::Z,
            uv: Vec2::ZERO,
        }
    }

    fn diffuse(albedo: f32) -> Material {
        Material {
            color: [albedo; 3],
            ..Material::default()
        }
    }

    fn mix(a: u32, b: u32, amount: f32) -> Material {
        Material {
            tag: material_kind::MIX,
            alpha_u: amount,
            alpha_v: amount,
            k: [a as f32, b as f32, 0.0],
            ..Material::default()
        }
    }

    /// Over many vertices the second material is chosen with probability `amount`, nested mixes
    /// multiply, and the ends choose one material only; a planted 1 % error in the amount is
    /// seen.
    #[test]
    fn chooses_the_second_with_probability_amount() {
        let counts = |nested_amount: f32| {
            let materials = [
                diffuse(0.1),
                diffuse(0.2),
                diffuse(0.3),
                mix(0, 1, 0.3),
                mix(3, 2, nested_amount),
                mix(0, 1, 0.0),
                mix(0, 1, 1.0),
            ];
            let mut counts = [0usize; 3];
            for k in 0..400_000u32 {
                let at = Vertex {
                    key: k / 64,
                    sample: k % 64,
                    depth: k % 5,
                };
                let m = resolve(&materials, &[], 4, &mut hit(), at, no_tangents);
                counts[(m.color[0] * 10.0).round() as usize - 1] += 1;
                assert_eq!(
                    resolve(&materials, &[], 5, &mut hit(), at, no_tangents).color[0],
                    0.1
                );
                assert_eq!(
                    resolve(&materials, &[], 6, &mut hit(), at, no_tangents).color[0],
                    0.2
                );
            }
            counts
        };
        // Material 2 with 0.6, else mix 3: material 1 with 0.4 · 0.3, material 0 with 0.4 · 0.7.
        let within = |counts: [usize; 3]| {
            counts.iter().zip([0.28, 0.12, 0.6]).all(|(&count, p)| {
                let expected = p * 400_000.0;
                (count as f64 - expected).abs() < 4.5 * (expected * (1.0 - p)).sqrt()
            })
        };
        let right = counts(0.6);
        assert!(within(right), "{right:?}");
        let planted = counts(0.6 * 1.01);
        assert!(!within(planted), "a 1 % wrong amount passed: {planted:?}");
    }

    /// One vertex always chooses alike; other depths, samples and pixels choose anew.
    #[test]
    fn the_choice_is_a_function_of_the_vertex() {
        let materials = [diffuse(0.1), diffuse(0.2), mix(0, 1, 0.5)];
        let at = Vertex {
            key: 7,
            sample: 3,
            depth: 1,
        };
        let first = resolve(&materials, &[], 2, &mut hit(), at, no_tangents).color[0];
        for _ in 0..10 {
            assert_eq!(
                resolve(&materials, &[], 2, &mut hit(), at, no_tangents).color[0],
                first
            );
        }
        for vary in [
            |at: Vertex, k| Vertex { depth: k, ..at },
            |at: Vertex, k| Vertex { sample: k, ..at },
            |at: Vertex, k| Vertex { key: k, ..at },
        ] {
            let differs = (0..64).any(|k| {
                resolve(&materials, &[], 2, &mut hit(), vary(at, k), no_tangents).color[0] != first
            });
            assert!(differs);
        }
    }

    /// A map on the way tilts the hit's shading normal and hands on to its material; a mix
    /// that draws its unmapped side leaves the normal alone. A map over a mix over a map is
    /// followed to the end.
    #[test]
    fn maps_on_the_way_tilt_the_normal_and_hand_on_to_their_material() {
        // A constant height over a surface whose normal's derivative leaves the tangent plane
        // (∂n/∂u = z, only for the test): ∂p′/∂u = x + ½ z, and the normal tilts.
        let tangents = |_: &Hit| Tangents {
            dpdu: Vec3::X,
            dpdv: Vec3::Y,
            dndu: Vec3::Z,
            dndv: Vec3::ZERO,
        };
        let bump = |inner: u32| Material {
            tag: material_kind::BUMP,
            color: [0.5, 0.0, 0.0],
            k: [inner as f32, 0.0, 0.0],
            ..Material::default()
        };
        let materials = [
            diffuse(0.1),
            diffuse(0.2),
            bump(0),
            mix(2, 1, 1.0),
            mix(2, 1, 0.0),
            bump(4),
        ];
        let at = Vertex {
            key: 1,
            sample: 2,
            depth: 0,
        };
        let mut h = hit();
        assert_eq!(
            resolve(&materials, &[], 2, &mut h, at, tangents).color[0],
            0.1
        );
        // (1, 0, 0.5) × (0, 1, 0) = (−0.5, 0, 1), normalized.
        let tilted = Vec3::new(-0.5, 0.0, 1.0).normalize();
        assert!((h.ns - tilted).length() < 1e-6, "{}", h.ns);
        // A mix drawing its first (mapped) material, and its second.
        let mut h = hit();
        assert_eq!(
            resolve(&materials, &[], 4, &mut h, at, tangents).color[0],
            0.1
        );
        assert!((h.ns - tilted).length() < 1e-6);
        let mut h = hit();
        assert_eq!(
            resolve(&materials, &[], 3, &mut h, at, tangents).color[0],
            0.2
        );
        assert_eq!(h.ns, Vec3::Z);
        // Map, mix, map: both maps are met (here the second tilts as the first did).
        let mut h = hit();
        assert_eq!(
            resolve(&materials, &[], 5, &mut h, at, tangents).color[0],
            0.1
        );
        assert!((h.ns - tilted).length() < 1e-6);
    }
}
