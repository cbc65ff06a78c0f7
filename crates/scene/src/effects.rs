//! Which sample domains, light kinds and material kinds a scene calls for.
//!
//! Both renderers consume only the domains listed here (a static pinhole scene draws no lens or
//! time dimension); the GPU renderer turns them into `override` constants.

use crate::records::{light_kind, material_flag, material_kind, surface_flag, NONE};
use crate::settings::{RenderSettings, ROULETTE_START};
use crate::FlatScene;

/// Names of the [`light_kind`]s, by kind.
pub const LIGHT_KIND_NAMES: [&str; 11] = [
    "triangle",
    "rectangle",
    "disk",
    "sphere",
    "line",
    "point",
    "distant",
    "sky",
    "environment",
    "octahedral-environment",
    "spot",
];
/// Names of the [`material_kind`]s, by kind.
pub const MATERIAL_KIND_NAMES: [&str; 14] = [
    "diffuse",
    "conductor",
    "dielectric",
    "complex-conductor",
    "rough-dielectric",
    "plastic",
    "rough-plastic",
    "thin-dielectric",
    "diffuse-transmission",
    "mix",
    "coated-diffuse",
    "coated-conductor",
    "bump",
    "normal-map",
];

/// The names of the kinds whose bits are set in `mask`, joined by `sep` ("none" if none).
pub fn kind_names(mask: u32, names: &[&str], sep: &str) -> String {
    let list: Vec<&str> = names
        .iter()
        .enumerate()
        .filter(|(k, _)| mask & (1 << k) != 0)
        .map(|(_, n)| *n)
        .collect();
    if list.is_empty() {
        "none".into()
    } else {
        list.join(sep)
    }
}

/// The effects a scene rendered with given settings calls for ([`Effects::of`]): which domains
/// are sampled (lens, time), which light and material kinds occur, and which path decisions need
/// a dimension. It decides the [`DimLayout`](crate::DimLayout) and the GPU kernel's
/// specialization, so a static pinhole scene never pays for lens or time sampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Effects {
    /// Thin lens with aperture > 0: the lens domain (2 dims).
    pub lens: bool,
    /// Something moves while the shutter is open: the time domain (1 dim).
    pub time: bool,
    /// Bit `1 << k` set for every [`light_kind`] `k` present.
    pub light_kinds: u32,
    /// Bit `1 << k` set for every [`material_kind`] `k` present.
    pub material_kinds: u32,
    /// Some material reads a texture ([`crate::texture`]): hits compute texture coordinates.
    pub textures: bool,
    /// Some surface has an alpha (cut-outs, pbrt-v4's `alpha`): traversal tests it at hits.
    pub alpha: bool,
    /// Next-event estimation happens at some vertex: the light domain (1 + 2 dims per vertex).
    pub nee: bool,
    /// Paths continue past the first hit (max depth > 1).
    pub path: bool,
    /// Some material must choose between lobes (dielectric reflect/refract): 1 dim per vertex.
    pub lobe: bool,
    /// Paths are long enough for Russian roulette: 1 dim per vertex.
    pub roulette: bool,
}

impl Effects {
    /// One line of what the scene calls for, e.g. `pinhole, static, rectangle lights,
    /// diffuse+conductor, NEE, roulette`.
    pub fn summary(&self) -> String {
        let mut parts = vec![
            if self.lens { "thin lens" } else { "pinhole" }.to_string(),
            if self.time { "motion blur" } else { "static" }.to_string(),
        ];
        let lights = self.light_kinds & !(1 << light_kind::SKY);
        if lights != 0 {
            parts.push(format!(
                "{} lights",
                kind_names(lights, &LIGHT_KIND_NAMES, "+")
            ));
        }
        if self.has_sky() {
            parts.push("sky".into());
        }
        parts.push(kind_names(self.material_kinds, &MATERIAL_KIND_NAMES, "+"));
        if self.textures {
            parts.push("textures".into());
        }
        if self.alpha {
            parts.push("alpha".into());
        }
        if self.nee {
            parts.push("NEE".into());
        }
        if !self.path {
            parts.push("direct light only".into());
        }
        if self.lobe {
            parts.push("lobe choice".into());
        }
        if self.roulette {
            parts.push("roulette".into());
        }
        parts.join(", ")
    }

