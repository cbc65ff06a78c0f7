//! strata's materials as Mitsuba 3 BSDFs, and the textures they read as Mitsuba textures.
//!
//! strata's materials are modelled on Mitsuba's, so most map one to one: `diffuse`,
//! `conductor` / `roughconductor` (GGX, visible normals), `dielectric` / `roughdielectric`,
//! `plastic` / `roughplastic` (with `nonlinear`), `thindielectric`, `blendbsdf` for a mix,
//! indices relative (`ext_ior` 1). Every material but a dielectric, smooth, rough or thin, is wrapped in `twosided`:
//! strata's are two-sided (a thin sheet is so by itself). Diffuse transmission has no Mitsuba
//! counterpart: it is written as its diffuse reflection, warned. Bump and normal maps are
//! Mitsuba's `bumpmap` and `normalmap` over the material they wrap.

use super::xml::Element;
use super::Writer;
use stratapt_scene::environment::pfm_bytes;
use stratapt_scene::records::{
    material_flag as flag, material_kind as kind, texture_flag, texture_kind, Material,
    MIRROR_ALPHA,
};
use stratapt_scene::texture;

impl Writer<'_> {
    /// The id of material `index`'s BSDF, declared on first use.
    pub(super) fn bsdf(&mut self, index: u32) -> String {
        if let Some(id) = self.bsdfs.get(&index) {
            return id.clone();
        }
        let id = format!("bsdf{index}");
        let m = self.scene.materials[index as usize];
        let name = self
            .scene
            .material_names
            .get(index as usize)
            .cloned()
            .unwrap_or_default();
        if m.kind() == kind::BUMP && !m.has(flag::COLOR_TEXTURE) {
            self.warn(format!(
                "material `{name}`: a constant displacement has no Mitsuba 3 counterpart; \
                 written without it (it moves the surface, and tilts only a curved one's normal)"
            ));
            let id = self.bsdf(m.k[0] as u32);
            self.bsdfs.insert(index, id.clone());
            return id;
        }
        let mut bsdf = self.material(&m, &name);
        // Dielectrics are two-sided by themselves, and a mix's materials are wrapped already.
        let wrapped = [
            kind::DIELECTRIC,
            kind::ROUGH_DIELECTRIC,
            kind::THIN_DIELECTRIC,
            kind::MIX,
            kind::BUMP,
            kind::NORMAL_MAP,
        ];
        if !wrapped.contains(&m.kind()) {
            bsdf = Element::plugin("bsdf", "twosided").child(bsdf);
        }
        let mut bsdf = bsdf.attr("id", &id);
        bsdf.comment(&format!("strata material `{name}`"));
        self.declarations.push(bsdf);
        self.bsdfs.insert(index, id.clone());
        id
    }

    /// The id of material `index`'s BSDF cut out by `alpha`, declared on first use: Mitsuba's
    /// `mask` of the alpha (its `opacity`, a number or the texture) over the BSDF, which passes a
    /// ray with probability `1 − opacity` as strata's alpha does (the same image, measured:
    /// `docs/measurements/pbrt-materials.md`).
    pub(super) fn mask(&mut self, index: u32, alpha: stratapt_scene::Alpha) -> String {
        let (flags, word) = alpha.encode();
        if let Some(id) = self.masks.get(&(index, flags, word)) {
            return id.clone();
        }
        let inner = self.bsdf(index);
        let id = format!("mask{}", self.masks.len());
        let opacity = match alpha {
            stratapt_scene::Alpha::Texture(t) => reference("opacity", &self.float_texture(t)),
            stratapt_scene::Alpha::Constant(a) => Element::float("opacity", a),
            stratapt_scene::Alpha::Opaque => Element::float("opacity", 1.0),
        };
        let e = Element::plugin("bsdf", "mask")
            .child(opacity)
            .child(reference("bsdf", &inner))
            .attr("id", &id);
        self.declarations.push(e);
        self.masks.insert((index, flags, word), id.clone());
        id
    }

    /// One material's BSDF (one-sided).
    fn material(&mut self, m: &Material, name: &str) -> Element {
        match m.kind() {
            kind::DIFFUSE => Element::plugin("bsdf", "diffuse").child(self.color(
                "reflectance",
                m,
                flag::COLOR_TEXTURE,
                m.color,
            )),
            kind::CONDUCTOR => self.schlick_conductor(m, name),
            kind::COMPLEX_CONDUCTOR => {
                let e = self.microfacet(m, name, "conductor");
                e.child(self.color("eta", m, flag::ETA_TEXTURE, m.eta))
                    .child(self.color("k", m, flag::K_TEXTURE, m.k))
                    .child(self.color("specular_reflectance", m, flag::COLOR_TEXTURE, m.color))
            }
            kind::DIELECTRIC | kind::ROUGH_DIELECTRIC => {
                let e = self.microfacet(m, name, "dielectric");
                e.child(Element::float("int_ior", m.ior))
                    .child(Element::float("ext_ior", 1.0))
                    .child(self.color("specular_transmittance", m, flag::COLOR_TEXTURE, m.color))
            }
            kind::THIN_DIELECTRIC => Element::plugin("bsdf", "thindielectric")
                .child(Element::float("int_ior", m.ior))
                .child(Element::float("ext_ior", 1.0))
                .child(self.color("specular_transmittance", m, flag::COLOR_TEXTURE, m.color)),
            kind::DIFFUSE_TRANSMISSION => {
                self.warn(format!(
                    "material `{name}`: diffuse transmission has no Mitsuba 3 counterpart; \
                     written as its diffuse reflection (the light it transmits is lost)"
                ));
                Element::plugin("bsdf", "diffuse").child(self.color(
                    "reflectance",
                    m,
                    flag::COLOR_TEXTURE,
                    m.color,
                ))
            }
            kind::MIX => self.mix(m),
            kind::BUMP | kind::NORMAL_MAP => self.map(m),
            kind::COATED_DIFFUSE | kind::COATED_CONDUCTOR => self.coated(m, name),
            _ => self.plastic(m, name),
        }
    }

    /// A bump map as Mitsuba's `bumpmap` (scale 1: the heights are pbrt's, in scene units; Mitsuba
    /// differentiates the bilinear texture exactly where strata and pbrt take a finite difference
    /// of step 0.0005) and a normal map as its `normalmap`, each over its material's BSDF. A
    /// constant height tilts no normal of a flat surface: written as the material alone, warned
    /// ([`Writer::bsdf`]).
    fn map(&mut self, m: &Material) -> Element {
        let inner = self.bsdf(m.k[0] as u32);
        // pbrt's maps (and strata's) neither flip a normal that faces away from the incident
        // direction nor dim by a shadowing term, which Mitsuba (3.7 on) does by default.
        let pbrt = |e: Element| {
            e.child(Element::boolean("flip_invalid_normals", false))
                .child(Element::boolean("use_shadowing_function", false))
                .child(reference("bsdf", &inner))
        };
        if m.kind() == kind::NORMAL_MAP {
            let map = self.texture(m.color[0] as u32);
            return pbrt(Element::plugin("bsdf", "normalmap").child(reference("normalmap", &map)));
        }
        let height = self.float_texture(m.color[0] as u32);
        pbrt(
            Element::plugin("bsdf", "bumpmap")
                .child(reference("height", &height))
                .child(Element::float("scale", 1.0)),
        )
    }

    /// A coated material: Mitsuba 3 has no layered BSDF. A coat over a diffuse base is written
    /// as the plastic it approximates (`nonlinear`, the coat's index and roughness, the base's
    /// reflectance), a coat over a conductor as the bare conductor; both warned.
    fn coated(&mut self, m: &Material, name: &str) -> Element {
        let base = self.scene.materials[m.k[1] as usize];
        if m.kind() == kind::COATED_CONDUCTOR {
            self.warn(format!(
                "material `{name}`: a coated conductor (pbrt-v4's layered BSDF) has no Mitsuba 3 \
                 counterpart; written as its bare conductor"
            ));
            return self.material(&base, name);
        }
        self.warn(format!(
            "material `{name}`: a coated diffuse (pbrt-v4's layered BSDF, a random walk between \
             the coat and the base) has no Mitsuba 3 counterpart; written as Mitsuba's plastic \
             with `nonlinear`, which leaves out the slab and differs towards grazing angles"
        ));
        let alpha = match m.has(flag::ALPHA_TEXTURE) {
            true => {
                self.warn(format!(
                    "material `{name}`: Mitsuba's rough plastic takes one roughness; the coat's \
                     texture is written as its mean"
                ));
                self.texture_mean(m.alpha_u as u32)[0]
            }
            false => m.alpha_u,
        };
        let e = match alpha > MIRROR_ALPHA {
            true => self
                .rough(m, name, "plastic")
                .child(Element::float("alpha", alpha)),
            false => Element::plugin("bsdf", "plastic"),
        };
        e.child(self.color(
            "diffuse_reflectance",
            &base,
            flag::COLOR_TEXTURE,
            base.color,
        ))
        .child(Element::float("int_ior", m.ior))
        .child(Element::float("ext_ior", 1.0))
        .child(Element::boolean("nonlinear", true))
    }

    /// A mix as Mitsuba's `blendbsdf` of its two materials, `weight` the amount (a number or a
    /// texture): the same blend in expectation, which Mitsuba draws by sampling one BSDF per
    /// evaluation and strata by choosing one per path vertex.
    fn mix(&mut self, m: &Material) -> Element {
        let [a, b] = [m.k[0] as u32, m.k[1] as u32].map(|i| self.bsdf(i));
        let weight = match m.has(flag::ALPHA_TEXTURE) {
            true => reference("weight", &self.float_texture(m.alpha_u as u32)),
            false => Element::float("weight", m.alpha_u),
        };
        Element::plugin("bsdf", "blendbsdf")
            .child(weight)
            .child(Element::new("ref").attr("id", &a))
            .child(Element::new("ref").attr("id", &b))
    }

    /// A conductor with Schlick's Fresnel: Mitsuba has none, so the dielectric Fresnel whose
    /// normal-incidence reflectance is F0 (the curve Schlick's approximates), η = (1 + √F0) /
    /// (1 − √F0).
    fn schlick_conductor(&mut self, m: &Material, name: &str) -> Element {
        self.warn(format!(
            "material `{name}`: Schlick's Fresnel (conductor `reflectance`) has no Mitsuba \
             counterpart; written as a conductor with the dielectric Fresnel of the same \
             reflectance at normal incidence (k = 0), which differs at grazing angles"
        ));
        if m.has(flag::COLOR_TEXTURE) {
            self.warn(format!(
                "material `{name}`: a textured Schlick reflectance is written as its mean"
            ));
        }
        let f0 = match m.has(flag::COLOR_TEXTURE) {
            true => self.texture_mean(m.color[0] as u32),
            false => m.color,
        };
        let eta = f0.map(|f| {
            let s = f.clamp(0.0, 0.9999).sqrt();
            (1.0 + s) / (1.0 - s)
        });
        self.microfacet(m, name, "conductor")
            .child(Element::rgb("eta", eta))
            .child(Element::rgb("k", [0.0; 3]))
    }

    /// A plastic, smooth or rough (strata's rough plastic has one α, not textured: its
    /// coating's table is computed for it).
    fn plastic(&mut self, m: &Material, name: &str) -> Element {
        let e = match m.kind() == kind::ROUGH_PLASTIC {
            true => self
                .rough(m, name, "plastic")
                .child(Element::float("alpha", m.alpha_u.max(MIRROR_ALPHA))),
            false => Element::plugin("bsdf", "plastic"),
        };
        e.child(self.color("diffuse_reflectance", m, flag::COLOR_TEXTURE, m.color))
            .child(self.color("specular_reflectance", m, flag::ETA_TEXTURE, m.eta))
            .child(Element::float("int_ior", m.ior))
            .child(Element::float("ext_ior", 1.0))
            .child(Element::boolean("nonlinear", m.has(flag::NONLINEAR)))
    }

    /// `base` (`conductor`, `dielectric`) smooth, or `rough…` with its GGX α (textured or not,
    /// anisotropic where strata's is).
    fn microfacet(&mut self, m: &Material, name: &str, base: &str) -> Element {
        let textured = m.has(flag::ALPHA_TEXTURE);
        let mirror = !textured && m.alpha_u <= MIRROR_ALPHA && m.alpha_v <= MIRROR_ALPHA;
        if mirror || m.kind() == kind::DIELECTRIC {
            return Element::plugin("bsdf", base);
        }
        let e = self.rough(m, name, base);
        if textured {
            let (u, v) = (m.alpha_u as u32, m.alpha_v as u32);
            let (u, v) = (self.float_texture(u), self.float_texture(v));
            return match u == v {
                true => e.child(reference("alpha", &u)),
                false => e
                    .child(reference("alpha_u", &u))
                    .child(reference("alpha_v", &v)),
            };
        }
        let (au, av) = (m.alpha_u.max(MIRROR_ALPHA), m.alpha_v.max(MIRROR_ALPHA));
        if au == av {
            return e.child(Element::float("alpha", au));
        }
        self.warn(format!(
            "material `{name}`: anisotropic roughness along strata's tangents (Duff et al.'s frame \
             of the shading normal); Mitsuba's tangents follow the mesh's uv"
        ));
        e.child(Element::float("alpha_u", au))
            .child(Element::float("alpha_v", av))
    }

    /// Mitsuba's `rough{base}` with GGX sampled by visible normals, as strata's; its masking is
    /// separable, and a warning says so where strata's is not.
    fn rough(&mut self, m: &Material, name: &str, base: &str) -> Element {
        if !m.has(flag::SEPARABLE_MASKING) {
            self.warn(format!(
                "material `{name}`: Mitsuba's microfacet masking is separable; strata's is \
                 height-correlated (its default), which reflects a little more at grazing angles \
                 (`masking = \"separable\"` draws Mitsuba's)"
            ));
        }
        Element::plugin("bsdf", &format!("rough{base}"))
            .child(Element::string("distribution", "ggx"))
            .child(Element::boolean("sample_visible", true))
    }

    /// A colour parameter: `value`, or a reference to its texture when `m` has `texture_flag`
    /// (the texture's index is then `value[0]`).
    fn color(&mut self, name: &str, m: &Material, texture_flag: u32, value: [f32; 3]) -> Element {
        match m.has(texture_flag) {
            true => reference(name, &self.texture(value[0] as u32)),
            false => Element::rgb(name, value),
        }
    }

    /// The id of texture `index`, declared on first use: a `bitmap` of its linear texels (its
    /// scale multiplied in) as a PFM file, or a `checkerboard`.
    fn texture(&mut self, index: u32) -> String {
        if let Some(id) = self.textures.get(&index) {
            return id.clone();
        }
        let id = format!("texture{index}");
        let t = texture::record(&self.scene.tables, index);
        let to_uv = glam::Mat3::from_cols_array_2d(&[
            [t.uv_u[0], t.uv_v[0], 0.0],
            [t.uv_u[1], t.uv_v[1], 0.0],
            [t.uv_u[2], t.uv_v[2], 1.0],
        ]);
        let mut e = match t.tag & 0xff {
            texture_kind::CHECKERBOARD => Element::plugin("texture", "checkerboard")
                .child(Element::rgb("color0", t.value))
                .child(Element::rgb("color1", t.other)),
            _ => self.bitmap(index),
        };
        e = e.child(Element::matrix3("to_uv", to_uv)).attr("id", &id);
        self.declarations.push(e);
        self.textures.insert(index, id.clone());
        id
    }

    /// The id of texture `index` read as one number (a roughness, a mix's amount): the texture
    /// itself, except a checkerboard, whose copy with its two colours swapped is declared once
    /// beside it: Mitsuba 3.9.1's `checkerboard` returns `color1` from `eval_1` where `eval`
    /// returns `color0` (at uv (0.25, 0.25) of a black / white board, `eval` 0 and `eval_1` 1),
    /// which drew a checkered mix's squares the wrong way round in the differential check.
    fn float_texture(&mut self, index: u32) -> String {
        let t = texture::record(&self.scene.tables, index);
        if t.tag & 0xff != texture_kind::CHECKERBOARD {
            return self.texture(index);
        }
        let id = format!("texture{index}-as-number");
        if self.float_textures.insert(index) {
            let to_uv = glam::Mat3::from_cols_array_2d(&[
                [t.uv_u[0], t.uv_v[0], 0.0],
                [t.uv_u[1], t.uv_v[1], 0.0],
                [t.uv_u[2], t.uv_v[2], 1.0],
            ]);
            let mut e = Element::plugin("texture", "checkerboard")
                .child(Element::rgb("color0", t.other))
                .child(Element::rgb("color1", t.value))
                .child(Element::matrix3("to_uv", to_uv))
                .attr("id", &id);
            e.comment("colours swapped: Mitsuba's eval_1 of a checkerboard swaps them back");
            self.declarations.push(e);
        }
        id
    }

    /// An image texture as a `bitmap` of its linear RGB texels times its scale, bilinear.
    fn bitmap(&mut self, index: u32) -> Element {
        let t = texture::record(&self.scene.tables, index);
        let mut texels = self.texels(index);
        if t.tag & texture_flag::CLAMP != 0 {
            self.warn(format!(
                "texture {index}: strata clamps each lookup to [0, 1] (as pbrt-v4 does), Mitsuba \
                 cannot; written with its texels clamped, which differs where a lookup blends \
                 texels on both sides of 1"
            ));
            texels.iter_mut().for_each(|x| *x = x.clamp(0.0, 1.0));
        }
        let (wrap_u, wrap_v) = ((t.tag >> 16) & 0xf, (t.tag >> 20) & 0xf);
        if wrap_u != wrap_v {
            self.warn(format!(
                "texture {index}: Mitsuba wraps both axes alike; written with the u axis's wrap"
            ));
        }
        let wrap = ["repeat", "clamp", "mirror"]
            .get(wrap_u as usize)
            .unwrap_or(&"repeat");
        let bytes = pfm_bytes(&texels, t.width as usize, t.height as usize);
        let file = self.file(format!("texture{index}.pfm"), bytes);
        Element::plugin("texture", "bitmap")
            .child(Element::string("filename", &file))
            .child(Element::string("filter_type", "bilinear"))
            .child(Element::string("wrap_mode", wrap))
    }

    /// Texture `index`'s texels, linear RGB from the top row, times its scale.
    fn texels(&self, index: u32) -> Vec<f32> {
        let tables = &self.scene.tables;
        let t = texture::record(tables, index);
        (0..t.width * t.height)
            .flat_map(|i| {
                let rgb = texture::texel(tables, &t, i);
                std::array::from_fn::<f32, 3, _>(|c| rgb[c] * t.value[c])
            })
            .collect()
    }

    /// The mean of texture `index`'s texels (its scale multiplied in, each clamped where the
    /// texture clamps its lookups).
    fn texture_mean(&self, index: u32) -> [f32; 3] {
        let t = texture::record(&self.scene.tables, index);
        if t.tag & 0xff == texture_kind::CHECKERBOARD {
            return std::array::from_fn(|c| 0.5 * (t.value[c] + t.other[c]));
        }
        let mut texels = self.texels(index);
        if t.tag & texture_flag::CLAMP != 0 {
            texels.iter_mut().for_each(|x| *x = x.clamp(0.0, 1.0));
        }
        let n = (texels.len() / 3).max(1) as f64;
        std::array::from_fn(|c| {
            (texels
                .iter()
                .skip(c)
                .step_by(3)
                .map(|&x| x as f64)
                .sum::<f64>()
                / n) as f32
        })
    }
}

/// `<ref name="name" id="id"/>`.
fn reference(name: &str, id: &str) -> Element {
    Element::new("ref").attr("name", name).attr("id", id)
}
