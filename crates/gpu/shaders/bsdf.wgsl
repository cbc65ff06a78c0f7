// needs: frame warp mis intersect texture sampler detail
// BSDFs: diffuse, GGX conductor with Schlick's or a complex index of refraction's Fresnel (a
// mirror when both alphas ≤ MIRROR_ALPHA), smooth and rough dielectric, smooth and rough
// plastic, thin dielectric, diffuse transmission, pbrt-v4's coated materials (the layered BSDF,
// in bsdf_layered.wgsl, composed after this file as part of this module), and the world-space
// shading point with its leak guard. Mirrors `crates/cpu/src/bsdf.rs` and `bsdf/{diffuse,
// conductor,dielectric,rough_dielectric,plastic,thin_dielectric,diffuse_transmission}.rs`: same
// formulas, same branches.
//
// Local convention: z is the shading normal flipped to the side of wo, so wo.z ≥ 0. `eval`
// returns f·|cos θi|, `pdf` the solid-angle density of `sample` (0 for delta lobes), `sample`
// the weight f·|cos θi| / pdf. Rust `Option<BsdfSample>` becomes `BsdfSample.valid`.
// `strategy` is one of STRATEGY_* (scene.wgsl); uniform / cosine pick the hemisphere lobes,
// bsdf / light / mis the BSDF's own sampling (`Lobe::of`).
//
// Interface (other modules may call):
//   struct Bsdf { kind: u32, color: vec3f, ior: f32, alpha: vec2f, eta: vec3f, k: vec3f,
//                 separable: bool, nonlinear: bool, layered: Layered }
//     (plastics: color the diffuse reflectance, ior the coating's η, eta the specular
//      reflectance, k = (R_int, specular sampling weight, table index))
//     (ior: dielectrics' η_t/η_i, a thin sheet's η; alpha: (αu, αv) of conductors and rough
//      dielectrics; eta, k: complex conductor; eta: diffuse transmission's transmittance;
//      layered: the coated kinds' BSDF, set by shading_point_new, zero for the other kinds)
//   struct BsdfSample { valid: bool, wi: vec3f, weight: vec3f, pdf: f32, eta: f32, delta: bool }
//   struct ShadingPoint { p: vec3f, err: vec3f, ng: vec3f, frame: Frame, bsdf: Bsdf }
//   fn bsdf_new(material: Material, entering: bool) -> Bsdf
//   fn bsdf_is_delta(sp: ShadingPoint) -> bool
//   fn bsdf_eval(b: Bsdf, wo: vec3f, wi: vec3f) -> vec3f                   (local frame)
//   fn bsdf_pdf(b: Bsdf, wo: vec3f, wi: vec3f, strategy: u32) -> f32       (local frame)
//   fn bsdf_sample(b: Bsdf, wo: vec3f, u: vec2f, u_lobe: f32, strategy: u32) -> BsdfSample
//   fn shading_point_new(hit: Hit, material: Material, base: Material, wo: vec3f) -> ShadingPoint
//     (base: a coated material's base record, its k.y; read for the coated kinds only)
//   fn bsdf_is_coated(kind: u32) -> bool      (MATERIAL_COATED_DIFFUSE / _CONDUCTOR, if compiled)
//   fn shading_point_eval(sp: ShadingPoint, wo: vec3f, wi: vec3f) -> vec3f        (world)
//   fn shading_point_pdf(sp: ShadingPoint, wo: vec3f, wi: vec3f, strategy: u32) -> f32
//   fn shading_point_sample(sp: ShadingPoint, wo: vec3f, u_dir: vec2f, u_lobe: f32,
//                           strategy: u32) -> BsdfSample
struct Bsdf {
    kind: u32,
    color: vec3f,
    // Dielectric: relative index of refraction η_t / η_i across the surface from wo's side.
    ior: f32,
    // Conductors: GGX (αu, αv) along the frame's x and y; zero for a mirror, else ≥ MIRROR_ALPHA.
    alpha: vec2f,
    // Complex conductor: index of refraction η + ik per channel.
    eta: vec3f,
    k: vec3f,
    // GGX materials: separable masking-shadowing (MATERIAL_SEPARABLE_MASKING).
    separable: bool,
    // Plastics: Mitsuba's `nonlinear` (MATERIAL_NONLINEAR).
    nonlinear: bool,
    // Coated materials: the coat, the base and the slab (`Bsdf::Layered`, bsdf_layered.wgsl).
    layered: Layered,
}

struct BsdfSample {
    valid: bool,
    wi: vec3f,
    // f·|cos θi| / pdf (delta lobes: the lobe's weight over its selection probability).
    weight: vec3f,
    // Solid-angle pdf; for delta lobes the discrete probability of the lobe.
    pdf: f32,
    // Relative index of refraction crossed (η_t / η_i), 1 for reflection.
    eta: f32,
    delta: bool,
}

struct ShadingPoint {
    p: vec3f,
    // Bound on the rounding error of p's coordinates (Hit::err).
    err: vec3f,
    // Unit geometric normal flipped to the side of wo.
    ng: vec3f,
    // Shading frame; n is the shading normal flipped to the side of wo.
    frame: Frame,
    bsdf: Bsdf,
}

fn bsdf_none() -> BsdfSample {
    return BsdfSample(false, vec3f(0.0), vec3f(0.0), 0.0, 1.0, false);
}

