//! Named materials (`[materials.NAME]`) and the ones meshes bring from their MTL files.

use super::textures::Textures;
use super::validate::{Ctx, Result};
use crate::desc::{CoatedDesc, Detail, Spanned};
use crate::desc::{
    ColorParam, MaterialDesc, MixDesc, Numbers, PlasticDesc, RoughnessParam, Textured,
};
use std::collections::HashMap;
use std::ops::Range;
use stratapt_sampling::warp::ggx::Masking;
use stratapt_scene::coating::{fresnel_diffuse_reflectance, RoughCoating};
use stratapt_scene::records::{
    material_flag, material_kind, texel_format, texture_kind, Material, MAX_MIX_DEPTH, MIRROR_ALPHA,
};

/// The scene's materials, in [`stratapt_scene::FlatScene::materials`] order.
#[derive(Default)]
pub struct Materials {
    pub gpu: Vec<Material>,
    pub names: Vec<String>,
    /// [`stratapt_scene::FlatScene::tables`].
    pub tables: Vec<f32>,
    by_name: HashMap<String, u32>,
    /// How many come from `[materials]` (the ones a scene may name).
    named: usize,
}

impl Materials {
    /// Validate and convert the `[materials.NAME]` tables, whose textures are `textures` (their
    /// records already in `tables`, which the materials' tables follow).
    pub fn from_descs(
        ctx: &Ctx,
        descs: &[(Spanned<String>, MaterialDesc)],
        textures: &Textures,
        tables: Vec<f32>,
    ) -> Result<Self> {
        let mut out = Materials {
            tables,
            ..Materials::default()
        };
        for (name, desc) in descs {
            let material = match desc {
                // Its materials are named, maybe further on: resolved below.
                MaterialDesc::Mix(d) => mix(ctx, d, emission_of(ctx, &d.emission)?, textures)?,
                MaterialDesc::Coated(d) => {
                    coated(ctx, d, emission_of(ctx, &d.emission)?, textures)?
                }
                _ => convert(ctx, name.span(), desc, textures, &mut out.tables)?,
            };
            out.add(name.get_ref().clone(), material);
        }
        out.named = out.gpu.len();
        for (i, (_, desc)) in descs.iter().enumerate() {
            if let MaterialDesc::Mix(d) = desc {
                let names = d.materials.get_ref();
                let pick = [out.lookup(ctx, &names[0])?, out.lookup(ctx, &names[1])?];
                out.gpu[i].k = [pick[0] as f32, pick[1] as f32, 0.0];
            }
        }
        // Bump and normal maps: the named index becomes the map, over a copy of the material.
        for (i, (name, desc)) in descs.iter().enumerate() {
            if let Some(map) = detail(ctx, desc.detail(), textures)? {
                let inner = out.gpu[i];
                out.gpu.push(inner);
                out.names
                    .push(format!("{} (under its map)", name.get_ref()));
                out.gpu[i] = Material {
                    emission: inner.emission,
                    k: [(out.gpu.len() - 1) as f32, 0.0, 0.0],
                    ..map
                };
            }
        }
        for (i, (name, desc)) in descs.iter().enumerate() {
            if let MaterialDesc::Mix(d) = desc {
                out.check_nesting(ctx, i as u32, name, d)?;
            }
        }
        for (i, (_, desc)) in descs.iter().enumerate() {
            if let MaterialDesc::Coated(d) = desc {
                out.set_base(ctx, i, d)?;
            }
        }
        Ok(out)
    }

    /// Coated material `i`'s base, named by `d.base`: its index, and the kind it makes the coated
    /// material (a coated diffuse or conductor); an error for any other material.
    fn set_base(&mut self, ctx: &Ctx, i: usize, d: &CoatedDesc) -> Result<()> {
        let base = self.lookup(ctx, &d.base)?;
        let kind = match self.gpu[base as usize].kind() {
            material_kind::BUMP | material_kind::NORMAL_MAP => {
                return Err(ctx.err(
                    d.base.span(),
                    format!(
                        "`{}` has a displacement or normal map, which a coat's base cannot \
                         have (pbrt-v4's coated materials take them on the coat): give it to \
                         the coated material",
                        d.base.get_ref()
                    ),
                ))
            }
            material_kind::DIFFUSE => material_kind::COATED_DIFFUSE,
            material_kind::CONDUCTOR | material_kind::COMPLEX_CONDUCTOR => {
                material_kind::COATED_CONDUCTOR
            }
            _ => {
                return Err(ctx.err(
                    d.base.span(),
                    format!(
                        "`{}` is no diffuse or conductor material: a coat goes over one of \
                         those (pbrt-v4's coateddiffuse and coatedconductor)",
                        d.base.get_ref()
                    ),
                ))
            }
        };
        // A coated material with a bump or normal map: the record under the map.
        let i = match is_map(&self.gpu[i]) {
            true => self.gpu[i].k[0] as usize,
            false => i,
        };
        let m = &mut self.gpu[i];
        m.tag = (m.tag & !material_kind::MASK) | kind;
        m.k[1] = base as f32;
        Ok(())
    }

