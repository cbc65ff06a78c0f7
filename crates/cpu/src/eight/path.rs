//! The path loop of [`crate::integrator`] for eight paths at once: one path per lane, the
//! vertex's shading, light sample, MIS weights, BSDF sample and roulette in AVX2 vectors, the
//! eight rays of a query traced together (`accel::wave8`). A lane whose path ends takes the next
//! (pixel, sample) of the queue, so the lanes stay busy while paths of different lengths run
//! side by side.
//!
//! What runs lane by lane: the MIS weight of emission a ray finds on a light (few lanes, the
//! one-lane routine), and libm's `sinf`/`cosf` (the reference's bits).

use super::Support;
use super::{rectangle, sobol};
use crate::accel::{Accel, Rays8};
use crate::lanes::{self, bits, flip, mask_of, Mask, LANES, V3};
use crate::light;
use glam::Vec3;
use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4};
use stratapt_sampling::hash;
use stratapt_sampling::mis::power_heuristic;
use stratapt_sampling::warp::spherical_rectangle::Basis;
use stratapt_scene::records::NONE;
use stratapt_scene::shared::{
    AREA_SAMPLED_ANGULAR_SIZE_SQ, GAMMA_3, GAMMA_5, IN_PLANE_COS, MAX_SURVIVAL, MIN_SURVIVAL,
    ROULETTE_START, SHADOW_STOP_SHORT,
};
use stratapt_scene::{DimLayout, FlatScene, RenderSettings};
use wide::{f32x8, u32x8, CmpEq, CmpGe, CmpGt, CmpLt, CmpNe};

/// The eight-lane path tracer for one scene and one set of render settings (a scene
/// [`super::supports`]).
pub struct Paths<'a> {
    scene: &'a FlatScene,
    accel: &'a Accel<'a>,
    seed: u32,
    max_depth: u32,
    layout: DimLayout,
    camera: Pinhole,
    /// The one light next-event estimation samples.
    light: Option<Rectangle>,
    /// Each stored light's prepared part (for the emission a ray finds).
    prepared: Vec<light::Prepared<'a>>,
}

/// The pinhole camera's frame and film, as [`crate::camera::generate_ray`] computes them.
struct Pinhole {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    size: (f32, f32),
    tan_half_fov: f32,
    filter_width: f32,
}

/// A one-sided rectangle light as next-event estimation samples it (the one-lane
/// [`light::rectangle::Prepared`] values).
struct Rectangle {
    corner: Vec3,
    ex: Vec3,
    ey: Vec3,
    n: Vec3,
    area: f32,
    half_diagonal: Vec3,
    diagonal_sq: f32,
    radiance: Vec3,
    select_pdf: f32,
    /// The spherical-rectangle frame (edges at right angles), else area sampling only.
    frame: Option<rectangle::Frame>,
}

/// Eight paths in flight and what each vertex needs of the one before.
struct Wave {
    /// The queue position each lane's path came from (its pixel slot `j`).
    slot: [usize; LANES],
    /// Lanes whose path is in flight.
    live: u32,
    key: u32x8,
    index: u32x8,
    depth: u32x8,
    origin: V3,
    dir: V3,
    throughput: V3,
    radiance: V3,
    prev_p: V3,
    prev_pdf: f32x8,
    prev_specular: Mask,
}

/// The surfaces the wave's rays found, lane by lane.
#[derive(Default)]
struct Hits {
    p: [Vec3; LANES],
    err: [Vec3; LANES],
    ng: [Vec3; LANES],
    ns: [Vec3; LANES],
    albedo: [Vec3; LANES],
}

/// A vertex's shading point in eight lanes ([`crate::bsdf::ShadingPoint`] of a diffuse surface).
struct Shade {
    p: V3,
    err: V3,
    /// Geometric normal flipped to the side of `wo`.
    ng: V3,
    /// The shading frame (`n`: the shading normal flipped to the side of `wo`).
    s: V3,
    t: V3,
    n: V3,
    wo_z: f32x8,
    albedo: V3,
}

