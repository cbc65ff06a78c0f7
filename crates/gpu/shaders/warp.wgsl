// needs: frame
// Warps: maps from [0,1)^k to points and directions, with their densities. Mirrors
// `crates/sampling/src/warp.rs` and `warp/{ggx,line,spherical_triangle,spherical_rectangle}.rs`
// (the pixel filter is `filter.wgsl`). Local directions have z up; pdfs are per solid angle
// unless stated.
//
// Rust `Option<(Vec3, f32)>` becomes a struct with a `valid: bool` field.
//
// Interface (other modules may call):
//   fn warp_uniform_hemisphere(u: vec2f) -> vec3f        fn warp_uniform_hemisphere_pdf() -> f32
//   fn warp_cosine_hemisphere(u: vec2f) -> vec3f         fn warp_cosine_hemisphere_pdf(cos_theta: f32) -> f32
//   fn warp_uniform_sphere(u: vec2f) -> vec3f            fn warp_uniform_sphere_pdf() -> f32
//   fn warp_concentric_disk(u: vec2f) -> vec2f           fn warp_concentric_disk_pdf() -> f32
//   fn warp_uniform_cone(u: vec2f, cos_max: f32) -> vec3f  fn warp_uniform_cone_pdf(cos_max: f32) -> f32
//   fn warp_uniform_triangle(u: vec2f) -> vec3f          (barycentrics b0, b1, b2)
//   fn warp_line_segment(a: vec3f, b: vec3f, u: f32) -> vec3f
//   fn warp_ggx_d(h: vec3f, alpha: vec2f) -> f32          fn warp_ggx_lambda(w: vec3f, alpha: vec2f) -> f32
//   fn warp_ggx_g1(w: vec3f, alpha: vec2f) -> f32         fn warp_ggx_g2(wo: vec3f, wi: vec3f, alpha: vec2f, separable: bool) -> f32
//   fn warp_ggx_sample_vndf(wo: vec3f, alpha: vec2f, u: vec2f) -> vec3f
//   fn warp_ggx_vndf_pdf(wo: vec3f, h: vec3f, alpha: vec2f) -> f32
//   fn warp_ggx_reflect(wo: vec3f, h: vec3f) -> vec3f
//   fn warp_ggx_reflection_pdf(wo: vec3f, wi: vec3f, alpha: vec2f) -> f32
//   struct WarpSphericalTriangleSample { valid: bool, dir: vec3f, pdf: f32 }
//   fn warp_spherical_triangle_solid_angle(p, a, b, c: vec3f) -> f32
//   fn warp_spherical_triangle_sample(p, a, b, c: vec3f, u: vec2f) -> WarpSphericalTriangleSample
//   struct WarpSphericalRectangleSample { valid: bool, point: vec3f, pdf: f32 }
//   fn warp_spherical_rectangle_solid_angle(p, corner, ex, ey: vec3f) -> f32
//   fn warp_spherical_rectangle_sample(p, corner, ex, ey: vec3f, u: vec2f) -> WarpSphericalRectangleSample
//   struct WarpSphRectSetup { valid: bool, …, omega: f32 }: the rectangle seen from p, set up once
//   fn warp_sph_rect_setup(p, corner, ex, ey: vec3f) -> WarpSphRectSetup
//   fn warp_sph_rect_point(s: WarpSphRectSetup, corner, ex, ey: vec3f, u: vec2f) -> vec3f
// ---- Hemisphere, sphere, disk, cone, triangle ------------------------------------------------

fn warp_uniform_hemisphere(u: vec2f) -> vec3f {
    // cos θ uniform in [0, 1): equal solid angle per slice (Archimedes).
    let z = u.x;
    let r = sqrt(max((1.0 - z) * (1.0 + z), 0.0));
    let phi = TAU * u.y;
    return vec3f(r * cos(phi), r * sin(phi), z);
}

fn warp_uniform_hemisphere_pdf() -> f32 {
    return INV_PI * 0.5;
}

// Malley's method: uniform on the disk, lifted onto the hemisphere.
fn warp_cosine_hemisphere(u: vec2f) -> vec3f {
    let d = warp_concentric_disk(u);
    let z = sqrt(max(1.0 - dot(d, d), 0.0));
    return vec3f(d.x, d.y, z);
}

