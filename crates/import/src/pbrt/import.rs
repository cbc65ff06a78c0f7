//! A pbrt-v4 scene as strata's own: the directives read in order into strata's scene
//! [`Description`], every value spanned by the pbrt file, line and column it came from, with the
//! triangle meshes held in [`Description::meshes`] under the file names its shapes give them.
//! `strata render scene.pbrt` validates that description; `strata convert` writes it as TOML and
//! the meshes as binary PLY files of the same names, so that the converted scene is the
//! imported one, bit for bit.
//!
//! Geometry is baked into strata's world: pbrt's CTM (any affine matrix), then the camera's
//! mirror ([`super::camera`]). Triangles keep pbrt's front side (their winding, or their
//! normals when the mesh has them; `ReverseOrientation` and a CTM that swaps handedness flip
//! it), which decides where an area light emits and which side of glass is inside. Spheres and
//! disks stay analytic when the CTM is a similarity, and are tessellated otherwise.
//! `ObjectInstance`s are flattened into copies. Everything strata draws differently from what
//! the file asks is one [`Warning`] in [`Report::warnings`].

use super::camera::{camera_of, Camera};
use super::include::{parse_scene, Parsed};
use super::params::Params;
use super::parse::{Arg, Directive, ParamType, Values};
use super::settings::{settings, Settings};
use super::state::{State, Warning};
use crate::desc::{
    CameraDesc, Description, FilmDesc, ImageTextureDesc, MaterialDesc, MeshData, RenderDesc,
    SceneDesc, Spanned,
};
use glam::{DMat3, DMat4, DVec3};
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use stratapt_scene::error::SceneError;
use stratapt_scene::records::filter_kind;

/// At most this many triangles after instances are flattened.
pub const MAX_TRIANGLES: usize = 1 << 28;

pub use crate::desc::Report;

/// Import the pbrt-v4 scene at `path`: its description, whose relative file names resolve in
/// the scene file's folder and whose meshes are named `{mesh_dir}/NNNNN.ply`.
pub fn import(path: &Path, mesh_dir: &str) -> Result<Description, SceneError> {
    import_parsed(parse_scene(path)?, mesh_dir)
}

/// [`import`] of what is already read.
pub fn import_parsed(parsed: Parsed, mesh_dir: &str) -> Result<Description, SceneError> {
    let mut desc = {
        let mut b = Builder::new(&parsed, mesh_dir)?;
        for (source, d) in &parsed.directives {
            b.directive(*source, d)?;
        }
        b.state.finish(&parsed)?;
        b.finish()?
    };
    desc.base_dir = parsed
        .sources
        .main()
        .parent()
        .unwrap_or(Path::new(""))
        .to_path_buf();
    desc.sources = parsed.sources;
    Ok(desc)
}

/// A material as a shape refers to it: pbrt's default, a named one, or the `Material` directive
/// at this index of [`Parsed::directives`].
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(super) enum MaterialRef {
    Default,
    /// A name, and where the `NamedMaterial` giving it is (source, offset).
    Named(String, usize, usize),
    Anonymous(usize),
}

impl MaterialRef {
    /// What tells materials apart (a named one is the same wherever it is named).
    pub fn key(&self) -> String {
        match self {
            MaterialRef::Default => "default".into(),
            MaterialRef::Named(name, _, _) => format!("named {name}"),
            MaterialRef::Anonymous(i) => format!("anonymous {i}"),
        }
    }
}

/// An `AreaLightSource "diffuse"`: its radiance, and its index (which names the material).
#[derive(Clone, Debug)]
pub(super) struct AreaLight {
    pub radiance: [f64; 3],
    pub index: usize,
    /// pbrt-v4's `twosided`: it emits from both sides.
    pub two_sided: bool,
    /// Where its radiance is written.
    pub span: Range<usize>,
}

/// The graphics state beyond the transform (which [`State`] keeps).
#[derive(Clone, Debug)]
struct Gfx {
    material: MaterialRef,
    area: Option<AreaLight>,
}

/// Where a mesh's object-space triangles come from.
#[derive(Clone)]
pub(super) enum MeshSource {
    Data(Arc<MeshData>),
    /// A PLY file, and where the `Shape` naming it is (source, offset).
    Ply(PathBuf, usize, usize),
}

