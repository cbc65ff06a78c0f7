// needs: frame warp motion
// Lights: placement at the ray's time, sampling from a shading point, the solid-angle pdf of
// that sampling (for MIS), the radiance of environment lights, and the alias-table draw.
// Mirrors `crates/cpu/src/light.rs`, `light/*.rs` and `stratapt_scene::light_table::select`:
// same formulas, same branches; `sample` and `pdf` make the same choice of method.
//
// Delta lights (point, line, distant with cos_max ≥ 1) return `delta: true`, `pdf = 1` and a
// `radiance` that already holds what a unit-pdf estimator needs; their pdf is 0.
// Rust `Option<LightSample>` becomes `LightSample.valid`.
//
// Interface (other modules may call):
//   struct LightSample { valid: bool, wi: vec3f, radiance: vec3f, dist: f32, pdf: f32, delta: bool,
//                        n: vec3f, err: vec3f }
//   struct LightChoice { index: u32, pdf: f32 }
//   fn light_placed(index: u32, time: f32) -> Light          (lights[index] at shutter time)
//   fn light_sample(light: Light, p: vec3f, u: vec2f) -> LightSample
//   fn light_pdf(light: Light, p: vec3f, dir: vec3f) -> f32
//   fn light_in_plane(light: Light, p: vec3f, err: vec3f, ng: vec3f) -> bool
//                                                              (p on a planar light's plane)
//   fn light_escaped_radiance(light: Light, dir: vec3f) -> vec3f
//   fn light_is_environment(light: Light) -> bool
//   fn light_select(full_table: bool, u: f32) -> LightChoice  (light_table, else unhittable_table)
struct LightSample {
    valid: bool,
    // Unit direction from the shading point towards the light.
    wi: vec3f,
    // Radiance arriving along wi (delta lights: the unit-pdf equivalent).
    radiance: vec3f,
    // Distance to the sampled point (+inf for directional lights).
    dist: f32,
    // Solid-angle pdf (1 for delta lights).
    pdf: f32,
    delta: bool,
    // Unit normal of the light's surface at the sampled point (zero for points, lines and
    // directions), and the bound on the sampled point's distance from that surface for the
    // offset v = wi·dist as sampling computed it relative to p (light.rs `LightSample`): the
    // shadow ray ends off the surface on p's side.
    n: vec3f,
    err: vec3f,
}

struct LightChoice {
    index: u32,
    pdf: f32,
}

// Generated from `stratapt_scene::shared`: spherical sampling for polygons with solid angle in
// LIGHT_MIN_SPHERICAL_SOLID_ANGLE .. LIGHT_MAX_SPHERICAL_SOLID_ANGLE, area sampling otherwise;
// sphere lights sample by area from within r²·LIGHT_SPHERE_INSIDE of the centre, and below
// sin²θmax = LIGHT_SPHERE_SMALL_SIN2 take 1 − cos θmax by its series. Sampled points are computed
// relative to the shading point (differences of nearby coordinates are exact), as precisely 10⁵
// from the origin as at it.

fn light_none() -> LightSample {
    return LightSample(false, vec3f(0.0), vec3f(0.0), 0.0, 0.0, false, vec3f(0.0), vec3f(0.0));
}

// A sample of a light with no surface (point, line, direction): its end is not offset.
fn light_unoffset(wi: vec3f, dist: f32, radiance: vec3f, pdf: f32, delta: bool) -> LightSample {
    return LightSample(true, wi, radiance, dist, pdf, delta, vec3f(0.0), vec3f(0.0));
}

fn light_use_spherical(solid_angle: f32) -> bool {
    return solid_angle > LIGHT_MIN_SPHERICAL_SOLID_ANGLE
        && solid_angle < LIGHT_MAX_SPHERICAL_SOLID_ANGLE;
}

// A polygon light of squared diameter diameter_sq, its centre at `centre` from the shading
// point, seen under a small angle: sampled by area, with no spherical setup (light.rs
// `seen_small`).
fn light_seen_small(diameter_sq: f32, centre: vec3f) -> bool {
    return diameter_sq < LIGHT_AREA_SAMPLED_ANGULAR_SIZE_SQ * dot(centre, centre);
}

// The solid angle of triangle abc seen from p if the spherical method applies (not seen small,
// moderate Ω), else 0 (area sampling; triangle.rs `spherical`).
fn light_triangle_spherical(a: vec3f, b: vec3f, c: vec3f, p: vec3f) -> f32 {
    let ab = b - a;
    let ac = c - a;
    let bc = c - b;
    let diameter_sq = max(max(dot(ab, ab), dot(ac, ac)), dot(bc, bc));
    if (light_seen_small(diameter_sq, (a - p) + (ab + ac) / 3.0)) {
        return 0.0;
    }
    let solid_angle = warp_spherical_triangle_solid_angle(p, a, b, c);
    return select(0.0, solid_angle, light_use_spherical(solid_angle));
}