fn warp_cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    return max(cos_theta, 0.0) * INV_PI;
}

fn warp_uniform_sphere(u: vec2f) -> vec3f {
    // z uniform in (-1, 1]; sin θ from 1 − z² = 4 u (1 − u), exact near the poles.
    let z = 1.0 - 2.0 * u.x;
    let r = 2.0 * sqrt(max(u.x * (1.0 - u.x), 0.0));
    let phi = TAU * u.y;
    return vec3f(r * cos(phi), r * sin(phi), z);
}

fn warp_uniform_sphere_pdf() -> f32 {
    return INV_PI * 0.25;
}

// Clarberg's equal-area map between the unit square and the sphere, pbrt-v4's octahedral layout
// (warp/equal_area.rs): the square's centre +z, its corners −z. Signs by comparison, as there.
fn warp_equal_area_square_to_sphere(p: vec2f) -> vec3f {
    let u = 2.0 * p.x - 1.0;
    let v = 2.0 * p.y - 1.0;
    let up = abs(u);
    let vp = abs(v);
    let sd = 1.0 - (up + vp);
    let r = 1.0 - abs(sd);
    var phi = 1.0;
    if (r != 0.0) {
        phi = (vp - up) / r + 1.0;
    }
    phi = phi * 0.7853981633974483;
    let z = select(1.0 - r * r, -(1.0 - r * r), sd < 0.0);
    let sin_phi = sin(phi);
    let cos_phi = cos(phi);
    let s = r * sqrt(max(2.0 - r * r, 0.0));
    return vec3f(select(cos_phi, -cos_phi, u < 0.0) * s, select(sin_phi, -sin_phi, v < 0.0) * s, z);
}

// The point of the square of unit direction d, the angle by pbrt-v4's polynomial for 2/π·atan in
// the same operations and order as warp/equal_area.rs (the same bits on lavapipe).
fn warp_equal_area_sphere_to_square(d: vec3f) -> vec2f {
    let x = abs(d.x);
    let y = abs(d.y);
    let z = abs(d.z);
    let r = sqrt(max(1.0 - z, 0.0));
    let a = max(x, y);
    var b = 0.0;
    if (a != 0.0) {
        b = min(x, y) / a;
    }
    let phi = 4.067586e-6
        + b * (0.6362265
            + b * (0.6157202e-2
                + b * (-0.24733373
                    + b * (0.8817707e-1 + b * (0.4190388e-1 + b * -0.25139097e-1)))));
    let near = phi * r;
    var u = r - near;
    var v = near;
    if (x < y) {
        u = near;
        v = r - near;
    }
    if (d.z < 0.0) {
        let t = u;
        u = 1.0 - v;
        v = 1.0 - t;
    }
    if (d.x < 0.0) {
        u = -u;
    }
    if (d.y < 0.0) {
        v = -v;
    }
    return vec2f(0.5 * (u + 1.0), 0.5 * (v + 1.0));
}

// Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square".
fn warp_concentric_disk(u: vec2f) -> vec2f {
    // Map to [-1, 1]² and send concentric squares to concentric circles.
    let o = 2.0 * u - vec2f(1.0);
    if (o.x == 0.0 && o.y == 0.0) {
        return vec2f(0.0);
    }
    var r: f32;
    var theta: f32;
    if (abs(o.x) > abs(o.y)) {
        r = o.x;
        theta = FRAC_PI_4 * (o.y / o.x);
    } else {
        r = o.y;
        theta = FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y);
    }
    return r * vec2f(cos(theta), sin(theta));
}

fn warp_concentric_disk_pdf() -> f32 {
    return INV_PI;
}

// Uniform in the cone cos θ ≥ cos_max around +z; 1 − cos θ is formed directly.
fn warp_uniform_cone(u: vec2f, cos_max: f32) -> vec3f {
    let one_minus_cos = u.x * (1.0 - clamp(cos_max, -1.0, 1.0));
    let z = 1.0 - one_minus_cos;
    let r = sqrt(max(one_minus_cos * (2.0 - one_minus_cos), 0.0));
    let phi = TAU * u.y;
    return vec3f(r * cos(phi), r * sin(phi), z);
}

