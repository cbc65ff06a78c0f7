//! What strata renders, written as a Mitsuba 3 scene (`strata convert scene -o scene.xml`): the
//! XML file, and beside it in one folder the PLY meshes and PFM images it names.
//!
//! It is written from the flattened records ([`FlatScene`]), not from a scene file, so that it
//! says what strata draws after every default, import and clamp: the camera and film with
//! strata's pixel filter, each material as the Mitsuba BSDF strata's is modelled on (every one
//! `twosided` but the dielectrics, as strata's are), textures as bitmaps of their linear texels,
//! lights and the sky as emitters, the path integrator at strata's depth. Triangles are grouped
//! into one PLY mesh per material, shading (vertex normals or faces), texture coordinates, motion
//! and emission, in world space; spheres and disks stay analytic.
//!
//! What Mitsuba 3 cannot express is drawn as near as it can and said in a warning: Schlick's
//! Fresnel (as the dielectric Fresnel of the same normal-incidence reflectance), height-correlated
//! masking (Mitsuba's is separable), line lights (thin emitting cylinders), sun cones (delta
//! directional lights of the same irradiance), octahedral maps (resampled), pbrt's spot falloff,
//! textures clamped per lookup (their texels clamped), a textured Schlick reflectance (its mean),
//! anisotropic roughness (whose tangents differ), a texture wrapped differently along u and v
//! (u's wrap), sphere lights seen from inside (Mitsuba's emit outwards only), box filters of
//! another width than one pixel, motion blur (the shutter-open pose), diffuse transmission (its
//! reflection), coated materials (a plastic or the bare conductor), two-sided lights (one-sided),
//! a constant displacement (no bump map). Bump and normal maps are `bumpmap` and `normalmap` with
//! pbrt's behaviour (`flip_invalid_normals` and `use_shadowing_function` off), alpha a `mask`.
//! `scripts/mitsuba-diff.py` renders a scene and its export and compares them pixel by pixel
//! (`docs/measurements/mitsuba-diff.md`).
//!
//! The XML's `<default>`s (`spp`, `seed`, `resx`, `resy`, `max_depth`) can be overridden with
//! `mitsuba -Dspp=…` or `mi.load_file(path, spp=…)`.

mod bsdf;
mod emitters;
mod shapes;
mod xml;

use glam::Vec3;
use std::f32::consts::PI;
use std::fmt::Write;
use stratapt_scene::records::filter_kind;
use stratapt_scene::FlatScene;
use xml::Element;

/// A scene written for Mitsuba 3.
#[derive(Clone, Debug, Default)]
pub struct Export {
    /// The XML file's text.
    pub xml: String,
    /// The files it names, by their path relative to the XML file's folder (all in the folder
    /// the export was asked to use): PLY meshes and PFM images.
    pub files: Vec<(String, Vec<u8>)>,
    /// What Mitsuba cannot express, and how it was drawn instead.
    pub warnings: Vec<String>,
}

/// `scene` as a Mitsuba 3 scene whose meshes and images go to folder `dir` (relative to the XML
/// file, `/`-separated).
pub fn export(scene: &FlatScene, dir: &str) -> Export {
    let mut w = Writer::new(scene, dir);
    let mut root = Element::new("scene").attr("version", "3.0.0");
    root.comment(&format!(
        "Written by strata from {}: what strata renders.",
        scene.path.display()
    ));
    for e in w.defaults() {
        root.push(e);
    }
    root.push(w.integrator());
    root.push(w.sensor());
    let shapes = w.shapes();
    let emitters = w.emitters();
    // Textures and BSDFs are declared before the shapes that refer to them.
    for e in w.declarations.drain(..).chain(shapes).chain(emitters) {
        root.push(e);
    }
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    if !w.warnings.is_empty() {
        let _ = writeln!(xml, "<!-- Drawn differently from strata:");
        for line in &w.warnings {
            let _ = writeln!(xml, "     {}", xml::comment_text(line));
        }
        let _ = writeln!(xml, "-->");
    }
    root.write(&mut xml, 0);
    Export {
        xml,
        files: w.files,
        warnings: w.warnings,
    }
}

/// The export under way: the scene, the files and top-level declarations made so far.
struct Writer<'a> {
    scene: &'a FlatScene,
    dir: String,
    files: Vec<(String, Vec<u8>)>,
    warnings: Vec<String>,
    /// Textures and BSDFs, declared once by id and referred to.
    declarations: Vec<Element>,
    /// Texture index → its id, once declared.
    textures: std::collections::HashMap<u32, String>,
    /// Checkerboards declared with their colours swapped, for Mitsuba's `eval_1`.
    float_textures: std::collections::HashSet<u32>,
    /// `mask` BSDFs declared, by material and encoded alpha.
    masks: std::collections::HashMap<(u32, u32, u32), String>,
    /// Whether the two-sided lights' warning was given.
    two_sided_warned: bool,
    /// Material index → its BSDF's id, once declared.
    bsdfs: std::collections::HashMap<u32, String>,
}

