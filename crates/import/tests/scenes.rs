//! Every scene shipped in `scenes/` (and `scenes/mitsuba/`) loads, has something that emits, and
//! a sane camera.

use std::path::PathBuf;
use stratapt_import::scene_file::load;
use stratapt_scene::records::NONE;

/// The scenes in `scenes/`, and Mitsuba's Cornell box rebuilt for `scripts/compare-mitsuba.py`.
fn scene_files() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    [root.clone(), root.join("mitsuba")]
        .iter()
        .flat_map(|dir| {
            stratapt_import::load::scene_files(dir)
                .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        })
        .collect()
}

#[test]
fn every_scene_loads_with_light_and_sane_camera() {
    let files = scene_files();
    assert!(
        files.len() >= 10,
        "expected the shipped scenes, found {files:?}"
    );
    for file in files {
        let scene = load(&file).unwrap_or_else(|e| panic!("{e}"));
        let name = file.display();
        assert!(
            !scene.lights.is_empty() || scene.sky != NONE,
            "{name}: nothing emits"
        );
        assert!(!scene.geometry.is_empty(), "{name}: no geometry");
        let c = &scene.camera;
        assert!(
            c.width > 0 && c.height > 0 && c.width <= 256 && c.height <= 256,
            "{name}: film"
        );
        assert!(
            c.tan_half_fov > 0.0 && c.tan_half_fov.is_finite(),
            "{name}: fov"
        );
        assert!(
            c.focus_distance > 0.0 && c.lens_radius >= 0.0,
            "{name}: lens"
        );
        assert!(c.shutter_close >= c.shutter_open, "{name}: shutter");
        assert!(
            c.eye0 != c.target0 && c.eye1 != c.target1,
            "{name}: view direction"
        );
        assert!(
            scene.settings.pattern_spp <= 64,
            "{name}: keep the default spp modest"
        );
        // Light tables are consistent with the lights.
        assert_eq!(scene.light_table.len(), scene.lights.len(), "{name}");
        let total: f32 = scene.lights.iter().map(|l| l.select_pdf).sum();
        assert!(
            (total - 1.0).abs() < 1e-4,
            "{name}: select pdfs sum to {total}"
        );
        // BVH order.
        assert!(
            scene
                .bvh
                .primitive_indices
                .iter()
                .enumerate()
                .all(|(i, &p)| p as usize == i),
            "{name}"
        );
    }
}

/// `scenes/metals.toml` gives conductors by complex index of refraction and anisotropic
/// roughness; the records carry them as written.
#[test]
fn metals_load_as_complex_conductors() {
    use stratapt_scene::records::material_kind;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let scene = load(&root.join("metals.toml")).unwrap_or_else(|e| panic!("{e}"));
    let named = |name: &str| {
        let i = scene
            .material_names
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("no material {name}"));
        scene.materials[i]
    };
    let gold = named("gold");
    assert_eq!(gold.kind(), material_kind::COMPLEX_CONDUCTOR);
    assert_eq!(gold.eta, [0.143, 0.374, 1.442]);
    assert_eq!(gold.k, [3.983, 2.385, 1.603]);
    assert_eq!(gold.color, [1.0; 3]);
    assert_eq!((gold.alpha_u, gold.alpha_v), (0.05, 0.05));
    let aluminium = named("aluminium");
    assert_eq!((aluminium.alpha_u, aluminium.alpha_v), (0.04, 0.35));
    let silver = named("silver");
    assert_eq!((silver.alpha_u, silver.alpha_v), (0.0, 0.0));
    assert_eq!(named("floor").kind(), material_kind::DIFFUSE);
}

/// The material `glass` of `scenes/glass.toml` with its `ior = 1.5` line replaced by `keys`.
fn glass_with(keys: &str) -> stratapt_scene::records::Material {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let base = std::fs::read_to_string(root.join("glass.toml")).unwrap();
    let header = "[materials.glass]\ntype = \"dielectric\"\n";
    let text = base.replace(&format!("{header}ior = 1.5\n"), &format!("{header}{keys}"));
    assert_ne!(text, base);
    let scene = stratapt_import::load::load_str(&text, std::path::Path::new("glass.toml")).unwrap();
    let i = scene
        .material_names
        .iter()
        .position(|n| n == "glass")
        .unwrap();
    scene.materials[i]
}

