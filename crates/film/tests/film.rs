//! Film statistics and image output.

use stratapt_film::Film;

fn film_with_samples() -> Film {
    let mut film = Film::new(3, 2);
    for (x, y) in [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)] {
        for k in 0..4 {
            let v = (x + 3 * y) as f32 + k as f32 * 0.5;
            film.add_sample(x, y, [v, 2.0 * v, 0.25]);
        }
    }
    film
}

#[test]
fn mean_and_variance_of_the_mean_follow_the_samples() {
    let film = film_with_samples();
    assert_eq!(film.held_spp(), 4);
    // Pixel (1, 1) saw 4, 4.5, 5, 5.5: mean 4.75, sample variance 5/12, variance of mean 5/48.
    let i = film.index(1, 1);
    let m = film.mean(i);
    let v = film.sample_variance_of_mean(i);
    // Without twins the calibrated variance is the per-sample one.
    assert_eq!(film.variances()[i], v);
    assert!((m[0] - 4.75).abs() < 1e-12 && (m[1] - 9.5).abs() < 1e-12 && m[2] == 0.25);
    assert!((v[0] - 5.0 / 48.0).abs() < 1e-12, "{v:?}");
    assert!((v[1] - 4.0 * 5.0 / 48.0).abs() < 1e-12);
    assert_eq!(v[2], 0.0);
}

#[test]
fn merging_films_equals_adding_their_samples() {
    let mut a = film_with_samples();
    let b = film_with_samples();
    a.merge(&b);
    assert_eq!(a.held_spp(), 8);
    assert_eq!(a.mean(a.index(2, 0)), b.mean(b.index(2, 0)));
}

#[test]
fn exr_holds_mean_variance_and_spp() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("f.exr");
    let film = film_with_samples();
    film.write(&path).unwrap();
    let image = read_all_flat_layers_from_file(&path).unwrap();
    let layer = &image.layer_data[0];
    assert_eq!(layer.size, Vec2(3, 2));
    let channel = |name: &str| {
        let c = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.eq(name))
            .unwrap();
        c.sample_data.values_as_f32().collect::<Vec<f32>>()
    };
    let (r, var_g) = (channel("R"), channel("var.G"));
    for i in 0..6 {
        assert_eq!(r[i], film.mean(i)[0] as f32);
        assert_eq!(var_g[i], film.variances()[i][1] as f32);
    }
    let spp = layer.attributes.other.get(&Text::from("spp")).unwrap();
    assert_eq!(*spp, AttributeValue::I32(4));
    let kappa = layer.attributes.other.get(&Text::from("kappa")).unwrap();
    assert_eq!(*kappa, AttributeValue::FloatVec3((1.0, 1.0, 1.0)));
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temp file left"
    );
}

#[test]
fn png_is_srgb_encoded_and_clamped() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("f.png");
    let mut film = Film::new(2, 1);
    film.add_sample(0, 0, [0.0, 0.5, 1.0]);
    film.add_sample(1, 0, [7.0, -1.0, f32::NAN]);
    film.write(&path).unwrap();
    let img = image::open(&path).unwrap().to_rgb8();
    assert_eq!(img.get_pixel(0, 0).0, [0, 188, 255]);
    assert_eq!(img.get_pixel(1, 0).0, [255, 0, 0]);
}

#[test]
fn failed_write_names_the_path_and_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let film = film_with_samples();
    let err = film.write(&dir.path().join("missing/f.exr")).unwrap_err();
    assert!(err.to_string().contains("missing/f.exr"), "{err}");
    let err = film.write(&dir.path().join("f.tiff")).unwrap_err();
    assert!(err.to_string().contains(".exr or .png"), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

/// The same film written again gives the same bytes: plain EXR and a part EXR (ten custom
/// attributes, which the exr crate emits in hash-map order until strata sorts them).
#[test]
fn writing_a_film_twice_gives_the_same_bytes() {
    use stratapt_film::part::{self, PartInfo};
    let dir = tempfile::tempdir().unwrap();
    let film = film_with_samples();
    // A part with twin pixels: a second layer, so a multi-part file.
    let mut twinned = Film::with_twins(3, 2, true);
    twinned.merge(&{
        let mut f = Film::with_twins(3, 2, true);
        f.sum = film.sum.clone();
        f.sum_sq = film.sum_sq.clone();
        f.count = film.count.clone();
        f
    });
    assert!(!twinned.twin_sum.is_empty());
    for k in 0..twinned.twin_sum.len() {
        twinned.add_twin_sample(k, [k as f32, 1.0, 2.0]);
    }
    let info = PartInfo {
        samples: std::iter::once(0..4).collect(),
        settings: stratapt_scene::RenderSettings {
            pattern_spp: 8,
            ..Default::default()
        },
        scene_hash: 0x1234,
        scene: "scenes/cornell-box.toml".into(),
    };
    let mut plain = Vec::new();
    let mut parts = Vec::new();
    for k in 0..6 {
        let path = dir.path().join(format!("f{k}.exr"));
        film.write(&path).unwrap();
        plain.push(std::fs::read(&path).unwrap());
        let path = dir.path().join(format!("p{k}.exr"));
        part::write(&twinned, &info, &path).unwrap();
        parts.push(std::fs::read(&path).unwrap());
    }
    assert!(
        plain.windows(2).all(|w| w[0] == w[1]),
        "EXR bytes differ between writes"
    );
    assert!(
        parts.windows(2).all(|w| w[0] == w[1]),
        "part EXR bytes differ between writes"
    );
    // Still read as what they are.
    let (read, read_info) = part::read(&dir.path().join("p5.exr")).unwrap();
    assert_eq!(read_info, info);
    assert_eq!((read.sum, read.twin_sum), (twinned.sum, twinned.twin_sum));
}
