//! Every malformed scene gives a `SceneError` naming the file, the line (and column) of the
//! offending key or value, and a reason that names the problem — never a panic.

use std::path::Path;
use stratapt_import::load::load_str;
use stratapt_import::scene_file::load;
use stratapt_scene::SceneError;

/// A valid preamble; tests append the part under test.
const BASE: &str = r#"[camera]
eye = [0, 0, -5]
look_at = [0, 0, 0]
fov = 40

[materials.white]
type = "diffuse"
albedo = 0.5
"#;

/// Load `text` (named `bad.toml`), which must fail.
fn fail(text: &str) -> SceneError {
    match load_str(text, Path::new("bad.toml")) {
        Ok(_) => panic!("loaded without error:\n{text}"),
        Err(e) => e,
    }
}

/// 1-based line and column of `needle` (unique in `text`). A `|` in the needle marks the column
/// (e.g. `spp = |0`); it is not part of the searched text.
fn position(text: &str, needle: &str) -> (usize, usize) {
    let (prefix, rest) = needle.split_once('|').unwrap_or(("", needle));
    let whole = format!("{prefix}{rest}");
    let at = text
        .find(&whole)
        .unwrap_or_else(|| panic!("`{whole}` not in the text"))
        + prefix.len();
    assert_eq!(text.matches(&whole).count(), 1, "`{whole}` is not unique");
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

/// `text` fails at `needle` (its line, and its column), with a reason containing every word of
/// `reason` (case-insensitive).
fn fails_at(text: &str, needle: &str, reason: &[&str]) -> SceneError {
    let e = fail(text);
    let (line, column) = position(text, needle);
    assert_eq!(e.location.file, Path::new("bad.toml"), "{e}");
    assert_eq!(
        e.location.line,
        Some(line),
        "wrong line for `{needle}`: {e}"
    );
    assert_eq!(
        e.location.column,
        Some(column),
        "wrong column for `{needle}`: {e}"
    );
    let lower = e.reason.to_lowercase();
    for word in reason {
        assert!(
            lower.contains(&word.to_lowercase()),
            "reason lacks `{word}`: {e}"
        );
    }
    e
}

/// Same, for text appended to [`BASE`].
fn base_fails_at(extra: &str, needle: &str, reason: &[&str]) -> SceneError {
    fails_at(&format!("{BASE}{extra}"), needle, reason)
}

/// A camera table with one line replaced.
fn camera_with(key: &str, line: &str) -> String {
    BASE.lines()
        .map(|l| {
            if l.starts_with(&format!("{key} =")) {
                line.to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

fn sphere(extra: &str) -> String {
    format!("\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"white\"\n{extra}")
}

// --- TOML level --------------------------------------------------------------------------------

#[test]
fn toml_syntax_error() {
    let e = fails_at("[camera]\neye = [0, 0, -5\nfov = 40\n", "fov", &[]);
    assert!(!e.reason.is_empty());
}

#[test]
fn unknown_top_level_key() {
    fails_at(
        &format!("colour = 1\n{BASE}"),
        "colour",
        &["unknown key", "colour", "shapes"],
    );
}

#[test]
fn unknown_camera_key() {
    fails_at(
        &camera_with("fov", "fov = 40\nfoov = 2"),
        "foov",
        &["unknown key", "foov", "fov"],
    );
}

#[test]
fn unknown_shape_key() {
    base_fails_at(
        &sphere("radiuss = 2\n"),
        "radiuss",
        &["unknown key", "radiuss", "radius"],
    );
}

#[test]
fn unknown_material_key() {
    base_fails_at(
        "[materials.red]\ntype = \"diffuse\"\nalbedo = 0.5\nalbdo = 1\n",
        "albdo",
        &["albdo", "albedo"],
    );
}

#[test]
fn unknown_key_in_inline_transform() {
    base_fails_at(
        &sphere("transform = { translat = [1, 2, 3] }\n"),
        "translat ",
        &["translat", "translate"],
    );
}

#[test]
fn unknown_light_key() {
    base_fails_at(
        "[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 1\ncolor = 1\n",
        "color",
        &["color", "intensity"],
    );
}

#[test]
fn wrong_type() {
    fails_at(
        &camera_with("fov", "fov = \"wide\""),
        "\"wide\"",
        &["invalid type", "string"],
    );
}

#[test]
fn wrong_vector_length() {
    fails_at(
        &camera_with("eye", "eye = [0, 0]"),
        "eye = |[0, 0]",
        &["length"],
    );
}

#[test]
fn wrong_type_inside_color() {
    base_fails_at(
        "[materials.red]\ntype = \"diffuse\"\nalbedo = [0.5, \"x\", 0.5]\n",
        "\"x\"",
        &["invalid type"],
    );
}

#[test]
fn missing_required_key() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nmaterial = \"white\"\n",
        "[[shapes]]",
        &["missing key", "radius"],
    );
}

#[test]
fn missing_camera() {
    let e = fail("[film]\nwidth = 64\n");
    assert_eq!(e.location.file, Path::new("bad.toml"));
    assert!(e.location.line.is_some());
    assert!(e.reason.contains("camera"), "{e}");
}

#[test]
fn missing_type() {
    base_fails_at(
        "\n[[shapes]]\ncenter = [0, 0, 0]\n",
        "[[shapes]]",
        &["missing key `type`", "sphere"],
    );
}

#[test]
fn missing_material_on_shape() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n",
        "[[shapes]]",
        &["material"],
    );
}

// --- Numbers -----------------------------------------------------------------------------------

#[test]
fn nan_number() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = nan\nmaterial = \"white\"\n",
        "nan",
        &["radius", "finite"],
    );
}

