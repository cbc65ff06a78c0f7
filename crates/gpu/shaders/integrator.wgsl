// needs: sampler twin camera offset accel bsdf light mis frame
// The path integrator and the kernel entry point: the estimator of
// `crates/cpu/src/integrator.rs` (with `integrator/nee.rs` and `integrator/emission.rs`), step
// for step, consuming the same sample dimensions (`dim_*()`, the scene's `DimLayout`). Veach
// 1997, "Robust Monte Carlo Methods for Light Transport Simulation", ch. 9 (MIS) and §10.4.1
// (path tracing with next-event estimation).
//
// One invocation renders one slice of one pixel of the dispatch's band (or of one twin pixel, in
// the rows after the film): `batch_spp` consecutive samples of the batch, whole paths one after
// the other (a megakernel; a finished path's lane starts the next sample at once), and writes
// their sum and sum of squares to the slice's tile of `accum` for the host to fold into f64, with
// the number of rays it traced. A batch splits each pixel's samples into `params.split` slices
// when the image alone would leave a large GPU idle.

// Russian roulette's survival bounds and first vertex (INTEGRATOR_MIN_SURVIVAL, _MAX_SURVIVAL,
// _ROULETTE_START) and the shadow rays' stop (INTEGRATOR_SHADOW_STOP_SHORT) are generated from
// `stratapt_scene::shared`.

// Rays this invocation has traced (path and shadow rays), reported with its sums.
var<private> integrator_rays: u32;

// What the emission at the next hit must know about the vertex the ray left.
struct PrevVertex {
    // Where the ray left the vertex (its offset origin): MIS evaluates light pdfs from here.
    p: vec3f,
    // Solid-angle pdf of the sampled direction.
    pdf: f32,
    // The camera, or a delta lobe: emission is always counted in full.
    specular: bool,
}

fn integrator_max3(v: vec3f) -> f32 {
    return max(v.x, max(v.y, v.z));
}

fn integrator_is_black(v: vec3f) -> bool {
    return all(v == vec3f(0.0));
}

// Whether the strategy draws next-event lights from the full table (else only unhittable ones).
fn integrator_samples_lights() -> bool {
    return params.strategy == STRATEGY_LIGHT || params.strategy == STRATEGY_MIS;
}

// ---- A path as state, advanced one vertex at a time ------------------------------------------
// The kernel loops over vertices rather than over samples then vertices: a lane whose path ends
// starts its pixel's next sample at once instead of idling until the longest path of its SIMD
// group or warp has ended ("path regeneration", Novák, Havran & Dachsbacher 2010).

// Everything a path carries from one vertex to the next.
struct PathState {
    ray: Ray,
    prev: PrevVertex,
    throughput: vec3f,
    radiance: vec3f,
    // Product of η² over refractions, undoing the 1/η² radiance scaling for roulette.
    eta_scale: f32,
    // Vertex the next step finds; its sample dimensions are block `depth` after the camera's.
    depth: u32,
    time: f32,
    // Sample index within the pixel.
    index: u32,
}

// Sample `index` of `pixel`: filter, lens, shutter, then the camera ray.
fn integrator_start(pixel: vec2u, index: u32) -> PathState {
    // The shutter instant is drawn with the position in the pixel (integrator.rs).
    var u_pixel: vec2f;
    var time = 0.0;
    if (has_time()) {
        let u = sampler_sample_1d_2d(index, dim_time(), dim_pixel());
        time = u.x;
        u_pixel = u.yz;
    } else {
        u_pixel = sampler_sample_2d(index, dim_pixel());
    }
    var u_lens = vec2f(0.0);
    if (has_lens()) {
        u_lens = sampler_sample_2d(index, dim_lens());
    }
    let ray = camera_generate_ray(pixel, u_pixel, u_lens, time);
    return PathState(
        ray_new(ray.origin, ray.dir, f32_infinity()),
        PrevVertex(ray.origin, 0.0, true),
        vec3f(1.0),
        vec3f(0.0),
        1.0,
        0u,
        time,
        index,
    );
}

