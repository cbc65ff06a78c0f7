//! The Mitsuba 3 export of every bundled scene: well-formed XML whose plugins are Mitsuba's,
//! whose references and files resolve, with every triangle, light and texture strata renders.
//! (That Mitsuba 3 loads each export and renders the same image is measured by
//! `scripts/mitsuba-diff.py`, `docs/measurements/mitsuba-diff.md`: Mitsuba is no dependency.)

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use stratapt_import::export::mitsuba::{export, Export};
use stratapt_scene::records::{light_kind, prim_kind, NONE};
use stratapt_scene::FlatScene;
use xml::reader::{EventReader, XmlEvent};

/// Every bundled scene: `scenes/`, `scenes/hard/`, `scenes/mitsuba/`, and the pbrt-v4 ones.
fn scenes() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut files: Vec<PathBuf> = ["", "hard", "mitsuba"]
        .iter()
        .flat_map(|d| stratapt_import::load::scene_files(&root.join(d)).unwrap())
        .collect();
    let mut pbrt: Vec<PathBuf> = std::fs::read_dir(root.join("pbrt"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "pbrt"))
        .collect();
    pbrt.sort();
    files.extend(pbrt);
    files
}

/// The plugins Mitsuba 3 has, by tag, among those the export may write.
fn known(tag: &str, kind: &str) -> bool {
    let kinds: &[&str] = match tag {
        "integrator" => &["path"],
        "sensor" => &["perspective", "thinlens"],
        "film" => &["hdrfilm"],
        "rfilter" => &["box", "tent", "gaussian"],
        "sampler" => &["independent"],
        "bsdf" => &[
            "diffuse",
            "conductor",
            "roughconductor",
            "dielectric",
            "roughdielectric",
            "plastic",
            "roughplastic",
            "thindielectric",
            "blendbsdf",
            "bumpmap",
            "normalmap",
            "mask",
            "twosided",
        ],
        "shape" => &["ply", "sphere", "disk", "cylinder"],
        "emitter" => &["area", "point", "spot", "directional", "constant", "envmap"],
        "texture" => &["bitmap", "checkerboard"],
        _ => &[],
    };
    kinds.contains(&kind)
}

/// What an export's XML holds, read back.
#[derive(Default)]
struct Read {
    /// `type`s by tag, counted.
    plugins: HashMap<(String, String), usize>,
    files: Vec<String>,
}

/// Parses `x`'s XML (panicking on anything malformed), checking each plugin is Mitsuba's,
/// each reference names an id declared before it, each number is finite.
fn read(name: &str, x: &Export) -> Read {
    let mut out = Read::default();
    let mut ids = HashSet::new();
    let mut defaults = HashSet::new();
    for event in EventReader::new(x.xml.as_bytes()) {
        let event = event.unwrap_or_else(|e| panic!("{name}: malformed XML: {e}\n{}", x.xml));
        let XmlEvent::StartElement {
            name: tag,
            attributes,
            ..
        } = event
        else {
            continue;
        };
        let tag = tag.local_name;
        let attr = |k: &str| {
            attributes
                .iter()
                .find(|a| a.name.local_name == k)
                .map(|a| a.value.clone())
        };
        if let Some(kind) = attr("type") {
            assert!(
                known(&tag, &kind),
                "{name}: <{tag} type=\"{kind}\"> is not a Mitsuba 3 plugin here"
            );
            *out.plugins.entry((tag.clone(), kind)).or_default() += 1;
        }
        if let Some(id) = attr("id") {
            if tag == "ref" {
                assert!(
                    ids.contains(&id),
                    "{name}: <ref id=\"{id}\"> before its declaration"
                );
            } else {
                assert!(ids.insert(id.clone()), "{name}: id {id} declared twice");
            }
        }
        if tag == "default" {
            defaults.insert(attr("name").unwrap());
        }
        let value = attr("value").unwrap_or_default();
        if let Some(param) = value.strip_prefix('$') {
            assert!(
                defaults.contains(param),
                "{name}: ${param} has no <default>"
            );
        } else if matches!(tag.as_str(), "float" | "rgb" | "matrix" | "integer") {
            for v in value.split([',', ' ']).filter(|v| !v.is_empty()) {
                let v: f64 = v
                    .parse()
                    .unwrap_or_else(|_| panic!("{name}: {tag} value {value:?}"));
                assert!(v.is_finite(), "{name}: {tag} value {value:?}");
            }
        }
        if attr("name").as_deref() == Some("filename") {
            out.files.push(attr("value").unwrap());
        }
    }
    out
}