// `entering`: wo on the front side of the geometric surface (decides the dielectric's η).
fn bsdf_new(material: Material, entering: bool) -> Bsdf {
    let kind = material.tag & MATERIAL_KIND_MASK;
    var ior = material.ior;
    if (kind == MATERIAL_DIELECTRIC || kind == MATERIAL_ROUGH_DIELECTRIC) {
        ior = select(1.0 / material.ior, material.ior, entering);
    }
    // A conductor is a mirror when both alphas are at most MIRROR_ALPHA; otherwise (and always
    // for a rough dielectric) each is at least that (`Conductor::new`, `Bsdf::new`).
    var alpha = vec2f(material.alpha_u, material.alpha_v);
    let always_rough = kind == MATERIAL_ROUGH_DIELECTRIC || kind == MATERIAL_ROUGH_PLASTIC;
    if (!always_rough && max(alpha.x, alpha.y) <= MIRROR_ALPHA) {
        alpha = vec2f(0.0);
    } else {
        alpha = max(alpha, vec2f(MIRROR_ALPHA));
    }
    let separable = (material.tag & MATERIAL_SEPARABLE_MASKING) != 0u;
    let nonlinear = (material.tag & MATERIAL_NONLINEAR) != 0u;
    return Bsdf(kind, material.color, ior, alpha, material.eta, material.k, separable, nonlinear, Layered());
}

fn bsdf_is_complex_conductor(b: Bsdf) -> bool {
    return has_material_kind(MATERIAL_COMPLEX_CONDUCTOR) && b.kind == MATERIAL_COMPLEX_CONDUCTOR;
}

fn bsdf_is_conductor(b: Bsdf) -> bool {
    return (has_material_kind(MATERIAL_CONDUCTOR) && b.kind == MATERIAL_CONDUCTOR)
        || bsdf_is_complex_conductor(b);
}

fn bsdf_is_dielectric(b: Bsdf) -> bool {
    return has_material_kind(MATERIAL_DIELECTRIC) && b.kind == MATERIAL_DIELECTRIC;
}

fn bsdf_is_rough_dielectric(b: Bsdf) -> bool {
    return has_material_kind(MATERIAL_ROUGH_DIELECTRIC) && b.kind == MATERIAL_ROUGH_DIELECTRIC;
}

fn bsdf_is_rough_plastic(b: Bsdf) -> bool {
    return has_material_kind(MATERIAL_ROUGH_PLASTIC) && b.kind == MATERIAL_ROUGH_PLASTIC;
}

fn bsdf_is_plastic(b: Bsdf) -> bool {
    return (has_material_kind(MATERIAL_PLASTIC) && b.kind == MATERIAL_PLASTIC)
        || bsdf_is_rough_plastic(b);
}

fn bsdf_is_thin_dielectric(b: Bsdf) -> bool {
    return has_material_kind(MATERIAL_THIN_DIELECTRIC) && b.kind == MATERIAL_THIN_DIELECTRIC;
}

fn bsdf_is_diffuse_transmission(b: Bsdf) -> bool {
    return has_material_kind(MATERIAL_DIFFUSE_TRANSMISSION) && b.kind == MATERIAL_DIFFUSE_TRANSMISSION;
}

// A coated material's kind (pbrt-v4's `coateddiffuse`, `coatedconductor`), where compiled in.
fn bsdf_is_coated(kind: u32) -> bool {
    return (has_material_kind(MATERIAL_COATED_DIFFUSE) && kind == MATERIAL_COATED_DIFFUSE)
        || (has_material_kind(MATERIAL_COATED_CONDUCTOR) && kind == MATERIAL_COATED_CONDUCTOR);
}

fn bsdf_is_layered(b: Bsdf) -> bool {
    return bsdf_is_coated(b.kind);
}

fn bsdf_is_mirror(b: Bsdf) -> bool {
    return bsdf_is_conductor(b) && max(b.alpha.x, b.alpha.y) <= MIRROR_ALPHA;
}

// Every lobe a Dirac delta: no next-event estimation, no MIS (never a layered BSDF).
fn bsdf_is_delta(sp: ShadingPoint) -> bool {
    return bsdf_is_mirror(sp.bsdf) || bsdf_is_dielectric(sp.bsdf)
        || bsdf_is_thin_dielectric(sp.bsdf);
}

// ---- Hemisphere lobes (strategies uniform / cosine) ------------------------------------------

fn bsdf_uniform_lobe(strategy: u32) -> bool {
    return strategy == STRATEGY_UNIFORM;
}

fn bsdf_own_lobe(strategy: u32) -> bool {
    return strategy != STRATEGY_UNIFORM && strategy != STRATEGY_COSINE;
}

// Density of the hemisphere lobe (0 below the horizon).
fn bsdf_hemisphere_pdf(wi: vec3f, uniform: bool) -> f32 {
    if (wi.z <= 0.0) {
        return 0.0;
    }
    if (uniform) {
        return warp_uniform_hemisphere_pdf();
    }
    return warp_cosine_hemisphere_pdf(wi.z);
}