#[test]
fn infinite_vector_component() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"sphere\"\ncenter = [inf, 0, 0]\nradius = 1\nmaterial = \"white\"\n",
        "[inf",
        &["center", "finite"],
    );
}

#[test]
fn number_too_large_for_f32() {
    fails_at(
        &camera_with("eye", "eye = [0, 0, -1e300]"),
        "[0, 0, -1e300]",
        &["eye", "finite"],
    );
}

#[test]
fn negative_radius() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = -1\nmaterial = \"white\"\n",
        "radius = |-1",
        &["radius", "positive"],
    );
}

#[test]
fn zero_radius() {
    base_fails_at("\n[[shapes]]\ntype = \"disk\"\ncenter = [0, 0, 0]\nnormal = [0, 1, 0]\nradius = 0\nmaterial = \"white\"\n", "radius = |0", &["radius", "positive"]);
}

#[test]
fn zero_resolution() {
    base_fails_at("[film]\nwidth = 0\n", "width = |0", &["width", "1..=16384"]);
}

#[test]
fn negative_resolution() {
    base_fails_at("[film]\nheight = -4\n", "-4", &["height"]);
}

#[test]
fn resolution_too_large() {
    base_fails_at("[film]\nwidth = 20000\n", "20000", &["width", "16384"]);
}

#[test]
fn fov_out_of_range() {
    for fov in ["0", "180", "200", "-10"] {
        fails_at(
            &camera_with("fov", &format!("fov = {fov}")),
            &format!("fov = |{fov}\n"),
            &["fov", "(0, 180)"],
        );
    }
}

#[test]
fn spp_zero() {
    base_fails_at("[render]\nspp = 0\n", "spp = |0", &["spp"]);
}

#[test]
fn max_depth_zero() {
    base_fails_at(
        "[render]\nmax_depth = 0\n",
        "max_depth = |0",
        &["max_depth"],
    );
}

#[test]
fn max_depth_beyond_its_limit() {
    base_fails_at(
        "[render]\nmax_depth = 1025\n",
        "max_depth = |1025",
        &["max_depth", "1..=1024", "1025"],
    );
}

