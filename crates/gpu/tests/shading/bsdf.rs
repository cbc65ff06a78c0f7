//! BSDFs at a shading point (`bsdf.wgsl`) against `stratapt_cpu::bsdf::ShadingPoint`: eval,
//! and pdf and sample under every strategy.

use super::*;

const BSDF_PROBE: &str = r#"
fn probe(i: u32) {
    let k = i * 32u;
    let o = i * 60u;
    let hit = Hit(1.0, 0u, probe_v3(k), vec3f(0.0), probe_v3(k + 3u), probe_v3(k + 6u), vec2f(0.0));
    let wo = probe_v3(k + 9u);
    let wi = probe_v3(k + 12u);
    let u = probe_v2(k + 15u);
    let u_lobe = probe_f(k + 17u);
    let material = Material(
        probe_v3(k + 18u),
        probe_in[k + 21u],
        vec3f(0.0),
        probe_f(k + 22u),
        probe_v3(k + 25u),
        probe_f(k + 23u),
        probe_v3(k + 28u),
        probe_f(k + 24u),
    );
    let sp = shading_point_new(hit, material, material, wo);
    probe_put_bool(o, bsdf_is_delta(sp));
    probe_put3(o + 1u, shading_point_eval(sp, wo, wi));
    for (var strategy = 0u; strategy < 5u; strategy++) {
        let q = o + 4u + strategy * 11u;
        probe_put(q, shading_point_pdf(sp, wo, wi, strategy));
        let s = shading_point_sample(sp, wo, u, u_lobe, strategy);
        probe_put_bool(q + 1u, s.valid);
        probe_put3(q + 2u, s.wi);
        probe_put3(q + 5u, s.weight);
        probe_put(q + 8u, s.pdf);
        probe_put(q + 9u, s.eta);
        probe_put_bool(q + 10u, s.delta);
    }
}
"#;

