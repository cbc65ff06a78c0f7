//! A pbrt-v4 scene is validated as the description it becomes, and every error found there names
//! the pbrt file, line and column the offending value was written at (an included file's own
//! lines for what it holds), never a text strata generated in between.

use std::path::Path;
use stratapt_import::scene_file::load;

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

#[test]
fn a_scaled_image_above_one_as_a_reflectance_names_the_parameter_that_uses_it() {
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
    let e = error(dir.path(), "crown.pbrt", &text);
    let (line, column) = line_col(&text, "\"texture reflectance\"");
    assert!(
        e.contains(&format!("crown.pbrt:{line}:{column}: ")),
        "expected crown.pbrt:{line}:{column}: {e}"
    );
    assert!(e.contains("reaches 1.5"), "{e}");
    assert!(!e.contains("TOML"), "{e}");
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
    // The included file's third line holds a reflectance texture that reaches 2.
    white_png(dir.path(), "white.png");
    let included = "# materials\n\
        Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"white.png\" \"float scale\" 2\n\
        MakeNamedMaterial \"m\" \"string type\" \"diffuse\" \"texture reflectance\" \"img\"\n";
    std::fs::write(dir.path().join("materials.pbrt"), included).unwrap();
    let text = format!("{HEAD}Include \"materials.pbrt\"\nNamedMaterial \"m\"\nShape \"sphere\"\n");
    let e = error(dir.path(), "main.pbrt", &text);
    let (line, column) = line_col(included, "\"texture reflectance\"");
    assert!(
        e.contains(&format!("materials.pbrt:{line}:{column}: ")),
        "{e}"
    );
    assert!(e.contains("reaches 2"), "{e}");
}

#[test]
fn warnings_and_errors_of_one_file_share_its_lines() {
    // A light's emission image is ignored with a warning at the light; the scene loads, and its
    // warning names the pbrt line, as the errors above do.
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "{HEAD}AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool twosided\" true\n\
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
