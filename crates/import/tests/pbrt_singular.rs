//! Singular transforms as pbrt-v4 takes them (its `Transform` keeps a NaN inverse): what they
//! flatten to nothing is dropped, what keeps an area is drawn flattened and shaded by its faces'
//! normals (pbrt-v4's vertex normals turn NaN, and it falls back to the face's), both told in one
//! warning at the directive that made the transform singular; nothing reaches the records as a
//! NaN, and a camera or light that the flattening leaves without a direction is a clear error.

use std::path::Path;
use stratapt_import::scene_file::load;
use stratapt_scene::{FlatScene, Prim};

const HEAD: &str =
    "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\nWorldBegin\n";

/// A triangle in the plane `z = 0` (a normal along −z at each corner when `normals`).
fn xy_triangle(normals: bool) -> String {
    let n = match normals {
        true => " \"normal N\" [0 0 -1  0 0 -1  0 0 -1]",
        false => "",
    };
    format!(
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \
         \"integer indices\" [0 1 2]{n}\n"
    )
}

/// A triangle in the plane `x = 0`, with normals along −x.
const YZ_TRIANGLE: &str = "Shape \"trianglemesh\" \"point3 P\" [0 0 0  0 1 0  0 0 1] \
     \"integer indices\" [0 1 2] \"normal N\" [-1 0 0  -1 0 0  -1 0 0]\n";

/// `text` written as `dir/s.pbrt` and loaded: the scene, or the error's text.
fn load_text(dir: &Path, text: &str) -> Result<FlatScene, String> {
    let path = dir.join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    load(&path).map_err(|e| e.to_string())
}

/// The scene's warnings as `at: message`.
fn warnings(scene: &FlatScene) -> Vec<String> {
    let report = scene.import.as_ref().expect("a pbrt import");
    report
        .warnings
        .iter()
        .map(|w| format!("{}: {}", w.at, w.message))
        .collect()
}

/// `s.pbrt:LINE:COLUMN:` of the first `needle` in `text`.
fn at(text: &str, needle: &str) -> String {
    let i = text.find(needle).expect("in the text");
    let line = text[..i].matches('\n').count() + 1;
    let column = i - text[..i].rfind('\n').map_or(0, |k| k + 1) + 1;
    format!("s.pbrt:{line}:{column}:")
}

/// Every number of every primitive (corners and normals) finite.
fn finite(prims: &[Prim]) -> bool {
    prims.iter().all(|p| {
        let normals = p.normals.iter().flatten().flatten();
        p.a.iter()
            .chain(&p.b)
            .chain(&p.c)
            .chain(normals)
            .all(|x| x.is_finite())
    })
}

/// One shape under a `ConcatTransform` with a zero column and one plain shape: the scene
/// loads, holds the plain shape alone, and warns once, at the `ConcatTransform`, that one shape
/// has no area left.
#[test]
fn a_shape_flattened_to_nothing_is_dropped_with_one_warning_at_its_transform() {
    let dir = tempfile::tempdir().unwrap();
    let flat = "ConcatTransform [0 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1]";
    let text = format!(
        "{HEAD}AttributeBegin\n  {flat}\n  {}AttributeEnd\n{}",
        xy_triangle(true),
        xy_triangle(false)
    );
    let scene = load_text(dir.path(), &text).unwrap_or_else(|e| panic!("{e}"));
    let prims: Vec<Prim> = scene.geometry.iter().collect();
    assert_eq!(prims.len(), 1, "the plain triangle only");
    assert!(finite(&prims));
    let w = warnings(&scene);
    let singular: Vec<&String> = w.iter().filter(|w| w.contains("singular")).collect();
    assert_eq!(singular.len(), 1, "{w:?}");
    assert!(singular[0].contains(&at(&text, flat)), "{w:?}");
    assert!(
        singular[0].contains("ConcatTransform makes the transform singular")
            && singular[0].contains("1 shape under it left without area, not drawn"),
        "{w:?}"
    );
    // No warning of its own for the dropped shape.
    assert!(
        !w.iter().any(|w| w.contains("not drawn: every triangle")),
        "{w:?}"
    );
}

