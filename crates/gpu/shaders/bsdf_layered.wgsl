// pbrt-v4's LayeredBxDF (Pharr, Jakob and Humphreys, *Physically Based Rendering* 4th ed., §14.3,
// after Guo et al. 2018), the BSDF of `coateddiffuse` and `coatedconductor`: a dielectric coat
// over an opaque base (Lambertian or GGX conductor) with a homogeneous slab of `thickness` mean
// free paths between them that scatters with `albedo` by a Henyey–Greenstein phase function.
// Mirrors `crates/cpu/src/bsdf/layered.rs` (and `layered/{walk,interface,slab}.rs`), whose
// module doc states the estimator, its random stream and its departures from pbrt: same
// formulas, same branches, same draws in the same order, so that CPU and GPU give the same bits
// wherever the built-ins (exp, log, sin, cos) do.
//
// Part of the `bsdf` module (composed after bsdf.wgsl, whose Fresnel, dielectric, rough
// dielectric, conductor and diffuse functions it calls; the dispatch there calls it).
//
// Rust's `Option<Scatter>` (an interface's sample) and `Option<(wi, weight, pdf, delta)>` (a
// walk's) are `BsdfSample`s with `valid`; `Top` (the coat seen from one side) is a `Bsdf` of the
// dielectric functions built by `layered_coat`; `Only` is BSDF_LAYERED_{ALL,REFLECTION,
// TRANSMISSION}; the random stream is a u32 behind a pointer.
//
// Interface (bsdf.wgsl calls):
//   struct Layered { eta, alpha, separable, rough, base_*, thickness, albedo, g, max_depth,
//                    samples }
//   fn layered_new(material: Material, base: Material) -> Layered    (`Bsdf::coated`)
//   fn layered_eval(l: Layered, wo: vec3f, wi: vec3f) -> vec3f                    (local frame)
//   fn layered_pdf(l: Layered, wo: vec3f, wi: vec3f, strategy: u32) -> f32
//   fn layered_sample(l: Layered, wo: vec3f, u: vec2f, u_lobe: f32, strategy: u32) -> BsdfSample

// A coat over a base with a scattering slab between them (`layered::Layered`, `Coat`, `Base`).
struct Layered {
    // The coat: relative index η (inside over outside), GGX (αu, αv), its masking; `rough`
    // false for a smooth coat (α at most MIRROR_ALPHA, or η = 1), whose tint is 1 either way.
    eta: f32,
    alpha: vec2f,
    separable: bool,
    rough: bool,
    // The base, the fields of its Bsdf (`layered_base`): MATERIAL_DIFFUSE (albedo base_color),
    // or a conductor whose complex η and k are relative to the coat.
    base_kind: u32,
    base_color: vec3f,
    base_alpha: vec2f,
    base_eta: vec3f,
    base_k: vec3f,
    base_separable: bool,
    // In mean free paths (σt = 1).
    thickness: f32,
    // Single-scattering albedo of the slab; 0 is a clear slab.
    albedo: vec3f,
    // Henyey–Greenstein asymmetry (clamped to [−0.99, 0.99] where used).
    g: f32,
    // Events per walk; walks per estimate (0 counts as 1).
    max_depth: u32,
    samples: u32,
}

// The random stream's domains (`EVAL`, `PDF`, `SAMPLE`).
const BSDF_LAYERED_EVAL: u32 = 1u;
const BSDF_LAYERED_PDF: u32 = 2u;
const BSDF_LAYERED_SAMPLE: u32 = 3u;

// Which lobes an interface may sample (`Only`).
const BSDF_LAYERED_ALL: u32 = 0u;
const BSDF_LAYERED_REFLECTION: u32 = 1u;
const BSDF_LAYERED_TRANSMISSION: u32 = 2u;

// A coated material (its textures resolved) over its base record (resolved too): `Bsdf::coated`.
fn layered_new(material: Material, base_record: Material) -> Layered {
    var l: Layered;
    l.eta = material.ior;
    l.alpha = vec2f(material.alpha_u, material.alpha_v);
    l.separable = (material.tag & MATERIAL_SEPARABLE_MASKING) != 0u;
    l.rough = max(l.alpha.x, l.alpha.y) > MIRROR_ALPHA && l.eta != 1.0;
    // The base as `Bsdf::new` makes it: a conductor (a complex index divided by the coat's,
    // `Conductor::relative_to`), a diffuse, or black diffuse for a kind the loader does not let through.
    let base = bsdf_new(base_record, true);
    l.base_kind = MATERIAL_DIFFUSE;
    l.base_color = vec3f(0.0);
    if (bsdf_is_conductor(base)) {
        l.base_kind = base.kind;
        l.base_color = base.color;
        l.base_alpha = base.alpha;
        l.base_eta = base.eta;
        l.base_k = base.k;
        l.base_separable = base.separable;
        if (bsdf_is_complex_conductor(base)) {
            l.base_eta = base.eta / l.eta;
            l.base_k = base.k / l.eta;
        }
    } else if (!bsdf_layered_black_base(base.kind)) {
        l.base_color = base.color;
    }
    l.thickness = material.eta.x;
    l.albedo = material.color;
    l.g = material.eta.y;
    l.max_depth = u32(material.eta.z);
    l.samples = u32(material.k.x);
    return l;
}