impl<'a> Paths<'a> {
    /// The tracer over `accel`'s scene; the scene must be [`super::supports`]ed.
    pub fn new(accel: &'a Accel<'a>, settings: &RenderSettings, support: &Support) -> Self {
        let scene = accel.scene();
        let c = &scene.camera;
        let v = Vec3::from_array;
        let (eye, target) = (v(c.eye0), v(c.target0));
        let forward = (target - eye).normalize();
        let right = forward.cross(v(c.up0).normalize()).normalize();
        let light = support.nee_light.map(|index| {
            let stored = scene.lights[index];
            let (corner, ex, ey) = (v(stored.p0), v(stored.p1), v(stored.p2));
            let n = ex.cross(ey);
            Rectangle {
                corner,
                ex,
                ey,
                n: n.normalize_or_zero(),
                area: n.length(),
                half_diagonal: 0.5 * (ex + ey),
                diagonal_sq: ex.dot(ex) + ey.dot(ey),
                radiance: v(stored.radiance),
                select_pdf: stratapt_scene::light_table::select(&scene.light_table, 0.0).1,
                // As the one-lane `rectangle::Prepared` decides it.
                frame: (ex.dot(ey).abs() <= 1e-4 * ex.length() * ey.length())
                    .then(|| Basis::new(ex, ey))
                    .flatten()
                    .map(|basis| rectangle::Frame::new(&basis)),
            }
        });
        Self {
            scene,
            accel,
            seed: settings.seed,
            max_depth: settings.max_depth,
            layout: DimLayout::new(&support.effects),
            camera: Pinhole {
                eye,
                forward,
                right,
                up: right.cross(forward),
                size: (c.width as f32, c.height as f32),
                tan_half_fov: c.tan_half_fov,
                filter_width: c.filter_param,
            },
            light,
            prepared: scene
                .lights
                .iter()
                .map(|l| light::Prepared::of(l, &scene.tables))
                .collect(),
        }
    }

    /// Trace samples `indices` of the pixels `pixel(0 .. count)`, each value to `add(j, value)`.
    pub fn trace_row(
        &self,
        count: usize,
        pixel: &dyn Fn(usize) -> [u32; 2],
        indices: std::ops::Range<u32>,
        add: &mut dyn FnMut(usize, Vec3),
    ) {
        let mut queue = (0..count).flat_map(|j| indices.clone().map(move |i| (j, i)));
        let mut wave = Wave::empty();
        loop {
            self.refill(&mut wave, &mut queue, pixel);
            if wave.live == 0 {
                return;
            }
            self.bounce(&mut wave, add);
        }
    }

    /// Start the next queued paths in the lanes that have none: camera rays through their
    /// pixels.
    fn refill(
        &self,
        wave: &mut Wave,
        queue: &mut dyn Iterator<Item = (usize, u32)>,
        pixel: &dyn Fn(usize) -> [u32; 2],
    ) {
        let mut fresh = 0u32;
        let (mut px, mut py, mut index) = ([0u32; LANES], [0u32; LANES], [0u32; LANES]);
        for lane in 0..LANES {
            if wave.live & (1 << lane) != 0 {
                continue;
            }
            let Some((j, i)) = queue.next() else { break };
            [px[lane], py[lane]] = pixel(j);
            index[lane] = i;
            wave.slot[lane] = j;
            fresh |= 1 << lane;
        }
        if fresh == 0 {
            return;
        }
        let (px, py, index) = (u32x8::from(px), u32x8::from(py), u32x8::from(index));
        let seed = u32x8::splat(hash::lowbias32(self.seed));
        let key = sobol::hash_combine(sobol::hash_combine(seed, px), py);
        let (dir, eye) = self.camera_rays(px, py, key, index);
        let m = mask_of(fresh);
        let mu: u32x8 = bytemuck::cast(m);
        wave.key = mu.blend(key, wave.key);
        wave.index = mu.blend(index, wave.index);
        wave.depth = mu.blend(u32x8::ZERO, wave.depth);
        wave.origin = V3::select(m, eye, wave.origin);
        wave.dir = V3::select(m, dir, wave.dir);
        wave.throughput = V3::select(m, V3::splat(Vec3::ONE), wave.throughput);
        wave.radiance = V3::select(m, V3::default(), wave.radiance);
        wave.prev_p = V3::select(m, eye, wave.prev_p);
        wave.prev_pdf = m.blend(f32x8::ZERO, wave.prev_pdf);
        wave.prev_specular = m | wave.prev_specular;
        wave.live |= fresh;
    }

