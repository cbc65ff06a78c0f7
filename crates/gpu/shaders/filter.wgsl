// needs: nothing
// Pixel-filter importance sampling, mirroring `crates/sampling/src/warp/filter.rs`: offsets from
// the pixel centre, in pixels, distributed exactly as the normalized filter (weight 1).
//
// Interface (other modules may call):
//   fn filter_box_filter(u: vec2f, width: f32) -> vec2f     // offset in [-width/2, width/2)^2
//   fn filter_tent(u: vec2f, radius: f32) -> vec2f          // offset in [-r, r]^2
//   fn filter_tent_pdf(p: vec2f, radius: f32) -> f32
//   fn filter_gaussian(u: vec2f, sigma: f32) -> vec2f       // untruncated, Box–Muller
//   fn filter_gaussian_pdf(p: vec2f, sigma: f32) -> f32
// No Option is involved.

// Box of full width `width`.
fn filter_box_filter(u: vec2f, width: f32) -> vec2f {
    return (u - vec2f(0.5)) * width;
}

// One axis of the tent: the inverse of its CDF.
fn filter_tent_1d(u: f32, r: f32) -> f32 {
    if (u < 0.5) {
        return -r + r * sqrt(max(2.0 * u, 0.0));
    }
    return r - r * sqrt(max(2.0 * (1.0 - u), 0.0));
}

// Separable tent of radius `radius`, by inverting its CDF per axis.
fn filter_tent(u: vec2f, radius: f32) -> vec2f {
    return vec2f(filter_tent_1d(u.x, radius), filter_tent_1d(u.y, radius));
}

// Density of filter_tent per unit area: t(x) t(y), t(x) = max(0, r - |x|) / r^2.
fn filter_tent_pdf(p: vec2f, radius: f32) -> f32 {
    let r2 = radius * radius;
    let tx = max(radius - abs(p.x), 0.0) / r2;
    let ty = max(radius - abs(p.y), 0.0) / r2;
    return tx * ty;
}

// Untruncated isotropic Gaussian of standard deviation sigma (Box–Muller 1958), using 1 - u.x
// so the logarithm never sees 0.
fn filter_gaussian(u: vec2f, sigma: f32) -> vec2f {
    // Radius from the Rayleigh inverse CDF, angle uniform.
    let r = sigma * sqrt(max(-2.0 * log(1.0 - u.x), 0.0));
    let phi = TAU * u.y;
    return vec2f(r * cos(phi), r * sin(phi));
}

// Density of filter_gaussian per unit area: exp(-|p|^2 / 2 sigma^2) / (2 pi sigma^2).
fn filter_gaussian_pdf(p: vec2f, sigma: f32) -> f32 {
    let s2 = sigma * sigma;
    return exp(-dot(p, p) / (2.0 * s2)) / (TAU * s2);
}