// The kinds `Bsdf::new` makes something other than a conductor or a diffuse of.
fn bsdf_layered_black_base(kind: u32) -> bool {
    return kind == MATERIAL_DIELECTRIC || kind == MATERIAL_ROUGH_DIELECTRIC
        || kind == MATERIAL_PLASTIC || kind == MATERIAL_ROUGH_PLASTIC
        || kind == MATERIAL_THIN_DIELECTRIC || kind == MATERIAL_DIFFUSE_TRANSMISSION;
}

fn layered_thickness(l: Layered) -> f32 {
    return max(l.thickness, F32_MIN_POSITIVE);
}

fn layered_scatters(l: Layered) -> bool {
    return any(l.albedo != vec3f(0.0));
}

fn bsdf_layered_max3(v: vec3f) -> f32 {
    return max(v.x, max(v.y, v.z));
}

// ---- eval: the coat's reflection plus one random walk per sample (pbrt's `f`) -------------------

fn layered_eval(l: Layered, wo_in: vec3f, wi_in: vec3f) -> vec3f {
    // Two-sided: seen from below, the same BSDF.
    let flip = wo_in.z < 0.0;
    let wo = select(wo_in, -wo_in, flip);
    let wi = select(wi_in, -wi_in, flip);
    if (!(wo.z > 0.0 && wi.z > 0.0)) {
        return vec3f(0.0);
    }
    let n = max(l.samples, 1u);
    var rng = bsdf_layered_rng(BSDF_LAYERED_EVAL, wo, wi);
    var f = layered_top_eval(l, wo, wi) * f32(n);
    for (var i = 0u; i < n; i++) {
        f += layered_walk_eval(l, wo, wi, &rng);
    }
    f = f / f32(n);
    if (frame_is_finite3(f)) {
        return max(f, vec3f(0.0));
    }
    return vec3f(0.0);
}