    /// Camera rays through pixels `(px, py)` for their samples `index` (pixel keys `key`):
    /// their directions, and the eye.
    fn camera_rays(&self, px: u32x8, py: u32x8, key: u32x8, index: u32x8) -> (V3, V3) {
        let c = &self.camera;
        let (ux, uy) = sobol::sample_2d(key, index, u32x8::splat(self.layout.pixel));
        let half = f32x8::splat(0.5);
        let (ox, oy) = ((ux - half) * c.filter_width, (uy - half) * c.filter_width);
        let (w, h) = (f32x8::splat(c.size.0), f32x8::splat(c.size.1));
        let (two, one) = (f32x8::splat(2.0), f32x8::ONE);
        let as_float = |x: u32x8| bytemuck::cast::<u32x8, wide::i32x8>(x).round_float();
        let tan = f32x8::splat(c.tan_half_fov);
        let sx =
            (two * (as_float(px) + half + ox) / w - one) * tan * f32x8::splat(c.size.0 / c.size.1);
        let sy = (one - two * (as_float(py) + half + oy) / h) * tan;
        let dir = V3::splat(c.forward) + V3::splat(c.right) * sx + V3::splat(c.up) * sy;
        (dir.normalize(), V3::splat(c.eye))
    }

    /// One vertex of every live path: its ray's hit, the emission found there, next-event
    /// estimation, the BSDF sample and roulette. Paths that end hand their value to `add`.
    fn bounce(&self, wave: &mut Wave, add: &mut dyn FnMut(usize, Vec3)) {
        // ---- Intersection, eight rays together --------------------------------------------
        let mut hits = Hits::default();
        let mut ended = 0u32;
        let mut emitted = [Vec3::ZERO; LANES];
        let rays = Rays8::new(wave.origin, wave.dir, f32x8::splat(f32::INFINITY));
        let found = self.accel.closest_hits8(&rays, wave.live);
        for lane in lanes_of(wave.live) {
            // A ray that escapes finds nothing: the scene has no environment light.
            let Some(hit) = found[lane] else {
                ended |= 1 << lane;
                continue;
            };
            let dir = wave.dir.lane(lane);
            let surface = self.scene.geometry.surface(hit.prim);
            let material = &self.scene.materials[surface.material as usize];
            // ---- Emission found by the ray (few lanes) ---------------------------------
            if material.emission != [0.0; 3] && hit.ng.dot(dir) < 0.0 {
                emitted[lane] = Vec3::from_array(material.emission)
                    * self.hit_weight(wave, lane, surface.light, dir);
            }
            hits.p[lane] = hit.p;
            hits.err[lane] = hit.err;
            hits.ng[lane] = hit.ng;
            hits.ns[lane] = hit.ns;
            hits.albedo[lane] = Vec3::from_array(material.color);
        }
        wave.radiance = wave.radiance + wave.throughput * V3::from_lanes(&emitted);
        let last: Mask = bytemuck::cast(wave.depth.cmp_eq(u32x8::splat(self.max_depth)));
        ended |= bits(last) & wave.live;
        self.end(wave, ended, add);
        if wave.live == 0 {
            return;
        }
        let sp = shade(&hits, wave.dir);
        let dims = u32x8::splat(self.layout.first_vertex)
            + wave.depth * u32x8::splat(self.layout.per_vertex);
        // ---- Next-event estimation ------------------------------------------------------
        if let (Some(light), Some(d)) = (&self.light, self.layout.light_point) {
            let u = sobol::sample_2d(wave.key, wave.index, dims + u32x8::splat(d));
            let direct = self.next_event(light, &sp, u, wave.live);
            wave.radiance = wave.radiance + wave.throughput * direct;
        }
        // ---- BSDF sampling of the continuation --------------------------------------------
        let u = sobol::sample_2d(
            wave.key,
            wave.index,
            dims + u32x8::splat(self.layout.direction),
        );
        let (local, pdf) = cosine_hemisphere(u);
        let wi = sp.s * local.x + sp.t * local.y + sp.n * local.z;
        let ok = sp.wo_z.cmp_gt(f32x8::ZERO)
            & local.z.cmp_gt(f32x8::ZERO)
            & pdf.cmp_gt(f32x8::ZERO)
            & sp.ng.dot(wi).cmp_gt(f32x8::ZERO);
        wave.throughput = wave.throughput * sp.albedo;
        let ok = ok & wave.throughput.max_element().cmp_gt(f32x8::ZERO);
        let mut ended = wave.live & !bits(ok);
        // ---- Russian roulette (only when another scattering vertex can follow) ----------
        if let Some(d) = self.layout.roulette {
            let depth = wave.depth;
            let may: Mask = bytemuck::cast(
                !depth.cmp_lt(u32x8::splat(ROULETTE_START))
                    & (depth + u32x8::splat(1)).cmp_lt(u32x8::splat(self.max_depth)),
            );
            let q = wave
                .throughput
                .max_element()
                .max(f32x8::splat(MIN_SURVIVAL))
                .min(f32x8::splat(MAX_SURVIVAL));
            let u = sobol::sample_1d(wave.key, wave.index, dims + u32x8::splat(d));
            ended |= wave.live & bits(may & u.cmp_ge(q));
            wave.throughput = V3::select(may, wave.throughput.div(q), wave.throughput);
        }
        self.end(wave, ended, add);
        // ---- The next ray leaves from the offset origin -------------------------------------
        let origin = lanes::spawn_origin(sp.p, sp.err, sp.ng, wi);
        wave.prev_p = origin;
        wave.prev_pdf = pdf;
        wave.prev_specular = f32x8::ZERO;
        wave.origin = origin;
        wave.dir = wi;
        wave.depth += u32x8::splat(1);
    }

