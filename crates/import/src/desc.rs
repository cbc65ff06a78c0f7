//! The scene description: one typed form of a scene, which every reader makes (strata's TOML in
//! [`crate::load`](mod@crate::load), pbrt-v4 in [`crate::pbrt`]), validation turns into records
//! ([`crate::load::build`]) and [`write`](mod@write) serializes (`strata convert`).
//!
//! Every value an error may point at is [`Spanned`] by the place it was read from in the
//! description's [`Sources`], so that validation names the user's file, line and column, whatever
//! the file's format. Tables that carry a `type` key (materials, shapes, lights) are one struct
//! per type, chosen by the TOML reader from the `type` value: serde's internally tagged enums
//! would buffer the table and lose every span inside it.

mod spanned;
pub mod write;

pub use spanned::{Source, Sources, Spanned};
pub use stratapt_scene::report::{Report, Warning};

use serde::de::{self, IgnoredAny, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;
use std::path::PathBuf;

/// A scene as a reader made it, not yet validated: its settings, named textures and materials in
/// reading order, shapes, lights, the meshes held in memory that `mesh` shapes name, and the files
/// it was read from.
#[derive(Clone, Debug, Default)]
pub struct Description {
    /// The files read, the scene file first: what every span indexes.
    pub sources: Sources,
    /// Where the relative file names of the description (meshes, images) resolve.
    pub base_dir: PathBuf,
    pub scene: SceneDesc,
    /// `[textures.NAME]` in reading order, with the name's span.
    pub textures: Vec<(Spanned<String>, TextureDesc)>,
    /// `[materials.NAME]` in reading order, with the name's span.
    pub materials: Vec<(Spanned<String>, MaterialDesc)>,
    pub shapes: Vec<ShapeDesc>,
    /// `[[lights]]`, each spanned by its whole table.
    pub lights: Vec<Spanned<LightDesc>>,
    /// Meshes held in memory by the `file` name a `mesh` shape gives (an import's baked
    /// triangles; `strata convert` writes each as a PLY file of that name).
    pub meshes: MeshStore,
    /// What an import drew differently from its file (none for strata's own TOML).
    pub import: Option<Report>,
}

/// A triangle mesh held in memory rather than in a file: what the pbrt-v4 importer makes of a
/// scene's shapes (in world space), and what `strata convert` writes as a PLY file of the same
/// name. Arrays as a mesh file gives them (xyz, normals, uv, three indices per triangle),
/// unchecked until loaded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<f32>,
    pub normals: Option<Vec<f32>>,
    pub uvs: Option<Vec<f32>>,
    pub indices: Vec<u32>,
}

/// Meshes by the `file` name a `mesh` shape gives: the loader takes a mesh from here (once)
/// before it looks on disk.
pub type MeshStore = std::collections::HashMap<String, MeshData>;

/// A point or direction: `[x, y, z]`.
pub type Vector = Spanned<[f64; 3]>;

/// `N` numbers written either as an array `[a, b, …]` or as one number meaning all `N` equal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Numbers<const N: usize>(pub [f64; N]);

impl<const N: usize> Default for Numbers<N> {
    fn default() -> Self {
        Self([0.0; N])
    }
}

/// Written as one number when all `N` are equal, else as an array.
impl<const N: usize> Serialize for Numbers<N> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self.0.iter().all(|x| x.to_bits() == self.0[0].to_bits()) {
            true => self.0[0].serialize(serializer),
            false => self.0.as_slice().serialize(serializer),
        }
    }
}

/// Three numbers, or one for all three (colours and scales).
pub type Triple = Numbers<3>;

/// Two numbers, or one for both (anisotropic roughness).
pub type Pair = Numbers<2>;

/// A material parameter: numbers, or the name of a texture (`[textures.NAME]`) to read them from.
#[derive(Clone, Debug, PartialEq)]
pub enum Textured<T> {
    Value(T),
    Texture(String),
}

impl<T: Default> Default for Textured<T> {
    fn default() -> Self {
        Textured::Value(T::default())
    }
}

/// Written as the numbers, or the texture's name.
impl<T: Serialize> Serialize for Textured<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Textured::Value(v) => v.serialize(serializer),
            Textured::Texture(name) => name.serialize(serializer),
        }
    }
}