/// Triangles, and the sum of their areas, in `x`'s PLY files.
fn ply_triangles(x: &Export) -> (usize, f64) {
    let dir = tempfile::tempdir().unwrap();
    let (mut count, mut area) = (0, 0.0);
    for (name, bytes) in x.files.iter().filter(|(n, _)| n.ends_with(".ply")) {
        let path = dir.path().join(name.replace('/', "_"));
        std::fs::write(&path, bytes).unwrap();
        let mesh = stratapt_import::load::read_ply(&path).unwrap();
        let p = |i: u32| glam::Vec3::from_slice(&mesh.positions[3 * i as usize..]).as_dvec3();
        for t in mesh.indices.chunks_exact(3) {
            area += 0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length();
            count += 1;
        }
    }
    (count, area)
}

/// Triangles of `scene` that do not move, and the sum of their areas (world space).
fn scene_triangles(scene: &FlatScene) -> (usize, f64, bool) {
    let (mut count, mut area, mut moving) = (0, 0.0, false);
    for p in scene
        .geometry
        .iter()
        .filter(|p| p.kind == prim_kind::TRIANGLE)
    {
        count += 1;
        moving |= p.motion != NONE;
        let [a, b, c] = [p.a, p.b, p.c].map(|v| glam::Vec3::from(v).as_dvec3());
        area += 0.5 * (b - a).cross(c - a).length();
    }
    (count, area, moving)
}

#[test]
fn every_bundled_scene_exports_mitsuba_plugins_with_its_triangles_lights_and_files() {
    let files = scenes();
    assert!(files.len() >= 30, "{files:?}");
    for file in files {
        let name = file.display().to_string();
        let scene = stratapt_import::load(&file).unwrap_or_else(|e| panic!("{e}"));
        let x = export(&scene, "files");
        let read = read(&name, &x);
        // Every file named is written, and every file written is named.
        let written: HashSet<&String> = x.files.iter().map(|(n, _)| n).collect();
        let named: HashSet<&String> = read.files.iter().collect();
        assert_eq!(written, named, "{name}");
        // Every triangle, of the same area (where nothing moves).
        let (n, area, moving) = scene_triangles(&scene);
        let (m, exported) = ply_triangles(&x);
        assert_eq!(n, m, "{name}: triangles");
        if !moving {
            assert!(
                (exported - area).abs() <= 1e-5 * area,
                "{name}: area {exported} vs {area}"
            );
        }
        // Every light that is not a surface's is one emitter (a line light a cylinder's).
        let count =
            |tag: &str, kind: &str| *read.plugins.get(&(tag.into(), kind.into())).unwrap_or(&0);
        let lights = |kinds: &[u32]| {
            scene
                .lights
                .iter()
                .filter(|l| kinds.contains(&l.kind))
                .count()
        };
        assert_eq!(
            count("emitter", "point"),
            lights(&[light_kind::POINT]),
            "{name}"
        );
        assert_eq!(
            count("emitter", "spot"),
            lights(&[light_kind::SPOT]),
            "{name}"
        );
        assert_eq!(
            count("emitter", "directional"),
            lights(&[light_kind::DISTANT]),
            "{name}"
        );
        assert_eq!(
            count("shape", "cylinder"),
            lights(&[light_kind::LINE]),
            "{name}"
        );
        let skies = count("emitter", "constant") + count("emitter", "envmap");
        assert_eq!(skies, usize::from(scene.sky != NONE), "{name}");
        // Every surface that emits, as area emitters (a mesh per emission at least).
        let emitting = scene.geometry.iter().any(|p| p.light != NONE);
        assert_eq!(
            count("emitter", "area") > count("shape", "cylinder"),
            emitting,
            "{name}"
        );
    }
}