    /// An error unless mix `i` (named `name`) leads to materials within [`MAX_MIX_DEPTH`] mixes,
    /// and never back to itself.
    fn check_nesting(&self, ctx: &Ctx, i: u32, name: &Spanned<String>, d: &MixDesc) -> Result<()> {
        // Depth-first through the mixes, the path so far on the stack.
        let mut stack = vec![(i, 1u32)];
        while let Some((m, depth)) = stack.pop() {
            let record = &self.gpu[m as usize];
            if is_map(record) {
                stack.push((record.k[0] as u32, depth));
                continue;
            }
            if record.kind() != material_kind::MIX {
                continue;
            }
            if depth > MAX_MIX_DEPTH {
                return Err(ctx.err(
                    d.materials.span(),
                    format!(
                        "mix `{}` nests more than {MAX_MIX_DEPTH} mixes deep (a mix that leads \
                         back to itself, through `{}`?)",
                        name.get_ref(),
                        self.names[m as usize]
                    ),
                ));
            }
            stack.extend(record.k[..2].iter().map(|&c| (c as u32, depth + 1)));
        }
        Ok(())
    }

    /// Whether material `i` reads a texture, itself or through the materials it mixes: hits on
    /// it need their texture coordinates.
    pub fn reads_texture(&self, i: u32) -> bool {
        let mut pending = vec![(i, 0)];
        while let Some((m, depth)) = pending.pop() {
            let record = &self.gpu[m as usize];
            if record.tag & material_flag::TEXTURES != 0 {
                return true;
            }
            if record.kind() == material_kind::MIX && depth < MAX_MIX_DEPTH {
                pending.extend(record.k[..2].iter().map(|&c| (c as u32, depth + 1)));
            }
            if is_map(record) && depth < MAX_MIX_DEPTH {
                pending.push((record.k[0] as u32, depth + 1));
            }
            let coated = [
                material_kind::COATED_DIFFUSE,
                material_kind::COATED_CONDUCTOR,
            ];
            if coated.contains(&record.kind()) && depth < MAX_MIX_DEPTH {
                pending.push((record.k[1] as u32, depth + 1));
            }
        }
        false
    }

    /// Add a material (or find the one already added under `name`); its index.
    pub fn add(&mut self, name: String, material: Material) -> u32 {
        if let Some(&i) = self.by_name.get(&name) {
            return i;
        }
        let i = self.gpu.len() as u32;
        self.gpu.push(material);
        self.by_name.insert(name.clone(), i);
        self.names.push(name);
        i
    }

    /// The index of a material named in the scene file (only `[materials]` names qualify).
    pub fn lookup(&self, ctx: &Ctx, name: &Spanned<String>) -> Result<u32> {
        match self.by_name.get(name.get_ref()) {
            Some(&i) if (i as usize) < self.named => Ok(i),
            _ => {
                let known = &self.names[..self.named];
                let list = if known.is_empty() {
                    "none defined".to_string()
                } else {
                    known.join(", ")
                };
                Err(ctx.err(
                    name.span(),
                    format!(
                        "unknown material `{}`; known materials: {list}",
                        name.get_ref()
                    ),
                ))
            }
        }
    }

    /// Emitted radiance of material `i` (zero for non-emitters).
    pub fn emission(&self, i: u32) -> [f32; 3] {
        self.gpu[i as usize].emission
    }
}

/// Whether `m` is a bump or normal map over another material (its `k[0]`).
fn is_map(m: &Material) -> bool {
    matches!(m.kind(), material_kind::BUMP | material_kind::NORMAL_MAP)
}