// 1 / (2π (1 − cos_max)); +inf for a degenerate cone (a delta direction).
fn warp_uniform_cone_pdf(cos_max: f32) -> f32 {
    let one_minus_cos = 1.0 - clamp(cos_max, -1.0, 1.0);
    if (one_minus_cos <= 0.0) {
        return f32_infinity();
    }
    return 1.0 / (TAU * one_minus_cos);
}

// Heitz 2019, "A Low-Distortion Map Between Triangle and Square": barycentrics (b0, b1, b2).
fn warp_uniform_triangle(u: vec2f) -> vec3f {
    var b0: f32;
    var b1: f32;
    if (u.x < u.y) {
        b0 = 0.5 * u.x;
        b1 = u.y - b0;
    } else {
        b1 = 0.5 * u.y;
        b0 = u.x - b1;
    }
    return vec3f(b0, b1, 1.0 - b0 - b1);
}

// Point at fraction u along the segment a → b (length pdf 1 / |b − a|).
fn warp_line_segment(a: vec3f, b: vec3f, u: f32) -> vec3f {
    return a + (b - a) * u;
}

// ---- GGX (Trowbridge–Reitz), local frame, alpha = (αx, αy) > 0 ------------------------------

// D(h) = 1 / (π αx αy q²), q = (h.x/αx)² + (h.y/αy)² + h.z² (finite for tiny α).
fn warp_ggx_d(h: vec3f, alpha: vec2f) -> f32 {
    if (h.z <= 0.0) {
        return 0.0;
    }
    let sx = h.x / alpha.x;
    let sy = h.y / alpha.y;
    let q = sx * sx + sy * sy + h.z * h.z;
    return 1.0 / (PI * alpha.x * alpha.y * q * q);
}

// Smith Λ(w) = a / (2 (1 + √(1 + a))), a = ((αx w.x)² + (αy w.y)²) / w.z²; +inf at grazing w.
fn warp_ggx_lambda(w: vec3f, alpha: vec2f) -> f32 {
    if (w.x == 0.0 && w.y == 0.0) {
        return 0.0;
    }
    let sx = alpha.x * w.x;
    let sy = alpha.y * w.y;
    let a = (sx * sx + sy * sy) / (w.z * w.z);
    if (!frame_is_finite(a)) {
        return f32_infinity();
    }
    return a / (2.0 * (1.0 + sqrt(1.0 + a)));
}

fn warp_ggx_g1(w: vec3f, alpha: vec2f) -> f32 {
    return 1.0 / (1.0 + warp_ggx_lambda(w, alpha));
}

// Masking-shadowing: separable G1(wo) G1(wi), or height-correlated (`ggx::Masking`).
fn warp_ggx_g2(wo: vec3f, wi: vec3f, alpha: vec2f, separable: bool) -> f32 {
    if (separable) {
        return warp_ggx_g1(wo, alpha) * warp_ggx_g1(wi, alpha);
    }
    return 1.0 / (1.0 + warp_ggx_lambda(wo, alpha) + warp_ggx_lambda(wi, alpha));
}

// Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT 7(4)); wo.z > 0.
fn warp_ggx_sample_vndf(wo: vec3f, alpha: vec2f, u: vec2f) -> vec3f {
    // Stretch the view direction to the hemisphere configuration (α = 1).
    let vh = frame_normalize_or(vec3f(alpha.x * wo.x, alpha.y * wo.y, wo.z), vec3f(0.0, 0.0, 1.0));
    // Orthonormal basis around it (T1 horizontal).
    let len2 = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3f(1.0, 0.0, 0.0);
    if (len2 > 0.0) {
        t1 = vec3f(-vh.y, vh.x, 0.0) / sqrt(len2);
    }
    let t2 = cross(vh, t1);
    // Uniform point on the disk, warped onto the projected visible half-disk.
    let r = sqrt(u.x);
    let phi = TAU * u.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    // Lift onto the hemisphere, then unstretch back to the ellipsoid.
    let pz = sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    let nh = p1 * t1 + p2 * t2 + pz * vh;
    return frame_normalize_or(vec3f(alpha.x * nh.x, alpha.y * nh.y, max(nh.z, 0.0)), vec3f(0.0, 0.0, 1.0));
}