// Hemisphere direction in xyz, its pdf in w.
fn bsdf_sample_hemisphere(u: vec2f, uniform: bool) -> vec4f {
    if (uniform) {
        return vec4f(warp_uniform_hemisphere(u), warp_uniform_hemisphere_pdf());
    }
    let wi = warp_cosine_hemisphere(u);
    return vec4f(wi, warp_cosine_hemisphere_pdf(wi.z));
}

// ---- Diffuse (Lambert) -------------------------------------------------------------------------

fn bsdf_diffuse_eval(albedo: vec3f, wo: vec3f, wi: vec3f) -> vec3f {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return vec3f(0.0);
    }
    return albedo * (INV_PI * wi.z);
}

fn bsdf_diffuse_sample(albedo: vec3f, wo: vec3f, u: vec2f, strategy: u32) -> BsdfSample {
    if (wo.z <= 0.0) {
        return bsdf_none();
    }
    let uniform = bsdf_uniform_lobe(strategy);
    let s = bsdf_sample_hemisphere(u, uniform);
    if (s.z <= 0.0 || s.w <= 0.0) {
        return bsdf_none();
    }
    // Cosine sampling cancels f·cos exactly; uniform leaves 2·cos θ.
    let weight = select(albedo, albedo * (2.0 * s.z), uniform);
    return BsdfSample(true, s.xyz, weight, s.w, 1.0, false);
}

// ---- GGX conductor (Schlick or complex Fresnel, height-correlated Smith) -----------------------

// Schlick's approximation F0 + (1 − F0)(1 − cos)⁵.
fn bsdf_schlick(f0: vec3f, cos_theta: f32) -> vec3f {
    let m = clamp(1.0 - cos_theta, 0.0, 1.0);
    let m2 = m * m;
    return f0 + (vec3f(1.0) - f0) * (m2 * m2 * m);
}

// Unpolarized reflectance of a conductor with index of refraction eta + ik per channel
// (`conductor::fresnel_complex`, which derives it); 1 where the closed form is 0/0, clamped
// to [0, 1] against rounding.
fn bsdf_fresnel_complex(cos_in: f32, eta: vec3f, k: vec3f) -> vec3f {
    let c = clamp(cos_in, 0.0, 1.0);
    let cos2 = c * c;
    let sin2 = 1.0 - cos2;
    let sin4 = sin2 * sin2;
    let t = eta * eta - k * k - vec3f(sin2);
    let a2_b2 = sqrt(max(t * t + 4.0 * eta * eta * k * k, vec3f(0.0)));
    let a = sqrt(max(0.5 * (a2_b2 + t), vec3f(0.0)));
    let term1 = a2_b2 + vec3f(cos2);
    let term2 = 2.0 * c * a;
    let term3 = a2_b2 * cos2 + vec3f(sin4);
    let term4 = term2 * sin2;
    let d_s = term1 + term2;
    let d_p = term3 + term4;
    let rs = (term1 - term2) / d_s;
    let rp = rs * (term3 - term4) / d_p;
    let f = select(vec3f(1.0), 0.5 * (rs + rp), d_s > vec3f(0.0) & d_p > vec3f(0.0));
    return clamp(f, vec3f(0.0), vec3f(1.0));
}

// The conductor's Fresnel reflectance at cos_theta to the (micro)normal.
fn bsdf_conductor_fresnel(b: Bsdf, cos_theta: f32) -> vec3f {
    if (bsdf_is_complex_conductor(b)) {
        return b.color * bsdf_fresnel_complex(cos_theta, b.eta, b.k);
    }
    return bsdf_schlick(b.color, cos_theta);
}

fn bsdf_conductor_eval(b: Bsdf, wo: vec3f, wi: vec3f) -> vec3f {
    if (bsdf_is_mirror(b) || wo.z <= 0.0 || wi.z <= 0.0) {
        return vec3f(0.0);
    }
    let h = normalize(wo + wi);
    let d = warp_ggx_d(h, b.alpha);
    let g = warp_ggx_g2(wo, wi, b.alpha, b.separable);
    // f · cos θi = F D G / (4 cos θo cos θi) · cos θi.
    return bsdf_conductor_fresnel(b, dot(wo, h)) * (d * g / (4.0 * wo.z));
}

fn bsdf_conductor_pdf(b: Bsdf, wo: vec3f, wi: vec3f, strategy: u32) -> f32 {
    if (bsdf_is_mirror(b) || wo.z <= 0.0 || wi.z <= 0.0) {
        return 0.0;
    }
    if (!bsdf_own_lobe(strategy)) {
        return bsdf_hemisphere_pdf(wi, bsdf_uniform_lobe(strategy));
    }
    let h = normalize(wo + wi);
    // Reflection Jacobian dh/dωi = 1 / (4 wo·h).
    return warp_ggx_vndf_pdf(wo, h, b.alpha) / (4.0 * dot(wo, h));
}

