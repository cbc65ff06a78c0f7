//! Textures in scene files: images of every format read as the texels they hold (8-bit sRGB
//! decoded, `raw` linear, 16-bit and float linear), texture coordinates from the shapes and
//! meshes that carry them (an OBJ's `v` flipped, a PLY's taken as they are), none where no
//! material reads a texture, and every mistake refused with its line and reason.

use std::path::{Path, PathBuf};
use stratapt_import::load::load_str;
use stratapt_import::scene_file::load;
use stratapt_scene::records::{material_flag, surface_flag, texel_format, texture_flag};
use stratapt_scene::texture::{self, record, srgb_to_linear};
use stratapt_scene::{Effects, FlatScene, RenderSettings};

const CAMERA: &str = "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n\n";

/// Load `text` from `dir/s.toml`.
fn scene(dir: &Path, text: &str) -> FlatScene {
    let path = dir.join("s.toml");
    std::fs::write(&path, format!("{CAMERA}{text}")).unwrap();
    load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The error of loading `text` from `dir/s.toml` (with the camera above it): its message.
fn error(dir: &Path, text: &str) -> String {
    let path = dir.join("s.toml");
    std::fs::write(&path, format!("{CAMERA}{text}")).unwrap();
    match load(&path) {
        Ok(_) => panic!("loaded without error:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// A 2 × 1 RGB PNG of `texels` at `dir/name`, 8 or 16 bits.
fn png(dir: &Path, name: &str, texels: [[u16; 3]; 2], sixteen: bool) -> PathBuf {
    let path = dir.join(name);
    if sixteen {
        let raw: Vec<u16> = texels.iter().flatten().copied().collect();
        image::ImageBuffer::<image::Rgb<u16>, _>::from_raw(2, 1, raw)
            .unwrap()
            .save(&path)
            .unwrap();
    } else {
        let raw: Vec<u8> = texels.iter().flatten().map(|&x| x as u8).collect();
        image::RgbImage::from_raw(2, 1, raw)
            .unwrap()
            .save(&path)
            .unwrap();
    }
    path
}

/// A diffuse material `m` reading texture `t`, on a rectangle.
const TEXTURED_RECTANGLE: &str = r#"
[materials.m]
type = "diffuse"
albedo = "t"

[[shapes]]
type = "rectangle"
corner = [-1, -1, 0]
edge_u = [2, 0, 0]
edge_v = [0, 2, 0]
material = "m"
"#;

/// Texture 0's value at the centre of texel column `i` of a 2 × 1 image.
fn texel(scene: &FlatScene, i: usize) -> [f32; 3] {
    texture::eval(&scene.tables, 0, [0.25 + 0.5 * i as f32, 0.5])
}

#[test]
fn every_image_format_reads_its_texels() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let bytes = [[0, 128, 255], [51, 10, 200]];
    png(d, "eight.png", bytes, false);
    let with = |file: &str, extra: &str| {
        scene(
            d,
            &format!("[textures.t]\ntype = \"image\"\nfile = \"{file}\"\nwrap = \"clamp\"\n{extra}\n{TEXTURED_RECTANGLE}"),
        )
    };
    // 8-bit: sRGB decoded per texel; `raw`: x / 255.
    let s = with("eight.png", "");
    assert_eq!(record(&s.tables, 0).tag >> 8 & 0xff, texel_format::SRGB8);
    let decode = |b: u16| srgb_to_linear(b as f64 / 255.0) as f32;
    assert_eq!(texel(&s, 0), [0.0, decode(128), 1.0]);
    assert_eq!(texel(&s, 1), [decode(51), decode(10), decode(200)]);
    // TGA: the same bytes; JPEG (lossy): 8-bit sRGB too.
    let rgb = image::RgbImage::from_raw(2, 1, vec![0, 128, 255, 51, 10, 200]).unwrap();
    rgb.save(d.join("eight.tga")).unwrap();
    assert_eq!(texel(&with("eight.tga", ""), 1), texel(&s, 1));
    image::RgbImage::from_pixel(8, 8, image::Rgb([200, 100, 50]))
        .save(d.join("flat.jpg"))
        .unwrap();
    let jpeg = with("flat.jpg", "");
    assert_eq!(record(&jpeg.tables, 0).tag >> 8 & 0xff, texel_format::SRGB8);
    let expected = [200.0, 100.0, 50.0].map(|b: f64| srgb_to_linear(b / 255.0) as f32);
    for (a, b) in texel(&jpeg, 0).iter().zip(expected) {
        assert!((a - b).abs() < 0.02, "{a} vs {b}");
    }
    let raw = with("eight.png", "raw = true");
    assert_eq!(
        texel(&raw, 1),
        [0.2, 10.0 / 255.0, 200.0 / 255.0].map(|x| x as f32)
    );
    // 16-bit: decoded to linear floats at load.
    png(d, "sixteen.png", [[0, 32768, 65535], [13107, 0, 0]], true);
    let s16 = with("sixteen.png", "");
    assert_eq!(record(&s16.tables, 0).tag >> 8 & 0xff, texel_format::RGB32F);
    let mid = srgb_to_linear(32768.0 / 65535.0) as f32;
    assert!(
        (texel(&s16, 0)[1] - mid).abs() < 1e-6,
        "{:?}",
        texel(&s16, 0)
    );
    assert!((texel(&s16, 1)[0] - srgb_to_linear(0.2) as f32).abs() < 1e-6);
    // Floats: as they are; a grey map keeps one channel.
    let grey = stratapt_scene::environment::pfm_bytes(&[0.1, 0.1, 0.1, 0.7, 0.7, 0.7], 2, 1);
    std::fs::write(d.join("grey.pfm"), grey).unwrap();
    let g = with("grey.pfm", "scale = 0.5");
    assert_eq!(record(&g.tables, 0).tag >> 8 & 0xff, texel_format::GREY32F);
    assert_eq!(texel(&g, 1), [0.35; 3]);
    exr::prelude::write_rgb_file(d.join("c.exr"), 2, 1, |x, _| {
        [(0.25, 0.5, 0.75), (0.125, 0.0, 1.0)][x]
    })
    .unwrap();
    let c = with("c.exr", "");
    assert_eq!(texel(&c, 0), [0.25, 0.5, 0.75]);
    assert_eq!(texel(&c, 1), [0.125, 0.0, 1.0]);
    assert_eq!(c.textures, 1);
    assert_eq!(c.texture_bytes, 80 + 24);
}

#[test]
fn shapes_carry_texture_coordinates_only_when_textured() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let checks = "[textures.t]\ntype = \"checkerboard\"\n";
    // A rectangle: corner (0, 0), along edge_u (1, 0), the opposite corner (1, 1).
    let s = scene(d, &format!("{checks}{TEXTURED_RECTANGLE}"));
    let uvs: Vec<_> = s.geometry.iter().flat_map(|p| p.uvs.unwrap()).collect();
    let points: Vec<_> = s.geometry.iter().flat_map(|p| [p.a, p.b, p.c]).collect();
    for (uv, p) in uvs.iter().zip(&points) {
        assert_eq!(*uv, [(p[0] + 1.0) / 2.0, (p[1] + 1.0) / 2.0], "at {p:?}");
    }
    assert!(Effects::of(&s, &RenderSettings::default()).textures);
    assert!(s.geometry.iter().all(|p| p.textured));
    // Without a texture: no coordinates stored, no texture effect.
    let plain = scene(
        d,
        &TEXTURED_RECTANGLE.replace("albedo = \"t\"", "albedo = 0.5"),
    );
    assert!(plain.geometry.uvs.is_empty());
    assert!(plain
        .geometry
        .iter()
        .all(|p| p.uvs.is_none() && !p.textured));
    assert!(!Effects::of(&plain, &RenderSettings::default()).textures);
    // A textured box: each face its own corners, (0, 0) … (1, 1).
    let b = scene(
        d,
        &format!("{checks}[materials.m]\ntype = \"diffuse\"\nalbedo = \"t\"\n\n[[shapes]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nmaterial = \"m\"\n"),
    );
    assert_eq!(b.geometry.len(), 12);
    for p in b.geometry.iter() {
        let uv = p.uvs.unwrap();
        assert!(uv.iter().flatten().all(|&x| x == 0.0 || x == 1.0), "{uv:?}");
    }
    // An OBJ's vt, v flipped (Mitsuba 3's reading); a PLY's u v as they are.
    std::fs::write(
        d.join("t.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.125\nvt 0.5 0.25\nvt 0.75 1\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    std::fs::write(
        d.join("t.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0.25 0.125\n1 0 0 0.5 0.25\n0 1 0 0.75 1\n3 0 1 2\n",
    )
    .unwrap();
    for (file, v) in [("t.obj", [0.875, 0.75, 0.0]), ("t.ply", [0.125, 0.25, 1.0])] {
        let m = scene(
            d,
            &format!("{checks}[materials.m]\ntype = \"diffuse\"\nalbedo = \"t\"\n\n[[shapes]]\ntype = \"mesh\"\nfile = \"{file}\"\nmaterial = \"m\"\n"),
        );
        let uv = m.geometry.prim(0).uvs.unwrap();
        assert_eq!(uv.map(|uv| uv[0]), [0.25, 0.5, 0.75], "{file}");
        assert_eq!(uv.map(|uv| uv[1]), v, "{file}");
        let surface = m.geometry.surface(0);
        assert_ne!(surface.flags & surface_flag::UV, 0);
    }
}

#[test]
fn the_bundled_scene_reads_its_textures() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/textures.toml");
    let s = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.textures, 5);
    // `tiles` and `tiles_once` read one file: its texels are held once. Five records, two
    // 64² images of 4 bytes a texel, a 32×16 one, the 8-bit decode tables.
    assert_eq!(record(&s.tables, 0).texels, record(&s.tables, 1).texels);
    assert_eq!(
        s.texture_bytes,
        5 * 80 + 2 * 64 * 64 * 4 + 32 * 16 * 4 + 512 * 4
    );
    // Only the textured surfaces compute texture coordinates: not the wall or the lamp.
    let textured = s.geometry.iter().filter(|p| p.textured).count();
    assert!(textured > 0 && textured < s.geometry.len(), "{textured}");
    let flags = |name: &str| {
        let i = s.material_names.iter().position(|n| n == name).unwrap();
        s.materials[i].tag & material_flag::TEXTURES
    };
    assert_eq!(flags("floor"), material_flag::COLOR_TEXTURE);
    assert_eq!(flags("scratched_gold"), material_flag::ALPHA_TEXTURE);
    assert_eq!(flags("labelled"), material_flag::COLOR_TEXTURE);
    assert_eq!(flags("wall"), 0);
    // The scratches map: 0.05 with 0.4 scratches.
    let alphas: Vec<f32> = (0..64)
        .map(|i| texture::eval_scalar(&s.tables, 3, [(i as f32 + 0.5) / 64.0, 0.5 / 64.0]))
        .collect();
    assert!(alphas
        .iter()
        .all(|&a| a == 0.05 || a == 0.4 || (0.05..0.4).contains(&a)));
    assert!(alphas.contains(&0.4) && alphas.contains(&0.05));
}

#[test]
fn texture_mistakes_name_the_line_and_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let bright = stratapt_scene::environment::pfm_bytes(&[2.0; 6], 2, 1);
    std::fs::write(d.join("bright.pfm"), bright).unwrap();
    std::fs::write(d.join("notes.txt"), "not an image").unwrap();
    let cases: &[(&str, &[&str])] = &[
        (
            "[materials.m]\ntype = \"diffuse\"\nalbedo = \"wood\"\n",
            &["s.toml:8:", "unknown texture `wood`", "none defined"],
        ),
        (
            "[textures.b]\ntype = \"image\"\nfile = \"bright.pfm\"\n[materials.m]\ntype = \"diffuse\"\nalbedo = \"b\"\n",
            &["s.toml:11:", "reaches 2", "`albedo` must lie in [0, 1]"],
        ),
        (
            "[textures.c]\ntype = \"checkerboard\"\n[materials.m]\ntype = \"plastic\"\nroughness = \"c\"\n",
            &["s.toml:10:", "cannot be a texture"],
        ),
        (
            "[textures.c]\ntype = \"image\"\nfile = \"bright.pfm\"\nwrap = \"wrap\"\n",
            &["s.toml:9:", "wrap", "repeat", "clamp", "mirror"],
        ),
        (
            "[textures.c]\ntype = \"image\"\nfile = \"notes.txt\"\n",
            &["s.toml:8:", "notes.txt", ".png", ".exr"],
        ),
        (
            "[textures.c]\ntype = \"image\"\nfile = \"missing.png\"\n",
            &["s.toml:8:", "missing.png"],
        ),
        (
            "[textures.c]\ntype = \"checkerboard\"\nuv_scale = 2\nuv_transform = [[1, 0, 0], [0, 1, 0]]\n",
            &["s.toml:8:", "not both"],
        ),
        (
            "[textures.c]\ntype = \"marble\"\n",
            &["s.toml:7:", "unknown texture type `marble`", "image", "checkerboard"],
        ),
        (
            "[textures.c]\ntype = \"checkerboard\"\ncolor0 = -1\n",
            &["s.toml:8:", "color0", "negative"],
        ),
    ];
    for (text, words) in cases {
        let message = error(d, text);
        for word in *words {
            assert!(message.contains(word), "`{word}` not in: {message}\n{text}");
        }
    }
    // A texture that exists but is never used costs nothing and is no error.
    let unused = load_str(
        &format!("{CAMERA}[textures.c]\ntype = \"checkerboard\"\n"),
        Path::new("u.toml"),
    )
    .unwrap();
    assert!(!Effects::of(&unused, &RenderSettings::default()).textures);
}

/// `clamp = true` clamps each lookup of a texture to [0, 1] (pbrt-v4's reflectance): a float
/// image reaching 2 is then a valid diffuse albedo and plastic diffuse, its lookups read at
/// most 1 (the clamp of the interpolation, not the interpolation of clamped texels), and
/// without the key the same texture is still an error at the parameter that reads it.
#[test]
fn a_clamped_texture_above_one_is_a_valid_albedo() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Texels 2 and 0.
    let texels = [2.0, 2.0, 2.0, 0.0, 0.0, 0.0];
    std::fs::write(
        d.join("two.pfm"),
        stratapt_scene::environment::pfm_bytes(&texels, 2, 1),
    )
    .unwrap();
    let texture = "[textures.t]\ntype = \"image\"\nfile = \"two.pfm\"\nwrap = \"clamp\"\n";
    let s = scene(d, &format!("{texture}clamp = true\n{TEXTURED_RECTANGLE}"));
    assert_ne!(record(&s.tables, 0).tag & texture_flag::CLAMP, 0);
    assert_eq!(texel(&s, 0), [1.0; 3]);
    assert_eq!(texel(&s, 1), [0.0; 3]);
    // Halfway the blend is 1 (clamped: 1), a quarter of the way 1.5 (clamped: 1), three
    // quarters ½; the clamped texels would blend to ½, ¾ and ¼.
    let at = |u: f32| texture::eval(&s.tables, 0, [u, 0.5])[0];
    assert_eq!([at(0.5), at(0.375), at(0.625)], [1.0, 1.0, 0.5]);
    let plastic = "[materials.p]\ntype = \"plastic\"\ndiffuse = \"t\"\n";
    scene(d, &format!("{texture}clamp = true\n{plastic}"));
    // Without `clamp` the albedo is refused where it is read.
    let e = error(d, &format!("{texture}{TEXTURED_RECTANGLE}"));
    assert!(
        e.contains("s.toml:13:") && e.contains("reaches 2") && e.contains("clamp = true"),
        "{e}"
    );
}