#[test]
fn the_cornell_box_exports_its_camera_materials_and_light_as_mitsuba_reads_them() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let scene = stratapt_import::load(&root.join("cornell-box.toml")).unwrap();
    let x = export(&scene, "cb");
    assert!(x.warnings.is_empty(), "{:?}", x.warnings);
    for expected in [
        r#"<default name="max_depth" value="9"/>"#,
        r#"<lookat origin="278, 273, -800" target="278, 273, -799" up="0, 1, 0"/>"#,
        r#"<string name="fov_axis" value="y"/>"#,
        r#"<rgb name="reflectance" value="0.63, 0.065, 0.05"/>"#,
        r#"<rgb name="radiance" value="17, 12, 4"/>"#,
        r#"<string name="filename" value="cb/mesh0.ply"/>"#,
    ] {
        assert!(
            x.xml.contains(expected),
            "{expected} missing from\n{}",
            x.xml
        );
    }
}

/// The number attributes of the first element after `after` in `xml` that starts with `tag`.
fn numbers_after(xml: &str, after: &str, tag: &str) -> Vec<f32> {
    let start = xml.find(after).unwrap_or_else(|| panic!("no {after}"));
    let at = start
        + xml[start..]
            .find(tag)
            .unwrap_or_else(|| panic!("no {tag} after {after}"));
    let element = &xml[at..at + xml[at..].find("/>").unwrap()];
    element
        .split('"')
        .skip(1)
        .step_by(2)
        .flat_map(|v| v.split([',', ' ']))
        .filter_map(|v| v.parse().ok())
        .collect()
}

#[test]
fn lights_and_the_sky_carry_strata_s_directions_and_amounts_into_mitsuba_s_terms() {
    let text = r#"
[camera]
eye = [0, 1, 5]
look_at = [0, 0, 0]
fov = 40
[sky]
top = [1, 0.5, 0.25]
bottom = [0.1, 0.2, 0.3]
up = [0.3, 1, 0.2]
[materials.white]
type = "diffuse"
albedo = 0.5
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "white"
[[lights]]
type = "distant"
direction = [1, 2, 1]
irradiance = 3
angular_diameter = 0.53
[[lights]]
type = "line"
from = [-1, 2, 0]
to = [1, 2, 0]
intensity = [2, 4, 6]
[[lights]]
type = "spot"
position = [0, 3, 0]
look_at = [0, 0, 0]
intensity = 5
cone_angle = 30
cone_delta = 10
"#;
    let scene = stratapt_import::load::load_str(text, Path::new("lights.toml")).unwrap();
    let x = export(&scene, "f");
    let light = |kind: u32| scene.lights.iter().find(|l| l.kind == kind).unwrap();
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * b.abs().max(1.0);
    // The sun: Mitsuba's direction is where the light goes (−p0), its irradiance L·π·sin²α.
    let sun = light(light_kind::DISTANT);
    let d = numbers_after(&x.xml, "type=\"directional\"", "<vector");
    assert!((0..3).all(|i| close(d[i], -sun.p0[i])), "{d:?}");
    let e = numbers_after(&x.xml, "type=\"directional\"", "<rgb");
    let sin2 = 1.0 - (sun.p2[0] as f64).powi(2);
    assert!(close(
        e[0],
        (sun.radiance[0] as f64 * std::f64::consts::PI * sin2) as f32
    ));
    assert!(
        close(e[0], 3.0),
        "{e:?}: the cone's irradiance is the file's"
    );
    // The line: a cylinder of radius 10⁻³ of its length, radiance I / 2r.
    let r = numbers_after(&x.xml, "type=\"cylinder\"", "<float name=\"radius\"");
    assert!(close(r[0], 2e-3), "{r:?}");
    let l = numbers_after(&x.xml, "type=\"cylinder\"", "<rgb name=\"radiance\"");
    assert!(
        (0..3).all(|i| close(l[i], [2.0, 4.0, 6.0][i] / (2.0 * r[0]))),
        "{l:?}"
    );
    // The spot: cutoff 30°, full intensity within 20°.
    assert!(close(
        numbers_after(&x.xml, "type=\"spot\"", "<float name=\"cutoff_angle\"")[0],
        30.0
    ));
    assert!(close(
        numbers_after(&x.xml, "type=\"spot\"", "<float name=\"beam_width\"")[0],
        20.0
    ));
    // The gradient: the map's +y (its top row, `top`) turned onto `up`; its last row `bottom`.
    let m = numbers_after(&x.xml, "type=\"envmap\"", "<matrix");
    let up = glam::Vec3::new(0.3, 1.0, 0.2).normalize();
    assert!((0..3).all(|i| close(m[4 * i + 1], up[i])), "{m:?}");
    let (_, pfm) = x
        .files
        .iter()
        .find(|(n, _)| n.ends_with("sky.pfm"))
        .unwrap();
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sky.pfm"), pfm).unwrap();
    let (texels, _, _) =
        stratapt_scene::environment::read_image(&dir.path().join("sky.pfm")).unwrap();
    // Read back top row first: the top row is `top`, the bottom row `bottom`.
    assert_eq!(&texels[..3], &[1.0, 0.5, 0.25]);
    assert_eq!(&texels[texels.len() - 3..], &[0.1, 0.2, 0.3]);
}