#[test]
fn unknown_key_in_film() {
    base_fails_at(
        "[film]\nwidth = 64\nwidht = 64\n",
        "widht",
        &["unknown key", "widht", "width"],
    );
}

#[test]
fn unknown_key_in_render() {
    base_fails_at(
        "[render]\nspp = 4\nsamples = 4\n",
        "samples",
        &["unknown key", "samples", "spp"],
    );
}

#[test]
fn unknown_key_in_sky() {
    base_fails_at(
        "[sky]\ncolour = 1\n",
        "colour",
        &["unknown key", "colour", "color"],
    );
}

#[test]
fn unknown_key_in_camera_close() {
    fails_at(
        &camera_with(
            "fov",
            "fov = 40\nshutter = [0, 1]\n[camera.close]\nlook = [0, 0, 1]",
        ),
        "look =",
        &["unknown key", "look", "look_at"],
    );
}

#[test]
fn negative_seed() {
    base_fails_at("[render]\nseed = -1\n", "-1", &["seed"]);
}

// --- Names -------------------------------------------------------------------------------------

#[test]
fn unknown_material_name_lists_known() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"whit\"\n",
        "\"whit\"",
        &["unknown material `whit`", "white"],
    );
}

#[test]
fn unknown_shape_type_lists_valid() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"cube\"\n",
        "\"cube\"",
        &["unknown shape type", "cube", "box", "sphere", "mesh"],
    );
}

#[test]
fn unknown_light_type_lists_valid() {
    base_fails_at(
        "\n[[lights]]\ntype = \"goniometric\"\n",
        "\"goniometric\"",
        &["goniometric", "point", "line", "distant", "spot"],
    );
}

#[test]
fn unknown_material_type_lists_valid() {
    base_fails_at(
        "[materials.m]\ntype = \"velvet\"\n",
        "\"velvet\"",
        &["velvet", "diffuse", "conductor", "dielectric", "plastic"],
    );
}

#[test]
fn unknown_filter_lists_valid() {
    base_fails_at(
        "[film]\nfilter = \"mitchell\"\n",
        "\"mitchell\"",
        &["mitchell", "box", "tent", "gaussian"],
    );
}

#[test]
fn unknown_sampler_lists_valid() {
    base_fails_at(
        "[render]\nsampler = \"halton\"\n",
        "\"halton\"",
        &["halton", "independent", "stratified", "sobol"],
    );
}

#[test]
fn unknown_strategy_lists_valid() {
    base_fails_at(
        "[render]\nstrategy = \"bdpt\"\n",
        "\"bdpt\"",
        &["bdpt", "uniform", "cosine", "bsdf", "light", "mis"],
    );
}

// --- Geometry ----------------------------------------------------------------------------------

#[test]
fn degenerate_rectangle() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"rectangle\"\ncorner = [0, 0, 0]\nedge_u = [1, 0, 0]\nedge_v = [2, 0, 0]\nmaterial = \"white\"\n",
        "[2, 0, 0]",
        &["degenerate", "parallel"],
    );
}

#[test]
fn rectangle_edges_not_perpendicular() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"rectangle\"\ncorner = [0, 0, 0]\nedge_u = [1, 0, 0]\nedge_v = [1, 1, 0]\nmaterial = \"white\"\n",
        "[1, 1, 0]",
        &["perpendicular", "quad"],
    );
}

#[test]
fn rectangle_sheared_by_scale() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"rectangle\"\ncorner = [0, 0, 0]\nedge_u = [1, 1, 0]\nedge_v = [-1, 1, 0]\nmaterial = \"white\"\ntransform = { scale = [1, 2, 1] }\n",
        "[1, 2, 1]",
        &["scale", "parallelogram"],
    );
}

#[test]
fn degenerate_triangle() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"triangle\"\nvertices = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]\nmaterial = \"white\"\n",
        "[[0, 0, 0]",
        &["degenerate"],
    );
}