impl<'a> Writer<'a> {
    fn new(scene: &'a FlatScene, dir: &str) -> Self {
        Self {
            scene,
            dir: dir.trim_end_matches('/').to_string(),
            files: Vec::new(),
            warnings: Vec::new(),
            declarations: Vec::new(),
            textures: Default::default(),
            float_textures: Default::default(),
            masks: Default::default(),
            two_sided_warned: false,
            bsdfs: Default::default(),
        }
    }

    /// Adds file `name` (in the export's folder) and returns its path relative to the XML.
    fn file(&mut self, name: String, bytes: Vec<u8>) -> String {
        let path = format!("{}/{name}", self.dir);
        self.files.push((path.clone(), bytes));
        path
    }

    fn warn(&mut self, message: String) {
        if !self.warnings.contains(&message) {
            self.warnings.push(message);
        }
    }

    /// The parameters a user may override: samples, seed, resolution and path depth.
    fn defaults(&self) -> Vec<Element> {
        let s = &self.scene.settings;
        let c = &self.scene.camera;
        let default = |name: &str, value: u32| {
            Element::new("default")
                .attr("name", name)
                .attr("value", value)
        };
        vec![
            default("spp", s.pattern_spp),
            default("seed", s.seed),
            default("resx", c.width),
            default("resy", c.height),
            // strata's depth counts the path's vertices after the camera (1: direct light only),
            // Mitsuba's the emitter's vertex too.
            default("max_depth", s.max_depth + 1),
        ]
    }

    fn integrator(&self) -> Element {
        Element::plugin("integrator", "path").child(Element::integer("max_depth", "$max_depth"))
    }

    /// The camera at shutter open, its film and filter, and an independent sampler.
    fn sensor(&mut self) -> Element {
        let c = self.scene.camera;
        let moving = c.eye0 != c.eye1 || c.target0 != c.target1 || c.up0 != c.up1;
        let motion = self.scene.motions.iter().any(|m| m.is_moving());
        if moving || motion {
            self.warn(
                "motion blur: Mitsuba 3 has none; the camera and every shape are written at \
                 shutter open"
                    .into(),
            );
        }
        let fov = 2.0 * c.tan_half_fov.atan() * 180.0 / PI;
        let (eye, target) = (Vec3::from(c.eye0), Vec3::from(c.target0));
        let (near, far) = self.clip_planes();
        let lookat = Element::new("lookat")
            .attr("origin", triple(eye))
            .attr("target", triple(target))
            .attr("up", triple(Vec3::from(c.up0)));
        let mut sensor = match c.lens_radius > 0.0 {
            true => Element::plugin("sensor", "thinlens")
                .child(Element::float("aperture_radius", c.lens_radius))
                .child(Element::float("focus_distance", c.focus_distance)),
            false => Element::plugin("sensor", "perspective"),
        };
        sensor = sensor
            .child(Element::float("fov", fov))
            .child(Element::string("fov_axis", "y"))
            .child(Element::float("near_clip", near))
            .child(Element::float("far_clip", far))
            .child(
                Element::new("transform")
                    .attr("name", "to_world")
                    .child(lookat),
            );
        let film = Element::plugin("film", "hdrfilm")
            .child(Element::integer("width", "$resx"))
            .child(Element::integer("height", "$resy"))
            .child(Element::string("pixel_format", "rgb"))
            .child(self.filter());
        let sampler = Element::plugin("sampler", "independent")
            .child(Element::integer("sample_count", "$spp"))
            .child(Element::integer("seed", "$seed"));
        sensor.child(film).child(sampler)
    }

    /// Near and far clip planes that clip nothing strata draws (Mitsuba's default near plane,
    /// 0.01, would cut scenes a millimetre across): 10⁻⁶ and 10³ of the scene's extent.
    fn clip_planes(&self) -> (f32, f32) {
        let c = self.scene.camera;
        let extent = Vec3::from(self.scene.bounds_max) - Vec3::from(self.scene.bounds_min);
        let span =
            extent.length().max(1e-30) + (Vec3::from(c.eye0) - Vec3::from(c.target0)).length();
        ((span * 1e-6).max(f32::MIN_POSITIVE), span * 1e3)
    }

    /// strata's pixel filter as Mitsuba's.
    fn filter(&mut self) -> Element {
        let c = self.scene.camera;
        match c.filter {
            filter_kind::TENT => {
                Element::plugin("rfilter", "tent").child(Element::float("radius", c.filter_param))
            }
            filter_kind::GAUSSIAN => Element::plugin("rfilter", "gaussian")
                .child(Element::float("stddev", c.filter_param)),
            _ => {
                if c.filter_param != 1.0 {
                    self.warn(format!(
                        "pixel filter: Mitsuba's box filter is one pixel wide; strata's is {} \
                         pixels",
                        c.filter_param
                    ));
                }
                Element::plugin("rfilter", "box")
            }
        }
    }
}

/// `x, y, z`, as Mitsuba's `lookat` attributes take a point.
fn triple(v: Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}