#[test]
fn an_environment_map_turns_back_into_the_world_as_strata_turns_it() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let scene = stratapt_import::load(&root.join("environment.toml")).unwrap();
    let x = export(&scene, "f");
    let sky = scene
        .lights
        .iter()
        .find(|l| l.kind == light_kind::ENVIRONMENT)
        .unwrap();
    let m = numbers_after(&x.xml, "type=\"envmap\"", "<matrix");
    let to_world =
        glam::Mat3::from_cols_array(&[m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10]]);
    let (r0, r1) = (glam::Vec3::from(sky.p0), glam::Vec3::from(sky.p1));
    let to_map = glam::Mat3::from_cols(r0, r1, r0.cross(r1)).transpose();
    for d in [
        glam::Vec3::X,
        glam::Vec3::Y,
        glam::Vec3::new(0.3, -0.5, 0.8).normalize(),
    ] {
        let back = to_world * (to_map * d);
        assert!((back - d).length() < 1e-5, "{d} came back as {back}");
    }
}

/// scenes/detail.toml's bump maps are Mitsuba's `bumpmap` (scale 1, over their material's BSDF)
/// and its normal maps `normalmap`, with nothing warned.
#[test]
fn bump_and_normal_maps_export_as_mitsuba_s() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let scene = stratapt_import::load(&root.join("detail.toml")).unwrap();
    let x = export(&scene, "files");
    let read = read("detail", &x);
    let count = |kind: &str| {
        *read
            .plugins
            .get(&("bsdf".into(), kind.into()))
            .unwrap_or(&0)
    };
    // The floor, the gold, the tile and the pitted side of the mix; the box and the disk.
    assert_eq!(count("bumpmap"), 4);
    assert_eq!(count("normalmap"), 2);
    assert!(
        x.xml.contains(r#"<float name="scale" value="1"/>"#),
        "{}",
        x.xml
    );
    assert!(x.xml.contains(r#"<ref name="normalmap" id="#), "{}", x.xml);
    let bumps = x
        .warnings
        .iter()
        .filter(|w| w.contains("displacement") || w.contains("normal"));
    assert_eq!(bumps.count(), 0, "{:?}", x.warnings);
}
