// needs: nothing
// Textures: images and checkerboards a material's colours and numbers read at a hit's (u, v).
// Mirrors `crates/scene/src/texture.rs`: the same operations in the same order (the transform,
// the period reduction, the four wrapped indices, 8-bit texels decoded by the table in `tables`
// before the bilinear weights, a flagged texture's clamp to [0, 1] last), plain multiplies and
// adds (no `fma`, which lavapipe computes unfused), never a hardware sampler.
//
// Interface (other modules may call):
//   struct Texture (records.rs `Texture`, read from `tables` by `texture_at`)
//   fn texture_eval(index: u32, uv: vec2f) -> vec3f
//   fn texture_eval_scalar(index: u32, uv: vec2f) -> f32
//   fn texture_resolve(material: Material, uv: vec2f) -> Material

// 80 bytes; texture i at word TEXTURE_WORDS · i of the tables.
struct Texture {
    tag: u32,
    texels: u32,
    width: u32,
    height: u32,
    uv_u: vec3f,
    decode: u32,
    uv_v: vec3f,
    _pad0: u32,
    value: vec3f,
    _pad1: u32,
    other: vec3f,
    _pad2: u32,
}

fn texture_vec3(at: u32) -> vec3f {
    return vec3f(table_f32(at), table_f32(at + 1u), table_f32(at + 2u));
}

// Texture `index`'s record.
fn texture_at(index: u32) -> Texture {
    let at = TEXTURE_WORDS * index;
    return Texture(
        table_u32(at),
        table_u32(at + 1u),
        table_u32(at + 2u),
        table_u32(at + 3u),
        texture_vec3(at + 4u),
        table_u32(at + 7u),
        texture_vec3(at + 8u),
        0u,
        texture_vec3(at + 12u),
        0u,
        texture_vec3(at + 16u),
        0u,
    );
}

// The value of texture `index` at `uv` (linear RGB), clamped to [0, 1] per channel when the
// texture says so (texture.rs `eval`).
fn texture_eval(index: u32, uv: vec2f) -> vec3f {
    let t = texture_at(index);
    let value = texture_lookup(t, uv);
    if ((t.tag & TEXTURE_FLAG_CLAMP) != 0u) {
        // max, then min, as texture.rs computes it.
        return min(max(value, vec3f(0.0)), vec3f(1.0));
    }
    return value;
}

// The value of texture `t` at `uv`, unclamped (texture.rs `lookup`).
fn texture_lookup(t: Texture, uv: vec2f) -> vec3f {
    let u = t.uv_u.x * uv.x + (t.uv_u.y * uv.y + t.uv_u.z);
    let v = t.uv_v.x * uv.x + (t.uv_v.y * uv.y + t.uv_v.z);
    if ((t.tag & 0xffu) == TEXTURE_CHECKERBOARD) {
        let a = u - floor(u) > 0.5;
        let b = v - floor(v) > 0.5;
        return select(t.other, t.value, a == b);
    }
    let wrap_u = (t.tag >> 16u) & 0xfu;
    let wrap_v = (t.tag >> 20u) & 0xfu;
    // Continuous texel coordinates, one period of the wrap.
    let x = texture_reduce(u, wrap_u) * f32(t.width) - 0.5;
    let y = texture_reduce(v, wrap_v) * f32(t.height) - 0.5;
    let x0f = floor(x);
    let y0f = floor(y);
    let fx = x - x0f;
    let fy = y - y0f;
    let x0 = i32(x0f);
    let y0 = i32(y0f);
    let c0 = texture_wrap(x0, t.width, wrap_u);
    let c1 = texture_wrap(x0 + 1, t.width, wrap_u);
    let r0 = texture_wrap(y0, t.height, wrap_v);
    let r1 = texture_wrap(y0 + 1, t.height, wrap_v);
    let t00 = texture_texel(t, r0 * t.width + c0);
    let t10 = texture_texel(t, r0 * t.width + c1);
    let t01 = texture_texel(t, r1 * t.width + c0);
    let t11 = texture_texel(t, r1 * t.width + c1);
    let gx = 1.0 - fx;
    let gy = 1.0 - fy;
    let top = t00 * gx + t10 * fx;
    let bottom = t01 * gx + t11 * fx;
    return (top * gy + bottom * fy) * t.value;
}