fn bsdf_conductor_sample(b: Bsdf, wo: vec3f, u: vec2f, strategy: u32) -> BsdfSample {
    if (wo.z <= 0.0) {
        return bsdf_none();
    }
    // Mirror: reflect about the normal, weight F(cos θo).
    if (bsdf_is_mirror(b)) {
        let wi = vec3f(-wo.x, -wo.y, wo.z);
        return BsdfSample(true, wi, bsdf_conductor_fresnel(b, wo.z), 1.0, 1.0, true);
    }
    var wi: vec3f;
    var pdf: f32;
    var weight: vec3f;
    if (!bsdf_own_lobe(strategy)) {
        let s = bsdf_sample_hemisphere(u, bsdf_uniform_lobe(strategy));
        wi = s.xyz;
        pdf = s.w;
        weight = bsdf_conductor_eval(b, wo, wi) / pdf;
    } else {
        // Visible normals (Heitz 2018), reflected about h.
        let h = warp_ggx_sample_vndf(wo, b.alpha, u);
        wi = 2.0 * dot(wo, h) * h - wo;
        if (wi.z <= 0.0) {
            return bsdf_none();
        }
        pdf = warp_ggx_vndf_pdf(wo, h, b.alpha) / (4.0 * dot(wo, h));
        // F D G2 / (4 cos θo) over G1(wo) D / (4 cos θo) = F G2 / G1.
        let g = warp_ggx_g2(wo, wi, b.alpha, b.separable) / warp_ggx_g1(wo, b.alpha);
        weight = bsdf_conductor_fresnel(b, dot(wo, h)) * g;
    }
    if (!(wi.z > 0.0 && pdf > 0.0 && frame_is_finite3(weight))) {
        return bsdf_none();
    }
    return BsdfSample(true, wi, weight, pdf, 1.0, false);
}

// ---- Smooth dielectric ---------------------------------------------------------------------------