/// A colour or the name of a texture.
pub type ColorParam = Textured<Triple>;

/// A roughness (one α or `[αu, αv]`) or the name of a texture.
pub type RoughnessParam = Textured<Pair>;

impl<'de, const N: usize> Deserialize<'de> for Textured<Numbers<N>> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct TexturedVisitor<const N: usize>;
        impl<'de, const N: usize> Visitor<'de> for TexturedVisitor<N> {
            type Value = Textured<Numbers<N>>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(
                    f,
                    "a number, an array of {N} numbers or the name of a texture"
                )
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                Ok(Textured::Texture(v.to_string()))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
                NumbersVisitor::<N>.visit_f64(v).map(Textured::Value)
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
                NumbersVisitor::<N>.visit_i64(v).map(Textured::Value)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
                NumbersVisitor::<N>.visit_u64(v).map(Textured::Value)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
                NumbersVisitor::<N>.visit_seq(seq).map(Textured::Value)
            }
        }
        deserializer.deserialize_any(TexturedVisitor::<N>)
    }
}

/// Reads [`Numbers`].
struct NumbersVisitor<const N: usize>;

impl<'de, const N: usize> Deserialize<'de> for Numbers<N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(NumbersVisitor::<N>)
    }
}

impl<'de, const N: usize> Visitor<'de> for NumbersVisitor<N> {
    type Value = Numbers<N>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a number or an array of {N} numbers")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Numbers<N>, E> {
        Ok(Numbers([v; N]))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Numbers<N>, E> {
        Ok(Numbers([v as f64; N]))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Numbers<N>, E> {
        Ok(Numbers([v as f64; N]))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Numbers<N>, A::Error> {
        let expected = format!("{N} numbers");
        let mut out = [0.0; N];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = seq
                .next_element()?
                .ok_or_else(|| de::Error::invalid_length(i, &expected.as_str()))?;
        }
        if seq.next_element::<IgnoredAny>()?.is_some() {
            return Err(de::Error::invalid_length(N + 1, &expected.as_str()));
        }
        Ok(Numbers(out))
    }
}

/// The whole file. `materials`, `shapes` and `lights` are read by the TOML reader as typed tables
/// (`load::parse`); they are listed here only so that an unknown top-level key names them among
/// the valid ones.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    pub camera: Spanned<CameraDesc>,
    pub film: Option<Spanned<FilmDesc>>,
    pub render: Option<Spanned<RenderDesc>>,
    pub sky: Option<Spanned<SkyDesc>>,
    #[serde(rename = "textures", skip_serializing)]
    pub(crate) _textures: Option<IgnoredAny>,
    #[serde(rename = "materials", skip_serializing)]
    pub(crate) _materials: Option<IgnoredAny>,
    #[serde(rename = "shapes", skip_serializing)]
    pub(crate) _shapes: Option<IgnoredAny>,
    #[serde(rename = "lights", skip_serializing)]
    pub(crate) _lights: Option<IgnoredAny>,
}

/// `[camera]`: the pose at shutter open, the lens and the shutter.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    pub eye: Vector,
    pub look_at: Vector,
    pub up: Option<Vector>,
    pub fov: Spanned<f64>,
    pub aperture: Option<Spanned<f64>>,
    pub focus_distance: Option<Spanned<f64>>,
    pub shutter: Option<Spanned<[f64; 2]>>,
    pub close: Option<Spanned<CameraPoseDesc>>,
}

/// `[camera.close]`: the pose at shutter close; each key defaults to the open pose's.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraPoseDesc {
    pub eye: Option<Vector>,
    pub look_at: Option<Vector>,
    pub up: Option<Vector>,
}

/// `[film]`: resolution and pixel filter.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FilmDesc {
    pub width: Option<Spanned<i64>>,
    pub height: Option<Spanned<i64>>,
    pub filter: Option<Spanned<String>>,
    pub filter_width: Option<Spanned<f64>>,
}

/// `[render]`: default render settings (the command line overrides them).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RenderDesc {
    pub spp: Option<Spanned<i64>>,
    pub max_depth: Option<Spanned<i64>>,
    pub sampler: Option<Spanned<String>>,
    pub strategy: Option<Spanned<String>>,
    pub seed: Option<Spanned<i64>>,
    /// The exact value of every pixel, for scenes with a closed-form answer (a white furnace):
    /// `strata study` measures errors against it.
    pub exact: Option<Spanned<Triple>>,
}