// The distance along wi from p to the plane through a of normal n, relative to p (light.rs
// `plane_distance`).
fn light_plane_distance(a: vec3f, n: vec3f, p: vec3f, wi: vec3f) -> f32 {
    return dot(a - p, n) / dot(wi, n);
}

// Area pdf 1/area at distance dist along wi on a surface of normal n, per solid angle:
// dist² / (|cos θ_light| area); 0 edge-on or from the back of a one-sided emitter.
fn light_area_to_solid_angle(area: f32, n: vec3f, wi: vec3f, dist: f32, two_sided: bool) -> f32 {
    var c = -dot(n, wi);
    if (two_sided) {
        c = abs(c);
    }
    // Edge-on, from behind, no area, or an undefined normal (NaN): no density; a product that
    // underflows is not divided by, and one that overflows (10²⁰ scales) is no density either,
    // so that sampling refuses the light and a BSDF ray that hits it keeps its full weight.
    let denom = c * area;
    if (!(c > 0.0 && area > 0.0 && denom > 0.0)) {
        return 0.0;
    }
    let pdf = dist * dist / denom;
    return select(0.0, pdf, frame_is_finite(pdf));
}

// A sample towards the point v from the shading point, with the area pdf converted to solid angle
// (valid if pdf > 0); err bounds the point's distance from the surface of normal n.
fn light_area_sample(v: vec3f, le: vec3f, area: f32, n: vec3f, two_sided: bool, err: vec3f) -> LightSample {
    let dist = length(v);
    let wi = v / dist;
    let pdf = light_area_to_solid_angle(area, n, wi, dist, two_sided);
    return LightSample(pdf > 0.0, wi, le, dist, pdf, false, n, err);
}

// ---- Placement ---------------------------------------------------------------------------------

// The light with its geometry in world space at normalized shutter time `time` (moving lights
// are scaled uniformly: scale.x scales disk and sphere radii).
fn light_placed(index: u32, time: f32) -> Light {
    var l = light_at(index);
    if (!(has_motion() && l.motion != NONE)) {
        return l;
    }
    let pose = motion_at(l.motion, time);
    switch l.kind {
        case LIGHT_TRIANGLE, LIGHT_LINE: {
            l.p0 = motion_pose_point_to_world(pose, l.p0);
            l.p1 = motion_pose_point_to_world(pose, l.p1);
            l.p2 = motion_pose_point_to_world(pose, l.p2);
        }
        case LIGHT_RECTANGLE: {
            l.p0 = motion_pose_point_to_world(pose, l.p0);
            l.p1 = motion_pose_vector_to_world(pose, l.p1);
            l.p2 = motion_pose_vector_to_world(pose, l.p2);
        }
        case LIGHT_DISK: {
            l.p0 = motion_pose_point_to_world(pose, l.p0);
            l.p1 = motion_pose_normal_to_world(pose, l.p1);
            l.p2.x = l.p2.x * pose.scale.x;
        }
        case LIGHT_SPHERE: {
            l.p0 = motion_pose_point_to_world(pose, l.p0);
            l.p2.x = l.p2.x * pose.scale.x;
        }
        case LIGHT_POINT: {
            l.p0 = motion_pose_point_to_world(pose, l.p0);
        }
        case LIGHT_SPOT: {
            l.p0 = motion_pose_point_to_world(pose, l.p0);
            l.p1 = motion_normalize(motion_quat_rotate(pose.rotation, l.p1));
        }
        case LIGHT_DISTANT, LIGHT_SKY: {
            l.p0 = motion_normalize(motion_quat_rotate(pose.rotation, l.p0));
        }
        default: {}
    }
    return l;
}

// ---- Triangle (one-sided): Arvo 1995 spherical sampling, else area -----------------------------

fn light_triangle_sample(a: vec3f, b: vec3f, c: vec3f, le: vec3f, p: vec3f, u: vec2f) -> LightSample {
    let nn = cross(b - a, c - a);
    let area = 0.5 * length(nn);
    let n = frame_normalize_or(nn, vec3f(0.0));
    // Only the front side emits; a point on the plane sees nothing.
    if (dot(n, p - a) <= 0.0 || area <= 0.0) {
        return light_none();
    }
    let solid_angle = light_triangle_spherical(a, b, c, p);
    if (solid_angle > 0.0) {
        let s = warp_spherical_triangle_sample(p, a, b, c, u);
        if (!s.valid) {
            return light_none();
        }
        let dist = light_plane_distance(a, n, p, s.dir);
        let ok = dist > 0.0 && frame_is_finite(dist);
        let err = vec3f(GAMMA_16 * (length(a - p) + dist));
        return LightSample(ok, s.dir, le, dist, 1.0 / solid_angle, false, n, err);
    }
    let bary = warp_uniform_triangle(u);
    // One difference of far-apart coordinates at most (a − p), the edges' parts small.
    let pa = a - p;
    let ab = b - a;
    let ac = c - a;
    let err = GAMMA_6 * (abs(pa) + abs(ab) + abs(ac));
    return light_area_sample(pa + ab * bary.y + ac * bary.z, le, area, n, false, err);
}