// Unpolarized Fresnel reflectance for cos_i ≥ 0 and eta = η_t / η_i; 1 under total reflection.
fn bsdf_fresnel(cos_in: f32, eta: f32) -> f32 {
    let cos_i = clamp(cos_in, 0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0) {
        return 1.0;
    }
    let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
    let r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

fn bsdf_dielectric_sample(b: Bsdf, wo: vec3f, u_lobe: f32) -> BsdfSample {
    let cos_i = wo.z;
    if (cos_i <= 0.0) {
        return bsdf_none();
    }
    let eta = b.ior;
    let f = bsdf_fresnel(cos_i, eta);
    // Specular reflection, chosen with probability F: weight F / F.
    if (u_lobe < f) {
        return BsdfSample(true, vec3f(-wo.x, -wo.y, wo.z), vec3f(1.0), f, 1.0, true);
    }
    // Refraction (Snell), chosen with probability 1 − F: weight (1 − F) / (1 − F) / η².
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
    let wi = vec3f(-wo.x / eta, -wo.y / eta, -cos_t);
    return BsdfSample(true, wi, b.color / (eta * eta), 1.0 - f, eta, true);
}

// ---- Thin dielectric (two interfaces, their inter-reflections summed) --------------------------

// The sheet's reflectance R + T²R / (1 − R²) at cos_i ≥ 0 (`ThinDielectric::reflectance`).
fn bsdf_thin_reflectance(cos_i: f32, eta: f32) -> f32 {
    let r = bsdf_fresnel(cos_i, eta);
    if (r >= 1.0) {
        return 1.0;
    }
    let t = 1.0 - r;
    return r + t * t * r / (1.0 - r * r);
}

fn bsdf_thin_dielectric_sample(b: Bsdf, wo: vec3f, u_lobe: f32) -> BsdfSample {
    if (wo.z <= 0.0) {
        return bsdf_none();
    }
    let r = bsdf_thin_reflectance(wo.z, b.ior);
    // Mirror reflection with probability R' (weight 1), else straight through (weight tint).
    if (u_lobe < r) {
        return BsdfSample(true, vec3f(-wo.x, -wo.y, wo.z), vec3f(1.0), r, 1.0, true);
    }
    return BsdfSample(true, -wo, b.color, 1.0 - r, 1.0, true);
}

// ---- Diffuse transmission (R / π on wo's side, T / π through) ---------------------------------

fn bsdf_diffuse_transmission_eval(b: Bsdf, wo: vec3f, wi: vec3f) -> vec3f {
    if (wo.z <= 0.0 || wi.z == 0.0) {
        return vec3f(0.0);
    }
    return select(b.eta, b.color, wi.z > 0.0) * (INV_PI * abs(wi.z));
}

// The probability of sampling the reflection side: ½ under uniform / cosine, else
// max(R) / (max(R) + max(T)).
fn bsdf_diffuse_transmission_reflect(b: Bsdf, strategy: u32) -> f32 {
    if (!bsdf_own_lobe(strategy)) {
        return 0.5;
    }
    let r = max(max(max(b.color.x, b.color.y), b.color.z), 0.0);
    let t = max(max(max(b.eta.x, b.eta.y), b.eta.z), 0.0);
    if (r + t > 0.0) {
        return r / (r + t);
    }
    return 0.5;
}

fn bsdf_diffuse_transmission_pdf(b: Bsdf, wo: vec3f, wi: vec3f, strategy: u32) -> f32 {
    if (wo.z <= 0.0 || wi.z == 0.0) {
        return 0.0;
    }
    let p_reflect = bsdf_diffuse_transmission_reflect(b, strategy);
    let side = select(1.0 - p_reflect, p_reflect, wi.z > 0.0);
    return side * bsdf_hemisphere_pdf(vec3f(wi.xy, abs(wi.z)), bsdf_uniform_lobe(strategy));
}

fn bsdf_diffuse_transmission_sample(b: Bsdf, wo: vec3f, u: vec2f, u_lobe: f32, strategy: u32) -> BsdfSample {
    if (wo.z <= 0.0) {
        return bsdf_none();
    }
    let p_reflect = bsdf_diffuse_transmission_reflect(b, strategy);
    let reflect = u_lobe < p_reflect;
    let side = select(1.0 - p_reflect, p_reflect, reflect);
    let colour = select(b.eta, b.color, reflect);
    let uniform = bsdf_uniform_lobe(strategy);
    let s = bsdf_sample_hemisphere(u, uniform);
    if (s.z <= 0.0 || s.w <= 0.0 || side <= 0.0) {
        return bsdf_none();
    }
    // The colour over the side's probability, times 2 cos θ for uniform directions.
    let cosine = select(1.0, 2.0 * s.z, uniform);
    let wi = select(vec3f(s.xy, -s.z), s.xyz, reflect);
    return BsdfSample(true, wi, colour * (cosine / side), side * s.w, 1.0, false);
}

// ---- Rough dielectric (Walter et al. 2007, visible normals) ------------------------------------

// The microfacet normal taking wo to wi (reflection when wi.z > 0, else refraction with relative
// index eta), on the +z side, in xyz, and wi·h in w; w = 0 when no microfacet faces both the
// right way (`rough_dielectric::half_vector`).
fn bsdf_rough_half(wo: vec3f, wi: vec3f, eta: f32) -> vec4f {
    let reflect = wi.z > 0.0;
    let sum = select(wo + eta * wi, wo + wi, reflect);
    var h = frame_normalize_or(sum, vec3f(0.0));
    if (h.z < 0.0) {
        h = -h;
    }
    let o = dot(wo, h);
    let i = dot(wi, h);
    if (h.z > 0.0 && o > 0.0 && (i > 0.0) == reflect && i != 0.0) {
        return vec4f(h, i);
    }
    return vec4f(0.0);
}

fn bsdf_rough_dielectric_eval(b: Bsdf, wo: vec3f, wi: vec3f) -> vec3f {
    if (wo.z <= 0.0 || wi.z == 0.0) {
        return vec3f(0.0);
    }
    let hw = bsdf_rough_half(wo, wi, b.ior);
    if (hw.w == 0.0) {
        return vec3f(0.0);
    }
    let h = hw.xyz;
    let wi_h = hw.w;
    let wo_h = dot(wo, h);
    let d = warp_ggx_d(h, b.alpha);
    let g = warp_ggx_g2(wo, wi, b.alpha, b.separable);
    let f = bsdf_fresnel(wo_h, b.ior);
    if (wi.z > 0.0) {
        return vec3f(f * d * g / (4.0 * wo.z));
    }
    let denom = wo_h + b.ior * wi_h;
    let value = (1.0 - f) * d * g * abs(wo_h * wi_h) / (wo.z * denom * denom);
    // Near index matching (η → 1) the transmission lobe tends to a delta: 0 where it overflows.
    return select(vec3f(0.0), b.color * value, frame_is_finite(value));
}

fn bsdf_rough_dielectric_pdf(b: Bsdf, wo: vec3f, wi: vec3f, strategy: u32) -> f32 {
    if (wo.z <= 0.0 || wi.z == 0.0) {
        return 0.0;
    }
    if (!bsdf_own_lobe(strategy)) {
        return 0.5 * bsdf_hemisphere_pdf(vec3f(wi.x, wi.y, abs(wi.z)), bsdf_uniform_lobe(strategy));
    }
    let hw = bsdf_rough_half(wo, wi, b.ior);
    if (hw.w == 0.0) {
        return 0.0;
    }
    let h = hw.xyz;
    let wo_h = dot(wo, h);
    let vndf = warp_ggx_vndf_pdf(wo, h, b.alpha);
    let f = bsdf_fresnel(wo_h, b.ior);
    if (wi.z > 0.0) {
        // Reflection Jacobian dh/dωi = 1 / (4 wo·h).
        return f * vndf / (4.0 * wo_h);
    }
    // Refraction Jacobian dh/dωi = η² |wi·h| / (wo·h + η wi·h)².
    let denom = wo_h + b.ior * hw.w;
    let pdf = (1.0 - f) * vndf * b.ior * b.ior * abs(hw.w) / (denom * denom);
    return select(0.0, pdf, frame_is_finite(pdf));
}

fn bsdf_rough_dielectric_sample(b: Bsdf, wo: vec3f, u: vec2f, u_lobe: f32, strategy: u32) -> BsdfSample {
    if (wo.z <= 0.0) {
        return bsdf_none();
    }
    var wi: vec3f;
    var pdf: f32;
    var weight: vec3f;
    if (!bsdf_own_lobe(strategy)) {
        // The lobe dimension picks the side, ½ each.
        let s = bsdf_sample_hemisphere(u, bsdf_uniform_lobe(strategy));
        wi = select(vec3f(s.x, s.y, -s.z), s.xyz, u_lobe < 0.5);
        pdf = 0.5 * s.w;
        weight = bsdf_rough_dielectric_eval(b, wo, wi) / pdf;
    } else {
        let h = warp_ggx_sample_vndf(wo, b.alpha, u);
        let wo_h = dot(wo, h);
        if (wo_h <= 0.0) {
            return bsdf_none();
        }
        let vndf = warp_ggx_vndf_pdf(wo, h, b.alpha);
        let f = bsdf_fresnel(wo_h, b.ior);
        if (u_lobe < f) {
            wi = 2.0 * wo_h * h - wo;
            if (wi.z <= 0.0) {
                return bsdf_none();
            }
            pdf = f * vndf / (4.0 * wo_h);
            // F D G2 / (4 cos θo) over F G1(wo) D / (4 cos θo).
            weight = vec3f(warp_ggx_g2(wo, wi, b.alpha, b.separable) / warp_ggx_g1(wo, b.alpha));
        } else {
            // Refraction about h (Snell); u_lobe ≥ F excludes total internal reflection.
            let eta = b.ior;
            let sin2_t = (1.0 - wo_h * wo_h) / (eta * eta);
            let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
            // Normalized: at extreme η the rounding of 1 − (wo·h)² is amplified by 1/η².
            wi = frame_normalize_or((wo_h / eta - cos_t) * h - wo / eta, vec3f(0.0));
            if (wi.z >= 0.0) {
                return bsdf_none();
            }
            let wi_h = dot(wi, h);
            let denom = wo_h + eta * wi_h;
            pdf = (1.0 - f) * vndf * eta * eta * abs(wi_h) / (denom * denom);
            // The eval over the pdf: tint G2 / (G1(wo) η²).
            let g = warp_ggx_g2(wo, wi, b.alpha, b.separable) / warp_ggx_g1(wo, b.alpha);
            weight = b.color * (g / (eta * eta));
        }
    }
    if (!(wi.z != 0.0 && pdf > 0.0 && frame_is_finite(pdf) && frame_is_finite3(weight))) {
        return bsdf_none();
    }
    return BsdfSample(true, wi, weight, pdf, select(b.ior, 1.0, wi.z > 0.0), false);
}

// ---- Plastic and rough plastic (Mitsuba 3's `plastic` / `roughplastic`, bsdf/plastic.rs) -----

// The coating's transmittance at `cos` from outside: 1 − F (smooth), or the rough coating's
// table, linearly between entries (`coating::transmittance`).
fn bsdf_plastic_transmittance(b: Bsdf, cos: f32) -> f32 {
    if (!bsdf_is_rough_plastic(b)) {
        return 1.0 - bsdf_fresnel(cos, b.ior);
    }
    let x = clamp(cos, 0.0, 1.0) * f32(TRANSMITTANCE_RES - 1u);
    let i = min(u32(x), TRANSMITTANCE_RES - 2u);
    let f = x - f32(i);
    let at = u32(b.k.z) + i;
    return table_f32(at) * (1.0 - f) + table_f32(at + 1u) * f;
}

// Probability of sampling the coating rather than the base, seen from wo.
fn bsdf_plastic_specular_probability(b: Bsdf, wo: vec3f) -> f32 {
    let t = bsdf_plastic_transmittance(b, wo.z);
    let specular = (1.0 - t) * b.k.y;
    let diffuse = t * (1.0 - b.k.y);
    if (specular + diffuse > 0.0) {
        return specular / (specular + diffuse);
    }
    return 0.0;
}

fn bsdf_plastic_eval(b: Bsdf, wo: vec3f, wi: vec3f) -> vec3f {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return vec3f(0.0);
    }
    // The base: diffuse / (1 − R_int) · (cos θi / π) · T(θo) T(θi) / η².
    let scatter = select(vec3f(b.k.x), b.color * b.k.x, b.nonlinear);
    let diffuse = b.color / (vec3f(1.0) - scatter);
    let t = bsdf_plastic_transmittance(b, wo.z) * bsdf_plastic_transmittance(b, wi.z);
    var f = diffuse * (INV_PI * wi.z * t / (b.ior * b.ior));
    if (bsdf_is_rough_plastic(b)) {
        // The rough coating: specular · F D G2 / (4 cos θo).
        let h = normalize(wo + wi);
        let d = warp_ggx_d(h, b.alpha);
        let g = warp_ggx_g2(wo, wi, b.alpha, b.separable);
        f += b.eta * (bsdf_fresnel(dot(wo, h), b.ior) * d * g / (4.0 * wo.z));
    }
    return f;
}