/// `[sky]`: a constant `color`, a `bottom`→`top` gradient along `up`, or an environment `map`.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SkyDesc {
    pub color: Option<Spanned<Triple>>,
    pub top: Option<Spanned<Triple>>,
    pub bottom: Option<Spanned<Triple>>,
    pub up: Option<Vector>,
    /// An HDR image, relative to the scene file.
    pub map: Option<Spanned<String>>,
    /// The map's layout: `equirectangular` (default, Mitsuba 3's) or `octahedral` (pbrt-v4's
    /// equal-area square).
    pub mapping: Option<Spanned<String>>,
    /// Multiplies the map's radiance (default 1).
    pub scale: Option<Spanned<Triple>>,
    /// The map's orientation: Euler angles in degrees about X, then Y, then Z (world axes).
    pub rotate: Option<Vector>,
    /// The map's own x axis reversed (default false): a left-handed map, as a pbrt-v4 scene's
    /// environment is once mirrored into strata's right-handed world. `rotate` turns it after.
    pub mirror: Option<Spanned<bool>>,
}

/// `transform = { translate, rotate, scale }`: object-to-world `T · R · S`.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TransformDesc {
    pub translate: Option<Vector>,
    /// Euler angles in degrees, applied about X, then Y, then Z (world axes).
    pub rotate: Option<Vector>,
    pub scale: Option<Spanned<Triple>>,
}

// ---------------------------------------------------------------------------------------------
// Textures
// ---------------------------------------------------------------------------------------------

/// A named texture, `[textures.NAME]`, by `type`.
#[derive(Clone, Debug)]
pub enum TextureDesc {
    Image(ImageTextureDesc),
    Checkerboard(CheckerboardDesc),
}

impl TextureDesc {
    pub const TYPES: &'static [&'static str] = &["image", "checkerboard"];

    /// Its `type`.
    pub fn type_name(&self) -> &'static str {
        match self {
            TextureDesc::Image(_) => "image",
            TextureDesc::Checkerboard(_) => "checkerboard",
        }
    }
}

/// `image`: a PNG, JPEG or TGA (8-bit sRGB, or linear with `raw`), or an OpenEXR, Radiance HDR
/// or PFM (linear floats) file, relative to the scene file.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ImageTextureDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    pub file: Spanned<String>,
    /// 8-bit files: the bytes are linear values (`x / 255`), not sRGB (default false).
    pub raw: Option<bool>,
    /// `"repeat"` (default), `"clamp"` or `"mirror"`.
    pub wrap: Option<Spanned<String>>,
    /// Multiplies the texels (default 1).
    pub scale: Option<Spanned<Triple>>,
    /// Clamp each lookup (scaled, interpolated) to `[0, 1]` per channel, as pbrt-v4 clamps a
    /// diffuse reflectance (default false). Not `wrap = "clamp"`, which clamps coordinates.
    pub clamp: Option<bool>,
    pub uv_scale: Option<Spanned<Pair>>,
    pub uv_offset: Option<Spanned<Pair>>,
    pub uv_transform: Option<Spanned<[[f64; 3]; 2]>>,
}

/// `checkerboard`: `color0` where `frac(u) > ½` and `frac(v) > ½` agree, `color1` elsewhere
/// (Mitsuba 3's; defaults 0.4 and 0.2), one period per unit of `(u, v)`.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CheckerboardDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    pub color0: Option<Spanned<Triple>>,
    pub color1: Option<Spanned<Triple>>,
    pub uv_scale: Option<Spanned<Pair>>,
    pub uv_offset: Option<Spanned<Pair>>,
    pub uv_transform: Option<Spanned<[[f64; 3]; 2]>>,
}

// ---------------------------------------------------------------------------------------------
// Materials
// ---------------------------------------------------------------------------------------------

/// A named material, `[materials.NAME]`, by `type`.
#[derive(Clone, Debug)]
pub enum MaterialDesc {
    Diffuse(DiffuseDesc),
    Conductor(ConductorDesc),
    Dielectric(DielectricDesc),
    Plastic(PlasticDesc),
    Mix(MixDesc),
    Coated(CoatedDesc),
}