// One walk from wo's refraction into the coat, with next-event estimates through the coat
// towards wi (`walk_eval`).
fn layered_walk_eval(l: Layered, wo: vec3f, wi: vec3f, rng: ptr<function, u32>) -> vec3f {
    let thickness = layered_thickness(l);
    // Into the coat from wo (radiance), and the virtual light from wi (importance); a loop, so
    // that the kernel holds one copy of the coat's sampling for both.
    var into: array<BsdfSample, 2>;
    for (var k = 0u; k < 2u; k++) {
        let uc = bsdf_layered_next(rng);
        let u = bsdf_layered_u2(rng);
        into[k] = layered_top_sample(l, select(wo, wi, k == 1u), uc, u, BSDF_LAYERED_TRANSMISSION);
        if (!into[k].valid) {
            return vec3f(0.0);
        }
    }
    let wos = into[0];
    let light = layered_light_new(l, wi, into[1]);
    if (!light.valid) {
        return vec3f(0.0);
    }
    let scatters = layered_scatters(l);
    let base_specular = layered_base_specular(l);
    var f = vec3f(0.0);
    var beta = wos.weight;
    var z = thickness;
    var w = wos.wi;
    for (var depth = 0u; depth < l.max_depth; depth++) {
        // Russian roulette on a low throughput.
        if (depth > 3u && bsdf_layered_max3(beta) < 0.25) {
            let q = max(1.0 - bsdf_layered_max3(beta), 0.0);
            if (bsdf_layered_next(rng) < q) {
                break;
            }
            beta = beta / (1.0 - q);
        }
        if (!scatters) {
            // Straight across the clear slab.
            z = select(thickness, 0.0, z == thickness);
            beta = beta * bsdf_layered_transmittance(thickness, w);
        } else {
            // Free flight; a medium event inside the slab.
            let dz = -log(1.0 - bsdf_layered_next(rng)) * abs(w.z);
            let zp = select(z - dz, z + dz, w.z > 0.0);
            if (zp == z) {
                continue;
            }
            if (0.0 < zp && zp < thickness) {
                // Next event along wis (and the mirror's chains), then scatter and the next event
                // along the phase function's direction.
                let p = bsdf_layered_hg(dot(-w, -light.wis.wi), l.g);
                let value = l.albedo * p;
                f += beta * layered_light_along_wis(l, light, value, p, zp - thickness);
                if (!l.rough && base_specular) {
                    f += beta * l.albedo * light.exit * layered_mirror_chains(l, light, -w, zp);
                }
                let hs = bsdf_layered_sample_hg(-w, l.g, bsdf_layered_u2(rng));
                if (!(hs.w > 0.0)) {
                    continue;
                }
                beta = beta * l.albedo;
                w = hs.xyz;
                z = zp;
                if (w.z > 0.0) {
                    f += beta * layered_light_along(l, light, w, hs.w, false, zp - thickness);
                }
                continue;
            }
            z = clamp(zp, 0.0, thickness);
        }
        if (z == thickness) {
            // At the coat's inside: reflection only (leaving is the next events' part).
            let uc = bsdf_layered_next(rng);
            let u = bsdf_layered_u2(rng);
            let bs = layered_top_sample(l, -w, uc, u, BSDF_LAYERED_REFLECTION);
            if (!bs.valid) {
                break;
            }
            beta = beta * bs.weight;
            w = bs.wi;
            continue;
        }
        // At the base: next event along wis, then a sampled reflection and its next event.
        if (!base_specular) {
            let value = layered_base_eval(l, -w, -light.wis.wi);
            let pdf = layered_base_pdf(l, -w, -light.wis.wi);
            f += beta * layered_light_along_wis(l, light, value, pdf, thickness);
        }
        // The lobe dimension pbrt draws for the base, which does not use it.
        _ = bsdf_layered_next(rng);
        let u = bsdf_layered_u2(rng);
        let bs = layered_base_sample(l, -w, u);
        if (!bs.valid) {
            break;
        }
        beta = beta * bs.weight;
        w = bs.wi;
        f += beta * layered_light_along(l, light, w, bs.pdf, bs.delta, thickness);
    }
    return f;
}

// Under a smooth coat over a mirror, the specular chains from a medium event at zp (seen from
// `back`) to the exit along wis that pbrt's `f` leaves out (`mirror_chains`).
fn layered_mirror_chains(l: Layered, light: LayeredLight, back: vec3f, zp: f32) -> vec3f {
    let wis = light.wis.wi;
    let thickness = layered_thickness(l);
    let up = -wis;
    let down = vec3f(-wis.x, -wis.y, wis.z);
    // The mirror's sample from −down and the smooth coat's reflection from inside along wis, in
    // closed form (what `layered_base_sample` and `layered_top_sample` give there, bit for bit,
    // without a copy of their general code): F_mirror(θ), and R = F(θ, 1/η) where positive.
    let cos_theta = -wis.z;
    if (!(cos_theta > 0.0)) {
        return vec3f(0.0);
    }
    let mirror = bsdf_conductor_fresnel(layered_base(l), cos_theta);
    if (all(mirror == vec3f(0.0))) {
        return vec3f(0.0);
    }
    let f = bsdf_fresnel(cos_theta, 1.0 / l.eta);
    let r = select(vec3f(0.0), vec3f(f), f > 0.0);
    let tr = bsdf_layered_transmittance(thickness, up);
    let round = r * mirror * (tr * tr);
    let rest = vec3f(1.0) - round;
    let up_part = round / rest
        * (bsdf_layered_hg(dot(back, up), l.g) * bsdf_layered_transmittance(zp - thickness, up));
    let down_part = mirror / rest
        * (bsdf_layered_hg(dot(back, down), l.g) * bsdf_layered_transmittance(zp, up) * tr);
    let chains = up_part + down_part;
    return select(vec3f(0.0), chains, frame_is_finite3(chains));
}

// ---- pdf: pbrt's estimate of the reflection and transmit–base–transmit densities --------------

fn layered_pdf(l: Layered, wo_in: vec3f, wi_in: vec3f, strategy: u32) -> f32 {
    let flip = wo_in.z < 0.0;
    let wo = select(wo_in, -wo_in, flip);
    let wi = select(wi_in, -wi_in, flip);
    if (!(wo.z > 0.0 && wi.z > 0.0)) {
        return 0.0;
    }
    if (!bsdf_own_lobe(strategy)) {
        let split = layered_delta_split(l, wo);
        let uniform = bsdf_uniform_lobe(strategy);
        return (1.0 - split.x) * (1.0 - split.y) * bsdf_hemisphere_pdf(wi, uniform);
    }
    return layered_pdf_estimate(l, wo, wi);
}