/// The bump or normal map record that a material's `displacement` or `normal_map` asks for (its
/// material, emission still to be filled in), or `None`.
fn detail(ctx: &Ctx, d: Detail<'_>, textures: &Textures) -> Result<Option<Material>> {
    match (d.displacement, d.normal_map) {
        (None, None) => Ok(None),
        (Some(_), Some(n)) => Err(ctx.err(
            n.span(),
            "a material takes a displacement or a normal map, not both",
        )),
        (Some(h), None) => {
            let (height, flag) = match h.get_ref() {
                Textured::Value(Numbers([v])) => {
                    (ctx.finite(&Spanned::new(h.span(), *v), "displacement")?, 0)
                }
                Textured::Texture(name) => (
                    textures.lookup(ctx, h.span(), name)? as f32,
                    material_flag::COLOR_TEXTURE,
                ),
            };
            Ok(Some(Material {
                tag: material_kind::BUMP | flag,
                color: [height, 0.0, 0.0],
                ..Material::default()
            }))
        }
        (None, Some(n)) => {
            let i = textures.lookup(ctx, n.span(), n.get_ref())?;
            let t = textures.record(i);
            let format = t.tag >> 8 & 0xff;
            if t.tag & 0xff != texture_kind::IMAGE {
                return Err(ctx.err(
                    n.span(),
                    format!("normal map `{}` is no image texture", n.get_ref()),
                ));
            }
            if format == texel_format::SRGB8 {
                return Err(ctx.err(
                    n.span(),
                    format!(
                        "normal map `{}` would be decoded from sRGB: a normal map holds \
                         directions, not colours; give its texture `raw = true`",
                        n.get_ref()
                    ),
                ));
            }
            Ok(Some(Material {
                tag: material_kind::NORMAL_MAP | material_flag::COLOR_TEXTURE,
                color: [i as f32, 0.0, 0.0],
                ..Material::default()
            }))
        }
    }
}

/// Whether an emission colour emits anything.
pub fn emits(emission: [f32; 3]) -> bool {
    emission.iter().any(|&e| e > 0.0)
}

/// An `emission` key's radiance (black without one).
fn emission_of(ctx: &Ctx, e: &Option<Spanned<crate::desc::Triple>>) -> Result<[f32; 3]> {
    match e {
        Some(e) => ctx.emitted(e, "emission"),
        None => Ok([0.0; 3]),
    }
}

/// A mix's record, its two materials still to be filled in (`k[0]`, `k[1]`): the amount (in
/// `[0, 1]`, 0.5 by default) or its texture, read as one number per point.
fn mix(ctx: &Ctx, d: &MixDesc, emission: [f32; 3], textures: &Textures) -> Result<Material> {
    if d.materials.get_ref().len() != 2 {
        return Err(ctx.err(
            d.materials.span(),
            format!(
                "a mix names two materials, not {}",
                d.materials.get_ref().len()
            ),
        ));
    }
    let (amount, flag) = match d.amount.as_ref().map(|a| (a.span(), a.get_ref())) {
        None => (0.5, 0),
        Some((span, Textured::Value(Numbers([a])))) => {
            if !(0.0..=1.0).contains(a) {
                return Err(ctx.err(span, format!("amount {a}: a probability, in [0, 1]")));
            }
            (*a as f32, 0)
        }
        Some((span, Textured::Texture(name))) => (
            textures.lookup(ctx, span, name)? as f32,
            material_flag::ALPHA_TEXTURE,
        ),
    };
    Ok(Material {
        tag: material_kind::MIX | flag,
        emission,
        alpha_u: amount,
        alpha_v: amount,
        ..Material::default()
    })
}

/// Events per random walk and walks per estimate at most (pbrt-v4 has no bound; these keep an
/// evaluation's cost bounded on the GPU).
const MAX_WALK_EVENTS: u32 = 100;
const MAX_WALKS: u32 = 16;