/// A dielectric with roughness is the rough dielectric, unless it is smoother than the mirror
/// threshold or index-matched (then its microfacets do nothing: the smooth one).
#[test]
fn rough_dielectrics_load_as_such_and_degenerate_ones_as_smooth() {
    use stratapt_scene::records::material_kind;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let scene = load(&root.join("rough-glass.toml")).unwrap_or_else(|e| panic!("{e}"));
    let named = |name: &str| {
        let i = scene.material_names.iter().position(|n| n == name).unwrap();
        scene.materials[i]
    };
    let brushed = named("brushed");
    assert_eq!(brushed.kind(), material_kind::ROUGH_DIELECTRIC);
    assert_eq!(
        (brushed.alpha_u, brushed.alpha_v, brushed.ior),
        (0.03, 0.4, 1.5)
    );
    assert_eq!(named("frosted").kind(), material_kind::ROUGH_DIELECTRIC);
    for (roughness, ior, kind) in [
        ("1e-3", "1.5", material_kind::DIELECTRIC),
        ("[0, 0.2]", "1.5", material_kind::ROUGH_DIELECTRIC),
        ("0.2", "1", material_kind::DIELECTRIC),
        ("0", "1.33", material_kind::DIELECTRIC),
    ] {
        let m = glass_with(&format!("ior = {ior}\nroughness = {roughness}\n"));
        assert_eq!(m.kind(), kind, "roughness {roughness} ior {ior}");
        if kind == material_kind::DIELECTRIC {
            assert_eq!((m.alpha_u, m.alpha_v), (0.0, 0.0));
        }
    }
}

/// `masking = "separable"` sets the flag above the kind; `"correlated"` and no key leave it
/// clear.
#[test]
fn masking_is_a_flag_above_the_kind() {
    use stratapt_scene::records::{material_flag, material_kind};
    for (masking, kind, separable) in [
        ("", material_kind::ROUGH_DIELECTRIC, false),
        (
            "masking = \"correlated\"\n",
            material_kind::ROUGH_DIELECTRIC,
            false,
        ),
        (
            "masking = \"separable\"\n",
            material_kind::ROUGH_DIELECTRIC,
            true,
        ),
    ] {
        let m = glass_with(&format!("ior = 1.5\nroughness = 0.2\n{masking}"));
        assert_eq!(m.kind(), kind, "{masking}");
        assert_eq!(
            m.has(material_flag::SEPARABLE_MASKING),
            separable,
            "{masking}"
        );
    }
}

/// `scenes/plastics.toml`: smooth and rough plastics with their coatings' quantities in the
/// record, one transmittance table per rough one, and the flags.
#[test]
fn plastics_load_with_their_coatings() {
    use stratapt_sampling::warp::ggx::Masking;
    use stratapt_scene::coating::{fresnel_diffuse_reflectance, RoughCoating, TRANSMITTANCE_RES};
    use stratapt_scene::records::{material_flag, material_kind};
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let scene = load(&root.join("plastics.toml")).unwrap_or_else(|e| panic!("{e}"));
    let named = |name: &str| {
        let i = scene.material_names.iter().position(|n| n == name).unwrap();
        scene.materials[i]
    };
    let red = named("red");
    assert_eq!(red.kind(), material_kind::PLASTIC);
    assert_eq!((red.ior, red.eta), (1.49, [1.0; 3]));
    assert_eq!(red.k[0], fresnel_diffuse_reflectance(1.0 / 1.49));
    // Mitsuba's sampling weight: mean specular / (mean diffuse + mean specular).
    let d_mean = (0.7f32 + 0.08 + 0.05) / 3.0;
    assert!(
        (red.k[1] - 1.0 / (1.0 + d_mean)).abs() < 1e-6,
        "{}",
        red.k[1]
    );
    assert_eq!(scene.tables.len(), 3 * TRANSMITTANCE_RES);
    for (name, alpha, masking, nonlinear, table) in [
        ("blue", 0.08, Masking::Correlated, false, 0),
        ("green", 0.3, Masking::Correlated, true, 1),
        ("white", 0.6, Masking::Separable, false, 2),
    ] {
        let m = named(name);
        assert_eq!(m.kind(), material_kind::ROUGH_PLASTIC, "{name}");
        assert_eq!((m.alpha_u, m.alpha_v), (alpha, alpha), "{name}");
        assert_eq!(m.has(material_flag::NONLINEAR), nonlinear, "{name}");
        assert_eq!(
            m.has(material_flag::SEPARABLE_MASKING),
            masking == Masking::Separable,
            "{name}"
        );
        let coating = RoughCoating::new(m.ior, alpha, masking);
        let start = table * TRANSMITTANCE_RES;
        assert_eq!(m.k[2], start as f32, "{name}");
        assert_eq!(m.k[0], coating.internal_reflectance, "{name}");
        assert_eq!(
            &scene.tables[start..start + TRANSMITTANCE_RES],
            &coating.transmittance[..],
            "{name}"
        );
    }
    assert_eq!(named("white").eta, [0.9; 3]);
}