fn bsdf_plastic_pdf(b: Bsdf, wo: vec3f, wi: vec3f, strategy: u32) -> f32 {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return 0.0;
    }
    return bsdf_plastic_pdf_with(b, wo, wi, strategy, bsdf_plastic_specular_probability(b, wo));
}

// bsdf_plastic_pdf for wo.z, wi.z > 0, with the coating's probability seen from wo.
fn bsdf_plastic_pdf_with(b: Bsdf, wo: vec3f, wi: vec3f, strategy: u32, p_specular: f32) -> f32 {
    let rough = bsdf_is_rough_plastic(b);
    if (!bsdf_own_lobe(strategy)) {
        // The rough one's whole lobe on the hemisphere; the smooth one's base after its mirror.
        let hemisphere = bsdf_hemisphere_pdf(wi, bsdf_uniform_lobe(strategy));
        return select((1.0 - p_specular) * hemisphere, hemisphere, rough);
    }
    if (!rough) {
        return (1.0 - p_specular) * warp_cosine_hemisphere_pdf(wi.z);
    }
    let glossy = warp_ggx_reflection_pdf(wo, wi, b.alpha);
    return p_specular * glossy + (1.0 - p_specular) * warp_cosine_hemisphere_pdf(wi.z);
}

fn bsdf_plastic_sample(b: Bsdf, wo: vec3f, u: vec2f, u_lobe: f32, strategy: u32) -> BsdfSample {
    if (wo.z <= 0.0) {
        return bsdf_none();
    }
    let p_specular = bsdf_plastic_specular_probability(b, wo);
    let rough = bsdf_is_rough_plastic(b);
    if (!rough && u_lobe < p_specular) {
        // The smooth coating's mirror: weight F · specular / P(specular).
        let f = bsdf_fresnel(wo.z, b.ior);
        return BsdfSample(true, vec3f(-wo.x, -wo.y, wo.z), b.eta * (f / p_specular), p_specular, 1.0, true);
    }
    var wi: vec3f;
    if (!bsdf_own_lobe(strategy)) {
        wi = bsdf_sample_hemisphere(u, bsdf_uniform_lobe(strategy)).xyz;
    } else if (rough && u_lobe < p_specular) {
        wi = warp_ggx_reflect(wo, warp_ggx_sample_vndf(wo, b.alpha, u));
    } else {
        wi = warp_cosine_hemisphere(u);
    }
    if (wi.z <= 0.0) {
        return bsdf_none();
    }
    let pdf = bsdf_plastic_pdf_with(b, wo, wi, strategy, p_specular);
    let weight = bsdf_plastic_eval(b, wo, wi) / pdf;
    if (!(pdf > 0.0 && frame_is_finite3(weight))) {
        return bsdf_none();
    }
    return BsdfSample(true, wi, weight, pdf, 1.0, false);
}