/// A coated material's record, its base still to be filled in (`k[1]`, and the kind, by
/// [`Materials::set_base`]): pbrt-v4's defaults, index 1.5, smooth, thickness 0.01, a clear
/// slab, 10 events, 1 walk.
fn coated(ctx: &Ctx, d: &CoatedDesc, emission: [f32; 3], textures: &Textures) -> Result<Material> {
    let ior = match &d.ior {
        Some(ior) => ctx.positive(ior, "ior")?,
        None => 1.5,
    };
    let roughness = roughness(ctx, &d.roughness, textures)?;
    let thickness = match &d.thickness {
        Some(t) => ctx.positive(t, "thickness")?,
        None => 0.01,
    };
    let albedo = match &d.albedo {
        Some(a) => unit_color(ctx, a, "albedo", textures)?,
        None => Param::constant([0.0; 3]),
    };
    let g = match &d.g {
        Some(g) => {
            let v = ctx.finite(g, "g")?;
            if !(-1.0 < v && v < 1.0) {
                return Err(ctx.err(g.span(), format!("g {v}: within (−1, 1)")));
            }
            v
        }
        None => 0.0,
    };
    let max_depth = match &d.max_depth {
        Some(n) => ctx.count(n, "max_depth", MAX_WALK_EVENTS)?,
        None => 10,
    };
    let samples = match &d.samples {
        Some(n) => ctx.count(n, "samples", MAX_WALKS)?,
        None => 1,
    };
    Ok(Material {
        color: albedo.value,
        tag: material_kind::COATED_DIFFUSE
            | albedo.flag(material_flag::COLOR_TEXTURE)
            | roughness.flag,
        emission,
        ior,
        eta: [thickness, g, max_depth as f32],
        alpha_u: roughness.alpha[0],
        k: [samples as f32, 0.0, 0.0],
        alpha_v: roughness.alpha[1],
    })
}