#[test]
fn zero_disk_normal() {
    base_fails_at("\n[[shapes]]\ntype = \"disk\"\ncenter = [0, 0, 0]\nnormal = [0, 0, 0]\nradius = 1\nmaterial = \"white\"\n", "normal = |[0, 0, 0]", &["normal", "non-zero"]);
}

#[test]
fn zero_distant_direction() {
    base_fails_at(
        "\n[[lights]]\ntype = \"distant\"\ndirection = [0, 0, 0]\nirradiance = 1\n",
        "direction = |[0, 0, 0]",
        &["direction", "non-zero"],
    );
}

#[test]
fn zero_camera_up() {
    fails_at(
        &camera_with("fov", "fov = 40\nup = [0, 0, 0]"),
        "up = |[0, 0, 0]",
        &["up", "non-zero"],
    );
}

#[test]
fn up_parallel_to_view() {
    fails_at(
        &camera_with("fov", "fov = 40\nup = [0, 0, 2]"),
        "[0, 0, 2]",
        &["up", "parallel"],
    );
}

#[test]
fn eye_equals_look_at() {
    fails_at(
        &camera_with("look_at", "look_at = [0, 0, -5]"),
        "look_at = |[0, 0, -5]",
        &["look_at", "eye"],
    );
}

#[test]
fn box_min_not_below_max() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 0, 1]\nmaterial = \"white\"\n",
        "[1, 0, 1]",
        &["max", "min"],
    );
}

#[test]
fn line_light_without_length() {
    base_fails_at(
        "\n[[lights]]\ntype = \"line\"\nfrom = [0, 1, 0]\nto = [0, 1, 0]\nintensity = 1\n",
        "to = |[0, 1, 0]",
        &["from", "to"],
    );
}

// --- Materials and emitters --------------------------------------------------------------------

#[test]
fn albedo_above_one() {
    base_fails_at(
        "[materials.m]\ntype = \"diffuse\"\nalbedo = [0.5, 1.2, 0.5]\n",
        "[0.5, 1.2, 0.5]",
        &["albedo", "[0, 1]"],
    );
}

#[test]
fn reflectance_below_zero() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\nreflectance = -0.1\n",
        "-0.1",
        &["reflectance", "[0, 1]"],
    );
}

#[test]
fn tint_above_one() {
    base_fails_at(
        "[materials.m]\ntype = \"dielectric\"\ntint = 2\n",
        "tint = |2",
        &["tint", "[0, 1]"],
    );
}

#[test]
fn negative_emission() {
    base_fails_at(
        "[materials.m]\ntype = \"diffuse\"\nalbedo = 0\nemission = [1, -1, 1]\n",
        "[1, -1, 1]",
        &["emission", "negative"],
    );
}

#[test]
fn negative_intensity() {
    base_fails_at(
        "\n[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = -3\n",
        "-3",
        &["intensity", "negative"],
    );
}

#[test]
fn negative_irradiance() {
    base_fails_at(
        "\n[[lights]]\ntype = \"distant\"\ndirection = [0, 1, 0]\nirradiance = [1, 1, -2]\n",
        "[1, 1, -2]",
        &["irradiance", "negative"],
    );
}

#[test]
fn angular_diameter_too_large() {
    base_fails_at("\n[[lights]]\ntype = \"distant\"\ndirection = [0, 1, 0]\nirradiance = 1\nangular_diameter = 180\n", "180", &["angular_diameter"]);
}

#[test]
fn ior_not_positive() {
    base_fails_at(
        "[materials.m]\ntype = \"dielectric\"\nior = 0\n",
        "ior = |0",
        &["ior", "positive"],
    );
}

#[test]
fn negative_roughness() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\nreflectance = 1\nroughness = -0.2\n",
        "-0.2",
        &["roughness", "negative"],
    );
}

#[test]
fn conductor_with_reflectance_and_eta() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\nreflectance = 0.5\neta = 0.2\nk = 3\n",
        "reflectance = |0.5",
        &["either", "reflectance", "eta", "not both"],
    );
}

