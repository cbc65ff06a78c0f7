//! TOML text → scene description: the untyped tables, and the typed tables (`materials`,
//! `shapes`, `lights`) dispatched on their `type` key so that every span survives.

use super::validate::{Ctx, Result};
use crate::desc::{
    self, Description, Geometry, LightDesc, MaterialDesc, SceneDesc, ShapeDesc, Sources, Spanned,
    TextureDesc,
};
use serde::de::DeserializeOwned;
use serde::Deserialize;
use std::ops::Range;
use std::path::Path;
use toml::de::{DeTable, DeValue, ValueDeserializer};

/// The description of the TOML scene `text`, named `path` (relative file names resolve in its
/// folder).
pub fn parse(text: &str, path: &Path) -> Result<Description> {
    let sources = Sources::one(path, text);
    let parts = parse_parts(&Ctx::new(&sources), text)?;
    Ok(Description {
        base_dir: path.parent().unwrap_or(Path::new("")).to_path_buf(),
        scene: parts.scene,
        textures: parts.textures,
        materials: parts.materials,
        shapes: parts.shapes,
        lights: parts.lights,
        sources,
        ..Description::default()
    })
}

/// The parts of a scene file.
struct Parsed {
    scene: SceneDesc,
    textures: Vec<(Spanned<String>, TextureDesc)>,
    materials: Vec<(Spanned<String>, MaterialDesc)>,
    shapes: Vec<ShapeDesc>,
    lights: Vec<Spanned<LightDesc>>,
}

fn parse_parts(ctx: &Ctx, text: &str) -> Result<Parsed> {
    let mut doc = DeTable::parse(text).map_err(|e| ctx.toml(e))?;
    let root = doc.get_mut();
    let textures = root.remove("textures");
    let materials = root.remove("materials");
    let shapes = root.remove("shapes");
    let lights = root.remove("lights");
    let scene =
        SceneDesc::deserialize(toml::de::Deserializer::from(doc)).map_err(|e| ctx.toml(e))?;
    Ok(Parsed {
        scene,
        textures: match textures {
            Some(t) => named_tables(ctx, t, "texture", TextureDesc::TYPES, |kind, value| {
                Ok(match kind {
                    "image" => Some(TextureDesc::Image(typed(ctx, value)?)),
                    "checkerboard" => Some(TextureDesc::Checkerboard(typed(ctx, value)?)),
                    _ => None,
                })
            })?,
            None => Vec::new(),
        },
        materials: match materials {
            Some(m) => named_tables(ctx, m, "material", MaterialDesc::TYPES, |kind, value| {
                Ok(match kind {
                    "diffuse" => Some(MaterialDesc::Diffuse(typed(ctx, value)?)),
                    "conductor" => Some(MaterialDesc::Conductor(typed(ctx, value)?)),
                    "dielectric" => Some(MaterialDesc::Dielectric(typed(ctx, value)?)),
                    "plastic" => Some(MaterialDesc::Plastic(typed(ctx, value)?)),
                    "mix" => Some(MaterialDesc::Mix(typed(ctx, value)?)),
                    "coated" => Some(MaterialDesc::Coated(typed(ctx, value)?)),
                    _ => None,
                })
            })?,
            None => Vec::new(),
        },
        shapes: array_of_tables(ctx, shapes, "shapes")?
            .into_iter()
            .map(|t| parse_shape(ctx, t))
            .collect::<Result<_>>()?,
        lights: array_of_tables(ctx, lights, "lights")?
            .into_iter()
            .map(|t| parse_light(ctx, t))
            .collect::<Result<_>>()?,
    })
}

/// The `[KEY.NAME]` tables of `value` (materials, textures) in file order, each converted by
/// `convert` from its `type` (`None`: not one of `valid`).
fn named_tables<'i, T>(
    ctx: &Ctx,
    value: toml::Spanned<DeValue<'i>>,
    what: &str,
    valid: &[&str],
    convert: impl Fn(&str, toml::Spanned<DeValue<'i>>) -> Result<Option<T>>,
) -> Result<Vec<(Spanned<String>, T)>> {
    let span = value.span();
    let DeValue::Table(table) = value.into_inner() else {
        return Err(ctx.err(
            span,
            format!("`{what}s` must be a table of named {what}s: [{what}s.NAME]"),
        ));
    };
    let mut entries: Vec<_> = table.into_iter().collect();
    // File order (the map is sorted by name).
    entries.sort_by_key(|(k, _)| k.span().start);
    entries
        .into_iter()
        .map(|(name, value)| {
            let name = Spanned::new(name.span(), name.get_ref().to_string());
            if !value.get_ref().is_table() {
                return Err(ctx.err(
                    value.span(),
                    format!(
                        "{what} `{}` must be a table with a `type` key",
                        name.get_ref()
                    ),
                ));
            }
            let (kind, kind_span) = type_of(ctx, &value, what, valid)?;
            match convert(&kind, value)? {
                Some(desc) => Ok((name, desc)),
                None => Err(unknown_type(ctx, kind_span, &kind, what, valid)),
            }
        })
        .collect()
}