// D_wo(h) = G1(wo) max(0, wo·h) D(h) / wo.z.
fn warp_ggx_vndf_pdf(wo: vec3f, h: vec3f, alpha: vec2f) -> f32 {
    if (wo.z <= 0.0) {
        return 0.0;
    }
    return warp_ggx_g1(wo, alpha) * max(dot(wo, h), 0.0) * warp_ggx_d(h, alpha) / wo.z;
}

fn warp_ggx_reflect(wo: vec3f, h: vec3f) -> vec3f {
    return 2.0 * dot(wo, h) * h - wo;
}

// Density of wi = reflect(wo, h): G1(wo) D(h) / (4 wo.z), h = normalize(wo + wi).
fn warp_ggx_reflection_pdf(wo: vec3f, wi: vec3f, alpha: vec2f) -> f32 {
    let h = frame_normalize_or(wo + wi, vec3f(0.0));
    if (wo.z <= 0.0 || dot(wo, h) <= 0.0) {
        return 0.0;
    }
    return warp_ggx_g1(wo, alpha) * warp_ggx_d(h, alpha) / (4.0 * wo.z);
}

// ---- Spherical triangle: Arvo 1995, "Stratified Sampling of Spherical Triangles" -------------
// (rewritten as on the CPU: Van Oosterom–Strackee solid angle, closed-form step 1).

struct WarpSphericalTriangleSample {
    valid: bool,
    dir: vec3f,
    pdf: f32,
}

struct WarpSphTriSetup {
    pa: vec3f,
    la: f32,
    lb: f32,
    lc: f32,
    e_ab: vec3f,
    e_ac: vec3f,
    triple: f32,
    omega: f32,
}

fn warp_sph_tri_setup(p: vec3f, a: vec3f, b: vec3f, c: vec3f) -> WarpSphTriSetup {
    let pa = a - p;
    let pb = b - p;
    let pc = c - p;
    let la = length(pa);
    let lb = length(pb);
    let lc = length(pc);
    let e_ab = b - a;
    let e_ac = c - a;
    let va = pa / la;
    let vb = pb / lb;
    let vc = pc / lc;
    // det(a−p, b−p, c−p) = (a−p)·((b−a)×(c−a)), each factor scaled by its length.
    let triple = dot(va, cross(e_ab / lb, e_ac / lc));
    let denom = 1.0 + dot(va, vb) + dot(vb, vc) + dot(vc, va);
    let omega = 2.0 * frame_atan2(abs(triple), denom);
    return WarpSphTriSetup(pa, la, lb, lc, e_ab, e_ac, triple, omega);
}

fn warp_sph_tri_is_degenerate(s: WarpSphTriSetup) -> bool {
    let finite = s.la > 0.0 && s.lb > 0.0 && s.lc > 0.0 && frame_is_finite(s.omega);
    return !(finite && s.triple != 0.0 && s.omega > 0.0 && frame_is_finite(1.0 / s.omega));
}

// Van Oosterom & Strackee 1983; 0 when p is a vertex.
fn warp_spherical_triangle_solid_angle(p: vec3f, a: vec3f, b: vec3f, c: vec3f) -> f32 {
    let s = warp_sph_tri_setup(p, a, b, c);
    return select(0.0, s.omega, frame_is_finite(s.omega));
}

// (pa + e)/|pa + e| − pa/|pa| without subtracting nearly equal unit vectors.
fn warp_unit_difference(pa: vec3f, la: f32, e: vec3f, lb: f32) -> vec3f {
    return (e - pa * ((2.0 * dot(pa, e) + dot(e, e)) / (la * (la + lb)))) / lb;
}