    /// End the paths of lanes `ended`, handing each value to `add`.
    fn end(&self, wave: &mut Wave, ended: u32, add: &mut dyn FnMut(usize, Vec3)) {
        for lane in lanes_of(ended) {
            add(wave.slot[lane], wave.radiance.lane(lane));
        }
        wave.live &= !ended;
    }

    /// MIS weight of emission of light `index` found by lane `lane`'s ray along `dir`
    /// ([`crate::Integrator`]'s `hit_weight` under MIS).
    fn hit_weight(&self, wave: &Wave, lane: usize, index: u32, dir: Vec3) -> f32 {
        if bits(wave.prev_specular) & (1 << lane) != 0 {
            return 1.0;
        }
        if index == NONE {
            return 1.0;
        }
        let stored = &self.scene.lights[index as usize];
        let prev_p = wave.prev_p.lane(lane);
        let light_pdf = light::pdf_prepared(stored, &self.prepared[index as usize], prev_p, dir);
        power_heuristic(
            wave.prev_pdf.as_array_ref()[lane],
            stored.select_pdf * light_pdf,
        )
    }

    /// Light reaching each lane's shading point directly from the rectangle, reflected
    /// towards `wo`, MIS-weighted against BSDF sampling ([`crate::integrator`]'s `next_event`).
    fn next_event(&self, light: &Rectangle, sp: &Shade, u: (f32x8, f32x8), live: u32) -> V3 {
        let (n, corner) = (V3::splat(light.n), V3::splat(light.corner));
        let (ex, ey) = (V3::splat(light.ex), V3::splat(light.ey));
        // ---- Points in the light's own plane see none of it ------------------------------------
        let slack = n
            .abs()
            .dot(sp.err + (sp.p.abs() + corner.abs()) * f32x8::splat(GAMMA_3));
        let in_plane = n.dot(sp.ng).abs().cmp_ge(f32x8::splat(IN_PLANE_COS))
            & slack.cmp_ge(n.dot(sp.p - corner).abs());
        let mut todo = live & !bits(in_plane);
        if light.n == Vec3::ZERO || light.area <= 0.0 {
            todo = 0;
        }
        // ---- A point on the light, by area where it is seen small -----------------------------
        let from = lanes::offset_ray_origin(sp.p, sp.err, sp.ng);
        todo &= bits(n.dot(from - corner).cmp_gt(f32x8::ZERO));
        let pc = corner - from;
        let centre = pc + V3::splat(light.half_diagonal);
        let small = f32x8::splat(light.diagonal_sq)
            .cmp_lt(f32x8::splat(AREA_SAMPLED_ANGULAR_SIZE_SQ) * centre.dot(centre));
        let mut v = pc + ex * u.0 + ey * u.1;
        // ---- ... by solid angle where it is not (and the spherical method applies) ---------
        let mut spherical = f32x8::ZERO;
        let mut pdf_spherical = f32x8::ZERO;
        if let Some(frame) = light.frame.as_ref().filter(|_| todo & !bits(small) != 0) {
            let (setup, applies) = rectangle::Setup::new(frame, pc);
            spherical = applies & !small;
            if bits(spherical) & todo != 0 {
                v = V3::select(spherical, setup.sample(pc, ex, ey, u), v);
                pdf_spherical = f32x8::ONE / setup.solid_angle();
            }
        }
        let dist = v.length();
        let wi = v.div(dist);
        let cos = -n.dot(wi);
        let denom = cos * f32x8::splat(light.area);
        let pdf_area =
            (dist * dist / denom) & (cos.cmp_gt(f32x8::ZERO) & denom.cmp_gt(f32x8::ZERO));
        let pdf = spherical.blend(pdf_spherical, pdf_area & pdf_area.is_finite());
        let err = (pc.abs() + ex.abs() + ey.abs()) * f32x8::splat(GAMMA_5);
        todo &= bits(pdf.cmp_gt(f32x8::ZERO) & dist.cmp_gt(f32x8::ZERO));
        // ---- The BSDF, and the MIS weight against its sampling --------------------------------
        let local_z = wi.dot(sp.n);
        let above = sp.ng.dot(wi);
        let sides_agree =
            above.cmp_ne(f32x8::ZERO) & !(above.cmp_gt(f32x8::ZERO) ^ local_z.cmp_gt(f32x8::ZERO));
        let front = sp.wo_z.cmp_gt(f32x8::ZERO) & local_z.cmp_gt(f32x8::ZERO);
        let cos_pdf = (local_z * f32x8::splat(FRAC_1_PI)) & front;
        todo &= bits(sides_agree & front);
        let f = sp.albedo * cos_pdf;
        let light_pdf = f32x8::splat(light.select_pdf) * pdf;
        let weight = power_heuristic8(light_pdf, cos_pdf);
        let direct = f * V3::splat(light.radiance) * (weight / light_pdf);
        // ---- Visibility, lane by lane -------------------------------------------------------
        let origin = lanes::spawn_origin(sp.p, sp.err, sp.ng, wi);
        let towards_p = flip(n, n.dot(wi).cmp_gt(f32x8::ZERO));
        // The point as the sample gives it: along `wi` at `dist`.
        let v = wi * dist;
        let end = lanes::offset_ray_origin(
            from + v,
            err + (from.abs() + v.abs()) * f32x8::splat(GAMMA_5),
            towards_p,
        );
        let to_light = end - origin;
        let reaches = to_light.dot(wi).cmp_gt(f32x8::ZERO);
        let len = to_light.length();
        let aim = to_light.div(len);
        let tmax = len * f32x8::splat(1.0 - SHADOW_STOP_SHORT);
        // Both ends within each other's rounding: nothing between them (a ray of length 0).
        let shadow = Rays8::new(origin, V3::select(reaches, aim, wi), reaches & tmax);
        let visible = todo & !self.accel.occluded_wave8(&shadow, todo);
        direct.keep(mask_of(visible))
    }
}

