//! Warps, the orthonormal frame and GGX (`warp.wgsl`, `frame.wgsl`), the spherical triangle and
//! rectangle maps, and `frame_atan2` against `stratapt_sampling::{warp, Frame}`.

use super::*;

const WARP_PROBE: &str = r#"
fn probe(i: u32) {
    let k = i * 16u;
    let o = i * 56u;
    let u = probe_v2(k);
    let cos_max = probe_f(k + 2u);
    let alpha = vec2f(probe_f(k + 3u), probe_f(k + 14u));
    let wo = probe_v3(k + 4u);
    let wi = probe_v3(k + 7u);
    let n = probe_v3(k + 10u);
    probe_put3(o, warp_uniform_hemisphere(u));
    probe_put(o + 3u, warp_uniform_hemisphere_pdf());
    probe_put3(o + 4u, warp_cosine_hemisphere(u));
    probe_put(o + 7u, warp_cosine_hemisphere_pdf(wi.z));
    probe_put3(o + 8u, warp_uniform_sphere(u));
    probe_put(o + 11u, warp_uniform_sphere_pdf());
    probe_put2(o + 12u, warp_concentric_disk(u));
    probe_put(o + 14u, warp_concentric_disk_pdf());
    probe_put3(o + 15u, warp_uniform_cone(u, cos_max));
    probe_put(o + 18u, warp_uniform_cone_pdf(cos_max));
    probe_put3(o + 19u, warp_uniform_triangle(u));
    probe_put3(o + 22u, warp_line_segment(wo, wi, probe_f(k + 13u)));
    let f = frame_from_normal(n);
    probe_put3(o + 25u, f.s);
    probe_put3(o + 28u, f.t);
    probe_put3(o + 31u, f.n);
    probe_put3(o + 34u, frame_to_local(f, wi));
    probe_put3(o + 37u, frame_to_world(f, wi));
    probe_put(o + 40u, warp_ggx_d(wi, alpha));
    probe_put(o + 41u, warp_ggx_lambda(wi, alpha));
    probe_put(o + 42u, warp_ggx_g1(wo, alpha));
    probe_put(o + 43u, warp_ggx_g2(wo, wi, alpha, false));
    probe_put(o + 54u, warp_ggx_g2(wo, wi, alpha, true));
    let h = warp_ggx_sample_vndf(wo, alpha, u);
    probe_put3(o + 44u, h);
    probe_put(o + 47u, warp_ggx_vndf_pdf(wo, wi, alpha));
    probe_put3(o + 48u, warp_ggx_reflect(wo, wi));
    probe_put(o + 51u, warp_ggx_reflection_pdf(wo, wi, alpha));
    probe_put(o + 52u, warp_ggx_vndf_pdf(wo, h, alpha));
    probe_put(o + 53u, warp_ggx_reflection_pdf(wo, warp_ggx_reflect(wo, h), alpha));
}
"#;