/// A pbrt-v4 reflectance texture that clamps is written by `strata convert` with `clamp =
/// true`, and the TOML reads back a texture that clamps; where a conductor's η reads the same
/// texture, it reads an unclamped copy.
#[test]
fn converted_pbrt_reflectances_keep_their_clamp() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    image::RgbImage::from_pixel(2, 1, image::Rgb([255, 255, 255]))
        .save(d.join("white.png"))
        .unwrap();
    let text = "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n\
        Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"white.png\" \"float scale\" 2\n\
        MakeNamedMaterial \"metal\" \"string type\" \"conductor\" \"texture eta\" \"t\" \"rgb k\" [1 1 1]\n\
        MakeNamedMaterial \"paint\" \"string type\" \"diffuse\" \"texture reflectance\" \"t\"\n\
        NamedMaterial \"metal\"\nShape \"sphere\"\n\
        NamedMaterial \"paint\"\nTranslate 3 0 0\nShape \"sphere\"\n";
    let path = d.join("s.pbrt");
    std::fs::write(&path, text).unwrap();
    let desc = stratapt_import::pbrt::import::import(&path, "meshes").unwrap();
    let toml = stratapt_import::desc::write::to_toml(&desc, d).unwrap();
    assert_eq!(toml.matches("clamp = true").count(), 1, "{toml}");
    std::fs::write(d.join("converted.toml"), &toml).unwrap();
    for scene in [
        load(&path).unwrap(),
        load(&d.join("converted.toml")).unwrap(),
    ] {
        let texture_of = |name: &str, eta: bool| {
            let m = scene.material_names.iter().position(|n| n == name).unwrap();
            let m = &scene.materials[m];
            (if eta { m.eta[0] } else { m.color[0] }) as u32
        };
        let (metal, paint) = (texture_of("metal", true), texture_of("paint", false));
        assert_ne!(metal, paint, "{toml}");
        assert_eq!(texture::eval(&scene.tables, metal, [0.25, 0.5]), [2.0; 3]);
        assert_eq!(texture::eval(&scene.tables, paint, [0.25, 0.5]), [1.0; 3]);
    }
}