fn layered_pdf_estimate(l: Layered, wo: vec3f, wi: vec3f) -> f32 {
    let n = max(l.samples, 1u);
    var rng = bsdf_layered_rng(BSDF_LAYERED_PDF, wi, wo);
    var sum = f32(n) * layered_top_pdf(l, wo, wi, BSDF_LAYERED_REFLECTION);
    let base_specular = layered_base_specular(l);
    for (var i = 0u; i < n; i++) {
        // Into the coat from wo and from wi, both drawn whatever the first gives (one copy of
        // the coat's sampling in the kernel, as in `layered_walk_eval`).
        var into: array<BsdfSample, 2>;
        for (var k = 0u; k < 2u; k++) {
            let uc = bsdf_layered_next(&rng);
            let u = bsdf_layered_u2(&rng);
            into[k] = layered_top_sample(l, select(wo, wi, k == 1u), uc, u, BSDF_LAYERED_TRANSMISSION);
        }
        let wos = into[0];
        let wis = into[1];
        if (!wos.valid || !wis.valid) {
            continue;
        }
        if (!l.rough) {
            sum += layered_base_pdf(l, -wos.wi, -wis.wi);
            continue;
        }
        // Both the base's and the coat's sampling, combined by the power heuristic.
        _ = bsdf_layered_next(&rng);
        let u = bsdf_layered_u2(&rng);
        let rs = layered_base_sample(l, -wos.wi, u);
        if (!rs.valid) {
            continue;
        }
        if (base_specular) {
            sum += layered_top_pdf(l, -rs.wi, wi, BSDF_LAYERED_ALL);
            continue;
        }
        let r_pdf = layered_base_pdf(l, -wos.wi, -wis.wi);
        sum += mis_power_heuristic(wis.pdf, r_pdf) * r_pdf;
        let t_pdf = layered_top_pdf(l, -rs.wi, wi, BSDF_LAYERED_ALL);
        sum += mis_power_heuristic(rs.pdf, t_pdf) * t_pdf;
    }
    // Mixed with the uniform sphere, as pbrt does: 0.1 / (4π) + 0.9 · estimate.
    let uniform = 0.25 * INV_PI;
    let pdf = 0.1 * uniform + 0.9 * (sum / f32(n));
    return select(uniform, pdf, frame_is_finite(pdf));
}

// ---- sample: the coat, then the walk until it leaves (pbrt's `Sample_f`) -----------------------

// `Layered::sample`, its `sample_walk` and `sample_hemisphere` merged so that the coat's
// sample, the walk, the pdf estimate and eval each have one call site (the driver inlines every
// call, and each site is a copy of the walk in the kernel). Same branches, draws and arithmetic.
fn layered_sample(l: Layered, wo_in: vec3f, u: vec2f, u_lobe: f32, strategy: u32) -> BsdfSample {
    let flip = wo_in.z < 0.0;
    let wo = select(wo_in, -wo_in, flip);
    if (!(wo.z > 0.0)) {
        return bsdf_none();
    }
    var rng = bsdf_layered_rng(BSDF_LAYERED_SAMPLE, wo, vec3f(u, u_lobe));
    // The BSDF's own sampling walks from the coat's sample (`sample_walk`); the hemisphere
    // strategies (`sample_hemisphere`) take a smooth coat's mirror, or a specular walk over a
    // mirror base (chosen with probability p, kept only if it stays specular), or a direction on
    // the hemisphere weighted by eval.
    let own = bsdf_own_lobe(strategy);
    var specular_walk = false;
    var p = 1.0;
    var s = bsdf_none();
    if (!own) {
        let split = layered_delta_split(l, wo);
        let p_mirror = split.x;
        let p_walk = split.y;
        let u_walk = (u_lobe - p_mirror) / (1.0 - p_mirror);
        if (u_lobe < p_mirror) {
            s = BsdfSample(true, vec3f(-wo.x, -wo.y, wo.z), vec3f(1.0), p_mirror, 1.0, true);
        } else if (u_walk < p_walk) {
            specular_walk = true;
            p = (1.0 - p_mirror) * p_walk;
        } else {
            let h = bsdf_sample_hemisphere(u, bsdf_uniform_lobe(strategy));
            let pdf = (1.0 - p_mirror) * (1.0 - p_walk) * h.w;
            let weight = layered_eval(l, wo, h.xyz) / pdf;
            s = BsdfSample(true, h.xyz, weight, pdf, 1.0, false);
        }
    }
    if (own || specular_walk) {
        let only = select(BSDF_LAYERED_TRANSMISSION, BSDF_LAYERED_ALL, own);
        let entry = layered_top_sample(l, wo, select(0.0, u_lobe, own), u, only);
        s = layered_sample_path(l, wo, entry, specular_walk, p, &rng);
    }
    if (!(s.valid && s.pdf > 0.0 && frame_is_finite3(s.weight) && s.wi.z > 0.0)) {
        return bsdf_none();
    }
    s.wi = select(s.wi, -s.wi, flip);
    return s;
}