    /// What `scene` rendered with `settings` calls for.
    pub fn of(scene: &FlatScene, settings: &RenderSettings) -> Self {
        let camera = &scene.camera;
        let shutter_open = camera.shutter_close > camera.shutter_open;
        let camera_moves = camera.eye0 != camera.eye1
            || camera.target0 != camera.target1
            || camera.up0 != camera.up1;
        let objects_move = scene.motions.iter().any(|m| m.is_moving());
        let light_kinds = scene.lights.iter().fold(0, |acc, l| acc | 1 << l.kind);
        // Kinds of the materials some primitive uses (a material only defined costs nothing).
        let mut used = vec![false; scene.materials.len()];
        let mut pending: Vec<u32> = scene.geometry.surfaces.iter().map(|s| s.material).collect();
        // A mix uses the materials it chooses among.
        while let Some(i) = pending.pop() {
            match used.get_mut(i as usize) {
                Some(u) if !*u => *u = true,
                _ => continue,
            }
            let m = &scene.materials[i as usize];
            match m.kind() {
                material_kind::MIX => pending.extend([m.k[0] as u32, m.k[1] as u32]),
                // Bump and normal maps tilt the normal of the material they wrap.
                material_kind::BUMP | material_kind::NORMAL_MAP => pending.push(m.k[0] as u32),
                // A coat's base is drawn through it.
                material_kind::COATED_DIFFUSE | material_kind::COATED_CONDUCTOR => {
                    pending.push(m.k[1] as u32)
                }
                _ => {}
            }
        }
        let in_use = || {
            scene
                .materials
                .iter()
                .zip(&used)
                .filter(|(_, used)| **used)
                .map(|(m, _)| m)
        };
        let material_kinds = in_use().fold(0, |acc, m| acc | 1 << m.kind());
        let surfaces = || scene.geometry.surfaces.iter();
        let alpha = surfaces().any(|s| s.flags & surface_flag::ALPHA != 0);
        // An alpha texture is looked up in traversal.
        let textures = in_use().any(|m| m.tag & material_flag::TEXTURES != 0)
            || surfaces().any(|s| s.flags & surface_flag::ALPHA_TEXTURE != 0);
        let has_unhittable = scene.lights.iter().any(|l| l.unhittable_select_pdf > 0.0);
        let has_hittable_nee = scene.lights.iter().any(|l| l.select_pdf > 0.0);
        Self {
            lens: camera.lens_radius > 0.0,
            time: shutter_open && (camera_moves || objects_move),
            light_kinds,
            material_kinds,
            textures,
            alpha,
            nee: has_unhittable || (settings.strategy.samples_lights() && has_hittable_nee),
            path: settings.max_depth > 1,
            // Materials with two lobes pick one with a dimension of their own.
            lobe: material_kinds
                & (1 << material_kind::DIELECTRIC
                    | 1 << material_kind::ROUGH_DIELECTRIC
                    | 1 << material_kind::PLASTIC
                    | 1 << material_kind::ROUGH_PLASTIC
                    | 1 << material_kind::THIN_DIELECTRIC
                    | 1 << material_kind::DIFFUSE_TRANSMISSION
                    | 1 << material_kind::COATED_DIFFUSE
                    | 1 << material_kind::COATED_CONDUCTOR)
                != 0,
            roulette: settings.max_depth > ROULETTE_START + 1,
        }
    }

    /// Every effect, light kind and material kind (what the generic GPU kernel compiles in).
    pub fn everything() -> Self {
        Self {
            lens: true,
            time: true,
            light_kinds: (1 << LIGHT_KIND_NAMES.len()) - 1,
            material_kinds: (1 << MATERIAL_KIND_NAMES.len()) - 1,
            textures: true,
            alpha: true,
            nee: true,
            path: true,
            lobe: true,
            roulette: true,
        }
    }

    /// Whether a light of `kind` (a [`crate::records::light_kind`]) occurs.
    pub fn has_light(&self, kind: u32) -> bool {
        self.light_kinds & (1 << kind) != 0
    }

    /// Whether a material of `kind` (a [`crate::records::material_kind`]) occurs.
    pub fn has_material(&self, kind: u32) -> bool {
        self.material_kinds & (1 << kind) != 0
    }

    /// Whether escaping rays can see a sky (for `override` specialization).
    pub fn has_sky(&self) -> bool {
        self.has_light(light_kind::SKY)
    }
}

/// `NONE` re-exported for callers matching optional indices.
pub const NO_INDEX: u32 = NONE;