// Vertex `depth` of the path (integrator.rs `radiance`, one loop iteration): intersect, add the
// emission found and next-event estimation, sample the continuation. False when the path ends;
// its radiance is then final.
fn integrator_step(state: ptr<function, PathState>) -> bool {
    let max_depth = params.max_depth;
    let depth = (*state).depth;
    let ray = (*state).ray;
    let time = (*state).time;
    let index = (*state).index;
    let prev = (*state).prev;
    let throughput = (*state).throughput;
    // ---- Intersection ----------------------------------------------------------------------
    var hit: Hit;
    integrator_rays++;
    if (!accel_closest_hit(ray, time, &hit)) {
        (*state).radiance += throughput * integrator_escaped(ray.dir, prev, time);
        return false;
    }
    // ---- Emission found by the ray ---------------------------------------------------------
    (*state).radiance += throughput * integrator_emitted(hit, ray.dir, prev, time);
    if (depth == max_depth) {
        return false;
    }
    let wo = -ray.dir;
    // Mixes choose, bump and normal maps tilt the shading normal.
    let material = bsdf_resolve_material(surface_of(hit.prim).material, &hit, index, depth, time);
    // A coated material's base record (integrator.rs).
    var base = material;
    if (bsdf_is_coated(material.tag & MATERIAL_KIND_MASK)) {
        base = material_at(u32(material.k.y));
    }
    let sp = shading_point_new(hit, material, base, wo);
    let dims = dim_first_vertex() + depth * dim_per_vertex();
    // ---- Next-event estimation (non-delta vertices) ----------------------------------------
    if (has_nee() && !bsdf_is_delta(sp)) {
        (*state).radiance += throughput * integrator_next_event(sp, wo, index, dims, time);
    }
    // ---- BSDF sampling of the continuation -------------------------------------------------
    let u_dir = sampler_sample_2d(index, dims + dim_direction());
    var u_lobe = 0.0;
    if (has_lobe()) {
        u_lobe = sampler_sample_1d(index, dims + dim_lobe());
    }
    let bs = shading_point_sample(sp, wo, u_dir, u_lobe, params.strategy);
    if (!bs.valid) {
        return false;
    }
    var next = throughput * bs.weight;
    let eta_scale = (*state).eta_scale * bs.eta * bs.eta;
    if (integrator_max3(next) <= 0.0) {
        return false;
    }
    // ---- Russian roulette (only when another scattering vertex can follow) -----------------
    if (has_roulette() && depth >= INTEGRATOR_ROULETTE_START && depth + 1u < max_depth) {
        let q = clamp(
            integrator_max3(next) * eta_scale,
            INTEGRATOR_MIN_SURVIVAL,
            INTEGRATOR_MAX_SURVIVAL,
        );
        if (sampler_sample_1d(index, dims + dim_roulette()) >= q) {
            return false;
        }
        next /= q;
    }
    (*state).throughput = next;
    (*state).eta_scale = eta_scale;
    // Emission the ray finds is weighed against light sampling from its origin (integrator.rs).
    let origin = offset_spawn_origin(sp.p, sp.err, sp.ng, bs.wi);
    (*state).prev = PrevVertex(origin, bs.pdf, bs.delta);
    (*state).ray = ray_new(origin, bs.wi, f32_infinity());
    (*state).depth = depth + 1u;
    return true;
}