// The sample that starts with the coat's sample `entry`: itself if it reflected, else the walk
// it starts (`walk`), then `finish`; a specular walk (chosen with probability p) is kept only if
// every event was specular.
fn layered_sample_path(
    l: Layered,
    wo: vec3f,
    entry: BsdfSample,
    specular_walk: bool,
    p: f32,
    rng: ptr<function, u32>,
) -> BsdfSample {
    if (!entry.valid) {
        return entry;
    }
    var path = entry;
    if (!(entry.wi.z > 0.0)) {
        path = layered_walk(l, entry, rng);
        if (!path.valid) {
            return path;
        }
    }
    if (specular_walk) {
        if (!path.delta) {
            return bsdf_none();
        }
        path.weight = path.weight / p;
        path.pdf = path.pdf * p;
    }
    return layered_finish(l, wo, path.wi, path.weight, path.pdf, path.delta);
}

// A walk that refracted in with `entry` until it leaves through the coat: its direction, the
// path's weight and pdf (a product of densities and probabilities), and whether every event was
// specular (`walk`).
fn layered_walk(l: Layered, entry: BsdfSample, rng: ptr<function, u32>) -> BsdfSample {
    let thickness = layered_thickness(l);
    let scatters = layered_scatters(l);
    var weight = entry.weight;
    var pdf = entry.pdf;
    var specular = entry.delta;
    var z = thickness;
    var w = entry.wi;
    for (var depth = 0u; depth < l.max_depth; depth++) {
        // Russian roulette on a low weight.
        let rr = bsdf_layered_max3(weight);
        if (depth > 3u && rr < 0.25) {
            let q = max(1.0 - rr, 0.0);
            if (bsdf_layered_next(rng) < q) {
                return bsdf_none();
            }
            weight = weight / (1.0 - q);
            pdf = pdf * (1.0 - q);
        }
        if (w.z == 0.0) {
            return bsdf_none();
        }
        if (scatters) {
            // Free flight; a medium event inside the slab scatters by the phase function.
            let dz = -log(1.0 - bsdf_layered_next(rng)) * abs(w.z);
            let zp = select(z - dz, z + dz, w.z > 0.0);
            if (zp == z) {
                return bsdf_none();
            }
            if (0.0 < zp && zp < thickness) {
                let hs = bsdf_layered_sample_hg(-w, l.g, bsdf_layered_u2(rng));
                if (!(hs.w > 0.0)) {
                    return bsdf_none();
                }
                weight = weight * l.albedo;
                pdf = pdf * hs.w;
                specular = false;
                w = hs.xyz;
                z = zp;
                continue;
            }
            z = clamp(zp, 0.0, thickness);
        } else {
            z = select(thickness, 0.0, z == thickness);
            weight = weight * bsdf_layered_transmittance(thickness, w);
        }
        // Scatter at the interface reached; leaving through the coat ends the walk.
        let uc = bsdf_layered_next(rng);
        let u = bsdf_layered_u2(rng);
        var bs: BsdfSample;
        if (z == 0.0) {
            bs = layered_base_sample(l, -w, u);
        } else {
            bs = layered_top_sample(l, -w, uc, u, BSDF_LAYERED_ALL);
        }
        if (!bs.valid) {
            return bs;
        }
        weight = weight * bs.weight;
        pdf = pdf * bs.pdf;
        specular = specular && bs.delta;
        w = bs.wi;
        if (z != 0.0 && w.z > 0.0) {
            return BsdfSample(true, w, weight, pdf, 1.0, specular);
        }
    }
    return bsdf_none();
}

// The sample as strata returns it: a non-delta one with `layered_pdf`'s estimate as its density.
fn layered_finish(l: Layered, wo: vec3f, wi: vec3f, weight: vec3f, pdf: f32, delta: bool) -> BsdfSample {
    var density = max(pdf, F32_MIN_POSITIVE);
    if (!delta) {
        density = layered_pdf_estimate(l, wo, wi);
    }
    return BsdfSample(true, wi, weight, density, 1.0, delta);
}