/// A shape's geometry in object space.
#[derive(Clone)]
pub(super) enum Geom {
    Mesh(MeshSource),
    /// One bilinear patch (`p00 p10 p01 p11`, two triangles): strata's rectangle when it is
    /// one once placed, else its triangles.
    Patch(Arc<MeshData>),
    Sphere {
        radius: f64,
    },
    Disk {
        height: f64,
        radius: f64,
    },
}

/// A shape placed in pbrt's world, with strata's material name.
#[derive(Clone)]
pub(super) struct Placed {
    pub geom: Geom,
    pub ctm: DMat4,
    pub reverse: bool,
    pub material: String,
    /// Its area light emits from both sides.
    pub two_sided: bool,
    /// Its `alpha` (none: opaque).
    pub alpha: Option<crate::desc::AmountParam>,
    /// Where its `Shape` is (source, offset), for warnings.
    pub at: (usize, usize),
    /// Where the directive that made `ctm` singular is (source, offset), if it is.
    pub flattened_at: Option<(usize, usize)>,
}

/// Reads the directives in order and builds strata's scene description.
pub(super) struct Builder<'a> {
    pub parsed: &'a Parsed,
    mesh_dir: &'a str,
    pub state: State,
    gfx: Gfx,
    gfx_stack: Vec<Gfx>,
    settings: Settings,
    camera: Option<Camera>,
    /// `MakeNamedMaterial`s by name: (source, directive index).
    pub named_materials: HashMap<String, (usize, &'a Directive)>,
    pub anonymous_materials: Vec<(usize, &'a Directive)>,
    /// pbrt's textures by (is float, name).
    pub textures: HashMap<(bool, String), super::textures::Texture>,
    /// strata's materials made so far, by what they are made of.
    pub materials_written: HashMap<(String, Option<usize>), Option<String>>,
    /// Each pbrt material as strata's (without emission), converted once, by
    /// [`MaterialRef::key`].
    pub material_bodies: HashMap<String, Option<MaterialDesc>>,
    /// The image textures made, by strata name (for `scale` textures).
    pub image_bodies: HashMap<String, ImageTextureDesc>,
    /// Whether the materials read each strata texture clamped to [0, 1] (a reflectance) or not,
    /// as its first reader read it; a reader of the other kind gets a copy
    /// ([`super::textures`]).
    pub texture_clamping: HashMap<String, bool>,
    /// strata's materials that read a texture (a sphere's or disk's texture coordinates are
    /// strata's, not pbrt's: warned).
    pub textured_materials: std::collections::HashSet<String>,
    /// Object definitions: the shapes of each, in the object's space.
    objects: HashMap<String, Vec<Placed>>,
    /// The object being defined, and the CTM at its `ObjectBegin`.
    current_object: Option<(String, Vec<Placed>)>,
    placed: Vec<Placed>,
    /// The description being built: textures, materials, lights and the sky as they are read
    /// (shapes, camera and settings at the end).
    pub desc: Description,
    pub report: Report,
    /// pbrt's world → strata's (the camera's mirror, or the identity).
    pub mirror: DMat4,
    /// `AreaLightSource`s read.
    pub area_lights: usize,
}

impl<'a> Builder<'a> {
    fn new(parsed: &'a Parsed, mesh_dir: &'a str) -> Result<Self, SceneError> {
        let settings = settings(
            parsed,
            parsed.last("Film"),
            parsed.last("Sampler"),
            parsed.last("Integrator"),
            parsed.last("PixelFilter"),
        )?;
        Ok(Self {
            parsed,
            mesh_dir,
            state: State::default(),
            gfx: Gfx {
                material: MaterialRef::Default,
                area: None,
            },
            gfx_stack: Vec::new(),
            settings,
            camera: None,
            named_materials: HashMap::new(),
            anonymous_materials: Vec::new(),
            textures: HashMap::new(),
            materials_written: HashMap::new(),
            material_bodies: HashMap::new(),
            image_bodies: HashMap::new(),
            texture_clamping: HashMap::new(),
            textured_materials: Default::default(),
            objects: HashMap::new(),
            current_object: None,
            placed: Vec::new(),
            desc: Description::default(),
            report: Report::default(),
            mirror: DMat4::IDENTITY,
            area_lights: 0,
        })
    }

    /// A warning at directive `d`.
    pub fn warn(&mut self, source: usize, at: usize, message: impl Into<String>) {
        self.report.warnings.push(Warning {
            at: self.parsed.location(source, at).to_string(),
            message: message.into(),
        });
    }

    /// A path the scene names, relative to the main file's directory as pbrt-v4 reads it, as
    /// the description gives it: relative to that directory (absolute if it is absolute).
    pub fn file_path(&self, name: &str) -> String {
        let path = self.resolve(name);
        if Path::new(name).is_absolute() {
            return path.to_string_lossy().into_owned();
        }
        let base = self.parsed.sources.main().parent().unwrap_or(Path::new(""));
        crate::desc::write::relative(&path, base)
            .to_string_lossy()
            .replace('\\', "/")
    }

    /// The main file's directory joined with `name` (where pbrt-v4 looks for it).
    pub fn resolve(&self, name: &str) -> PathBuf {
        self.parsed
            .sources
            .main()
            .parent()
            .unwrap_or(Path::new(""))
            .join(name)
    }

    /// An error at `p`'s string parameter `param` unless `file`, its value, is a file
    /// ([`Builder::resolve`]).
    pub fn existing_file(&self, p: &Params, param: &str, file: &str) -> Result<(), SceneError> {
        if self.resolve(file).is_file() {
            return Ok(());
        }
        let at = p
            .find(ParamType::String, param)
            .expect("the parameter was read");
        Err(p.err(
            at,
            format!("no file `{file}` ({})", self.resolve(file).display()),
        ))
    }

    fn directive(&mut self, source: usize, d: &'a Directive) -> Result<(), SceneError> {
        match d.name.as_str() {
            "AttributeBegin" | "ObjectBegin" => self.gfx_stack.push(self.gfx.clone()),
            "AttributeEnd" | "ObjectEnd" => {
                if let Some(g) = self.gfx_stack.pop() {
                    self.gfx = g;
                }
            }
            _ => {}
        }
        let before = self.state.warnings.len();
        let handled = self.state.apply(self.parsed, source, d)?;
        let new: Vec<Warning> = self.state.warnings.drain(before..).collect();
        self.report.warnings.extend(new);
        if handled {
            if d.name == "WorldBegin" {
                self.world_begin()?;
            }
            return Ok(());
        }
        let p = Params::new(self.parsed, source, d);
        match d.name.as_str() {
            "Camera" | "Film" | "Sampler" | "Integrator" | "PixelFilter" => {}
            "ObjectBegin" => {
                let name = first_string(d);
                if self.current_object.is_some() {
                    return Err(p.directive_err("ObjectBegin inside another object's definition"));
                }
                self.current_object = Some((name, Vec::new()));
            }
            "ObjectEnd" => match self.current_object.take() {
                Some((name, shapes)) => {
                    if self.objects.insert(name.clone(), shapes).is_some() {
                        // pbrt-v4 refuses it too.
                        return Err(p.directive_err(format!("object `{name}` defined again")));
                    }
                }
                None => return Err(p.directive_err("ObjectEnd outside an object's definition")),
            },
            "ObjectInstance" => {
                let name = first_string(d);
                let Some(shapes) = self.objects.get(&name) else {
                    return Err(p.directive_err(format!("no object named `{name}`")));
                };
                if self.current_object.is_some() {
                    return Err(p.directive_err("ObjectInstance inside an object's definition"));
                }
                let (ctm, flattened_at) = (
                    self.state.attributes.ctm,
                    self.state.attributes.flattened_at,
                );
                let copies: Vec<Placed> = shapes
                    .iter()
                    .map(|s| Placed {
                        ctm: ctm * s.ctm,
                        flattened_at: flattened_at.or(s.flattened_at),
                        ..s.clone()
                    })
                    .collect();
                self.report.instances += 1;
                self.report.instanced_shapes += copies.len();
                self.placed.extend(copies);
            }
            "Material" => {
                self.anonymous_materials.push((source, d));
                self.gfx.material = MaterialRef::Anonymous(self.anonymous_materials.len() - 1);
            }
            "MakeNamedMaterial" => {
                let name = first_string(d);
                if self
                    .named_materials
                    .insert(name.clone(), (source, d))
                    .is_some()
                {
                    // pbrt-v4 refuses it too.
                    return Err(p.directive_err(format!("material `{name}` defined again")));
                }
            }
            "NamedMaterial" => {
                self.gfx.material = MaterialRef::Named(first_string(d), source, d.at);
            }
            "Texture" => self.texture(source, d)?,
            "LightSource" | "AreaLightSource" if self.camera.is_none() => {
                return Err(p.directive_err(format!("{} before WorldBegin", d.name)))
            }
            "AreaLightSource" => self.gfx.area = super::lights::area_light(self, source, d)?,
            "LightSource" => super::lights::light(self, source, d)?,
            "Shape" => self.shape(source, d)?,
            "MakeNamedMedium" | "MediumInterface" => self.warn(
                source,
                d.at,
                format!(
                    "{}: strata renders no participating media (ignored)",
                    d.name
                ),
            ),
            "Option" | "ColorSpace" | "Attribute" => self.warn(
                source,
                d.at,
                format!("{} ignored (strata reads no such setting)", d.name),
            ),
            other => self.warn(source, d.at, format!("{other} ignored")),
        }
        Ok(())
    }

    /// The camera (and with it the mirror) once the camera's transform is known.
    fn world_begin(&mut self) -> Result<(), SceneError> {
        let camera_from_world = self.state.camera_from_world.unwrap_or(DMat4::IDENTITY);
        let (camera, warnings) = camera_of(
            self.parsed,
            self.parsed.last("Camera"),
            camera_from_world,
            self.settings.width,
            self.settings.height,
        )?;
        self.report.warnings.extend(warnings);
        self.mirror = camera.world;
        self.camera = Some(camera);
        Ok(())
    }

    /// A shape's `alpha` (a number, clamped to [0, 1] as pbrt's test reads it, or a float
    /// texture): `None` where it is 1, opaque.
    fn shape_alpha(&mut self, p: &Params) -> Result<Option<crate::desc::AmountParam>, SceneError> {
        use crate::desc::{Numbers, Textured};
        Ok(match self.float_param(p, "alpha", 1.0)? {
            Some(Textured::Value(Numbers([a]))) if a >= 1.0 => None,
            Some(Textured::Value(Numbers([a]))) => Some(Textured::Value(Numbers([a.max(0.0)]))),
            other => other,
        })
    }

    /// `Shape`: its geometry in object space, placed with the CTM and the current material.
    fn shape(&mut self, source: usize, d: &'a Directive) -> Result<(), SceneError> {
        let p = Params::new(self.parsed, source, d);
        if self.camera.is_none() {
            return Err(p.directive_err("Shape before WorldBegin"));
        }
        let Some(geom) = super::shapes::geometry(self, &p)? else {
            self.report.warnings.extend(p.unused());
            return Ok(());
        };
        let mut alpha = self.shape_alpha(&p)?;
        self.report.warnings.extend(p.unused());
        let area = match (&self.current_object, &self.gfx.area) {
            (Some(_), Some(_)) => {
                self.warn(
                    source,
                    d.at,
                    "an area light inside an object's definition does not emit (as in pbrt-v4)",
                );
                None
            }
            (_, area) => area.clone(),
        };
        if area.is_some() && alpha.is_some() {
            self.warn(
                source,
                d.at,
                "alpha on an area light ignored: strata's lights are opaque",
            );
            alpha = None;
        }
        let material = self.gfx.material.clone();
        let Some(material) = super::materials::material_name(self, &material, area.as_ref())?
        else {
            // pbrt's "interface": a boundary of media, no surface.
            return Ok(());
        };
        if self.current_object.is_none() {
            self.report.shapes += 1;
        }
        let placed = Placed {
            geom,
            ctm: self.state.attributes.ctm,
            reverse: self.state.attributes.reverse_orientation,
            material,
            two_sided: area.as_ref().is_some_and(|a| a.two_sided),
            alpha,
            at: (source, d.at),
            flattened_at: self.state.attributes.flattened_at,
        };
        match &mut self.current_object {
            Some((_, shapes)) => shapes.push(placed),
            None => self.placed.push(placed),
        }
        Ok(())
    }

    /// The description, with its shapes baked and their meshes, the camera and the settings.
    fn finish(mut self) -> Result<Description, SceneError> {
        if let Some((name, _)) = &self.current_object {
            return Err(SceneError::new(
                stratapt_scene::SourceLocation::file(self.parsed.sources.main()),
                format!("object `{name}` is never closed (ObjectEnd)"),
            ));
        }
        if self.camera.is_none() {
            self.world_begin()?;
        }
        let camera = self.camera.clone().expect("set above");
        let placed = std::mem::take(&mut self.placed);
        let (shapes, meshes) = super::shapes::bake(&mut self, placed)?;

        // The camera and the film where their directives are (else the file's start).
        let at = |name: &str| match self.parsed.last(name) {
            Some((source, d)) => self.parsed.span(source, d.at),
            None => self.parsed.span(0, 0),
        };
        let (at_camera, at_film) = (at("Camera"), at("Film"));
        let s = &self.settings;
        let lens = camera.aperture > 0.0;
        let filter = match s.filter {
            filter_kind::BOX => "box",
            filter_kind::TENT => "tent",
            _ => "gaussian",
        };
        let scene = SceneDesc {
            camera: Spanned::new(
                at_camera.clone(),
                CameraDesc {
                    eye: Spanned::new(at_camera.clone(), camera.eye.to_array()),
                    look_at: Spanned::new(at_camera.clone(), camera.look_at.to_array()),
                    up: Some(Spanned::new(at_camera.clone(), camera.up.to_array())),
                    fov: Spanned::new(at_camera.clone(), camera.fov_y),
                    aperture: lens.then(|| Spanned::new(at_camera.clone(), camera.aperture)),
                    focus_distance: lens
                        .then(|| Spanned::new(at_camera.clone(), camera.focus_distance)),
                    ..CameraDesc::default()
                },
            ),
            film: Some(Spanned::new(
                at_film.clone(),
                FilmDesc {
                    width: Some(Spanned::new(at_film.clone(), s.width as i64)),
                    height: Some(Spanned::new(at_film.clone(), s.height as i64)),
                    filter: Some(Spanned::new(at_film.clone(), filter.to_string())),
                    filter_width: Some(Spanned::new(at_film.clone(), s.filter_param)),
                },
            )),
            render: Some(Spanned::new(
                at_film.clone(),
                RenderDesc {
                    spp: Some(Spanned::new(at("Sampler"), s.spp as i64)),
                    max_depth: Some(Spanned::new(at("Integrator"), s.max_depth as i64)),
                    sampler: Some(Spanned::new(at("Sampler"), s.sampler.name().to_string())),
                    ..RenderDesc::default()
                },
            )),
            sky: self.desc.scene.sky.take(),
            ..SceneDesc::default()
        };

        let mut report = self.report;
        report.warnings.splice(0..0, self.settings.warnings.clone());
        report.triangles = meshes.values().map(|m| m.indices.len() / 3).sum();
        Ok(Description {
            scene,
            shapes,
            meshes,
            import: Some(report),
            ..self.desc
        })
    }

    /// The name of the `index`th mesh file.
    pub fn mesh_name(&self, index: usize) -> String {
        format!("{}/{index:05}.ply", self.mesh_dir)
    }

    /// A point of pbrt's world in strata's.
    pub fn world_point(&self, p: DVec3) -> DVec3 {
        self.mirror.transform_point3(p)
    }

    /// A direction of pbrt's world in strata's.
    pub fn world_vector(&self, v: DVec3) -> DVec3 {
        self.mirror.transform_vector3(v)
    }
}

/// A directive's first positional argument, a string (the parser has checked it is there).
pub(super) fn first_string(d: &Directive) -> String {
    match d.args.first() {
        Some(Arg::Str(s)) => s.clone(),
        _ => unreachable!("{} takes a name", d.name),
    }
}

/// The numbers of a parameter (the parser has checked their type).
pub(super) fn numbers(values: &Values) -> &[f64] {
    match values {
        Values::Numbers(n) => n,
        _ => &[],
    }
}

/// Whether every number is finite and within f32's range (what strata stores).
pub(super) fn fits_f32(v: &[f64]) -> bool {
    v.iter()
        .all(|x| x.is_finite() && x.abs() <= f32::MAX as f64)
}

/// Whether the upper 3×3 of `m` is a rotation times a uniform scale (columns orthogonal and of
/// one length, to 10⁻⁶); its scale when it is.
pub(super) fn similarity_scale(m: &DMat4) -> Option<f64> {
    let m3 = DMat3::from_mat4(*m);
    let [a, b, c] = [m3.x_axis, m3.y_axis, m3.z_axis];
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let tol = 1e-6 * la.max(lb).max(lc);
    let ok = (la - lb).abs() <= tol
        && (la - lc).abs() <= tol
        && a.dot(b).abs() <= tol * la
        && a.dot(c).abs() <= tol * la
        && b.dot(c).abs() <= tol * lb;
    (ok && la > 0.0).then_some((la + lb + lc) / 3.0)
}

/// A `point3`/`normal`/`vector3`/`point2` parameter's numbers, or `None` when absent.
pub(super) fn find_numbers<'p>(
    p: &Params<'p>,
    ty: ParamType,
    name: &str,
) -> Option<(&'p [f64], &'p super::parse::Param)> {
    p.find(ty, name)
        .map(|param| (numbers(&param.values), param))
}
