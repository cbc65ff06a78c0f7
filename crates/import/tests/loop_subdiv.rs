//! `Shape "loopsubdiv"` through the pbrt-v4 loader: subdivided `levels` times (3 when not
//! given) without a warning, each triangle into 4 per level; a negative or too large `levels`
//! an error at the parameter; a control mesh pbrt-v4 cannot subdivide drawn as it is, with
//! one warning naming the vertices at fault.

use std::path::Path;
use stratapt_import::scene_file::load;
use stratapt_scene::FlatScene;

/// A camera, and a filter strata draws as pbrt does (no warning of its own).
const HEAD: &str = "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
     PixelFilter \"triangle\"\nWorldBegin\n";

/// An octahedron's 8 triangles (wound outward) as a `loopsubdiv` with parameters `extra`.
fn octahedron(extra: &str) -> String {
    format!(
        "Shape \"loopsubdiv\" {extra} \"point3 P\" [1 0 0  -1 0 0  0 1 0  0 -1 0  0 0 1  0 0 -1] \
         \"integer indices\" [0 2 4  2 1 4  1 3 4  3 0 4  2 0 5  1 2 5  3 1 5  0 3 5]\n"
    )
}

/// `text` written as `dir/s.pbrt` and loaded: the scene, or the error's text.
fn load_text(dir: &Path, text: &str) -> Result<FlatScene, String> {
    let path = dir.join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    load(&path).map_err(|e| e.to_string())
}

/// The triangles the import wrote, and its warnings as `at: message`.
fn triangles_and_warnings(scene: &FlatScene) -> (usize, Vec<String>) {
    let report = scene.import.as_ref().expect("a pbrt import");
    let warnings = report
        .warnings
        .iter()
        .map(|w| format!("{}: {}", w.at, w.message))
        .collect();
    (report.triangles, warnings)
}

/// `s.pbrt:LINE:COLUMN:` of the first `needle` in `text`.
fn at(text: &str, needle: &str) -> String {
    let i = text.find(needle).expect("in the text");
    let line = text[..i].matches('\n').count() + 1;
    let column = i - text[..i].rfind('\n').map_or(0, |k| k + 1) + 1;
    format!("s.pbrt:{line}:{column}:")
}

#[test]
fn a_loopsubdiv_shape_is_subdivided_without_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    for (levels, triangles) in [("\"integer levels\" 2", 8 * 16), ("", 8 * 64)] {
        let text = format!("{HEAD}{}", octahedron(levels));
        let scene = load_text(dir.path(), &text).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            triangles_and_warnings(&scene),
            (triangles, vec![]),
            "{levels}"
        );
    }
}

#[test]
fn level_zero_draws_the_control_triangles_without_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("{HEAD}{}", octahedron("\"integer levels\" 0"));
    let scene = load_text(dir.path(), &text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(triangles_and_warnings(&scene), (8, vec![]));
}

#[test]
fn a_negative_level_is_an_error_at_the_parameter() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("{HEAD}{}", octahedron("\"integer levels\" -1"));
    let e = load_text(dir.path(), &text).err().expect("an error");
    assert!(
        e.contains(&at(&text, "\"integer levels\"")) && e.contains("levels -1"),
        "{e}"
    );
}

#[test]
fn levels_past_strata_s_triangle_limit_are_an_error_at_the_parameter() {
    let dir = tempfile::tempdir().unwrap();
    for levels in [13, 40] {
        let text = format!(
            "{HEAD}{}",
            octahedron(&format!("\"integer levels\" {levels}"))
        );
        let e = load_text(dir.path(), &text).err().expect("an error");
        assert!(
            e.contains(&at(&text, "\"integer levels\""))
                && e.contains(&format!("levels {levels}"))
                && e.contains("at most 268435456"),
            "{e}"
        );
    }
}

#[test]
fn a_control_mesh_pbrt_cannot_subdivide_is_drawn_as_it_is_with_one_warning() {
    let dir = tempfile::tempdir().unwrap();
    // Three triangles on the edge from vertex 0 to vertex 1.
    let fin = "Shape \"loopsubdiv\" \"integer levels\" 2 \
               \"point3 P\" [0 0 0  1 0 0  0 1 0  0 -1 0  0 0 1] \
               \"integer indices\" [0 1 2  1 0 3  0 1 4]\n";
    let text = format!("{HEAD}{fin}");
    let scene = load_text(dir.path(), &text).unwrap_or_else(|e| panic!("{e}"));
    let (triangles, warnings) = triangles_and_warnings(&scene);
    assert_eq!((triangles, warnings.len()), (3, 1), "{warnings:?}");
    let w = &warnings[0];
    assert!(
        w.contains(&at(&text, "Shape"))
            && w.contains("control mesh")
            && w.contains("between vertices 0 and 1")
            && w.contains("more than two triangles"),
        "{w}"
    );
}