fn warp_spherical_triangle_sample(p: vec3f, a: vec3f, b: vec3f, c: vec3f, u: vec2f) -> WarpSphericalTriangleSample {
    var out = WarpSphericalTriangleSample(false, vec3f(0.0), 0.0);
    let s = warp_sph_tri_setup(p, a, b, c);
    if (warp_sph_tri_is_degenerate(s)) {
        return out;
    }
    let va = s.pa / s.la;
    let vb = (s.pa + s.e_ab) / s.lb;
    // Unit tangent at â towards ĉ: the part of c − a orthogonal to â.
    let w_raw = s.e_ac - dot(s.e_ac, va) * va;
    let w_rcp = 1.0 / sqrt(dot(w_raw, w_raw));
    if (!(frame_is_finite(w_rcp) && w_rcp > 0.0)) {
        return out;
    }
    let w = w_raw * w_rcp;

    // Step 1: C' = cos t â + sin t w cuts off the sub-triangle (â, b̂, C') of area u₀ Ω.
    let m = dot(s.e_ab, w) / s.lb;
    let det = abs(dot(va, cross(s.e_ab, w))) / s.lb;
    let k = 1.0 + dot(va, vb);
    let hh = 0.5 * u.x * s.omega;
    let sin_h = sin(hh);
    let cos_h = cos(hh);
    let x = det * cos_h - m * sin_h;
    let y = k * sin_h;
    let r2 = x * x + y * y;
    if (!(r2 > 0.0)) {
        return out;
    }
    let sin_t = 2.0 * x * y / r2;
    let one_minus_cos_t = 2.0 * y * y / r2;

    // Step 2: cos θ uniform between 1 and b̂·C' along the arc from b̂ to C'.
    let d = sin_t * w - one_minus_cos_t * va - warp_unit_difference(s.pa, s.la, s.e_ab, s.lb);
    let one_minus_cos_theta = u.y * 0.5 * dot(d, d);
    let sin_theta = sqrt(max(one_minus_cos_theta * (2.0 - one_minus_cos_theta), 0.0));
    let tangent = frame_normalize_or(d - dot(d, vb) * vb, vec3f(0.0));
    let dir = frame_normalize_or((1.0 - one_minus_cos_theta) * vb + sin_theta * tangent, vb);
    out.valid = true;
    out.dir = dir;
    out.pdf = 1.0 / s.omega;
    return out;
}

// ---- Spherical rectangle: Ureña, Fajardo, King 2013 (EGSR), rewritten as on the CPU ---------

struct WarpSphericalRectangleSample {
    valid: bool,
    point: vec3f,
    pdf: f32,
}

struct WarpSphRectSetup {
    valid: bool,
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    exl: f32,
    eyl: f32,
    h: f32,
    delta0: f32,
    omega: f32,
}

// δ(X): signed solid angle of the strip [0, X] × [y0, y1].
fn warp_sph_rect_delta(s: WarpSphRectSetup, x: f32) -> f32 {
    let h = s.h;
    let y0 = s.y0;
    let y1 = s.y1;
    let d2 = x * x + h * h;
    let r0 = sqrt(d2 + y0 * y0);
    let r1 = sqrt(d2 + y1 * y1);
    // y1 r0 − y0 r1 without cancellation when y0, y1 share a sign.
    var n: f32;
    if (y0 * y1 > 0.0) {
        n = s.eyl * (y1 + y0) * d2 / (y1 * r0 + y0 * r1);
    } else {
        n = y1 * r0 - y0 * r1;
    }
    return frame_atan2(x * h * n, h * h * r0 * r1 + x * x * y0 * y1);
}

