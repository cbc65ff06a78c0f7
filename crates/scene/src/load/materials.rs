//! Named materials (`[materials.NAME]`) and the ones meshes bring from their MTL files.

use super::desc::MaterialDesc;
use super::validate::{Ctx, Result};
use crate::records::{material_kind, Material};
use std::collections::HashMap;
use toml::Spanned;

/// The scene's materials, in [`crate::FlatScene::materials`] order.
#[derive(Default)]
pub struct Materials {
    pub gpu: Vec<Material>,
    pub names: Vec<String>,
    by_name: HashMap<String, u32>,
    /// How many come from `[materials]` (the ones a scene may name).
    named: usize,
}

impl Materials {
    /// Validate and convert the `[materials.NAME]` tables.
    pub fn from_descs(ctx: &Ctx, descs: &[(Spanned<String>, MaterialDesc)]) -> Result<Self> {
        let mut out = Materials::default();
        for (name, desc) in descs {
            let material = convert(ctx, desc)?;
            out.add(name.get_ref().clone(), material);
        }
        out.named = out.gpu.len();
        Ok(out)
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

/// Whether an emission colour emits anything.
pub fn emits(emission: [f32; 3]) -> bool {
    emission.iter().any(|&e| e > 0.0)
}

fn convert(ctx: &Ctx, desc: &MaterialDesc) -> Result<Material> {
    let emission = |e: &Option<Spanned<super::desc::Triple>>| match e {
        Some(e) => ctx.emitted(e, "emission"),
        None => Ok([0.0; 3]),
    };
    Ok(match desc {
        MaterialDesc::Diffuse(d) => Material {
            color: ctx.unit_color(&d.albedo, "albedo")?,
            kind: material_kind::DIFFUSE,
            emission: emission(&d.emission)?,
            param: 0.0,
        },
        MaterialDesc::Conductor(d) => Material {
            color: ctx.unit_color(&d.reflectance, "reflectance")?,
            kind: material_kind::CONDUCTOR,
            emission: emission(&d.emission)?,
            param: match &d.roughness {
                Some(r) => ctx.non_negative(r, "roughness")?,
                None => 0.0,
            },
        },
        MaterialDesc::Dielectric(d) => Material {
            color: match &d.tint {
                Some(t) => ctx.unit_color(t, "tint")?,
                None => [1.0; 3],
            },
            kind: material_kind::DIELECTRIC,
            emission: emission(&d.emission)?,
            param: match &d.ior {
                Some(ior) => ctx.positive(ior, "ior")?,
                None => DEFAULT_IOR,
            },
        },
    })
}

/// Index of refraction when none is given (glass).
pub const DEFAULT_IOR: f32 = 1.5;