// Probabilities, under the hemisphere strategies, of a smooth coat's mirror (x), and (of the
// rest) of the specular walks over a mirror base (y).
fn layered_delta_split(l: Layered, wo: vec3f) -> vec2f {
    if (l.rough) {
        return vec2f(0.0);
    }
    let p_mirror = bsdf_fresnel(wo.z, l.eta);
    var p_walk = 0.0;
    if (layered_base_specular(l)) {
        p_walk = select(1.0, 0.5, layered_scatters(l));
    }
    return vec2f(p_mirror, p_walk);
}

// ---- The virtual light of eval's walk (`Light`) ------------------------------------------------

// wi, and wis, a transmission into the coat sampled from wi, with `exit`, pbrt's wis.f / wis.pdf
// in importance mode times the |cos θi| strata's eval carries.
struct LayeredLight {
    valid: bool,
    wi: vec3f,
    wis: BsdfSample,
    exit: vec3f,
}

fn layered_light_new(l: Layered, wi: vec3f, wis: BsdfSample) -> LayeredLight {
    // Importance mode: the radiance weight without the 1/η² of entering.
    let eta = l.eta;
    let exit = wis.weight * (eta * eta * wi.z / abs(wis.wi.z));
    return LayeredLight(frame_is_finite3(exit), wi, wis, exit);
}

// The next event along wis from a vertex dz below the coat that scatters into it with `value`
// (f · cos, or albedo × phase) and samples it with density `pdf`; weighted by the power
// heuristic against wis unless the coat is smooth.
fn layered_light_along_wis(l: Layered, light: LayeredLight, value: vec3f, pdf: f32, dz: f32) -> vec3f {
    var wt = 1.0;
    if (l.rough) {
        wt = mis_power_heuristic(light.wis.pdf, pdf);
    }
    return value * light.exit * (wt * bsdf_layered_transmittance(dz, light.wis.wi));
}

// The next event through a rough coat along w, sampled at a vertex dz below it with density
// `pdf` (`delta`: a mirror's), weighted against the density with which wis reaches w,
// pdf(wi → −w) (the module doc's departure (1) from pbrt).
fn layered_light_along(l: Layered, light: LayeredLight, w: vec3f, pdf: f32, delta: bool, dz: f32) -> vec3f {
    if (!l.rough) {
        return vec3f(0.0);
    }
    let f_exit = layered_top_eval(l, -w, light.wi);
    if (all(f_exit == vec3f(0.0))) {
        return vec3f(0.0);
    }
    var wt = 1.0;
    if (!delta) {
        wt = mis_power_heuristic(pdf, layered_top_pdf(l, light.wi, -w, BSDF_LAYERED_TRANSMISSION));
    }
    return f_exit * (bsdf_layered_transmittance(dz, w) * wt);
}

// ---- The coat as the walk calls it: from either side, sampling restricted by `only` ----------

// The coat seen from outside, or from inside (relative index 1/η) (`Top::facing`): the Bsdf the
// dielectric and rough dielectric functions read (ior, alpha, separable, tint 1).
fn layered_coat(l: Layered, inside: bool) -> Bsdf {
    var b: Bsdf;
    b.kind = select(MATERIAL_DIELECTRIC, MATERIAL_ROUGH_DIELECTRIC, l.rough);
    b.color = vec3f(1.0);
    b.ior = select(l.eta, 1.0 / l.eta, inside);
    b.alpha = l.alpha;
    b.separable = l.separable;
    return b;
}

fn layered_top_eval(l: Layered, wo: vec3f, wi: vec3f) -> vec3f {
    if (!l.rough) {
        return vec3f(0.0);
    }
    // From inside, directions are mirrored through the origin.
    let inside = !(wo.z >= 0.0);
    let s = select(1.0, -1.0, inside);
    return bsdf_rough_dielectric_eval(layered_coat(l, inside), s * wo, s * wi);
}