#[test]
fn warps_match_cpu() {
    use warp::ggx;
    let mut rng = Rng(1);
    let count = 2000;
    let mut input = Vec::new();
    for i in 0..count {
        let mut u = rng.u2();
        // Edges: the disk's centre and axes, the unit square's corners.
        match i % 50 {
            0 => u = Vec2::splat(0.5),
            1 => u = Vec2::new(0.5, rng.f32()),
            2 => u = Vec2::new(rng.f32(), 0.5),
            3 => u = Vec2::ZERO,
            4 => u = Vec2::splat(rng.f32()),
            _ => {}
        }
        let cos_max = match i % 7 {
            0 => 1.0,
            1 => -1.0,
            2 => 1.0 - rng.log_range(1e-7, 1e-2),
            _ => rng.range(-1.0, 1.0),
        };
        // Isotropic in half the cases, independent (αx, αy) in the others.
        let alpha_x = rng.log_range(2e-3, 1.0);
        let alpha_y = if i % 2 == 0 {
            alpha_x
        } else {
            rng.log_range(2e-3, 1.0)
        };
        let wo = if i % 20 == 0 {
            rng.sphere()
        } else {
            rng.upper()
        };
        let wi = match i % 30 {
            0 => Vec3::X,
            1 => Vec3::Z,
            _ => rng.sphere(),
        };
        let n = match i % 40 {
            0 => -Vec3::Z,
            1 => Vec3::Z,
            _ => rng.sphere(),
        };
        input.extend_from_slice(&[u.x, u.y, cos_max, alpha_x]);
        push3(&mut input, wo);
        push3(&mut input, wi);
        push3(&mut input, n);
        input.extend_from_slice(&[rng.f32(), alpha_y, 0.0]);
    }
    let scene = load_scene("cornell-box.toml");
    let out = run(
        &scene,
        &RenderSettings::default(),
        &["warp"],
        WARP_PROBE,
        &input,
        56,
        count,
    );
    let mut c = Check::new("warps");
    for i in 0..count {
        let inp = &input[i * 16..];
        let o = &out[i * 56..];
        let u = Vec2::new(inp[0], inp[1]);
        let (cos_max, alpha) = (inp[2], Vec2::new(inp[3], inp[14]));
        let (wo, wi, n) = (v3(inp, 4), v3(inp, 7), v3(inp, 10));
        c.v3(
            "uniform_hemisphere",
            i,
            v3(o, 0),
            warp::uniform_hemisphere(u),
        );
        c.f(
            "uniform_hemisphere_pdf",
            i,
            o[3],
            warp::uniform_hemisphere_pdf(),
        );
        // At the square's corners the disk point has |d| = 1 and z = √(1 − |d|²) turns last-ulp
        // differences of cos/sin into ~1e-4: ill-conditioned, compared on x, y only.
        let cosine = warp::cosine_hemisphere(u);
        if u.x == 0.0 || u.y == 0.0 {
            c.v2(
                "cosine_hemisphere(corner).xy",
                i,
                v3(o, 4).truncate(),
                cosine.truncate(),
            );
        } else {
            c.v3("cosine_hemisphere", i, v3(o, 4), cosine);
        }
        c.f(
            "cosine_hemisphere_pdf",
            i,
            o[7],
            warp::cosine_hemisphere_pdf(wi.z),
        );
        c.v3("uniform_sphere", i, v3(o, 8), warp::uniform_sphere(u));
        c.f("uniform_sphere_pdf", i, o[11], warp::uniform_sphere_pdf());
        let disk = Vec2::new(o[12], o[13]);
        c.v2("concentric_disk", i, disk, warp::concentric_disk(u));
        c.f("concentric_disk_pdf", i, o[14], warp::concentric_disk_pdf());
        c.v3("uniform_cone", i, v3(o, 15), warp::uniform_cone(u, cos_max));
        c.f(
            "uniform_cone_pdf",
            i,
            o[18],
            warp::uniform_cone_pdf(cos_max),
        );
        c.v3("uniform_triangle", i, v3(o, 19), warp::uniform_triangle(u));
        let seg = warp::line::segment(wo, wi, inp[13]);
        c.v3("line::segment", i, v3(o, 22), seg);
        let f = Frame::from_normal(n);
        c.v3("frame.s", i, v3(o, 25), f.s);
        c.v3("frame.t", i, v3(o, 28), f.t);
        c.v3("frame.n", i, v3(o, 31), f.n);
        c.v3("frame.to_local", i, v3(o, 34), f.to_local(wi));
        c.v3("frame.to_world", i, v3(o, 37), f.to_world(wi));
        c.f("ggx::d", i, o[40], ggx::d(wi, alpha));
        c.f("ggx::lambda", i, o[41], ggx::lambda(wi, alpha));
        c.f("ggx::g1", i, o[42], ggx::g1(wo, alpha));
        c.f(
            "ggx::g2",
            i,
            o[43],
            ggx::g2(wo, wi, alpha, ggx::Masking::Correlated),
        );
        c.f(
            "ggx::g2 separable",
            i,
            o[54],
            ggx::g2(wo, wi, alpha, ggx::Masking::Separable),
        );
        let h = ggx::sample_vndf(wo, alpha, u);
        // Defined for wo above the horizon only (its callers refuse the others); below it the
        // stretched view direction is ill-conditioned at small α.
        if wo.z > 0.0 {
            c.v3("ggx::sample_vndf", i, v3(o, 44), h);
        }
        c.f("ggx::vndf_pdf", i, o[47], ggx::vndf_pdf(wo, wi, alpha));
        c.v3("ggx::reflect", i, v3(o, 48), ggx::reflect(wo, wi));
        c.f(
            "ggx::reflection_pdf",
            i,
            o[51],
            ggx::reflection_pdf(wo, wi, alpha),
        );
        c.f(
            "ggx::vndf_pdf(sampled)",
            i,
            o[52],
            ggx::vndf_pdf(wo, h, alpha),
        );
        // At the GPU's sampled normal. h = normalize(wo + reflect(wo, h)) recovers h.xy ~ α with
        // an absolute error of a few ulp of 1, and D ∝ 1/q² amplifies it by ~1/α: widen.
        let r = ggx::reflection_pdf(wo, ggx::reflect(wo, v3(o, 44)), alpha);
        let widen = (0.03 / alpha.min_element()).max(1.0);
        c.f_rel("ggx::reflection_pdf(sampled)", i, o[53], r, widen);
    }
    c.finish();
}