impl Wave {
    fn empty() -> Self {
        Self {
            slot: [0; LANES],
            live: 0,
            key: u32x8::ZERO,
            index: u32x8::ZERO,
            depth: u32x8::ZERO,
            origin: V3::default(),
            dir: V3::default(),
            throughput: V3::default(),
            radiance: V3::default(),
            prev_p: V3::default(),
            prev_pdf: f32x8::ZERO,
            prev_specular: f32x8::ZERO,
        }
    }
}

/// The lanes whose bit is set in `bits`, lowest first.
fn lanes_of(mut bits: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (bits != 0).then(|| {
            let lane = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            lane
        })
    })
}

/// The shading points of the wave's hits, seen along `dir`.
fn shade(hits: &Hits, dir: V3) -> Shade {
    let wo = -dir;
    let ng = V3::from_lanes(&hits.ng);
    let ns = V3::from_lanes(&hits.ns);
    let ng = flip(ng, !ng.dot(wo).cmp_gt(f32x8::ZERO));
    let n = flip(ns, ns.dot(wo).cmp_lt(f32x8::ZERO));
    // Duff et al. 2017's branchless frame ([`stratapt_sampling::Frame::from_normal`]).
    let sign = n.z.cmp_ge(f32x8::ZERO).blend(f32x8::ONE, -f32x8::ONE);
    let a = -f32x8::ONE / (sign + n.z);
    let b = n.x * n.y * a;
    let s = V3 {
        x: f32x8::ONE + sign * n.x * n.x * a,
        y: sign * b,
        z: -sign * n.x,
    };
    let t = V3 {
        x: b,
        y: sign + n.y * n.y * a,
        z: -n.y,
    };
    Shade {
        p: V3::from_lanes(&hits.p),
        err: V3::from_lanes(&hits.err),
        ng,
        s,
        t,
        wo_z: wo.dot(n),
        n,
        albedo: V3::from_lanes(&hits.albedo),
    }
}