#[test]
fn conductor_eta_without_k() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\neta = [0.2, 0.4, 1.4]\n",
        "eta = |[0.2, 0.4, 1.4]",
        &["eta", "needs", "k"],
    );
}

#[test]
fn conductor_k_without_eta() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\nk = 3\n",
        "k = |3",
        &["k", "needs", "eta"],
    );
}

#[test]
fn conductor_without_fresnel() {
    base_fails_at(
        "[materials.metal]\ntype = \"conductor\"\nroughness = 0.1\n",
        "[materials.|metal]",
        &["conductor", "needs", "reflectance", "eta"],
    );
}

#[test]
fn conductor_tint_with_reflectance() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\nreflectance = 0.9\ntint = 0.5\n",
        "tint = |0.5",
        &["tint", "reflectance"],
    );
}

#[test]
fn conductor_eta_not_positive() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\neta = [0.2, 0, 1]\nk = 3\n",
        "[0.2, 0, 1]",
        &["eta", "positive"],
    );
}

#[test]
fn conductor_negative_k() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\neta = 0.2\nk = [3, -1, 2]\n",
        "[3, -1, 2]",
        &["k", "negative"],
    );
}

#[test]
fn anisotropic_roughness_negative() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\nreflectance = 1\nroughness = [0.1, -0.2]\n",
        "[0.1, -0.2]",
        &["roughness", "negative"],
    );
}

#[test]
fn anisotropic_roughness_of_three() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\nreflectance = 1\nroughness = [0.1, 0.2, 0.3]\n",
        "[0.1, 0.2, 0.3]",
        &["2 numbers"],
    );
}

#[test]
fn dielectric_negative_roughness() {
    base_fails_at(
        "[materials.m]\ntype = \"dielectric\"\nroughness = [0.2, -1]\n",
        "[0.2, -1]",
        &["roughness", "negative"],
    );
}

#[test]
fn unknown_masking() {
    base_fails_at(
        "[materials.m]\ntype = \"conductor\"\nreflectance = 1\nroughness = 0.2\nmasking = \"smith\"\n",
        "masking = |\"smith\"",
        &["masking", "smith", "correlated", "separable"],
    );
}

#[test]
fn unknown_masking_on_smooth_materials() {
    for material in ["dielectric", "plastic"] {
        base_fails_at(
            &format!("[materials.m]\ntype = \"{material}\"\nmasking = \"smith\"\n"),
            "masking = |\"smith\"",
            &["masking", "smith", "correlated", "separable"],
        );
    }
}

#[test]
fn plastic_anisotropic_roughness() {
    base_fails_at(
        "[materials.m]\ntype = \"plastic\"\nroughness = [0.1, 0.3]\n",
        "[0.1, 0.3]",
        &["plastic", "one", "isotropic"],
    );
}

#[test]
fn plastic_index_matched() {
    base_fails_at(
        "[materials.m]\ntype = \"plastic\"\nior = 1\n",
        "ior = |1",
        &["coating", "other than 1"],
    );
}

#[test]
fn plastic_diffuse_above_one() {
    base_fails_at(
        "[materials.m]\ntype = \"plastic\"\ndiffuse = [0.5, 1.2, 0.5]\n",
        "[0.5, 1.2, 0.5]",
        &["diffuse"],
    );
}

#[test]
fn diffuse_transmission_creating_energy() {
    base_fails_at(
        "[materials.m]\ntype = \"diffuse\"\nalbedo = [0.5, 0.6, 0.5]\ntransmittance = [0.5, 0.5, 0.5]\n",
        "transmittance = |[0.5, 0.5, 0.5]",
        &["sum", "green", "energy"],
    );
}

#[test]
fn diffuse_transmittance_above_one() {
    base_fails_at(
        "[materials.m]\ntype = \"diffuse\"\nalbedo = 0\ntransmittance = 1.5\n",
        "transmittance = |1.5",
        &["transmittance"],
    );
}