#[test]
fn bsdfs_match_cpu() {
    use stratapt_cpu::bsdf::ShadingPoint;
    use stratapt_cpu::intersect::Hit;
    use stratapt_scene::records::{material_flag, material_kind, Material};
    use stratapt_scene::Strategy;
    // The scene's buffers hold the rough plastics' tables the plastic cases use.
    let scene = load_scene("plastics.toml");
    let plastics: Vec<Material> = scene
        .materials
        .iter()
        .filter(|m| {
            matches!(
                m.kind(),
                material_kind::PLASTIC | material_kind::ROUGH_PLASTIC
            )
        })
        .copied()
        .collect();
    assert_eq!(plastics.len(), 4);
    let mut rng = Rng(4);
    let count = 4800;
    let mut input = Vec::new();
    for i in 0..count {
        let p = rng.point(3.0);
        let ng = rng.sphere();
        // Shading normals near the geometric one, sometimes on its other side.
        let ns = match i % 10 {
            0 => ng,
            1 => -ng,
            _ => (ng + 0.4 * rng.sphere()).normalize(),
        };
        let wo = rng.sphere();
        let wi = if i % 3 == 0 {
            // Near the mirror direction, where glossy lobes peak.
            (2.0 * wo.dot(ns) * ns - wo + 0.05 * rng.sphere()).normalize()
        } else {
            rng.sphere()
        };
        // (kind, ior, αu, αv, complex η, k)
        let rough = rng.log_range(2e-3, 1.0);
        let (kind, ior, alpha_u, alpha_v, eta, k) = match i % 12 {
            0 | 1 => (material_kind::DIFFUSE, 0.0, 0.0, 0.0, 0.0, 0.0),
            2 => (material_kind::CONDUCTOR, 0.0, rough, rough, 0.0, 0.0),
            3 => {
                let mirror = rng.range(0.0, 1e-3);
                (material_kind::CONDUCTOR, 0.0, mirror, mirror, 0.0, 0.0)
            }
            4 => {
                let other = rng.log_range(1e-4, 1.0);
                (material_kind::CONDUCTOR, 0.0, rough, other, 0.0, 0.0)
            }
            5 => {
                let other = if i % 16 == 5 {
                    rough
                } else {
                    rng.log_range(1e-4, 1.0)
                };
                let (eta, k) = (rng.log_range(0.05, 3.0), rng.range(0.0, 5.0));
                (material_kind::COMPLEX_CONDUCTOR, 0.0, rough, other, eta, k)
            }
            6 => {
                let ior = rng.range(1.05, 2.4);
                (material_kind::DIELECTRIC, ior, 0.0, 0.0, 0.0, 0.0)
            }
            8 | 9 => (material_kind::PLASTIC, 0.0, 0.0, 0.0, 0.0, 0.0),
            10 => {
                let ior = rng.range(1.05, 2.4);
                (material_kind::THIN_DIELECTRIC, ior, 0.0, 0.0, 0.0, 0.0)
            }
            11 => {
                // The transmittance (in `eta`), the reflectance being the colour.
                let t = rng.f32();
                (material_kind::DIFFUSE_TRANSMISSION, 0.0, 0.0, 0.0, t, 0.0)
            }
            _ => {
                let other = if i % 16 == 7 {
                    rough
                } else {
                    rng.log_range(1e-4, 1.0)
                };
                let ior = rng.range(1.05, 2.4);
                (material_kind::ROUGH_DIELECTRIC, ior, rough, other, 0.0, 0.0)
            }
        };
        // Every third GGX material with separable masking-shadowing.
        let tag = match kind {
            material_kind::DIFFUSE | material_kind::DIELECTRIC => kind,
            _ if i % 3 == 1 => kind | material_flag::SEPARABLE_MASKING,
            _ => kind,
        };
        // A plastic: one of the scene's (its table with it), its flags and roughness varied.
        let plastic = plastics[(i / 10) % plastics.len()];
        let (tag, ior, alpha_u, alpha_v, eta, k) = if kind == material_kind::PLASTIC {
            let flags = [
                0,
                material_flag::NONLINEAR,
                material_flag::SEPARABLE_MASKING,
            ][i % 3];
            let alpha = if plastic.kind() == material_kind::ROUGH_PLASTIC {
                rng.log_range(2e-3, 1.0)
            } else {
                0.0
            };
            (
                plastic.kind() | flags,
                plastic.ior,
                alpha,
                alpha,
                Vec3::from_array(plastic.eta),
                Vec3::from_array(plastic.k),
            )
        } else {
            (tag, ior, alpha_u, alpha_v, Vec3::splat(eta), Vec3::splat(k))
        };
        for v in [p, ng, ns, wo, wi] {
            push3(&mut input, v);
        }
        input.extend_from_slice(&[rng.f32(), rng.f32(), rng.f32()]);
        push3(&mut input, Vec3::new(rng.f32(), rng.f32(), rng.f32()));
        input.extend_from_slice(&[f32::from_bits(tag), ior, alpha_u, alpha_v]);
        // η and k per channel, around the drawn values (a plastic's as they are).
        let (eta, k) = if kind == material_kind::PLASTIC {
            (eta, k)
        } else {
            (
                eta * Vec3::new(1.0, rng.range(0.5, 1.5), rng.range(0.5, 1.5)),
                k * Vec3::new(1.0, rng.range(0.5, 1.5), rng.range(0.5, 1.5)),
            )
        };
        push3(&mut input, eta);
        push3(&mut input, k);
        input.push(0.0);
    }
    let settings = RenderSettings::default();
    let modules = ["frame", "warp", "motion", "intersect", "bsdf"];
    let out = run(&scene, &settings, &modules, BSDF_PROBE, &input, 60, count);
    let mut c = Check::new("bsdfs");
    let mut valid = [0usize; 5];
    for i in 0..count {
        let inp = &input[i * 32..];
        let o = &out[i * 60..];
        let hit = Hit {
            t: 1.0,
            prim: 0,
            p: v3(inp, 0),
            err: Vec3::ZERO,
            ng: v3(inp, 3),
            ns: v3(inp, 6),
            uv: Vec2::ZERO,
        };
        let (wo, wi) = (v3(inp, 9), v3(inp, 12));
        let (u, u_lobe) = (Vec2::new(inp[15], inp[16]), inp[17]);
        let material = Material {
            color: v3(inp, 18).to_array(),
            tag: inp[21].to_bits(),
            emission: [0.0; 3],
            ior: inp[22],
            eta: v3(inp, 25).to_array(),
            alpha_u: inp[23],
            k: v3(inp, 28).to_array(),
            alpha_v: inp[24],
        };
        let sp = ShadingPoint::new(&hit, &material, &scene.tables, wo);
        c.flag("is_delta", i, o[0], sp.bsdf.is_delta());
        c.v3("eval", i, v3(o, 1), sp.eval(wo, wi));
        for (si, strategy) in Strategy::ALL.into_iter().enumerate() {
            let q = &o[4 + si * 11..];
            c.f(
                &format!("pdf {strategy}"),
                i,
                q[0],
                sp.pdf(wo, wi, strategy),
            );
            let s = sp.sample(wo, u, u_lobe, strategy);
            if c.flag(&format!("sample {strategy} valid"), i, q[1], s.is_some()) {
                let s = s.unwrap();
                c.v3(&format!("sample {strategy} wi"), i, v3(q, 2), s.wi);
                // G2 / G1 varies as 1 / cos θi at grazing wi, whose cosine carries an absolute
                // error of ~1e-7 from the reflection; the hemisphere lobes' cos θi = √(1 − r²)
                // carries a relative one of ~1e-7 / cos² θi near the rim, and their pdf ∝ cos θi:
                // widen the weight's and the pdf's tolerance there.
                let cos_i = sp.frame.to_local(s.wi).z.abs();
                let widen = (1e-2 / cos_i).max(1e-3 / (cos_i * cos_i)).max(1.0);
                for k in 0..3 {
                    let what = format!("sample {strategy} weight[{k}] (cos θi {cos_i})");
                    c.f_rel(&what, i, q[5 + k], s.weight[k], widen);
                }
                c.f_rel(&format!("sample {strategy} pdf"), i, q[8], s.pdf, widen);
                c.f(&format!("sample {strategy} eta"), i, q[9], s.eta);
                c.flag(&format!("sample {strategy} delta"), i, q[10], s.delta);
                valid[si] += 1;
            }
        }
    }
    eprintln!("valid samples per strategy: {valid:?} of {count}");
    c.finish();
}