impl MaterialDesc {
    pub const TYPES: &'static [&'static str] = &[
        "diffuse",
        "conductor",
        "dielectric",
        "plastic",
        "mix",
        "coated",
    ];

    /// Its `type`.
    pub fn type_name(&self) -> &'static str {
        match self {
            MaterialDesc::Diffuse(_) => "diffuse",
            MaterialDesc::Conductor(_) => "conductor",
            MaterialDesc::Dielectric(_) => "dielectric",
            MaterialDesc::Plastic(_) => "plastic",
            MaterialDesc::Mix(_) => "mix",
            MaterialDesc::Coated(_) => "coated",
        }
    }

    /// Its `emission`.
    pub fn emission_mut(&mut self) -> &mut Option<Spanned<Triple>> {
        match self {
            MaterialDesc::Diffuse(d) => &mut d.emission,
            MaterialDesc::Conductor(d) => &mut d.emission,
            MaterialDesc::Dielectric(d) => &mut d.emission,
            MaterialDesc::Plastic(d) => &mut d.emission,
            MaterialDesc::Mix(d) => &mut d.emission,
            MaterialDesc::Coated(d) => &mut d.emission,
        }
    }

    /// Its surface detail: `displacement` and `normal_map`.
    pub fn detail(&self) -> Detail<'_> {
        let (displacement, normal_map) = match self {
            MaterialDesc::Diffuse(d) => (&d.displacement, &d.normal_map),
            MaterialDesc::Conductor(d) => (&d.displacement, &d.normal_map),
            MaterialDesc::Dielectric(d) => (&d.displacement, &d.normal_map),
            MaterialDesc::Plastic(d) => (&d.displacement, &d.normal_map),
            MaterialDesc::Mix(d) => (&d.displacement, &d.normal_map),
            MaterialDesc::Coated(d) => (&d.displacement, &d.normal_map),
        };
        Detail {
            displacement: displacement.as_ref(),
            normal_map: normal_map.as_ref(),
        }
    }

    /// Its `displacement` and `normal_map`, to set.
    pub fn detail_mut(
        &mut self,
    ) -> (
        &mut Option<Spanned<AmountParam>>,
        &mut Option<Spanned<String>>,
    ) {
        match self {
            MaterialDesc::Diffuse(d) => (&mut d.displacement, &mut d.normal_map),
            MaterialDesc::Conductor(d) => (&mut d.displacement, &mut d.normal_map),
            MaterialDesc::Dielectric(d) => (&mut d.displacement, &mut d.normal_map),
            MaterialDesc::Plastic(d) => (&mut d.displacement, &mut d.normal_map),
            MaterialDesc::Mix(d) => (&mut d.displacement, &mut d.normal_map),
            MaterialDesc::Coated(d) => (&mut d.displacement, &mut d.normal_map),
        }
    }

    /// Whether any of its parameters is read from a texture.
    pub fn reads_texture(&self) -> bool {
        fn tex<T>(p: &Option<Spanned<Textured<T>>>) -> bool {
            matches!(p.as_ref().map(|p| p.get_ref()), Some(Textured::Texture(_)))
        }
        match self {
            MaterialDesc::Diffuse(d) => {
                matches!(d.albedo.get_ref(), Textured::Texture(_)) || tex(&d.transmittance)
            }
            MaterialDesc::Conductor(d) => {
                tex(&d.reflectance) || tex(&d.eta) || tex(&d.k) || tex(&d.tint) || tex(&d.roughness)
            }
            MaterialDesc::Dielectric(d) => tex(&d.tint) || tex(&d.roughness),
            MaterialDesc::Plastic(d) => tex(&d.diffuse) || tex(&d.specular) || tex(&d.roughness),
            // The materials it mixes may: the loader follows them.
            MaterialDesc::Mix(d) => tex(&d.amount),
            MaterialDesc::Coated(d) => tex(&d.albedo) || tex(&d.roughness),
        }
    }
}