// ---- Dispatch on the material kind (local frame) ---------------------------------------------

fn bsdf_eval(b: Bsdf, wo: vec3f, wi: vec3f) -> vec3f {
    if (bsdf_is_conductor(b)) {
        return bsdf_conductor_eval(b, wo, wi);
    }
    if (bsdf_is_dielectric(b)) {
        return vec3f(0.0);
    }
    if (bsdf_is_rough_dielectric(b)) {
        return bsdf_rough_dielectric_eval(b, wo, wi);
    }
    if (bsdf_is_plastic(b)) {
        return bsdf_plastic_eval(b, wo, wi);
    }
    if (bsdf_is_thin_dielectric(b)) {
        return vec3f(0.0);
    }
    if (bsdf_is_diffuse_transmission(b)) {
        return bsdf_diffuse_transmission_eval(b, wo, wi);
    }
    if (bsdf_is_layered(b)) {
        return layered_eval(b.layered, wo, wi);
    }
    return bsdf_diffuse_eval(b.color, wo, wi);
}

fn bsdf_pdf(b: Bsdf, wo: vec3f, wi: vec3f, strategy: u32) -> f32 {
    if (bsdf_is_conductor(b)) {
        return bsdf_conductor_pdf(b, wo, wi, strategy);
    }
    if (bsdf_is_dielectric(b)) {
        return 0.0;
    }
    if (bsdf_is_rough_dielectric(b)) {
        return bsdf_rough_dielectric_pdf(b, wo, wi, strategy);
    }
    if (bsdf_is_plastic(b)) {
        return bsdf_plastic_pdf(b, wo, wi, strategy);
    }
    if (bsdf_is_thin_dielectric(b)) {
        return 0.0;
    }
    if (bsdf_is_diffuse_transmission(b)) {
        return bsdf_diffuse_transmission_pdf(b, wo, wi, strategy);
    }
    if (bsdf_is_layered(b)) {
        return layered_pdf(b.layered, wo, wi, strategy);
    }
    // Diffuse: uniform hemisphere for the uniform lobe, cosine-weighted otherwise.
    if (wo.z <= 0.0) {
        return 0.0;
    }
    return bsdf_hemisphere_pdf(wi, bsdf_uniform_lobe(strategy));
}

fn bsdf_sample(b: Bsdf, wo: vec3f, u: vec2f, u_lobe: f32, strategy: u32) -> BsdfSample {
    if (bsdf_is_conductor(b)) {
        return bsdf_conductor_sample(b, wo, u, strategy);
    }
    if (bsdf_is_dielectric(b)) {
        return bsdf_dielectric_sample(b, wo, u_lobe);
    }
    if (bsdf_is_rough_dielectric(b)) {
        return bsdf_rough_dielectric_sample(b, wo, u, u_lobe, strategy);
    }
    if (bsdf_is_plastic(b)) {
        return bsdf_plastic_sample(b, wo, u, u_lobe, strategy);
    }
    if (bsdf_is_thin_dielectric(b)) {
        return bsdf_thin_dielectric_sample(b, wo, u_lobe);
    }
    if (bsdf_is_diffuse_transmission(b)) {
        return bsdf_diffuse_transmission_sample(b, wo, u, u_lobe, strategy);
    }
    if (bsdf_is_layered(b)) {
        return layered_sample(b.layered, wo, u, u_lobe, strategy);
    }
    return bsdf_diffuse_sample(b.color, wo, u, strategy);
}

// ---- Mix (pbrt-v4's MixMaterial: one of two materials per point) ------------------------------