#[test]
fn thin_dielectric_with_roughness() {
    base_fails_at(
        "[materials.m]\ntype = \"dielectric\"\nthin = true\nroughness = 0.2\n",
        "roughness = |0.2",
        &["thin", "smooth", "roughness"],
    );
}

#[test]
fn mix_of_one_material() {
    base_fails_at(
        "[materials.m]\ntype = \"mix\"\nmaterials = [\"white\"]\n",
        "materials = |[\"white\"]",
        &["two materials"],
    );
}

#[test]
fn mix_of_an_unknown_material() {
    base_fails_at(
        "[materials.m]\ntype = \"mix\"\nmaterials = [\"white\", \"whit\"]\n",
        "\"whit\"",
        &["unknown material", "whit", "white"],
    );
}

#[test]
fn mix_amount_outside_zero_one() {
    base_fails_at(
        "[materials.m]\ntype = \"mix\"\nmaterials = [\"white\", \"white\"]\namount = 1.5\n",
        "amount = |1.5",
        &["amount", "[0, 1]"],
    );
}

#[test]
fn mix_that_names_itself() {
    base_fails_at(
        "[materials.m]\ntype = \"mix\"\nmaterials = [\"white\", \"n\"]\n\
         [materials.n]\ntype = \"mix\"\nmaterials = [\"m\", \"white\"]\n",
        "materials = |[\"white\", \"n\"]",
        &["mix", "more than 8", "itself"],
    );
}

#[test]
fn coated_over_a_dielectric() {
    base_fails_at(
        "[materials.glass]\ntype = \"dielectric\"\n[materials.m]\ntype = \"coated\"\n\
         base = \"glass\"\n",
        "base = |\"glass\"",
        &["diffuse or conductor", "glass"],
    );
}

#[test]
fn coated_with_g_outside_minus_one_one() {
    base_fails_at(
        "[materials.m]\ntype = \"coated\"\nbase = \"white\"\ng = 1\n",
        "g = |1",
        &["g", "(−1, 1)"],
    );
}

#[test]
fn coated_with_too_long_walks() {
    base_fails_at(
        "[materials.m]\ntype = \"coated\"\nbase = \"white\"\nmax_depth = 1000\n",
        "max_depth = |1000",
        &["max_depth", "1..=100"],
    );
}

#[test]
fn coated_with_zero_thickness() {
    base_fails_at(
        "[materials.m]\ntype = \"coated\"\nbase = \"white\"\nthickness = 0\n",
        "thickness = |0",
        &["thickness"],
    );
}

#[test]
fn two_sided_shape_that_emits_nothing() {
    base_fails_at(
        "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"white\"\n\
         two_sided = true\n",
        "two_sided = |true",
        &["two_sided", "emits nothing"],
    );
}

#[test]
fn plastic_unknown_key() {
    base_fails_at(
        "[materials.m]\ntype = \"plastic\"\nreflectance = 0.5\n",
        "reflectance",
        &["reflectance"],
    );
}

#[test]
fn sky_map_with_color() {
    base_fails_at(
        "[sky]\nmap = \"studio.exr\"\ncolor = 1\n",
        "color = |1",
        &["color", "map", "exclude"],
    );
}

#[test]
fn sky_map_missing() {
    base_fails_at(
        "[sky]\nmap = \"missing.exr\"\n",
        "map = |\"missing.exr\"",
        &["environment map", "missing.exr"],
    );
}

#[test]
fn sky_map_not_hdr() {
    base_fails_at(
        "[sky]\nmap = \"photo.png\"\n",
        "map = |\"photo.png\"",
        &["HDR", ".exr", ".hdr", ".pfm", "png"],
    );
}

#[test]
fn sky_scale_without_map() {
    base_fails_at(
        "[sky]\ncolor = 1\nscale = 2\n",
        "scale = |2",
        &["scale", "map"],
    );
}

#[test]
fn sky_with_color_and_gradient() {
    base_fails_at(
        "[sky]\ncolor = 1\ntop = 1\nbottom = 0\n",
        "color = |1",
        &["color", "top"],
    );
}