fn layered_top_pdf(l: Layered, wo_in: vec3f, wi_in: vec3f, only: u32) -> f32 {
    if (!l.rough) {
        return 0.0;
    }
    let inside = !(wo_in.z >= 0.0);
    let s = select(1.0, -1.0, inside);
    let r = layered_coat(l, inside);
    let wo = s * wo_in;
    let wi = s * wi_in;
    let full = bsdf_rough_dielectric_pdf(r, wo, wi, STRATEGY_BSDF);
    let reflect = wi.z > 0.0;
    if (only == BSDF_LAYERED_ALL) {
        return full;
    }
    if ((only == BSDF_LAYERED_REFLECTION) != reflect) {
        return 0.0;
    }
    // The lobe's probability F or 1 − F at the half vector, divided out.
    var h = frame_normalize_or(select(wo + r.ior * wi, wo + wi, reflect), vec3f(0.0));
    if (h.z < 0.0) {
        h = -h;
    }
    let f = bsdf_fresnel(dot(wo, h), r.ior);
    let prob = select(1.0 - f, f, reflect);
    let pdf = full / prob;
    if (full > 0.0 && frame_is_finite(pdf)) {
        return pdf;
    }
    return 0.0;
}

fn layered_top_sample(l: Layered, wo_in: vec3f, uc: f32, u: vec2f, only: u32) -> BsdfSample {
    let inside = !(wo_in.z >= 0.0);
    let s = select(1.0, -1.0, inside);
    let top = layered_coat(l, inside);
    let wo = s * wo_in;
    if (!(wo.z > 0.0)) {
        return bsdf_none();
    }
    var out: BsdfSample;
    if (l.rough) {
        out = bsdf_layered_sample_rough(top, wo, uc, u, only);
    } else {
        out = bsdf_layered_sample_smooth(top, wo, uc, only);
    }
    if (!out.valid) {
        return out;
    }
    out.wi = s * out.wi;
    return bsdf_layered_usable(out);
}

// pbrt's test of a usable sample: a density, a direction off the plane, some throughput.
fn bsdf_layered_usable(s: BsdfSample) -> BsdfSample {
    if (s.pdf > 0.0 && s.wi.z != 0.0 && any(s.weight != vec3f(0.0))) {
        return s;
    }
    return bsdf_none();
}

// A smooth interface's sample from above: both lobes by F, or one (`sample_smooth`).
fn bsdf_layered_sample_smooth(d: Bsdf, wo: vec3f, uc: f32, only: u32) -> BsdfSample {
    let f = bsdf_fresnel(wo.z, d.ior);
    if (only == BSDF_LAYERED_ALL) {
        return bsdf_dielectric_sample(d, wo, uc);
    }
    if (only == BSDF_LAYERED_REFLECTION) {
        if (f > 0.0) {
            return BsdfSample(true, vec3f(-wo.x, -wo.y, wo.z), vec3f(f), 1.0, 1.0, true);
        }
        return bsdf_none();
    }
    // The refraction (lobe dimension 1 ≥ F < 1), its weight times its probability 1 − F.
    if (f < 1.0) {
        var b = bsdf_dielectric_sample(d, wo, 1.0);
        if (b.valid) {
            b.weight = b.weight * (1.0 - f);
            b.pdf = 1.0;
        }
        return b;
    }
    return bsdf_none();
}

// A GGX interface's sample from above: both lobes by F at the visible normal, or one, with the
// lobe's probability moved from the pdf into the weight (`sample_rough`).
fn bsdf_layered_sample_rough(r: Bsdf, wo: vec3f, uc: f32, u: vec2f, only: u32) -> BsdfSample {
    var prob = 1.0;
    var u_lobe = uc;
    if (only != BSDF_LAYERED_ALL) {
        // The normal the rough dielectric's sample draws with u, and its F.
        let f = bsdf_fresnel(dot(wo, warp_ggx_sample_vndf(wo, r.alpha, u)), r.ior);
        if (only == BSDF_LAYERED_REFLECTION) {
            prob = f;
            u_lobe = 0.0;
        } else {
            prob = 1.0 - f;
            u_lobe = 1.0;
        }
    }
    if (!(prob > 0.0)) {
        return bsdf_none();
    }
    var b = bsdf_rough_dielectric_sample(r, wo, u, u_lobe, STRATEGY_BSDF);
    if (b.valid) {
        b.weight = b.weight * prob;
        b.pdf = b.pdf / prob;
        b.delta = false;
    }
    return b;
}

// ---- The base (`Base`): a diffuse or a conductor under its own sampling -----------------------

fn layered_base(l: Layered) -> Bsdf {
    var b: Bsdf;
    b.kind = l.base_kind;
    b.color = l.base_color;
    b.alpha = l.base_alpha;
    b.eta = l.base_eta;
    b.k = l.base_k;
    b.separable = l.base_separable;
    return b;
}

fn layered_base_specular(l: Layered) -> bool {
    return bsdf_is_mirror(layered_base(l));
}