// The uniform number choosing between mix `index`'s materials at vertex `depth` of sample
// `sample` of the current pixel (`records::mix_choice`, which says why not of the point).
fn bsdf_mix_choice(index: u32, sample: u32, depth: u32) -> f32 {
    var h = sampler_hash_combine(sampler_key, BSDF_MIX_SALT);
    h = sampler_hash_combine(h, sample);
    h = sampler_hash_combine(h, depth);
    h = sampler_hash_combine(h, index);
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// The material drawn at `hit` for material `index` at vertex `depth` of sample `sample`: itself,
// or the one its mixes choose there, with the hit's shading normal tilted by the bump and normal
// maps met on the way (`bsdf::mix::resolve`; their tangents at shutter time `time`).
fn bsdf_resolve_material(index: u32, hit: ptr<function, Hit>, sample: u32, depth: u32, time: f32) -> Material {
    var i = index;
    var m = material_at(i);
    let mixes = has_material_kind(MATERIAL_MIX);
    let maps = has_material_kind(MATERIAL_BUMP) || has_material_kind(MATERIAL_NORMAL_MAP);
    if (!mixes && !maps) {
        return m;
    }
    for (var step = 0u; step < BSDF_MAX_RESOLVE_STEPS; step++) {
        let kind = m.tag & MATERIAL_KIND_MASK;
        if (mixes && kind == MATERIAL_MIX) {
            var amount = m.alpha_u;
            if (has_textures() && (m.tag & MATERIAL_ALPHA_TEXTURE) != 0u) {
                amount = texture_eval_scalar(u32(m.alpha_u), (*hit).uv);
            }
            var second = amount >= 1.0;
            if (amount > 0.0 && amount < 1.0) {
                second = bsdf_mix_choice(i, sample, depth) < amount;
            }
            i = u32(select(m.k.x, m.k.y, second));
        } else if (maps && (kind == MATERIAL_BUMP || kind == MATERIAL_NORMAL_MAP)) {
            let t = detail_tangents(*hit, time);
            if (kind == MATERIAL_BUMP) {
                (*hit).ns = detail_bump(m, t, (*hit).ns, (*hit).uv);
            } else {
                (*hit).ns = detail_normal_map(m, t, (*hit).ns, (*hit).uv);
            }
            i = u32(m.k.x);
        } else {
            break;
        }
        m = material_at(i);
    }
    return m;
}

// ---- Shading point: the BSDF placed on a hit, in world space -----------------------------------

// Place `material` (its textures looked up at the hit's uv) at `hit`, seen from wo (pointing
// away from the surface); a coated material over `base_stored`, the record of its base (its
// k.y, textures looked up too), which no other kind reads (`ShadingPoint::with_base`).
fn shading_point_new(hit: Hit, material_stored: Material, base_stored: Material, wo: vec3f) -> ShadingPoint {
    // The material's textures, and a coated one's base's (a loop: one copy of the lookups).
    let coated = bsdf_is_coated(material_stored.tag & MATERIAL_KIND_MASK);
    var records = array<Material, 2>(material_stored, base_stored);
    for (var i = 0u; i < select(1u, 2u, coated); i++) {
        if (has_textures() && (records[i].tag & MATERIAL_TEXTURES) != 0u) {
            records[i] = texture_resolve(records[i], hit.uv);
        }
    }
    let material = records[0];
    let entering = dot(hit.ng, wo) > 0.0;
    let ng = select(-hit.ng, hit.ng, entering);
    let ns = select(hit.ns, -hit.ns, dot(hit.ns, wo) < 0.0);
    var bsdf = bsdf_new(material, entering);
    if (coated) {
        bsdf.layered = layered_new(material, records[1]);
    }
    return ShadingPoint(hit.p, hit.err, ng, frame_from_normal(ns), bsdf);
}

// f·|cos θi| for world directions; zero when the shading frame and the geometric surface
// disagree on the side of wi (a shading normal must not let light leak through, nor turn a
// reflection into a transmission).
fn shading_point_eval(sp: ShadingPoint, wo: vec3f, wi: vec3f) -> vec3f {
    let local = frame_to_local(sp.frame, wi);
    let above = dot(sp.ng, wi);
    if (above == 0.0 || (above > 0.0) != (local.z > 0.0)) {
        return vec3f(0.0);
    }
    return bsdf_eval(sp.bsdf, frame_to_local(sp.frame, wo), local);
}

fn shading_point_pdf(sp: ShadingPoint, wo: vec3f, wi: vec3f, strategy: u32) -> f32 {
    return bsdf_pdf(sp.bsdf, frame_to_local(sp.frame, wo), frame_to_local(sp.frame, wi), strategy);
}

// A world direction; invalid when the lobe's side (reflection / transmission) and the
// geometric side of wi disagree.
fn shading_point_sample(sp: ShadingPoint, wo: vec3f, u_dir: vec2f, u_lobe: f32, strategy: u32) -> BsdfSample {
    var s = bsdf_sample(sp.bsdf, frame_to_local(sp.frame, wo), u_dir, u_lobe, strategy);
    if (!s.valid) {
        return s;
    }
    let reflected = s.wi.z > 0.0;
    s.wi = frame_to_world(sp.frame, s.wi);
    let above = dot(sp.ng, s.wi) > 0.0;
    s.valid = reflected == above;
    return s;
}
