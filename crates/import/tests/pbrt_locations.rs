//! A pbrt-v4 scene is validated as the description it becomes, and every error found there names
//! the pbrt file, line and column the offending value was written at (an included file's own
//! lines for what it holds), never a text strata generated in between.

use std::path::Path;
use stratapt_import::scene_file::load;
use stratapt_scene::records::{material_flag, texture_flag};
use stratapt_scene::texture;

const HEAD: &str =
    "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\nWorldBegin\n";

/// The error of loading `text` written as `dir/name`.
fn error(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    match load(&path) {
        Ok(_) => panic!("loaded without error:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// A 2 × 1 white PNG at `dir/name`.
fn white_png(dir: &Path, name: &str) {
    image::RgbImage::from_pixel(2, 1, image::Rgb([255, 255, 255]))
        .save(dir.join(name))
        .unwrap();
}

/// Line and column (1-based) of the first `needle` in `text`.
fn line_col(text: &str, needle: &str) -> (usize, usize) {
    let at = text
        .find(needle)
        .unwrap_or_else(|| panic!("`{needle}` not in the text"));
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

/// pbrt-v4-scenes' crown: a `scale` texture of 1.5 over an image, read as a diffuse
/// reflectance, which pbrt-v4 clamps to [0, 1] at every lookup. The scene loads, the texture
/// clamps its lookups, and the warning names the parameter that reads it.
#[test]
fn a_scaled_image_above_one_as_a_reflectance_is_clamped_with_a_warning_at_the_parameter() {
    let dir = tempfile::tempdir().unwrap();
    white_png(dir.path(), "white.png");
    let text = format!(
        "{HEAD}Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"white.png\"\n\
         Texture \"bright\" \"spectrum\" \"scale\" \"texture tex\" \"img\" \"float scale\" 1.5\n\
         # a comment, so that the material is not on the texture's line\n\
         MakeNamedMaterial \"paint\" \"string type\" \"diffuse\"\n\
         \x20 \"texture reflectance\" \"bright\"\n\
         NamedMaterial \"paint\"\n\
         Shape \"sphere\"\n"
    );
    let path = dir.path().join("crown.pbrt");
    std::fs::write(&path, &text).unwrap();
    let scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let (line, column) = line_col(&text, "\"texture reflectance\"");
    let warnings = &scene.import.as_ref().unwrap().warnings;
    let clamped: Vec<_> = warnings
        .iter()
        .filter(|w| w.message.contains("clamped"))
        .collect();
    assert_eq!(clamped.len(), 1, "{warnings:?}");
    assert!(
        clamped[0]
            .at
            .ends_with(&format!("crown.pbrt:{line}:{column}")),
        "expected crown.pbrt:{line}:{column}: {clamped:?}"
    );
    assert!(
        clamped[0]
            .message
            .contains("`bright` may exceed 1 (scaled by 1.5)"),
        "{clamped:?}"
    );
    // The material's albedo texture clamps: the white texel scaled to 1.5 reads 1.
    let m = scene
        .material_names
        .iter()
        .position(|n| n == "paint")
        .unwrap();
    let material = scene.materials[m];
    assert!(material.has(material_flag::COLOR_TEXTURE));
    let index = material.color[0] as u32;
    assert_ne!(
        texture::record(&scene.tables, index).tag & texture_flag::CLAMP,
        0
    );
    assert_eq!(texture::eval(&scene.tables, index, [0.25, 0.5]), [1.0; 3]);
}

#[test]
fn a_broken_image_names_its_filename_parameter() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("broken.png"), b"not a png").unwrap();
    let text = format!(
        "{HEAD}Texture \"t\" \"spectrum\" \"imagemap\"\n  \"string filename\" \"broken.png\"\n\
         Material \"diffuse\" \"texture reflectance\" \"t\"\nShape \"sphere\"\n"
    );
    let e = error(dir.path(), "s.pbrt", &text);
    let (line, column) = line_col(&text, "\"string filename\"");
    assert!(
        e.starts_with(&format!(
            "{}:{line}:{column}: ",
            dir.path().join("s.pbrt").display()
        )),
        "{e}"
    );
    assert!(e.contains("broken.png"), "{e}");
}

#[test]
fn an_error_in_an_included_file_names_that_files_line() {
    let dir = tempfile::tempdir().unwrap();
    // The included file's third line holds a conductor's η, a texture that reaches 0.
    white_png(dir.path(), "white.png");
    let included = "# materials\n\
        Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"white.png\" \"float scale\" 0\n\
        MakeNamedMaterial \"m\" \"string type\" \"conductor\" \"texture eta\" \"img\" \"rgb k\" [1 1 1]\n";
    std::fs::write(dir.path().join("materials.pbrt"), included).unwrap();
    let text = format!("{HEAD}Include \"materials.pbrt\"\nNamedMaterial \"m\"\nShape \"sphere\"\n");
    let e = error(dir.path(), "main.pbrt", &text);
    let (line, column) = line_col(included, "\"texture eta\"");
    assert!(
        e.contains(&format!("materials.pbrt:{line}:{column}: ")),
        "{e}"
    );
    assert!(e.contains("reaches 0"), "{e}");
}

#[test]
fn warnings_and_errors_of_one_file_share_its_lines() {
    // A light's emission image is ignored with a warning at the light; the scene loads, and its
    // warning names the pbrt line, as the errors above do.
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "{HEAD}AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"string filename\" \"glow.exr\"\n\
         \x20 Shape \"sphere\"\nAttributeEnd\n"
    );
    let path = dir.path().join("w.pbrt");
    std::fs::write(&path, &text).unwrap();
    let scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let warnings = &scene.import.as_ref().unwrap().warnings;
    let (line, _) = line_col(&text, "AreaLightSource");
    assert!(
        warnings
            .iter()
            .any(|w| w.at.contains(&format!("w.pbrt:{line}:"))),
        "{warnings:?}"
    );
}