/// A material's surface detail ([`MaterialDesc::detail`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Detail<'a> {
    pub displacement: Option<&'a Spanned<AmountParam>>,
    pub normal_map: Option<&'a Spanned<String>>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DiffuseDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    pub albedo: Spanned<ColorParam>,
    /// Diffuse transmission through the surface (pbrt-v4's `diffusetransmission`; default none):
    /// `albedo` reflects, this transmits, their sum at most 1.
    pub transmittance: Option<Spanned<ColorParam>>,
    pub emission: Option<Spanned<Triple>>,
    /// Bump mapping (pbrt-v4's `displacement`): a height along the shading normal, in scene
    /// units, a number or a texture read as one.
    pub displacement: Option<Spanned<AmountParam>>,
    /// A normal map (pbrt-v4's `normalmap`): an image texture of tangent-space normals.
    pub normal_map: Option<Spanned<String>>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ConductorDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    /// Normal-incidence reflectance F0 (Schlick's Fresnel); or `eta` and `k`.
    pub reflectance: Option<Spanned<ColorParam>>,
    /// Complex index of refraction η + ik (exact Fresnel), with `k`.
    pub eta: Option<Spanned<ColorParam>>,
    pub k: Option<Spanned<ColorParam>>,
    /// Scales the complex-IOR reflectance (default 1).
    pub tint: Option<Spanned<ColorParam>>,
    /// GGX α, or `[αu, αv]` along the shading frame's two tangents.
    pub roughness: Option<Spanned<RoughnessParam>>,
    /// `"correlated"` (default) or `"separable"` Smith masking-shadowing.
    pub masking: Option<Spanned<String>>,
    pub emission: Option<Spanned<Triple>>,
    /// Bump mapping (pbrt-v4's `displacement`): a height along the shading normal, in scene
    /// units, a number or a texture read as one.
    pub displacement: Option<Spanned<AmountParam>>,
    /// A normal map (pbrt-v4's `normalmap`): an image texture of tangent-space normals.
    pub normal_map: Option<Spanned<String>>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DielectricDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    pub ior: Option<Spanned<f64>>,
    pub tint: Option<Spanned<ColorParam>>,
    /// GGX α, or `[αu, αv]`: a rough dielectric when above the mirror threshold.
    pub roughness: Option<Spanned<RoughnessParam>>,
    /// `"correlated"` (default) or `"separable"` Smith masking-shadowing.
    pub masking: Option<Spanned<String>>,
    /// A thin sheet (two smooth interfaces, light passing straight through) rather than the
    /// boundary of a solid (default false).
    pub thin: Option<Spanned<bool>>,
    pub emission: Option<Spanned<Triple>>,
    /// Bump mapping (pbrt-v4's `displacement`): a height along the shading normal, in scene
    /// units, a number or a texture read as one.
    pub displacement: Option<Spanned<AmountParam>>,
    /// A normal map (pbrt-v4's `normalmap`): an image texture of tangent-space normals.
    pub normal_map: Option<Spanned<String>>,
}

/// Mitsuba 3's `plastic` (smooth) or `roughplastic` (with `roughness`).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlasticDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    /// The base's diffuse reflectance (default 0.5).
    pub diffuse: Option<Spanned<ColorParam>>,
    /// Scales the coating's reflection (default 1).
    pub specular: Option<Spanned<ColorParam>>,
    /// The coating's index of refraction, inside / outside (default 1.49).
    pub ior: Option<Spanned<f64>>,
    /// The coating's GGX α (isotropic; default 0, smooth).
    pub roughness: Option<Spanned<RoughnessParam>>,
    pub masking: Option<Spanned<String>>,
    /// Mitsuba's `nonlinear` (default false).
    pub nonlinear: Option<bool>,
    pub emission: Option<Spanned<Triple>>,
    /// Bump mapping (pbrt-v4's `displacement`): a height along the shading normal, in scene
    /// units, a number or a texture read as one.
    pub displacement: Option<Spanned<AmountParam>>,
    /// A normal map (pbrt-v4's `normalmap`): an image texture of tangent-space normals.
    pub normal_map: Option<Spanned<String>>,
}