fn parse_shape(ctx: &Ctx, value: toml::Spanned<DeValue>) -> Result<ShapeDesc> {
    let span = value.span();
    let (kind, kind_span) = type_of(ctx, &value, "shape", Geometry::TYPES)?;
    Ok(match kind.as_str() {
        "rectangle" => typed::<desc::RectangleDesc>(ctx, value)?.into_shape(span),
        "triangle" => typed::<desc::TriangleDesc>(ctx, value)?.into_shape(span),
        "quad" => typed::<desc::QuadDesc>(ctx, value)?.into_shape(span),
        "disk" => typed::<desc::DiskDesc>(ctx, value)?.into_shape(span),
        "sphere" => typed::<desc::SphereDesc>(ctx, value)?.into_shape(span),
        "box" => typed::<desc::BoxDesc>(ctx, value)?.into_shape(span),
        "mesh" => typed::<desc::MeshDesc>(ctx, value)?.into_shape(span),
        _ => {
            return Err(unknown_type(
                ctx,
                kind_span,
                &kind,
                "shape",
                Geometry::TYPES,
            ))
        }
    })
}

fn parse_light(ctx: &Ctx, value: toml::Spanned<DeValue>) -> Result<Spanned<LightDesc>> {
    let span = value.span();
    let (kind, kind_span) = type_of(ctx, &value, "light", LightDesc::TYPES)?;
    let light = match kind.as_str() {
        "point" => LightDesc::Point(typed(ctx, value)?),
        "line" => LightDesc::Line(typed(ctx, value)?),
        "distant" => LightDesc::Distant(typed(ctx, value)?),
        "spot" => LightDesc::Spot(typed(ctx, value)?),
        _ => {
            return Err(unknown_type(
                ctx,
                kind_span,
                &kind,
                "light",
                LightDesc::TYPES,
            ))
        }
    };
    Ok(Spanned::new(span, light))
}

/// The tables of an `[[key]]` array (none when the key is absent).
fn array_of_tables<'i>(
    ctx: &Ctx,
    value: Option<toml::Spanned<DeValue<'i>>>,
    key: &str,
) -> Result<Vec<toml::Spanned<DeValue<'i>>>> {
    let Some(value) = value else {
        return Ok(Vec::new());
    };
    let span = value.span();
    let DeValue::Array(items) = value.into_inner() else {
        return Err(ctx.err(
            span,
            format!("`{key}` must be an array of tables: [[{key}]]"),
        ));
    };
    items
        .into_iter()
        .map(|item| match item.get_ref() {
            DeValue::Table(_) => Ok(item),
            _ => Err(ctx.err(
                item.span(),
                format!("each entry of `{key}` must be a table"),
            )),
        })
        .collect()
}

/// The `type` of a typed table, with its span.
fn type_of(
    ctx: &Ctx,
    value: &toml::Spanned<DeValue>,
    what: &str,
    valid: &[&str],
) -> Result<(String, Range<usize>)> {
    let table = value.get_ref().as_table().expect("checked to be a table");
    match table.get("type") {
        Some(kind) => match kind.get_ref().as_str() {
            Some(s) => Ok((s.to_string(), kind.span())),
            None => Err(ctx.err(
                kind.span(),
                format!(
                    "{what} `type` must be a string, one of: {}",
                    valid.join(", ")
                ),
            )),
        },
        None => Err(ctx.err(
            value.span(),
            format!(
                "missing key `type` in {what}; expected one of: {}",
                valid.join(", ")
            ),
        )),
    }
}

fn unknown_type(
    ctx: &Ctx,
    span: Range<usize>,
    kind: &str,
    what: &str,
    valid: &[&str],
) -> stratapt_scene::SceneError {
    ctx.err(
        span,
        format!(
            "unknown {what} type `{kind}`; expected one of: {}",
            valid.join(", ")
        ),
    )
}

/// Deserialize one typed table, keeping the document's spans.
fn typed<T: DeserializeOwned>(ctx: &Ctx, value: toml::Spanned<DeValue>) -> Result<T> {
    T::deserialize(ValueDeserializer::from(value)).map_err(|e| ctx.toml(e))
}