// ---- Next-event estimation: one light from the strategy's table, one point on it ---------------
fn integrator_next_event(
    sp: ShadingPoint,
    wo: vec3f,
    index: u32,
    dims: u32,
    time: f32,
) -> vec3f {
    let full = integrator_samples_lights();
    let table_len = select(params.unhittable_table_len, params.light_table_len, full);
    if (table_len == 0u) {
        return vec3f(0.0);
    }
    // Choose a light, then a direction towards it.
    // One light leaves nothing to choose: only its point is drawn (the point sampler_sample_1d_2d would
    // give).
    var u_select = 0.0;
    var u_point: vec2f;
    if (table_len == 1u) {
        u_point = sampler_sample_2d(index, dims + dim_light_point());
    } else {
        let u_light = sampler_sample_1d_2d(index, dims + dim_light_select(), dims + dim_light_point());
        u_select = u_light.x;
        u_point = u_light.yz;
    }
    let choice = light_select(full, u_select);
    let light = light_placed(choice.index, time);
    if (light_in_plane(light, sp.p, sp.err, sp.ng)) {
        return vec3f(0.0);
    }
    // Sampled from the point BSDF rays leave from (their MIS weights are evaluated there), except
    // point, spot and line lights: from the surface point (nee.rs `sampled_from`).
    var light_from = sp.p;
    if (light.kind != LIGHT_POINT && light.kind != LIGHT_SPOT && light.kind != LIGHT_LINE) {
        light_from = offset_ray_origin(sp.p, sp.err, sp.ng);
    }
    let ls = light_sample(light, light_from, u_point);
    if (!ls.valid || integrator_is_black(ls.radiance) || choice.pdf <= 0.0) {
        return vec3f(0.0);
    }
    let f = shading_point_eval(sp, wo, ls.wi);
    if (integrator_is_black(f)) {
        return vec3f(0.0);
    }
    // Visibility.
    let shadow = integrator_shadow_ray(sp.p, sp.err, sp.ng, light_from, ls);
    integrator_rays++;
    if (accel_occluded(shadow, time)) {
        return vec3f(0.0);
    }
    // Estimate, MIS-weighted against BSDF sampling.
    let light_pdf = choice.pdf * ls.pdf;
    var weight = 1.0;
    if (!ls.delta && params.strategy == STRATEGY_MIS) {
        weight = mis_power_heuristic(light_pdf, shading_point_pdf(sp, wo, ls.wi, params.strategy));
    }
    return f * ls.radiance * (weight / light_pdf);
}

// The shadow ray from `p` (error bound `err`, geometric normal `ng`) towards the light sample `ls`
// drawn from `light_from` (nee.rs `shadow_ray`): both ends moved off their surfaces by their error
// bounds (pbrt-v4 `SpawnRayTo`), the offset origin aimed at the offset end, stopping short of it.
// Keeping `wi` would shift the ray sideways into a sphere light near its silhouette; an end left
// on the light rounds behind its surface far from the origin, where the light shadowed itself.
fn integrator_shadow_ray(p: vec3f, err: vec3f, ng: vec3f, light_from: vec3f, ls: LightSample) -> Ray {
    let origin = offset_spawn_origin(p, err, ng, ls.wi);
    if (!(ls.dist < f32_infinity())) {
        return ray_new(origin, ls.wi, f32_infinity());
    }
    let v = ls.wi * ls.dist;
    var end = light_from + v;
    if (any(ls.n != vec3f(0.0))) {
        let towards_p = select(ls.n, -ls.n, dot(ls.n, ls.wi) > 0.0);
        end = offset_ray_origin(end, ls.err + GAMMA_5 * (abs(light_from) + abs(v)), towards_p);
    }
    let to_light = end - origin;
    // Both ends within each other's rounding (a point touching the light): nothing between.
    if (!(dot(to_light, ls.wi) > 0.0)) {
        return ray_new(origin, ls.wi, 0.0);
    }
    let len = length(to_light);
    return ray_new(origin, to_light / len, len * (1.0 - INTEGRATOR_SHADOW_STOP_SHORT));
}

// ---- Emission found by a ray, weighted under the strategy -----------------------------------
// The camera ray and delta lobes count it in full; `light` leaves it to NEE; `mis` weighs it by
// the power heuristic against `select_pdf · light pdf`; the others count it in full.
fn integrator_hit_weight(prev: PrevVertex, light_pdf: f32, select_pdf: f32) -> f32 {
    if (prev.specular) {
        return 1.0;
    }
    if (params.strategy == STRATEGY_LIGHT) {
        return 0.0;
    }
    if (params.strategy == STRATEGY_MIS) {
        return mis_power_heuristic(prev.pdf, select_pdf * light_pdf);
    }
    return 1.0;
}