fn convert(
    ctx: &Ctx,
    name: Range<usize>,
    desc: &MaterialDesc,
    textures: &Textures,
    tables: &mut Vec<f32>,
) -> Result<Material> {
    let emission = |e: &Option<Spanned<crate::desc::Triple>>| match e {
        Some(e) => ctx.emitted(e, "emission"),
        None => Ok([0.0; 3]),
    };
    let color = |p: &Spanned<ColorParam>, key| unit_color(ctx, p, key, textures);
    Ok(match desc {
        MaterialDesc::Diffuse(d) => {
            let albedo = color(&d.albedo, "albedo")?;
            let material = Material {
                color: albedo.value,
                tag: material_kind::DIFFUSE | albedo.flag(material_flag::COLOR_TEXTURE),
                emission: emission(&d.emission)?,
                ..Material::default()
            };
            match &d.transmittance {
                Some(t) => diffuse_transmission(ctx, material, albedo, t, textures)?,
                None => material,
            }
        }
        MaterialDesc::Conductor(d) => {
            let roughness = roughness(ctx, &d.roughness, textures)?;
            let conductor = Material {
                tag: masking(ctx, &d.masking)? | roughness.flag,
                emission: emission(&d.emission)?,
                alpha_u: roughness.alpha[0],
                alpha_v: roughness.alpha[1],
                ..Material::default()
            };
            match (&d.reflectance, &d.eta, &d.k) {
                (Some(reflectance), None, None) => {
                    if let Some(tint) = &d.tint {
                        return Err(ctx.err(
                            tint.span(),
                            "`tint` scales the reflectance of `eta` and `k`; with \
                             `reflectance`, multiply it in",
                        ));
                    }
                    let f0 = color(reflectance, "reflectance")?;
                    Material {
                        color: f0.value,
                        tag: conductor.tag
                            | material_kind::CONDUCTOR
                            | f0.flag(material_flag::COLOR_TEXTURE),
                        ..conductor
                    }
                }
                (None, Some(eta), Some(k)) => {
                    let tint = match &d.tint {
                        Some(t) => color(t, "tint")?,
                        None => Param::constant([1.0; 3]),
                    };
                    let eta = index_part(ctx, eta, "eta", textures, true)?;
                    let k = index_part(ctx, k, "k", textures, false)?;
                    Material {
                        color: tint.value,
                        tag: conductor.tag
                            | material_kind::COMPLEX_CONDUCTOR
                            | tint.flag(material_flag::COLOR_TEXTURE)
                            | eta.flag(material_flag::ETA_TEXTURE)
                            | k.flag(material_flag::K_TEXTURE),
                        eta: eta.value,
                        k: k.value,
                        ..conductor
                    }
                }
                (Some(reflectance), _, _) => {
                    return Err(ctx.err(
                        reflectance.span(),
                        "a conductor takes either `reflectance` (Schlick's Fresnel) or `eta` \
                         and `k` (a complex index of refraction), not both",
                    ))
                }
                (None, Some(eta), None) => {
                    return Err(ctx.err(
                        eta.span(),
                        "`eta` needs `k`, the imaginary part of the index of refraction",
                    ))
                }
                (None, None, Some(k)) => {
                    return Err(ctx.err(
                        k.span(),
                        "`k` needs `eta`, the real part of the index of refraction",
                    ))
                }
                (None, None, None) => {
                    return Err(ctx.err(
                        name,
                        "a conductor needs `reflectance` (Schlick's Fresnel) or `eta` and `k` \
                         (a complex index of refraction)",
                    ))
                }
            }
        }
        MaterialDesc::Plastic(d) => plastic(ctx, d, emission(&d.emission)?, textures, tables)?,
        MaterialDesc::Mix(d) => mix(ctx, d, emission(&d.emission)?, textures)?,
        MaterialDesc::Coated(d) => coated(ctx, d, emission(&d.emission)?, textures)?,
        MaterialDesc::Dielectric(d) => {
            let roughness = roughness(ctx, &d.roughness, textures)?;
            let [alpha_u, alpha_v] = roughness.alpha;
            let ior = match &d.ior {
                Some(ior) => ctx.positive(ior, "ior")?,
                None => DEFAULT_IOR,
            };
            // Smoother than the mirror threshold is the smooth (delta) dielectric; so is an
            // index-matched one, whose microfacets neither reflect nor bend light. A textured
            // roughness is rough everywhere (at least the threshold where the texture is less).
            let rough = (roughness.flag != 0 || alpha_u.max(alpha_v) > MIRROR_ALPHA) && ior != 1.0;
            let thin = d.thin.as_ref().filter(|t| *t.get_ref());
            if let (Some(_), Some(r)) = (thin, &d.roughness) {
                if roughness.flag != 0 || alpha_u.max(alpha_v) > 0.0 {
                    return Err(ctx.err(
                        r.span(),
                        "a thin dielectric is smooth (pbrt-v4's and Mitsuba 3's alike): \
                         `roughness` cannot go with `thin = true`",
                    ));
                }
            }
            let tint = match &d.tint {
                Some(t) => color(t, "tint")?,
                None => Param::constant([1.0; 3]),
            };
            Material {
                color: tint.value,
                // The masking key is checked even where no microfacets use it.
                tag: tint.flag(material_flag::COLOR_TEXTURE)
                    | match (thin.is_some(), rough, masking(ctx, &d.masking)?) {
                        (true, _, _) => material_kind::THIN_DIELECTRIC,
                        (false, true, flag) => {
                            material_kind::ROUGH_DIELECTRIC | flag | roughness.flag
                        }
                        (false, false, _) => material_kind::DIELECTRIC,
                    },
                emission: emission(&d.emission)?,
                ior,
                alpha_u: if rough { alpha_u } else { 0.0 },
                alpha_v: if rough { alpha_v } else { 0.0 },
                ..Material::default()
            }
        }
    })
}

/// A diffuse `material` of reflectance `albedo` that also transmits `t`: pbrt-v4's
/// `diffusetransmission`. Reflectance and transmittance may not sum above 1 in any channel (at
/// their largest, for textures), which would create energy.
fn diffuse_transmission(
    ctx: &Ctx,
    material: Material,
    albedo: Param,
    t: &Spanned<ColorParam>,
    textures: &Textures,
) -> Result<Material> {
    let transmittance = unit_color(ctx, t, "transmittance", textures)?;
    let largest = |p: &Param| match p.textured {
        true => [textures.stats[p.value[0] as usize].max; 3],
        false => p.value,
    };
    let (r, tr) = (largest(&albedo), largest(&transmittance));
    if let Some(c) = (0..3).find(|&c| r[c] + tr[c] > 1.0 + 1e-6) {
        return Err(ctx.err(
            t.span(),
            format!(
                "`albedo` {} and `transmittance` {} sum to {} in the {} channel{}: above 1 \
                 the surface would create energy",
                r[c],
                tr[c],
                r[c] + tr[c],
                ["red", "green", "blue"][c],
                if albedo.textured || transmittance.textured {
                    " (a texture's largest value)"
                } else {
                    ""
                }
            ),
        ));
    }
    Ok(Material {
        tag: material_kind::DIFFUSE_TRANSMISSION
            | albedo.flag(material_flag::COLOR_TEXTURE)
            | transmittance.flag(material_flag::ETA_TEXTURE),
        eta: transmittance.value,
        ..material
    })
}