fn light_triangle_pdf(a: vec3f, b: vec3f, c: vec3f, p: vec3f, wi: vec3f) -> f32 {
    let nn = cross(b - a, c - a);
    let area = 0.5 * length(nn);
    let n = frame_normalize_or(nn, vec3f(0.0));
    if (dot(n, p - a) <= 0.0 || area <= 0.0) {
        return 0.0;
    }
    let solid_angle = light_triangle_spherical(a, b, c, p);
    if (solid_angle > 0.0) {
        return 1.0 / solid_angle;
    }
    return light_area_to_solid_angle(area, n, wi, light_plane_distance(a, n, p, wi), false);
}

// ---- Rectangle (one-sided): Ureña et al. 2013 spherical sampling, else area --------------------

// The spherical rectangle seen from p if the spherical method applies (orthogonal edges, not
// seen under a small angle, moderate Ω), else an invalid setup (area sampling). Set up once per
// sample: it holds Ω and draws the point (the Rust mirror is `rectangle::spherical`).
fn light_rectangle_spherical(p: vec3f, corner: vec3f, ex: vec3f, ey: vec3f) -> WarpSphRectSetup {
    let orthogonal = abs(dot(ex, ey)) <= 1e-4 * length(ex) * length(ey);
    let small = light_seen_small(dot(ex, ex) + dot(ey, ey), (corner - p) + 0.5 * (ex + ey));
    if (!orthogonal || small) {
        return WarpSphRectSetup(false, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    }
    var s = warp_sph_rect_setup(p, corner, ex, ey);
    s.valid = s.valid && light_use_spherical(s.omega);
    return s;
}

fn light_rectangle_sample(corner: vec3f, ex: vec3f, ey: vec3f, le: vec3f, p: vec3f, u: vec2f) -> LightSample {
    let nn = cross(ex, ey);
    let area = length(nn);
    let n = frame_normalize_or(nn, vec3f(0.0));
    if (dot(n, p - corner) <= 0.0 || area <= 0.0) {
        return light_none();
    }
    // The point relative to p: the spherical method places it on the rectangle at corner − p.
    let pc = corner - p;
    let err = GAMMA_5 * (abs(pc) + abs(ex) + abs(ey));
    let rect = light_rectangle_spherical(p, corner, ex, ey);
    if (rect.valid) {
        let v = warp_sph_rect_point(rect, pc, ex, ey, u);
        let dist = length(v);
        return LightSample(dist > 0.0, v / dist, le, dist, 1.0 / rect.omega, false, n, err);
    }
    var s = light_area_sample(pc + u.x * ex + u.y * ey, le, area, n, false, err);
    s.valid = s.valid && s.dist > 0.0;
    return s;
}

fn light_rectangle_pdf(corner: vec3f, ex: vec3f, ey: vec3f, p: vec3f, wi: vec3f) -> f32 {
    let nn = cross(ex, ey);
    let area = length(nn);
    let n = frame_normalize_or(nn, vec3f(0.0));
    if (dot(n, p - corner) <= 0.0 || area <= 0.0) {
        return 0.0;
    }
    let rect = light_rectangle_spherical(p, corner, ex, ey);
    if (rect.valid) {
        return 1.0 / rect.omega;
    }
    return light_area_to_solid_angle(area, n, wi, light_plane_distance(corner, n, p, wi), false);
}

// ---- Disk (one-sided): uniform area by the concentric map ---------------------------------------

fn light_disk_sample(center: vec3f, normal: vec3f, radius: f32, le: vec3f, p: vec3f, u: vec2f) -> LightSample {
    if (dot(normal, p - center) <= 0.0) {
        return light_none();
    }
    let frame = frame_from_normal(normal);
    let d = warp_concentric_disk(u) * radius;
    let pc = center - p;
    let err = GAMMA_5 * (abs(pc) + vec3f(radius));
    return light_area_sample(pc + frame.s * d.x + frame.t * d.y, le, PI * radius * radius, normal,
        false, err);
}

fn light_disk_pdf(center: vec3f, normal: vec3f, radius: f32, p: vec3f, wi: vec3f) -> f32 {
    if (dot(normal, p - center) <= 0.0) {
        return 0.0;
    }
    let dist = light_plane_distance(center, normal, p, wi);
    return light_area_to_solid_angle(PI * radius * radius, normal, wi, dist, false);
}

// ---- Sphere: uniform in the subtended cone (pbrt-v4 `SphereShape`), by area from inside --------

// 1 − cos θmax, by its series for small cones.
fn light_sphere_one_minus_cos_max(sin2_max: f32) -> f32 {
    if (sin2_max < LIGHT_SPHERE_SMALL_SIN2) {
        return 0.5 * sin2_max;
    }
    return 1.0 - sqrt(max(1.0 - sin2_max, 0.0));
}

// The centre as seen from p (c − p) and whether p samples by area (sphere.rs `seen_from`): a point
// on the sphere to within LIGHT_SPHERE_ON_ERROR times a sphere hit point's error bound is moved
// onto it (c − p scaled to length r); one inside by LIGHT_SPHERE_INSIDE's margin samples by area.
struct LightSphereView {
    cp: vec3f,
    by_area: bool,
}

fn light_sphere_seen_from(center: vec3f, radius: f32, p: vec3f) -> LightSphereView {
    let cp = center - p;
    let d2 = dot(cp, cp);
    let m = abs(center);
    let e = LIGHT_SPHERE_ON_ERROR * GAMMA_5 * (max(max(m.x, m.y), m.z) + radius);
    let lo = max(radius - e, 0.0);
    let hi = radius + e;
    if (d2 > lo * lo && d2 <= hi * hi) {
        return LightSphereView(cp * (radius / sqrt(d2)), true);
    }
    return LightSphereView(cp, d2 <= radius * radius * LIGHT_SPHERE_INSIDE);
}

// The sampled point's error bound: that of cp + r·n.
fn light_sphere_error(cp: vec3f, radius: f32) -> vec3f {
    return GAMMA_8 * (abs(cp) + vec3f(radius));
}

fn light_sphere_sample(center: vec3f, radius: f32, le: vec3f, p: vec3f, u: vec2f) -> LightSample {
    let view = light_sphere_seen_from(center, radius, p);
    let cp = view.cp;
    // Inside (or on) the sphere: a uniform point on it, two-sided; its bound includes the move
    // onto the surface.
    if (view.by_area) {
        let n = warp_uniform_sphere(u);
        let err = light_sphere_error(cp, radius) + abs(center - p - cp);
        var s = light_area_sample(cp + radius * n, le, 4.0 * PI * radius * radius, n, true, err);
        s.valid = s.valid && frame_is_finite(s.pdf);
        return s;
    }
    let d2 = dot(cp, cp);
    // Direction in the cone: cos θ uniform in [cos θmax, 1].
    let sin2_max = radius * radius / d2;
    let sin_max = sqrt(sin2_max);
    let omc = light_sphere_one_minus_cos_max(sin2_max);
    var sin2: f32;
    var cos_t: f32;
    if (sin2_max < LIGHT_SPHERE_SMALL_SIN2) {
        sin2 = sin2_max * u.x;
        cos_t = sqrt(1.0 - sin2);
    } else {
        cos_t = 1.0 - omc * u.x;
        sin2 = 1.0 - cos_t * cos_t;
    }
    // Angle α at the centre between the axis and the sampled point.
    let cos_alpha = sin2 / sin_max + cos_t * sqrt(max(1.0 - sin2 / sin2_max, 0.0));
    let sin_alpha = sqrt(max(1.0 - cos_alpha * cos_alpha, 0.0));
    let phi = 2.0 * PI * u.y;
    let frame = frame_from_normal(cp / sqrt(d2));
    let n = -frame_to_world(frame, vec3f(sin_alpha * cos(phi), sin_alpha * sin(phi), cos_alpha));
    let v = cp + radius * n;
    let dist = length(v);
    let err = light_sphere_error(cp, radius);
    return LightSample(true, v / dist, le, dist, 1.0 / (2.0 * PI * omc), false, n, err);
}

fn light_sphere_pdf(center: vec3f, radius: f32, p: vec3f, wi: vec3f) -> f32 {
    let view = light_sphere_seen_from(center, radius, p);
    let cp = view.cp;
    let d2 = dot(cp, cp);
    if (view.by_area) {
        // Where the ray along wi leaves the sphere (the far root of |t·wi − cp| = r), from cp.
        let b = dot(wi, cp);
        let dist = b + sqrt(max(b * b - (d2 - radius * radius), 0.0));
        let n = (wi * dist - cp) / radius;
        return light_area_to_solid_angle(4.0 * PI * radius * radius, n, wi, dist, true);
    }
    // A cone of no solid angle (a point-sized sphere) cannot be hit: pdf 0, not 1/0.
    let omc = light_sphere_one_minus_cos_max(radius * radius / d2);
    return select(0.0, 1.0 / (2.0 * PI * omc), omc > 0.0);
}

// ---- Delta lights: line segment, point ---------------------------------------------------------

fn light_line_sample(a: vec3f, b: vec3f, intensity: vec3f, p: vec3f, u: vec2f) -> LightSample {
    let v = warp_line_segment(a - p, b - p, u.x);
    let dist2 = dot(v, v);
    if (dist2 <= 0.0) {
        return light_none();
    }
    let dist = sqrt(dist2);
    let wi = v / dist;
    // len · sin θ = |wi × (b − a)|.
    let len_sin = length(cross(wi, b - a));
    return light_unoffset(wi, dist, intensity * (len_sin / dist2), 1.0, true);
}

fn light_point_sample(position: vec3f, intensity: vec3f, p: vec3f) -> LightSample {
    let v = position - p;
    let dist2 = dot(v, v);
    if (dist2 <= 0.0) {
        return light_none();
    }
    let dist = sqrt(dist2);
    return light_unoffset(v / dist, dist, intensity / dist2, 1.0, true);
}

// pbrt-v4's SmoothStep: 0 below a, 1 above b, t²(3 − 2t) between; a step at a when a = b.
fn light_smoothstep(a: f32, b: f32, x: f32) -> f32 {
    if (a == b) {
        return select(1.0, 0.0, x < a);
    }
    let t = clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Spot (light/spot.rs): a point light along unit `axis`, smoothstep(cos_end, cos_start, cos θ).
fn light_spot_sample(position: vec3f, axis: vec3f, cos_end: f32, cos_start: f32,
                     intensity: vec3f, p: vec3f) -> LightSample {
    let v = position - p;
    let dist2 = dot(v, v);
    if (dist2 <= 0.0) {
        return light_none();
    }
    let dist = sqrt(dist2);
    let wi = v / dist;
    let falloff = light_smoothstep(cos_end, cos_start, -dot(wi, axis));
    if (falloff <= 0.0) {
        return light_none();
    }
    return light_unoffset(wi, dist, intensity * (falloff / dist2), 1.0, true);
}

// ---- Directional: distant (sun cone or delta), sky gradient --------------------------------------

fn light_distant_sample(dir: vec3f, cos_max: f32, le: vec3f, u: vec2f) -> LightSample {
    if (cos_max >= 1.0) {
        return light_unoffset(dir, f32_infinity(), le, 1.0, true);
    }
    let wi = frame_to_world(frame_from_normal(dir), warp_uniform_cone(u, cos_max));
    return light_unoffset(wi, f32_infinity(), le, warp_uniform_cone_pdf(cos_max), false);
}

fn light_in_cone(dir: vec3f, cos_max: f32, wi: vec3f) -> bool {
    return cos_max < 1.0 && dot(wi, dir) >= cos_max;
}

// Sky: bottom (the light's radiance) → top (p1) by 0.5 (1 + wi·up) (`Vec3::lerp`).
fn light_sky_radiance(up: vec3f, top: vec3f, bottom: vec3f, wi: vec3f) -> vec3f {
    let s = 0.5 * (1.0 + dot(wi, up));
    return bottom * (1.0 - s) + top * s;
}

// ---- Environment map (light/environment.rs, stratapt_scene::environment, warp::piecewise) --------
// Its data in `tables` from o = p2.z: texels (RGB, w × h, top row first), then the
// piecewise-constant distribution's marginal CDF (h + 1 entries) and each row's conditional CDF
// (w + 1). p0, p1: the first two rows of the world → map rotation.

fn light_env_to_map(light: Light, dir: vec3f) -> vec3f {
    let r2 = cross(light.p0, light.p1);
    return vec3f(dot(light.p0, dir), dot(light.p1, dir), dot(r2, dir));
}

// (u, v) of a map direction (`environment::direction_to_uv`).
fn light_env_uv(d: vec3f) -> vec2f {
    var u = frame_atan2(d.x, -d.z) * (0.5 * INV_PI);
    u = u - floor(u);
    if (u >= 1.0) {
        u = 0.0;
    }
    let v = frame_atan2(sqrt(d.x * d.x + d.z * d.z), d.y) * INV_PI;
    return vec2f(u, v);
}

fn light_env_texel(o: u32, w: u32, r: u32, c: u32) -> vec3f {
    let i = o + 3u * (r * w + c);
    return vec3f(table_f32(i), table_f32(i + 1u), table_f32(i + 2u));
}

// The radiance along world direction dir.
fn light_env_radiance(light: Light, dir: vec3f) -> vec3f {
    return light_env_lookup(light, light_env_to_map(light, dir));
}

// Mitsuba's bilinear lookup at map direction d (`environment::lookup`): x = u·w − ½ wrapping,
// y = v·(h − 1).
fn light_env_lookup(light: Light, d: vec3f) -> vec3f {
    let w = u32(light.p2.x);
    let h = u32(light.p2.y);
    let o = u32(light.p2.z);
    let uv = light_env_uv(d);
    let x = uv.x * f32(w) - 0.5;
    let y = clamp(uv.y, 0.0, 1.0) * f32(h - 1u);
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let c0 = u32((i32(x0) + i32(w)) % i32(w));
    let c1 = u32((i32(x0) + 1 + i32(w)) % i32(w));
    let r0 = min(u32(y0), h - 1u);
    let r1 = min(r0 + 1u, h - 1u);
    let top = light_env_texel(o, w, r0, c0) * (1.0 - fx) + light_env_texel(o, w, r0, c1) * fx;
    let bottom = light_env_texel(o, w, r1, c0) * (1.0 - fx) + light_env_texel(o, w, r1, c1) * fx;
    return top * (1.0 - fy) + bottom * fy;
}

// The largest i < n with cdf[i] ≤ u, the CDF at tables[start..] (`piecewise::find`).
fn light_env_find(start: u32, n: u32, u: f32) -> u32 {
    var lo = 0u;
    var hi = n;
    while (hi - lo > 1u) {
        let mid = (lo + hi) / 2u;
        if (table_f32(start + mid) <= u) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// A point drawn from the piecewise-constant distribution of a w × h grid whose tables start at
// `marginal` (`piecewise::sample_cell`): the cell's index (row · w + column), the point in
// [0, 1)², and its density over the square (not > 0: no point).
struct EnvDraw {
    cell: u32,
    p: vec2f,
    density: f32,
}

fn light_env_draw(marginal: u32, w: u32, h: u32, u: vec2f) -> EnvDraw {
    let row = light_env_find(marginal, h, u.y);
    let r0 = table_f32(marginal + row);
    let r1 = table_f32(marginal + row + 1u);
    let conditional = marginal + h + 1u + row * (w + 1u);
    let col = light_env_find(conditional, w, u.x);
    let c0 = table_f32(conditional + col);
    let c1 = table_f32(conditional + col + 1u);
    let pr = r1 - r0;
    let pc = c1 - c0;
    let density = pr * f32(h) * pc * f32(w);
    // Where u falls inside the cell, reused as the position in it (clamped below 1).
    let below_one = 1.0 - F32_EPSILON / 2.0;
    let fx = clamp((u.x - c0) / pc, 0.0, below_one);
    let fy = clamp((u.y - r0) / pr, 0.0, below_one);
    let p = min(vec2f((f32(col) + fx) / f32(w), (f32(row) + fy) / f32(h)), vec2f(below_one));
    return EnvDraw(row * w + col, p, density);
}

fn light_env_sample(light: Light, u: vec2f) -> LightSample {
    let w = u32(light.p2.x);
    let h = u32(light.p2.y);
    let draw = light_env_draw(u32(light.p2.z) + 3u * w * h, w, h, u);
    let density = draw.density;
    if (!(density > 0.0)) {
        return light_none();
    }
    let uv = draw.p;
    let sin_theta = sin(PI * uv.y);
    let cos_theta = cos(PI * uv.y);
    let sin_phi = sin(2.0 * PI * uv.x);
    let cos_phi = cos(2.0 * PI * uv.x);
    let d = vec3f(sin_phi * sin_theta, cos_theta, -cos_phi * sin_theta);
    let pdf = density / (2.0 * PI * PI * sin_theta);
    if (!(sin_theta > 0.0 && frame_is_finite(pdf))) {
        return light_none();
    }
    // Map → world: the transpose of world → map.
    let wi = light.p0 * d.x + light.p1 * d.y + cross(light.p0, light.p1) * d.z;
    return light_unoffset(wi, f32_infinity(), light_env_lookup(light, d), pdf, false);
}

fn light_env_pdf(light: Light, dir: vec3f) -> f32 {
    let d = light_env_to_map(light, dir);
    let sin_theta = sqrt(d.x * d.x + d.z * d.z);
    if (!(sin_theta > 0.0)) {
        return 0.0;
    }
    let w = u32(light.p2.x);
    let h = u32(light.p2.y);
    let marginal = u32(light.p2.z) + 3u * w * h;
    let uv = light_env_uv(d);
    let col = min(u32(uv.x * f32(w)), w - 1u);
    let row = min(u32(uv.y * f32(h)), h - 1u);
    let conditional = marginal + h + 1u + row * (w + 1u);
    let pr = table_f32(marginal + row + 1u) - table_f32(marginal + row);
    let pc = table_f32(conditional + col + 1u) - table_f32(conditional + col);
    return pr * f32(h) * pc * f32(w) / (2.0 * PI * PI * sin_theta);
}

// ---- Octahedral environment map (environment/octahedral.rs) ------------------------------------
// pbrt-v4's equal-area square map, w × w texels, laid out in `tables` as the latitude–longitude
// map's; the nearest texel, no filtering. p2 = (w, w, offset), p0, p1 as there.

// The texel (row · w + column) holding point p of the square (`octahedral::texel`).
fn light_oct_texel(w: u32, p: vec2f) -> u32 {
    let col = min(u32(p.x * f32(w)), w - 1u);
    let row = min(u32(p.y * f32(w)), w - 1u);
    return row * w + col;
}

fn light_oct_rgb(o: u32, i: u32) -> vec3f {
    return vec3f(table_f32(o + 3u * i), table_f32(o + 3u * i + 1u), table_f32(o + 3u * i + 2u));
}

fn light_oct_radiance(light: Light, dir: vec3f) -> vec3f {
    let w = u32(light.p2.x);
    let p = warp_equal_area_sphere_to_square(light_env_to_map(light, dir));
    return light_oct_rgb(u32(light.p2.z), light_oct_texel(w, p));
}

fn light_oct_sample(light: Light, u: vec2f) -> LightSample {
    let w = u32(light.p2.x);
    let o = u32(light.p2.z);
    let draw = light_env_draw(o + 3u * w * w, w, w, u);
    if (!(draw.density > 0.0)) {
        return light_none();
    }
    let d = warp_equal_area_square_to_sphere(draw.p);
    let wi = light.p0 * d.x + light.p1 * d.y + cross(light.p0, light.p1) * d.z;
    return light_unoffset(wi, f32_infinity(), light_oct_rgb(o, draw.cell),
        draw.density * warp_uniform_sphere_pdf(), false);
}

fn light_oct_pdf(light: Light, dir: vec3f) -> f32 {
    let w = u32(light.p2.x);
    let marginal = u32(light.p2.z) + 3u * w * w;
    let cell = light_oct_texel(w, warp_equal_area_sphere_to_square(light_env_to_map(light, dir)));
    let col = cell % w;
    let row = cell / w;
    let conditional = marginal + w + 1u + row * (w + 1u);
    let pr = table_f32(marginal + row + 1u) - table_f32(marginal + row);
    let pc = table_f32(conditional + col + 1u) - table_f32(conditional + col);
    return pr * f32(w) * pc * f32(w) * warp_uniform_sphere_pdf();
}

// ---- Dispatch ------------------------------------------------------------------------------------

// A two-sided triangle, rectangle or disk (LIGHT_FLAG_TWO_SIDED) seen from behind, turned round
// to face p: a triangle's winding reversed, a rectangle's edges swapped, a disk's normal negated
// (light.rs `turned_to`); every other light, and every other point, as it is.
fn light_turned_to(light: Light, p: vec3f) -> Light {
    var l = light;
    if ((light.flags & LIGHT_FLAG_TWO_SIDED) == 0u) {
        return l;
    }
    let a = light.p0;
    let b = light.p1;
    let c = light.p2;
    if (light.kind == LIGHT_TRIANGLE && dot(cross(b - a, c - a), p - a) <= 0.0) {
        l.p1 = c;
        l.p2 = b;
    } else if (light.kind == LIGHT_RECTANGLE && dot(cross(b, c), p - a) <= 0.0) {
        l.p1 = c;
        l.p2 = b;
    } else if (light.kind == LIGHT_DISK && dot(b, p - a) <= 0.0) {
        l.p1 = -b;
    }
    return l;
}

// A direction from p towards `light_given` (already placed).
fn light_sample(light_given: Light, p: vec3f, u: vec2f) -> LightSample {
    let light = light_turned_to(light_given, p);
    let a = light.p0;
    let b = light.p1;
    let c = light.p2;
    let le = light.radiance;
    var s = light_none();
    let kind = light.kind;
    if (kind == LIGHT_TRIANGLE && has_light_kind(LIGHT_TRIANGLE)) {
        s = light_triangle_sample(a, b, c, le, p, u);
    } else if (kind == LIGHT_RECTANGLE && has_light_kind(LIGHT_RECTANGLE)) {
        s = light_rectangle_sample(a, b, c, le, p, u);
    } else if (kind == LIGHT_DISK && has_light_kind(LIGHT_DISK)) {
        s = light_disk_sample(a, b, c.x, le, p, u);
    } else if (kind == LIGHT_SPHERE && has_light_kind(LIGHT_SPHERE)) {
        s = light_sphere_sample(a, c.x, le, p, u);
    } else if (kind == LIGHT_LINE && has_light_kind(LIGHT_LINE)) {
        s = light_line_sample(a, b, le, p, u);
    } else if (kind == LIGHT_POINT && has_light_kind(LIGHT_POINT)) {
        s = light_point_sample(a, le, p);
    } else if (kind == LIGHT_SPOT && has_light_kind(LIGHT_SPOT)) {
        s = light_spot_sample(a, b, c.x, c.y, le, p);
    } else if (kind == LIGHT_DISTANT && has_light_kind(LIGHT_DISTANT)) {
        s = light_distant_sample(a, c.x, le, u);
    } else if (kind == LIGHT_SKY && has_light_kind(LIGHT_SKY)) {
        s = light_unoffset(warp_uniform_sphere(u), f32_infinity(), vec3f(0.0),
            warp_uniform_sphere_pdf(), false);
        s.radiance = light_sky_radiance(a, b, le, s.wi);
    } else if (kind == LIGHT_ENVIRONMENT && has_light_kind(LIGHT_ENVIRONMENT)) {
        s = light_env_sample(light, u);
    } else if (kind == LIGHT_OCTAHEDRAL && has_light_kind(LIGHT_OCTAHEDRAL)) {
        s = light_oct_sample(light, u);
    }
    s.valid = s.valid && s.pdf > 0.0 && frame_is_finite(s.pdf) && frame_is_finite3(s.wi)
        && frame_is_finite3(s.radiance);
    return s;
}

// Whether `p` (within `err` of a surface point) lies in the plane of the planar `light` to within
// that error and the test's rounding, on a surface whose normal ng is parallel to the light's (to
// LIGHT_IN_PLANE_COS): it receives nothing from it (light.rs `in_plane`).
fn light_in_plane(light: Light, p: vec3f, err: vec3f, ng: vec3f) -> bool {
    var n: vec3f;
    if (light.kind == LIGHT_TRIANGLE) {
        n = cross(light.p1 - light.p0, light.p2 - light.p0);
    } else if (light.kind == LIGHT_RECTANGLE) {
        n = cross(light.p1, light.p2);
    } else if (light.kind == LIGHT_DISK) {
        n = light.p1;
    } else {
        return false;
    }
    let u = frame_normalize_or(n, vec3f(0.0));
    if (all(u == vec3f(0.0)) || abs(dot(u, ng)) < LIGHT_IN_PLANE_COS) {
        return false;
    }
    let slack = dot(abs(u), err + GAMMA_3 * (abs(p) + abs(light.p0)));
    return abs(dot(u, p - light.p0)) <= slack;
}

// Solid-angle pdf with which light_sample picks dir from p; where it depends on the point the ray
// reaches (area sampling), that point is found from p and the light's geometry, not from a hit
// point rounded to the coordinates' grid (light.rs `pdf`); 0 for delta lights.
fn light_pdf(light_given: Light, p: vec3f, dir: vec3f) -> f32 {
    let light = light_turned_to(light_given, p);
    let a = light.p0;
    let b = light.p1;
    let c = light.p2;
    let kind = light.kind;
    if (kind == LIGHT_TRIANGLE && has_light_kind(LIGHT_TRIANGLE)) {
        return light_triangle_pdf(a, b, c, p, dir);
    } else if (kind == LIGHT_RECTANGLE && has_light_kind(LIGHT_RECTANGLE)) {
        return light_rectangle_pdf(a, b, c, p, dir);
    } else if (kind == LIGHT_DISK && has_light_kind(LIGHT_DISK)) {
        return light_disk_pdf(a, b, c.x, p, dir);
    } else if (kind == LIGHT_SPHERE && has_light_kind(LIGHT_SPHERE)) {
        return light_sphere_pdf(a, c.x, p, dir);
    } else if (kind == LIGHT_DISTANT && has_light_kind(LIGHT_DISTANT)) {
        return select(0.0, warp_uniform_cone_pdf(c.x), light_in_cone(a, c.x, dir));
    } else if (kind == LIGHT_SKY && has_light_kind(LIGHT_SKY)) {
        return warp_uniform_sphere_pdf();
    } else if (kind == LIGHT_ENVIRONMENT && has_light_kind(LIGHT_ENVIRONMENT)) {
        return light_env_pdf(light, dir);
    } else if (kind == LIGHT_OCTAHEDRAL && has_light_kind(LIGHT_OCTAHEDRAL)) {
        return light_oct_pdf(light, dir);
    }
    return 0.0;
}

// Radiance an escaping ray in direction dir receives (sky, environment map, sun cone; 0
// otherwise).
fn light_escaped_radiance(light: Light, dir: vec3f) -> vec3f {
    if (light.kind == LIGHT_DISTANT && has_light_kind(LIGHT_DISTANT)) {
        return select(vec3f(0.0), light.radiance, light_in_cone(light.p0, light.p2.x, dir));
    }
    if (light.kind == LIGHT_SKY && has_light_kind(LIGHT_SKY)) {
        return light_sky_radiance(light.p0, light.p1, light.radiance, dir);
    }
    if (light.kind == LIGHT_ENVIRONMENT && has_light_kind(LIGHT_ENVIRONMENT)) {
        return light_env_radiance(light, dir);
    }
    if (light.kind == LIGHT_OCTAHEDRAL && has_light_kind(LIGHT_OCTAHEDRAL)) {
        return light_oct_radiance(light, dir);
    }
    return vec3f(0.0);
}

// Whether an escaping ray can see the light (sky, environment map, or a sun with a cone).
fn light_is_environment(light: Light) -> bool {
    return light.kind == LIGHT_SKY || light.kind == LIGHT_ENVIRONMENT
        || light.kind == LIGHT_OCTAHEDRAL
        || (light.kind == LIGHT_DISTANT && light.p2.x < 1.0);
}

// Alias-table draw with u ∈ [0, 1) (Walker 1977; `light_table::select`): the full table, or the
// table of lights an escaping ray cannot hit.
fn light_select(full_table: bool, u: f32) -> LightChoice {
    let n = select(params.unhittable_table_len, params.light_table_len, full_table);
    let scaled = u * f32(n);
    let i = min(u32(scaled), n - 1u);
    let v = scaled - f32(i);
    if (full_table) {
        let e = light_table_at(i);
        let j = select(e.alias_index, i, v < e.threshold);
        return LightChoice(j, light_table_at(j).pdf);
    }
    let e = unhittable_table_at(i);
    let j = select(e.alias_index, i, v < e.threshold);
    return LightChoice(j, unhittable_table_at(j).pdf);
}