/// pbrt-v4's `mix`: one of two named materials at each point, the second with probability
/// `amount`.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MixDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    /// The two materials' names.
    pub materials: Spanned<Vec<Spanned<String>>>,
    /// The probability of the second (default 0.5), or a texture of it.
    pub amount: Option<Spanned<AmountParam>>,
    pub emission: Option<Spanned<Triple>>,
    /// Bump mapping (pbrt-v4's `displacement`): a height along the shading normal, in scene
    /// units, a number or a texture read as one.
    pub displacement: Option<Spanned<AmountParam>>,
    /// A normal map (pbrt-v4's `normalmap`): an image texture of tangent-space normals.
    pub normal_map: Option<Spanned<String>>,
}

/// A number or the name of a texture.
pub type AmountParam = Textured<Numbers<1>>;

/// pbrt-v4's `coateddiffuse` and `coatedconductor`: a dielectric coat over a named diffuse or
/// conductor material, with a scattering slab between them, evaluated by pbrt's random walk.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CoatedDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    /// The material under the coat: a diffuse or a conductor.
    pub base: Spanned<String>,
    /// The coat's index of refraction, inside / outside (default 1.5).
    pub ior: Option<Spanned<f64>>,
    /// The coat's GGX α (default 0, smooth), or a texture.
    pub roughness: Option<Spanned<RoughnessParam>>,
    /// The slab's thickness in mean free paths (default 0.01).
    pub thickness: Option<Spanned<f64>>,
    /// The slab's single-scattering albedo (default 0, clear), or a texture.
    pub albedo: Option<Spanned<ColorParam>>,
    /// The Henyey–Greenstein asymmetry of the slab's scattering (default 0).
    pub g: Option<Spanned<f64>>,
    /// Events per random walk (default 10).
    pub max_depth: Option<Spanned<i64>>,
    /// Random walks per estimate (default 1).
    pub samples: Option<Spanned<i64>>,
    pub emission: Option<Spanned<Triple>>,
    /// Bump mapping (pbrt-v4's `displacement`): a height along the shading normal, in scene
    /// units, a number or a texture read as one.
    pub displacement: Option<Spanned<AmountParam>>,
    /// A normal map (pbrt-v4's `normalmap`): an image texture of tangent-space normals.
    pub normal_map: Option<Spanned<String>>,
}

// ---------------------------------------------------------------------------------------------
// Shapes
// ---------------------------------------------------------------------------------------------

/// The keys every shape accepts besides its geometry.
#[derive(Clone, Debug, Default)]
pub struct ShapeCommon {
    pub material: Option<Spanned<String>>,
    pub transform: Option<Spanned<TransformDesc>>,
    pub transform_close: Option<Spanned<TransformDesc>>,
    /// An emitting triangle, rectangle, disk or mesh emits from both sides (pbrt-v4's
    /// `twosided` area lights; default false).
    pub two_sided: Option<Spanned<bool>>,
    /// pbrt-v4's `alpha`: the probability that a ray meets the surface (a number in `[0, 1]` or
    /// a texture read as one; default 1, opaque).
    pub alpha: Option<Spanned<AmountParam>>,
}