/// A plastic: smooth, or rough when its roughness is above the mirror threshold, with the
/// coating's precomputed quantities in its record (and, rough, its table in `tables`).
fn plastic(
    ctx: &Ctx,
    d: &PlasticDesc,
    emission: [f32; 3],
    textures: &Textures,
    tables: &mut Vec<f32>,
) -> Result<Material> {
    let diffuse = match &d.diffuse {
        Some(c) => unit_color(ctx, c, "diffuse", textures)?,
        None => Param::constant([0.5; 3]),
    };
    let specular = match &d.specular {
        Some(c) => unit_color(ctx, c, "specular", textures)?,
        None => Param::constant([1.0; 3]),
    };
    let ior = match &d.ior {
        Some(ior) => ctx.positive(ior, "ior")?,
        None => DEFAULT_PLASTIC_IOR,
    };
    let alpha = match &d.roughness {
        Some(r) => {
            let Textured::Value(pair) = r.get_ref() else {
                return Err(ctx.err(
                    r.span(),
                    "a plastic's roughness cannot be a texture: its coating's tables are \
                     computed for one α (as Mitsuba 3's `roughplastic`)",
                ));
            };
            let [u, v] = ctx.non_negative2(&Spanned::new(r.span(), *pair), "roughness")?;
            if u != v {
                return Err(ctx.err(
                    r.span(),
                    "a plastic's roughness is one α: its coating is isotropic, as Mitsuba 3's \
                     `roughplastic`",
                ));
            }
            u
        }
        None => 0.0,
    };
    let rough = alpha > MIRROR_ALPHA;
    if let (Some(ior_key), true) = (&d.ior, ior == 1.0) {
        return Err(ctx.err(
            ior_key.span(),
            "a plastic's coating needs an index of refraction other than 1 (an index-matched \
             coating is the diffuse material)",
        ));
    }
    // Mitsuba's weight for sampling the coating: its mean reflectance against the base's.
    let (d_mean, s_mean) = (diffuse.mean, specular.mean);
    let specular_weight = if d_mean + s_mean > 0.0 {
        s_mean / (d_mean + s_mean)
    } else {
        0.5
    };
    let mut tag = if d.nonlinear == Some(true) {
        material_flag::NONLINEAR
    } else {
        0
    };
    // The masking key is checked even where no microfacets use it.
    let masking_flag = masking(ctx, &d.masking)?;
    let (kind, internal, table) = if rough {
        tag |= masking_flag;
        let separable = tag & material_flag::SEPARABLE_MASKING != 0;
        let coating = RoughCoating::new(
            ior,
            alpha,
            if separable {
                Masking::Separable
            } else {
                Masking::Correlated
            },
        );
        let index = tables.len();
        tables.extend_from_slice(&coating.transmittance);
        (
            material_kind::ROUGH_PLASTIC,
            coating.internal_reflectance,
            index as f32,
        )
    } else {
        (
            material_kind::PLASTIC,
            fresnel_diffuse_reflectance(1.0 / ior),
            0.0,
        )
    };
    if table as usize >= 1 << 24 {
        return Err(ctx.err(
            d.roughness.as_ref().map_or(0..0, |r| r.span()),
            "too many rough plastics: their tables exceed 2^24 entries",
        ));
    }
    tag |= diffuse.flag(material_flag::COLOR_TEXTURE) | specular.flag(material_flag::ETA_TEXTURE);
    Ok(Material {
        color: diffuse.value,
        tag: tag | kind,
        emission,
        ior,
        eta: specular.value,
        alpha_u: if rough { alpha } else { 0.0 },
        k: [internal, specular_weight, table],
        alpha_v: if rough { alpha } else { 0.0 },
    })
}

/// A colour parameter as a record holds it: the colour, or a texture's index in `value[0]`.
#[derive(Clone, Copy)]
struct Param {
    value: [f32; 3],
    textured: bool,
    /// Mitsuba 3's `mean()`: the mean channel of a colour, the mean luminance of an image.
    mean: f32,
}