const SPHERICAL_PROBE: &str = r#"
fn probe(i: u32) {
    let k = i * 24u;
    let o = i * 12u;
    let p = probe_v3(k);
    let a = probe_v3(k + 3u);
    let b = probe_v3(k + 6u);
    let c = probe_v3(k + 9u);
    let u = probe_v2(k + 12u);
    probe_put(o, warp_spherical_triangle_solid_angle(p, a, b, c));
    let t = warp_spherical_triangle_sample(p, a, b, c, u);
    probe_put_bool(o + 1u, t.valid);
    probe_put3(o + 2u, t.dir);
    probe_put(o + 5u, t.pdf);
    let corner = probe_v3(k + 14u);
    let ex = probe_v3(k + 17u);
    let ey = probe_v3(k + 20u);
    probe_put(o + 6u, warp_spherical_rectangle_solid_angle(p, corner, ex, ey));
    let r = warp_spherical_rectangle_sample(p, corner, ex, ey, u);
    probe_put_bool(o + 7u, r.valid);
    probe_put3(o + 8u, r.point);
    probe_put(o + 11u, r.pdf);
}
"#;

#[test]
fn spherical_warps_match_cpu() {
    use warp::{spherical_rectangle as rect, spherical_triangle as tri};
    let mut rng = Rng(2);
    let count = 2000;
    let mut input = Vec::new();
    for i in 0..count {
        // Shapes from tiny (far) to huge (near), and p on a vertex or in the plane.
        let scale = rng.log_range(1e-3, 10.0);
        let centre = rng.point(2.0);
        let (a, b, c) = (
            centre + scale * rng.sphere(),
            centre + scale * rng.sphere(),
            centre + scale * rng.sphere(),
        );
        let mut p = rng.point(2.0);
        match i % 25 {
            0 => p = a,
            1 => p = a + rng.f32() * (b - a) + rng.f32() * (c - a),
            _ => {}
        }
        let f = Frame::from_normal(rng.sphere());
        let (ex, ey) = (
            f.s * rng.log_range(1e-3, 5.0),
            f.t * rng.log_range(1e-3, 5.0),
        );
        let corner = if i % 25 == 2 {
            p - 0.3 * ex - 0.6 * ey
        } else {
            rng.point(2.0)
        };
        for v in [p, a, b, c] {
            push3(&mut input, v);
        }
        input.extend_from_slice(&[rng.f32(), rng.f32()]);
        for v in [corner, ex, ey] {
            push3(&mut input, v);
        }
        input.push(0.0);
    }
    let scene = load_scene("cornell-box.toml");
    let settings = RenderSettings::default();
    let out = run(
        &scene,
        &settings,
        &["warp"],
        SPHERICAL_PROBE,
        &input,
        12,
        count,
    );
    let mut c = Check::new("spherical warps");
    // Lights use the spherical maps only for Ω in (3e-4, 6.22) (`light::use_spherical`): outside,
    // tiny Ω (a difference of atan2s) and Ω near 2π are ill-conditioned, and only flags and Ω
    // are compared. Ω is compared absolutely near 0 (1e-6), and the pdf through Ω = 1/pdf.
    let in_range = |omega: f32| omega > 3e-4 && omega < 6.22;
    let mut compared = [0; 2];
    for i in 0..count {
        let inp = &input[i * 24..];
        let o = &out[i * 12..];
        let (p, a, b, cc) = (v3(inp, 0), v3(inp, 3), v3(inp, 6), v3(inp, 9));
        let u = Vec2::new(inp[12], inp[13]);
        let (corner, ex, ey) = (v3(inp, 14), v3(inp, 17), v3(inp, 20));
        c.f(
            "spherical_triangle::solid_angle",
            i,
            o[0],
            tri::solid_angle(p, a, b, cc),
        );
        let t = tri::sample(p, a, b, cc, u);
        if c.flag("spherical_triangle::sample valid", i, o[1], t.is_some()) {
            let (dir, pdf) = t.unwrap();
            c.f("spherical_triangle::sample 1/pdf", i, 1.0 / o[5], 1.0 / pdf);
            if in_range(1.0 / pdf) {
                c.v3("spherical_triangle::sample dir", i, v3(o, 2), dir);
                compared[0] += 1;
            }
        }
        let sa = rect::solid_angle(p, corner, ex, ey);
        c.f("spherical_rectangle::solid_angle", i, o[6], sa);
        let r = rect::sample(p, corner, ex, ey, u);
        if c.flag("spherical_rectangle::sample valid", i, o[7], r.is_some()) {
            let (x, pdf) = r.unwrap();
            c.f(
                "spherical_rectangle::sample 1/pdf",
                i,
                1.0 / o[11],
                1.0 / pdf,
            );
            if in_range(1.0 / pdf) {
                // The point relative to the rectangle's size and distance.
                let scale = ex.length().max(ey.length()).max((x - p).length());
                c.v3(
                    "spherical_rectangle::sample point",
                    i,
                    v3(o, 8) / scale,
                    x / scale,
                );
                compared[1] += 1;
            }
        }
    }
    eprintln!(
        "samples compared in the lights' range: triangle {}, rectangle {} of {count}",
        compared[0], compared[1]
    );
    c.finish();
}