/// Declares a shape struct (`type`, its own keys, then the common keys: serde's `flatten` would
/// defeat `deny_unknown_fields`) and its [`Geometry`] variant.
macro_rules! shape_desc {
    ($(#[$doc:meta])* $variant:ident($name:ident) { $($field:ident : $ty:ty),* $(,)? }) => {
        $(#[$doc])*
        #[derive(Clone, Debug, Default, Deserialize, Serialize)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            #[serde(rename = "type", default, skip_serializing)]
            pub(crate) _kind: IgnoredAny,
            $(pub $field: $ty,)*
            pub material: Option<Spanned<String>>,
            pub transform: Option<Spanned<TransformDesc>>,
            pub transform_close: Option<Spanned<TransformDesc>>,
            pub two_sided: Option<Spanned<bool>>,
            pub alpha: Option<Spanned<AmountParam>>,
        }
        impl $name {
            /// Splits off the common keys.
            pub fn into_shape(mut self, span: std::ops::Range<usize>) -> ShapeDesc {
                let common = ShapeCommon {
                    material: self.material.take(),
                    transform: self.transform.take(),
                    transform_close: self.transform_close.take(),
                    two_sided: self.two_sided.take(),
                    alpha: self.alpha.take(),
                };
                ShapeDesc { geometry: Geometry::$variant(self), common, span }
            }
        }
    };
}

shape_desc!(
    /// `rectangle`: `corner + a·edge_u + b·edge_v`, `a, b ∈ [0, 1]`; front = `edge_u × edge_v`.
    Rectangle(RectangleDesc) { corner: Vector, edge_u: Vector, edge_v: Vector }
);
shape_desc!(
    /// `triangle`: three vertices; front = `(v1 − v0) × (v2 − v0)`.
    Triangle(TriangleDesc) { vertices: Spanned<[[f64; 3]; 3]> }
);
shape_desc!(
    /// `quad`: four vertices, not necessarily planar, split into `(v0, v1, v2)` and
    /// `(v0, v2, v3)`.
    Quad(QuadDesc) { vertices: Spanned<[[f64; 3]; 4]> }
);
shape_desc!(
    /// `disk`: one-sided, front = `normal`.
    Disk(DiskDesc) { center: Vector, normal: Vector, radius: Spanned<f64> }
);
shape_desc!(
    /// `sphere`.
    Sphere(SphereDesc) { center: Vector, radius: Spanned<f64> }
);
shape_desc!(
    /// `box`: axis-aligned in object space, faces facing outwards.
    Box(BoxDesc) { min: Vector, max: Vector }
);
shape_desc!(
    /// `mesh`: an OBJ or PLY file (by its extension), relative to the scene file.
    Mesh(MeshDesc) { file: Spanned<String> }
);

/// One `[[shapes]]` entry: its geometry by type, and the common keys.
#[derive(Clone, Debug)]
pub struct ShapeDesc {
    pub geometry: Geometry,
    pub common: ShapeCommon,
    /// Span of the whole `[[shapes]]` table (for "missing key" errors).
    pub span: std::ops::Range<usize>,
}

#[derive(Clone, Debug)]
pub enum Geometry {
    Rectangle(RectangleDesc),
    Triangle(TriangleDesc),
    Quad(QuadDesc),
    Disk(DiskDesc),
    Sphere(SphereDesc),
    Box(BoxDesc),
    Mesh(MeshDesc),
}

impl Geometry {
    pub const TYPES: &'static [&'static str] = &[
        "rectangle",
        "triangle",
        "quad",
        "disk",
        "sphere",
        "box",
        "mesh",
    ];

    /// Its `type`.
    pub fn type_name(&self) -> &'static str {
        match self {
            Geometry::Rectangle(_) => "rectangle",
            Geometry::Triangle(_) => "triangle",
            Geometry::Quad(_) => "quad",
            Geometry::Disk(_) => "disk",
            Geometry::Sphere(_) => "sphere",
            Geometry::Box(_) => "box",
            Geometry::Mesh(_) => "mesh",
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Lights that are not surfaces
// ---------------------------------------------------------------------------------------------

/// One `[[lights]]` entry, by `type`.
#[derive(Clone, Debug)]
pub enum LightDesc {
    Point(PointDesc),
    Line(LineDesc),
    Distant(DistantDesc),
    Spot(SpotDesc),
}

impl LightDesc {
    pub const TYPES: &'static [&'static str] = &["point", "line", "distant", "spot"];

    /// Its `type`.
    pub fn type_name(&self) -> &'static str {
        match self {
            LightDesc::Point(_) => "point",
            LightDesc::Line(_) => "line",
            LightDesc::Distant(_) => "distant",
            LightDesc::Spot(_) => "spot",
        }
    }
}

/// `spot`: pbrt-v4's spot light, a point light at `position` aimed at `look_at`, at full
/// `intensity` within `cone_angle − cone_delta` degrees of its axis, falling off smoothly to
/// zero at `cone_angle` (defaults 30 and 5, pbrt's).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SpotDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    pub position: Vector,
    pub look_at: Vector,
    pub intensity: Spanned<Triple>,
    pub cone_angle: Option<Spanned<f64>>,
    pub cone_delta: Option<Spanned<f64>>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PointDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    pub position: Vector,
    pub intensity: Spanned<Triple>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LineDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    pub from: Vector,
    pub to: Vector,
    pub intensity: Spanned<Triple>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DistantDesc {
    #[serde(rename = "type", default, skip_serializing)]
    pub(crate) _kind: IgnoredAny,
    pub direction: Vector,
    pub irradiance: Spanned<Triple>,
    pub angular_diameter: Option<Spanned<f64>>,
}