impl Param {
    fn constant(c: [f32; 3]) -> Self {
        Self {
            value: c,
            textured: false,
            mean: (c[0] + c[1] + c[2]) / 3.0,
        }
    }

    /// `flag` when the parameter is a texture, else 0.
    fn flag(&self, flag: u32) -> u32 {
        if self.textured {
            flag
        } else {
            0
        }
    }
}

/// A reflectance-like colour or a texture whose values are all in `[0, 1]` (more would create
/// energy), such as one that clamps its lookups.
fn unit_color(ctx: &Ctx, p: &Spanned<ColorParam>, key: &str, textures: &Textures) -> Result<Param> {
    match p.get_ref() {
        Textured::Value(c) => Ok(Param::constant(
            ctx.unit_color(&Spanned::new(p.span(), *c), key)?,
        )),
        Textured::Texture(name) => {
            let i = textures.lookup(ctx, p.span(), name)?;
            let stats = textures.stats[i as usize];
            if stats.max > 1.0 {
                return Err(ctx.err(
                    p.span(),
                    format!(
                        "texture `{name}` reaches {} (scaled): `{key}` must lie in [0, 1] \
                         (above 1 the surface would create energy; `clamp = true` on the \
                         texture clamps each lookup)",
                        stats.max
                    ),
                ));
            }
            Ok(Param {
                value: [i as f32, 0.0, 0.0],
                textured: true,
                mean: stats.mean,
            })
        }
    }
}

/// A part of a complex index of refraction (`eta`, positive, or `k`, non-negative) or a texture
/// of it.
fn index_part(
    ctx: &Ctx,
    p: &Spanned<ColorParam>,
    key: &str,
    textures: &Textures,
    positive: bool,
) -> Result<Param> {
    match p.get_ref() {
        Textured::Value(c) => {
            let c = Spanned::new(p.span(), *c);
            Ok(Param::constant(match positive {
                true => ctx.positive3(&c, key)?,
                false => ctx.non_negative3(&c, key)?,
            }))
        }
        Textured::Texture(name) => {
            let i = textures.lookup(ctx, p.span(), name)?;
            let stats = textures.stats[i as usize];
            if positive && stats.min <= 0.0 {
                return Err(ctx.err(
                    p.span(),
                    format!("texture `{name}` reaches 0: `{key}` must be positive"),
                ));
            }
            Ok(Param {
                value: [i as f32, 0.0, 0.0],
                textured: true,
                mean: stats.mean,
            })
        }
    }
}

/// A GGX roughness as a record holds it: `[αu, αv]`, or the texture's index in both with
/// [`material_flag::ALPHA_TEXTURE`].
struct Roughness {
    alpha: [f32; 2],
    flag: u32,
}

fn roughness(
    ctx: &Ctx,
    p: &Option<Spanned<RoughnessParam>>,
    textures: &Textures,
) -> Result<Roughness> {
    Ok(match p {
        None => Roughness {
            alpha: [0.0; 2],
            flag: 0,
        },
        Some(r) => match r.get_ref() {
            Textured::Value(pair) => Roughness {
                alpha: ctx.non_negative2(&Spanned::new(r.span(), *pair), "roughness")?,
                flag: 0,
            },
            Textured::Texture(name) => {
                let i = textures.lookup(ctx, r.span(), name)? as f32;
                Roughness {
                    alpha: [i, i],
                    flag: material_flag::ALPHA_TEXTURE,
                }
            }
        },
    })
}

/// The coating's index of refraction when none is given: polypropylene, Mitsuba's default
/// `int_ior` (which it divides by air's 1.000277; strata's `ior` is relative).
pub const DEFAULT_PLASTIC_IOR: f32 = 1.49;

/// The [`material_flag`] of a GGX material's `masking` key (none for the default,
/// `"correlated"`).
fn masking(ctx: &Ctx, key: &Option<Spanned<String>>) -> Result<u32> {
    let Some(key) = key else {
        return Ok(0);
    };
    ctx.one_of(key, "masking", &["correlated", "separable"], |s| match s {
        "correlated" => Some(0),
        "separable" => Some(material_flag::SEPARABLE_MASKING),
        _ => None,
    })
}

/// Index of refraction when none is given (glass).
pub const DEFAULT_IOR: f32 = 1.5;