// ---- frame_atan2 --------------------------------------------------------------------------------

const ATAN2_PROBE: &str = r#"
fn probe(i: u32) {
    let y = probe_f(2u * i);
    let x = probe_f(2u * i + 1u);
    probe_put(2u * i, frame_atan2(y, x));
    probe_put(2u * i + 1u, atan2(y, x));
}
"#;

/// The solid angles subtract atan2s, and Vulkan lets the built-in be off by 4096 ulp: the warps
/// use `frame_atan2`, which must stay within a few ulp of Rust's.
#[test]
fn frame_atan2_is_accurate() {
    let mut rng = Rng(9);
    let mut pairs: Vec<(f32, f32)> = (0..4000)
        .map(|i| match i % 3 {
            0 => (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
            1 => (rng.log_range(1e-6, 1.0), 1.0),
            _ => (
                rng.range(-1e3, 1e3),
                rng.log_range(1e-3, 1e3) * rng.range(-1.0, 1.0),
            ),
        })
        .collect();
    for a in [0.0f32, -0.0, 1.0, -1.0] {
        for b in [0.0f32, -0.0, 1.0, -1.0] {
            pairs.push((a, b));
        }
    }
    let input: Vec<f32> = pairs.iter().flat_map(|&(y, x)| [y, x]).collect();
    let scene = load_scene("cornell-box.toml");
    let settings = RenderSettings::default();
    let out = run(
        &scene,
        &settings,
        &["warp"],
        ATAN2_PROBE,
        &input,
        2,
        pairs.len(),
    );
    let mut c = Check::new("frame_atan2");
    let (mut worst, mut builtin) = (0.0f32, 0.0f32);
    for (i, &(y, x)) in pairs.iter().enumerate() {
        let exact = y.atan2(x);
        let ulp = f32::EPSILON * exact.abs().max(f32::MIN_POSITIVE);
        worst = worst.max((out[2 * i] - exact).abs() / ulp);
        builtin = builtin.max((out[2 * i + 1] - exact).abs());
        c.f("frame_atan2", i, out[2 * i], exact);
    }
    eprintln!("atan2 error: frame_atan2 {worst} ulp; the built-in up to {builtin:e} absolute");
    assert!(worst <= 4.0, "frame_atan2 is {worst} ulp off");
    c.finish();
}

const EQUAL_AREA_PROBE: &str = r#"
fn probe(i: u32) {
    let k = i * 8u;
    let o = i * 8u;
    probe_put3(o, warp_equal_area_square_to_sphere(probe_v2(k)));
    probe_put2(o + 3u, warp_equal_area_sphere_to_square(probe_v3(k + 2u)));
}
"#;

/// Clarberg's equal-area map (octahedral environment maps) both ways: the square → sphere
/// direction within tolerance (it calls `sin` and `cos`), the sphere → square point bit for bit
/// (`+ − × ÷ √` only), so both renderers read the same texel for the same direction.
#[test]
fn equal_area_map_matches_cpu() {
    use warp::equal_area;
    let mut rng = Rng(11);
    let count = 4000;
    let mut input = Vec::new();
    for i in 0..count {
        let u = match i % 40 {
            0 => Vec2::splat(0.5),
            1 => Vec2::ZERO,
            2 => Vec2::new(rng.f32(), 0.5),
            3 => Vec2::new(0.75, 0.25),
            _ => rng.u2(),
        };
        // Random directions, the axes, and directions on the square's seams (the equator, the
        // planes x = 0 and y = 0).
        let d = match i % 20 {
            0 => [Vec3::X, -Vec3::Y, Vec3::Z, -Vec3::Z][(i / 20) % 4],
            1 => {
                let s = rng.sphere();
                Vec3::new(s.x, s.y, 0.0).normalize()
            }
            2 => {
                let s = rng.sphere();
                Vec3::new(0.0, s.y, s.z).normalize()
            }
            _ => rng.sphere(),
        };
        input.extend_from_slice(&[u.x, u.y]);
        push3(&mut input, d);
        input.extend_from_slice(&[0.0; 3]);
    }
    let scene = load_scene("cornell-box.toml");
    let out = run(
        &scene,
        &RenderSettings::default(),
        &["warp"],
        EQUAL_AREA_PROBE,
        &input,
        8,
        count,
    );
    let mut c = Check::new("equal-area map");
    let mut exact = 0;
    for i in 0..count {
        let inp = &input[i * 8..];
        let o = &out[i * 8..];
        let u = Vec2::new(inp[0], inp[1]);
        c.v3(
            "equal_area::square_to_sphere",
            i,
            v3(o, 0),
            equal_area::square_to_sphere(u),
        );
        let cpu = equal_area::sphere_to_square(v3(inp, 2));
        let gpu = Vec2::new(o[3], o[4]);
        c.v2("equal_area::sphere_to_square", i, gpu, cpu);
        exact += (cpu.to_array().map(f32::to_bits) == gpu.to_array().map(f32::to_bits)) as usize;
    }
    c.finish();
    eprintln!("sphere → square: {exact} of {count} bit for bit");
    assert_eq!(exact, count, "sphere → square differs in its bits");
}