/// Malley's cosine-weighted hemisphere over Shirley–Chiu's concentric disk
/// ([`stratapt_sampling::warp::cosine_hemisphere`]), and its pdf.
fn cosine_hemisphere(u: (f32x8, f32x8)) -> (V3, f32x8) {
    let (two, one) = (f32x8::splat(2.0), f32x8::ONE);
    let (ox, oy) = (two * u.0 - one, two * u.1 - one);
    let wide_x = ox.abs().cmp_gt(oy.abs());
    let r = wide_x.blend(ox, oy);
    let quarter = f32x8::splat(FRAC_PI_4);
    let theta = wide_x.blend(
        quarter * (oy / ox),
        f32x8::splat(FRAC_PI_2) - quarter * (ox / oy),
    );
    // libm's sine and cosine, lane by lane: the reference's values (a polynomial in the lanes
    // moved the directions by an ULP or so, and with them every later vertex's bits).
    let (mut sin, mut cos) = (theta, theta);
    for (i, &angle) in theta.as_array_ref().iter().enumerate() {
        (sin.as_array_mut()[i], cos.as_array_mut()[i]) = (angle.sin(), angle.cos());
    }
    let centre = ox.cmp_eq(f32x8::ZERO) & oy.cmp_eq(f32x8::ZERO);
    let (x, y) = (
        centre.blend(f32x8::ZERO, r * cos),
        centre.blend(f32x8::ZERO, r * sin),
    );
    let z = (one - (x * x + y * y)).max(f32x8::ZERO).sqrt();
    (V3 { x, y, z }, z.max(f32x8::ZERO) * f32x8::splat(FRAC_1_PI))
}

/// [`power_heuristic`] per lane, with its edge cases.
fn power_heuristic8(a: f32x8, b: f32x8) -> f32x8 {
    let (a, b) = (a.abs(), b.abs());
    let a_wins = a.cmp_ge(b);
    let r = a_wins.blend(b / a, a / b);
    let r2 = r * r;
    let w = a_wins.blend(f32x8::ONE / (f32x8::ONE + r2), r2 / (f32x8::ONE + r2));
    let w = b.is_nan().blend(f32x8::ONE, w);
    let w = a
        .is_inf()
        .blend(b.is_inf().blend(f32x8::splat(0.5), f32x8::ONE), w);
    (a.is_nan() | a.cmp_eq(f32x8::ZERO)).blend(f32x8::ZERO, w)
}