// A number from a texture: a grey value itself, else the luminance (texture.rs `scalar`).
fn texture_eval_scalar(index: u32, uv: vec2f) -> f32 {
    let c = texture_eval(index, uv);
    if (c.x == c.y && c.y == c.z) {
        return c.x;
    }
    return 0.212671 * c.x + 0.71516 * c.y + 0.072169 * c.z;
}

// `material` with its textured parameters looked up at `uv`, its texture flags cleared.
fn texture_resolve(material: Material, uv: vec2f) -> Material {
    var m = material;
    if ((m.tag & MATERIAL_COLOR_TEXTURE) != 0u) {
        m.color = texture_eval(u32(m.color.x), uv);
    }
    if ((m.tag & MATERIAL_ALPHA_TEXTURE) != 0u) {
        let iu = u32(m.alpha_u);
        let iv = u32(m.alpha_v);
        m.alpha_u = texture_eval_scalar(iu, uv);
        m.alpha_v = m.alpha_u;
        if (iv != iu) {
            m.alpha_v = texture_eval_scalar(iv, uv);
        }
    }
    if ((m.tag & MATERIAL_ETA_TEXTURE) != 0u) {
        m.eta = texture_eval(u32(m.eta.x), uv);
    }
    if ((m.tag & MATERIAL_K_TEXTURE) != 0u) {
        m.k = texture_eval(u32(m.k.x), uv);
    }
    m.tag = m.tag & ~MATERIAL_TEXTURES;
    return m;
}

// `t` reduced to one period of `wrap` (texture.rs `reduce`); not a number reads as 0.
fn texture_reduce(t: f32, wrap: u32) -> f32 {
    let s = select(0.0, t, t == t);
    if (wrap == TEXTURE_CLAMP) {
        return clamp(s, -1.0, 2.0);
    }
    if (wrap == TEXTURE_MIRROR) {
        return s - 2.0 * floor(0.5 * s);
    }
    return s - floor(s);
}

// Euclidean remainder of `i` by `n > 0`.
fn texture_rem(i: i32, n: i32) -> i32 {
    let m = i % n;
    return select(m, m + n, m < 0);
}

// Integer texel index `i` of an axis of `n` texels, wrapped (texture.rs `wrap`).
fn texture_wrap(i: i32, n: u32, wrap: u32) -> u32 {
    let ni = i32(n);
    var k: i32;
    if (wrap == TEXTURE_CLAMP) {
        k = clamp(i, 0, ni - 1);
    } else if (wrap == TEXTURE_MIRROR) {
        let m = texture_rem(i, 2 * ni);
        k = select(2 * ni - 1 - m, m, m < ni);
    } else {
        k = texture_rem(i, ni);
    }
    return min(u32(max(k, 0)), n - 1u);
}

// Texel `i` (row-major from the top-left) of image `t`, linear RGB, unscaled.
fn texture_texel(t: Texture, i: u32) -> vec3f {
    let format = (t.tag >> 8u) & 0xffu;
    if (format == TEXEL_RGB32F) {
        return texture_vec3(t.texels + 3u * i);
    }
    if (format == TEXEL_GREY32F) {
        return vec3f(table_f32(t.texels + i));
    }
    let word = table_u32(t.texels + i);
    return vec3f(
        table_f32(t.decode + (word & 0xffu)),
        table_f32(t.decode + ((word >> 8u) & 0xffu)),
        table_f32(t.decode + ((word >> 16u) & 0xffu)),
    );
}