// Radiance emitted by the surface at `hit` towards the ray's origin, weighted.
fn integrator_emitted(hit: Hit, dir: vec3f, prev: PrevVertex, time: f32) -> vec3f {
    let prim = surface_of(hit.prim);
    let le = material_emission(prim.material);
    if (integrator_is_black(le)) {
        return vec3f(0.0);
    }
    // One-sided emitters are dark from behind; spheres and two-sided lights emit from both sides.
    var two_sided = prim.kind == PRIM_SPHERE;
    if (!two_sided && prim.light != NONE) {
        two_sided = (light_at(prim.light).flags & LIGHT_FLAG_TWO_SIDED) != 0u;
    }
    if (!two_sided && dot(hit.ng, dir) >= 0.0) {
        return vec3f(0.0);
    }
    if (prev.specular) {
        return le;
    }
    if (params.strategy == STRATEGY_LIGHT) {
        return vec3f(0.0);
    }
    if (params.strategy != STRATEGY_MIS || prim.light == NONE) {
        return le;
    }
    let light = light_placed(prim.light, time);
    let pdf = light_pdf(light, prev.p, dir);
    return le * mis_power_heuristic(prev.pdf, light_select_pdf(prim.light) * pdf);
}

// Radiance of the environment (sun cones, sky, environment map: lights `env_first ..`) along an
// escaping ray.
fn integrator_escaped(dir: vec3f, prev: PrevVertex, time: f32) -> vec3f {
    var sum = vec3f(0.0);
    if (!has_light_kind(LIGHT_SKY) && !has_light_kind(LIGHT_DISTANT)
        && !has_light_kind(LIGHT_ENVIRONMENT) && !has_light_kind(LIGHT_OCTAHEDRAL)) {
        return sum;
    }
    for (var i = params.env_first; i < params.light_count; i++) {
        let light = light_placed(i, time);
        let le = light_escaped_radiance(light, dir);
        if (integrator_is_black(le)) {
            continue;
        }
        var pdf = 0.0;
        if (!prev.specular && params.strategy == STRATEGY_MIS) {
            pdf = light_pdf(light, prev.p, dir);
        }
        sum += le * integrator_hit_weight(prev, pdf, light_select_pdf(i));
    }
    return sum;
}

// ---- Kernel: one slice of one pixel's batch of samples ----------------------------------------

@compute @workgroup_size(WORKGROUP_SIDE, WORKGROUP_SIDE)
fn render(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= params.tile_size) || id.z >= params.split) {
        return;
    }
    // Slice `id.z` renders samples `first + k`, k < batch_spp, into its own tile of the
    // accumulator (the host adds the slices in order).
    let first = params.sample_base + id.z * params.batch_spp;
    let i = 2u * ((id.z * params.tile_size.y + id.y) * params.tile_size.x + id.x);
    // Rows past the film are twin pixels: their film pixel, in the independent replica 1.
    var pixel = params.tile_origin + id.xy;
    if (pixel.y >= params.film_rows) {
        let k = (pixel.y - params.film_rows) * params.tile_size.x + pixel.x;
        if (k >= params.twin_count) {
            accum[i] = vec4f(0.0);
            accum[i + 1u] = vec4f(0.0);
            return;
        }
        pixel = twin_pixel(k);
        sampler_replica = 1u;
    }
    sampler_begin_pixel(pixel);
    var sum = vec3f(0.0);
    var sum_sq = vec3f(0.0);
    // Non-finite samples are counted and replaced by zero, as on the CPU.
    var non_finite = 0u;
    // The slice's samples in order; each path advances one vertex per iteration and the next
    // sample starts as soon as it ends.
    var started = 1u;
    var state = integrator_start(pixel, first);
    loop {
        if (integrator_step(&state)) {
            continue;
        }
        var value = state.radiance;
        if (!frame_is_finite3(value)) {
            value = vec3f(0.0);
            non_finite++;
        }
        sum += value;
        sum_sq += value * value;
        if (started >= params.batch_spp) {
            break;
        }
        state = integrator_start(pixel, first + started);
        started++;
    }
    // Ray counts per pixel and batch stay far below 2^24 (exact in f32).
    accum[i] = vec4f(sum, f32(integrator_rays));
    accum[i + 1u] = vec4f(sum_sq, f32(non_finite));
}