/// Under `Scale 0 1 1`: shapes with no area left are dropped, and so are a sphere and a disk
/// (pbrt-v4 intersects them through the transform's inverse, which does not exist), one mesh that
/// keeps an area is drawn flattened without its vertex normals (their transform does not exist),
/// all in one warning at the `Scale`; an instance placed by a singular transform counts at that transform; an
/// invertible transform after `AttributeEnd` draws as ever.
#[test]
fn shapes_keeping_an_area_are_drawn_flat_and_counted_in_the_same_warning() {
    let dir = tempfile::tempdir().unwrap();
    let flat = "ConcatTransform [1 0 0 0  0 1 0 0  0 0 0 0  0 0 0 1]";
    let text = format!(
        "{HEAD}ObjectBegin \"wall\"\n{YZ_TRIANGLE}{}ObjectEnd\n\
         AttributeBegin\n  Scale 0 1 1\n  {}  {YZ_TRIANGLE}  {}  Shape \"sphere\"\n  \
         Shape \"disk\"\nAttributeEnd\n\
         AttributeBegin\n  {flat}\n  ObjectInstance \"wall\"\nAttributeEnd\n\
         Translate 0 0 1\n{YZ_TRIANGLE}",
        xy_triangle(false),
        xy_triangle(true),
        xy_triangle(false),
    );
    let scene = load_text(dir.path(), &text).unwrap_or_else(|e| panic!("{e}"));
    let prims: Vec<Prim> = scene.geometry.iter().collect();
    assert!(finite(&prims));
    // Drawn: the yz triangle under the Scale (x = 0 already), the instance's xy triangle (z = 0
    // already; its yz one keeps only a line) and the plain one at the end, its normals kept.
    assert_eq!(prims.len(), 3, "{prims:?}");
    assert_eq!(prims.iter().filter(|p| p.normals.is_some()).count(), 1);
    let w = warnings(&scene);
    let singular: Vec<&String> = w.iter().filter(|w| w.contains("singular")).collect();
    assert_eq!(singular.len(), 2, "{w:?}");
    assert!(singular[0].contains(&at(&text, "Scale 0 1 1")), "{w:?}");
    assert!(
        singular[0].contains("4 shapes under it left without area")
            && singular[0].contains("1 shape under it drawn flattened, without vertex normals"),
        "{w:?}"
    );
    assert!(singular[1].contains(&at(&text, flat)), "{w:?}");
    assert!(
        singular[1].contains("1 shape under it left without area")
            && singular[1].contains("1 shape under it drawn flattened"),
        "{w:?}"
    );
}

/// A singular camera transform is an error at the camera; a point light under a singular
/// transform is placed, and a spot or distant light it leaves without a direction is an error
/// that says so.
#[test]
fn cameras_and_lights_under_singular_transforms_are_placed_or_refused_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let text = "Scale 0 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n";
    let e = load_text(dir.path(), text).err().expect("loaded");
    assert!(
        e.contains(&at(text, "Camera")) && e.contains("singular"),
        "{e}"
    );

    let point = format!(
        "{HEAD}AttributeBegin\nScale 0 1 1\nLightSource \"point\" \"point3 from\" [1 2 3]\n\
         AttributeEnd\n{}",
        xy_triangle(false)
    );
    let scene = load_text(dir.path(), &point).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.lights.len(), 1);

    for light in [
        "LightSource \"spot\" \"point3 from\" [1 0 0] \"point3 to\" [2 0 0]",
        "LightSource \"distant\" \"point3 from\" [1 0 0] \"point3 to\" [2 0 0]",
    ] {
        let text = format!("{HEAD}Scale 0 1 1\n{light}\n");
        let e = load_text(dir.path(), &text).err().expect("loaded");
        assert!(e.contains(&at(&text, "LightSource")), "{e}");
        assert!(
            e.contains("no direction")
                && e.contains("singular since /")
                && e.contains(&format!("{},", at(&text, "Scale").trim_end_matches(':'))),
            "{e}"
        );
    }
}