// --- Camera and motion -------------------------------------------------------------------------

#[test]
fn shutter_close_before_open() {
    fails_at(
        &camera_with("fov", "fov = 40\nshutter = [1, 0.5]"),
        "[1, 0.5]",
        &["shutter", "before"],
    );
}

#[test]
fn negative_aperture() {
    fails_at(
        &camera_with("fov", "fov = 40\naperture = -0.1"),
        "-0.1",
        &["aperture"],
    );
}

#[test]
fn camera_motion_with_closed_shutter() {
    fails_at(
        &camera_with("fov", "fov = 40\n[camera.close]\neye = [1, 0, -5]"),
        "[camera.close]",
        &["shutter"],
    );
}

#[test]
fn object_motion_with_closed_shutter() {
    base_fails_at(
        &sphere("transform_close = { translate = [1, 0, 0] }\n"),
        "{ translate = [1, 0, 0] }",
        &["transform_close", "shutter"],
    );
}

#[test]
fn non_uniform_scale_on_sphere() {
    base_fails_at(
        &sphere("transform = { scale = [1, 2, 1] }\n"),
        "[1, 2, 1]",
        &["sphere", "uniform"],
    );
}

#[test]
fn non_uniform_scale_on_disk() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"disk\"\ncenter = [0, 0, 0]\nnormal = [0, 1, 0]\nradius = 1\nmaterial = \"white\"\ntransform = { scale = [2, 1, 1] }\n",
        "[2, 1, 1]",
        &["disk", "uniform"],
    );
}

#[test]
fn non_uniform_scale_at_close_on_moving_sphere() {
    let text = camera_with("fov", "fov = 40\nshutter = [0, 1]")
        + &sphere("transform_close = { scale = [1, 1, 3] }\n");
    fails_at(&text, "[1, 1, 3]", &["sphere", "uniform"]);
}

#[test]
fn zero_scale() {
    base_fails_at(
        &sphere("transform = { scale = 0 }\n"),
        "scale = |0 }",
        &["scale", "positive"],
    );
}

// --- Files -------------------------------------------------------------------------------------

#[test]
fn missing_scene_file() {
    let e = load(Path::new("/nonexistent/scene.toml"))
        .err()
        .expect("no such file");
    assert_eq!(e.location.file, Path::new("/nonexistent/scene.toml"));
    assert!(e.reason.contains("cannot read"), "{e}");
}

#[test]
fn missing_mesh_file() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"mesh\"\nfile = \"meshes/nope.obj\"\nmaterial = \"white\"\n",
        "\"meshes/nope.obj\"",
        &["nope.obj", "cannot read"],
    );
}

/// A scene file and its meshes in a temporary directory.
fn scene_dir(
    files: &[(&str, &str)],
    shape: &str,
) -> (tempfile::TempDir, std::path::PathBuf, String) {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let text = format!("{BASE}\n[[shapes]]\ntype = \"mesh\"\n{shape}\n");
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, &text).unwrap();
    (dir, path, text)
}

/// Load the scene at `path`, which must fail at `needle` of `text`, naming every word of `reason`.
fn file_fails_at(path: &Path, text: &str, needle: &str, reason: &[&str]) {
    let e = load(path).err().expect("loaded a malformed scene");
    assert_eq!(e.location.file, path, "{e}");
    assert_eq!(e.location.line, Some(position(text, needle).0), "{e}");
    for word in reason {
        assert!(e.reason.contains(word), "reason lacks `{word}`: {e}");
    }
}

#[test]
fn malformed_obj() {
    let obj = "v 0 0 0\nv 1 0 x\nv 0 1 0\nf 1 2 3\n";
    let (_dir, path, text) = scene_dir(
        &[("bad.obj", obj)],
        "file = \"bad.obj\"\nmaterial = \"white\"",
    );
    file_fails_at(
        &path,
        &text,
        "\"bad.obj\"",
        &["bad.obj", "position parse error"],
    );
}