fn warp_sph_rect_setup(p: vec3f, corner: vec3f, ex: vec3f, ey: vec3f) -> WarpSphRectSetup {
    var s = WarpSphRectSetup(false, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let exl = length(ex);
    let eyl = length(ey);
    let x = ex / exl;
    let z_raw = cross(x, ey);
    let z_rcp = 1.0 / sqrt(dot(z_raw, z_raw));
    if (!(frame_is_finite(z_rcp) && z_rcp > 0.0)) {
        return s;
    }
    let z = z_raw * z_rcp;
    let y = cross(z, x);
    let d = corner - p;
    // Distance to the plane: orientation of the frame does not matter.
    let h = abs(dot(d, z));
    if (!(h > 0.0 && frame_is_finite(exl) && frame_is_finite(eyl))) {
        return s;
    }
    s.x0 = dot(d, x);
    s.y0 = dot(d, y);
    s.x1 = s.x0 + exl;
    s.y1 = s.y0 + eyl;
    s.exl = exl;
    s.eyl = eyl;
    s.h = h;
    s.delta0 = warp_sph_rect_delta(s, s.x0);
    s.omega = warp_sph_rect_delta(s, s.x1) - s.delta0;
    s.valid = s.omega > 0.0 && frame_is_finite(s.omega) && frame_is_finite(1.0 / s.omega);
    return s;
}

// Step 1: the X whose strip [x0, X] holds the fraction u of the solid angle.
fn warp_sph_rect_invert_x(s: WarpSphRectSetup, u: f32) -> f32 {
    let h = s.h;
    let y0 = s.y0;
    let y1 = s.y1;
    let tau = s.delta0 + u * s.omega;
    let sin_t = sin(0.5 * tau);
    let cos_t = cos(0.5 * tau);
    let st2 = sin_t * sin_t;
    let ct2 = cos_t * cos_t;
    // Half of Δω = atan2(h·|ey|, h² + y0 y1) and of Σω = atan2(h (y1 + y0), h² − y0 y1).
    let a2 = warp_half_angle_sq(h * s.eyl, h * h + y0 * y1);
    let b2 = warp_half_angle_sq(h * (y1 + y0), h * h - y0 * y1);
    let pq = (a2.x * ct2 - a2.y * st2) * (b2.y * ct2 - b2.x * st2);
    let x = h * sin_t * cos_t / sqrt(max(pq, F32_MIN_POSITIVE));
    return clamp(x, s.x0, s.x1);
}

// (sin²(θ/2), cos²(θ/2)) of θ = atan2(y, x), |θ| ≤ π, without trigonometry (the one whose
// numerator would cancel as y² / (2r (r ± x))).
fn warp_half_angle_sq(y: f32, x: f32) -> vec2f {
    let r = sqrt(x * x + y * y);
    if (x >= 0.0) {
        return vec2f(y * y / (2.0 * r * (r + x)), (r + x) / (2.0 * r));
    }
    return vec2f((r - x) / (2.0 * r), y * y / (2.0 * r * (r - x)));
}

// Step 2: the Y at column x whose y/√(d² + y²) is the fraction v between the ends.
fn warp_sph_rect_invert_y(s: WarpSphRectSetup, x: f32, v: f32) -> f32 {
    let y0 = s.y0;
    let y1 = s.y1;
    let d2 = x * x + s.h * s.h;
    let m0 = sqrt(d2 + y0 * y0);
    let m1 = sqrt(d2 + y1 * y1);
    let s0 = y0 / m0;
    // s1 − s0 without cancellation when y0, y1 share a sign.
    var ds: f32;
    if (y0 * y1 > 0.0) {
        ds = s.eyl * (y1 + y0) * d2 / ((y1 * m0 + y0 * m1) * m0 * m1);
    } else {
        ds = y1 / m1 - s0;
    }
    let sv = s0 + v * ds;
    let c2 = (1.0 - sv) * (1.0 + sv);
    if (!(c2 > 0.0)) {
        // ±∞ clamped to the rectangle (sign of sv, as f32::signum).
        return select(y0, y1, sv > 0.0 || (sv == 0.0 && bitcast<u32>(sv) == 0u));
    }
    return clamp(sv * sqrt(d2) / sqrt(c2), y0, y1);
}

// Solid angle of corner + s·ex + t·ey (ex ⟂ ey) from p; 0 when p lies in its plane.
fn warp_spherical_rectangle_solid_angle(p: vec3f, corner: vec3f, ex: vec3f, ey: vec3f) -> f32 {
    let s = warp_sph_rect_setup(p, corner, ex, ey);
    return select(0.0, s.omega, s.valid);
}

// A point on the rectangle, uniform in solid angle from p, with pdf 1 / Ω.
fn warp_spherical_rectangle_sample(p: vec3f, corner: vec3f, ex: vec3f, ey: vec3f, u: vec2f) -> WarpSphericalRectangleSample {
    let s = warp_sph_rect_setup(p, corner, ex, ey);
    if (!s.valid) {
        return WarpSphericalRectangleSample(false, vec3f(0.0), 0.0);
    }
    return WarpSphericalRectangleSample(true, warp_sph_rect_point(s, corner, ex, ey, u), 1.0 / s.omega);
}

// The point of sample u on the rectangle set up as s (valid), as `Setup::sample` in Rust.
fn warp_sph_rect_point(s: WarpSphRectSetup, corner: vec3f, ex: vec3f, ey: vec3f, u: vec2f) -> vec3f {
    let x = warp_sph_rect_invert_x(s, u.x);
    let y = warp_sph_rect_invert_y(s, x, u.y);
    let fs = clamp((x - s.x0) / s.exl, 0.0, 1.0);
    let ft = clamp((y - s.y0) / s.eyl, 0.0, 1.0);
    return corner + fs * ex + ft * ey;
}