fn layered_base_eval(l: Layered, wo: vec3f, wi: vec3f) -> vec3f {
    let b = layered_base(l);
    if (bsdf_is_conductor(b)) {
        return bsdf_conductor_eval(b, wo, wi);
    }
    return bsdf_diffuse_eval(b.color, wo, wi);
}

fn layered_base_pdf(l: Layered, wo: vec3f, wi: vec3f) -> f32 {
    let b = layered_base(l);
    if (bsdf_is_conductor(b)) {
        return bsdf_conductor_pdf(b, wo, wi, STRATEGY_BSDF);
    }
    if (wo.z <= 0.0) {
        return 0.0;
    }
    return bsdf_hemisphere_pdf(wi, false);
}

// The base's own sampling (pbrt draws a lobe dimension it does not use; the caller draws it).
fn layered_base_sample(l: Layered, wo: vec3f, u: vec2f) -> BsdfSample {
    let b = layered_base(l);
    var s: BsdfSample;
    if (bsdf_is_conductor(b)) {
        s = bsdf_conductor_sample(b, wo, u, STRATEGY_BSDF);
    } else {
        s = bsdf_diffuse_sample(b.color, wo, u, STRATEGY_BSDF);
    }
    if (!s.valid) {
        return s;
    }
    return bsdf_layered_usable(s);
}

// ---- The slab: transmittance, the Henyey–Greenstein phase function, the random stream -------

// pbrt's Tr(dz, w) = exp(−|dz / w.z|) (1 for |dz| at most the smallest normal f32).
fn bsdf_layered_transmittance(dz: f32, w: vec3f) -> f32 {
    if (abs(dz) <= F32_MIN_POSITIVE) {
        return 1.0;
    }
    return exp(-abs(dz / w.z));
}

// Henyey–Greenstein in pbrt-v4's convention: `cos_theta` is wo · wi with both pointing away, so
// g > 0 peaks at cos_theta = −1 (forward): (1 − g²) / (4π (1 + g² + 2g cos)^{3/2}).
fn bsdf_layered_hg(cos_theta: f32, g_in: f32) -> f32 {
    let g = clamp(g_in, -0.99, 0.99);
    let denom = 1.0 + g * g + 2.0 * g * cos_theta;
    return 0.25 * INV_PI * (1.0 - g * g) / (denom * sqrt(max(denom, 0.0)));
}

// A direction from the phase function around wo in xyz, its density in w (0: none)
// (pbrt's SampleHenyeyGreenstein).
fn bsdf_layered_sample_hg(wo: vec3f, g_in: f32, u: vec2f) -> vec4f {
    let g = clamp(g_in, -0.99, 0.99);
    var c: f32;
    if (abs(g) < 1e-3) {
        c = 1.0 - 2.0 * u.x;
    } else {
        let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
        c = -(1.0 + g * g - s * s) / (2.0 * g);
    }
    c = clamp(c, -1.0, 1.0);
    let sin_theta = sqrt(max(1.0 - c * c, 0.0));
    let phi = TAU * u.y;
    let local = vec3f(sin_theta * cos(phi), sin_theta * sin(phi), c);
    let wi = frame_to_world(frame_from_normal(wo), local);
    let pdf = bsdf_layered_hg(c, g);
    return vec4f(wi, select(0.0, pdf, pdf > 0.0 && wi.z != 0.0));
}

// The counter-based stream of the module doc (`Rng::new`): the domain, the seed 0 (strata's
// renderers use no other; `Layered::eval_seeded` and `pdf_seeded` serve the CPU's tests), then
// the f32 bits of a's and b's coordinates.
fn bsdf_layered_rng(domain: u32, a: vec3f, b: vec3f) -> u32 {
    var h = sampler_hash_combine(sampler_lowbias32(domain), 0u);
    h = sampler_hash_combine(h, bitcast<u32>(a.x));
    h = sampler_hash_combine(h, bitcast<u32>(a.y));
    h = sampler_hash_combine(h, bitcast<u32>(a.z));
    h = sampler_hash_combine(h, bitcast<u32>(b.x));
    h = sampler_hash_combine(h, bitcast<u32>(b.y));
    h = sampler_hash_combine(h, bitcast<u32>(b.z));
    return h;
}

fn bsdf_layered_next(rng: ptr<function, u32>) -> f32 {
    *rng = *rng + 0x9e3779b9u;
    return f32(sampler_lowbias32(*rng) >> 8u) * (1.0 / 16777216.0);
}

fn bsdf_layered_u2(rng: ptr<function, u32>) -> vec2f {
    let x = bsdf_layered_next(rng);
    return vec2f(x, bsdf_layered_next(rng));
}