#[test]
fn obj_face_out_of_range() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
    let (_dir, path, text) = scene_dir(
        &[("bad.obj", obj)],
        "file = \"bad.obj\"\nmaterial = \"white\"",
    );
    file_fails_at(&path, &text, "\"bad.obj\"", &["bad.obj"]);
}

#[test]
fn obj_face_with_index_zero() {
    // OBJ indices start at 1; 0 refers to no vertex.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n";
    let (_dir, path, text) = scene_dir(
        &[("zero.obj", obj)],
        "file = \"zero.obj\"\nmaterial = \"white\"",
    );
    file_fails_at(&path, &text, "\"zero.obj\"", &["zero.obj", "malformed OBJ"]);
}

#[test]
fn obj_faces_with_fewer_than_three_vertices() {
    for face in ["f 1 2", "f 1"] {
        let obj = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\n{face}\n");
        let (_dir, path, text) = scene_dir(
            &[("short.obj", &obj)],
            "file = \"short.obj\"\nmaterial = \"white\"",
        );
        file_fails_at(&path, &text, "\"short.obj\"", &["short.obj"]);
    }
}

#[test]
fn obj_with_nan_vertex() {
    let obj = "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n";
    let (_dir, path, text) = scene_dir(
        &[("nan.obj", obj)],
        "file = \"nan.obj\"\nmaterial = \"white\"",
    );
    file_fails_at(&path, &text, "\"nan.obj\"", &["nan.obj", "not finite"]);
}

#[test]
fn obj_without_triangles() {
    let (_dir, path, text) = scene_dir(
        &[("empty.obj", "# nothing\n")],
        "file = \"empty.obj\"\nmaterial = \"white\"",
    );
    file_fails_at(
        &path,
        &text,
        "\"empty.obj\"",
        &["empty.obj", "no triangles"],
    );
}

#[test]
fn obj_missing_mtl() {
    let obj = "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    let (_dir, path, text) = scene_dir(&[("m.obj", obj)], "file = \"m.obj\"");
    file_fails_at(&path, &text, "\"m.obj\"", &["m.obj", "gone.mtl"]);
}

#[test]
fn obj_without_material() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let (_dir, path, text) = scene_dir(&[("m.obj", obj)], "file = \"m.obj\"");
    file_fails_at(&path, &text, "\"m.obj\"", &["m.obj", "no material"]);
}

#[test]
fn mtl_with_energy_gain() {
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl hot\nf 1 2 3\n";
    let mtl = "newmtl hot\nKd 1.5 0.5 0.5\n";
    let (_dir, path, text) = scene_dir(&[("m.obj", obj), ("m.mtl", mtl)], "file = \"m.obj\"");
    file_fails_at(&path, &text, "\"m.obj\"", &["m.obj", "hot", "Kd"]);
}

#[test]
fn transform_overflowing_f32() {
    base_fails_at(
        "\n[[shapes]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [3e38, 1, 1]\nmaterial = \"white\"\ntransform = { scale = 10 }\n",
        "[[shapes]]",
        &["overflow"],
    );
}

#[test]
fn mtl_color_with_two_numbers() {
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    let mtl = "newmtl a\nKd 0.5 0.5\n";
    let (_dir, path, text) = scene_dir(&[("m.obj", obj), ("m.mtl", mtl)], "file = \"m.obj\"");
    file_fails_at(&path, &text, "\"m.obj\"", &["m.mtl", "line 2", "Kd"]);
}

/// The MTL format allows a grey colour as one number (tobj alone would panic on it).
#[test]
fn mtl_color_with_one_number_is_grey() {
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    let (_dir, path, _) = scene_dir(
        &[("m.obj", obj), ("m.mtl", "newmtl a\nKd 0.25\n")],
        "file = \"m.obj\"",
    );
    let scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.materials.last().unwrap().color, [0.25; 3]);
}
