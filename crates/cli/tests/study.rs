//! `strata study` and the progressive render flags as a user meets them: on analytic scenes the
//! study's errors fall at each sampler's rate, its files hold every configuration and a ranking
//! the CSV bears out, Ctrl-C keeps what was measured, a wrong reference is a clear error;
//! `render --target-error` and `--time-limit` stop and say why.

mod common;

use common::{interrupted_after, scene_file, strata};
use std::collections::HashMap;
use std::path::Path;

/// A white furnace (albedo ½, emission 1, depth 8): every pixel is Σₖ₌₀⁸ ½ᵏ.
const FURNACE: &str = r#"
[camera]
eye = [0.1, -0.2, 0.15]
look_at = [0.5, 0.3, 1]
up = [0, 1, 0]
fov = 70
[film]
width = 16
height = 16
[render]
max_depth = 8
exact = 1.99609375
[materials.shell]
type = "diffuse"
albedo = 0.5
emission = 1
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "shell"
"#;

/// An albedo-1 floor under a constant sky of 0.5, direct light only: every pixel is 0.5, and
/// under uniform hemisphere sampling the integrand (cos θ) is smooth.
const SKY_FLOOR: &str = r#"
[camera]
eye = [0, 0, 0.3]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov = 0.02
[film]
width = 16
height = 16
[render]
max_depth = 1
exact = 0.5
[materials.floor]
type = "diffuse"
albedo = 1
[[shapes]]
type = "rectangle"
corner = [-10, -10, 0]
edge_u = [20, 0, 0]
edge_v = [0, 20, 0]
material = "floor"
[sky]
color = 0.5
"#;

/// One row of study.csv: spp, seed, seconds, relmse.
type CsvRow = (u32, u32, f64, f64);

/// study.csv as (sampler, strategy) → its rows.
fn read_csv(path: &Path) -> HashMap<(String, String), Vec<CsvRow>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (sampler, strategy, spp, seed, seconds, relmse) = (
        col("sampler"),
        col("strategy"),
        col("spp"),
        col("seed"),
        col("seconds"),
        col("relmse"),
    );
    let mut out: HashMap<_, Vec<_>> = HashMap::new();
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        out.entry((f[sampler].to_string(), f[strategy].to_string()))
            .or_default()
            .push((
                f[spp].parse().unwrap(),
                f[seed].parse().unwrap(),
                f[seconds].parse().unwrap(),
                f[relmse].parse().unwrap(),
            ));
    }
    out
}

/// Least-squares slope of log RMS relative error (over seeds) against log spp.
fn slope_vs_spp(rows: &[CsvRow]) -> f64 {
    let mut spps: Vec<u32> = rows.iter().map(|r| r.0).collect();
    spps.sort_unstable();
    spps.dedup();
    let points: Vec<(f64, f64)> = spps
        .iter()
        .map(|&spp| {
            let at: Vec<f64> = rows.iter().filter(|r| r.0 == spp).map(|r| r.3).collect();
            let mean = at.iter().sum::<f64>() / at.len() as f64;
            ((spp as f64).ln(), 0.5 * mean.ln())
        })
        .collect();
    let n = points.len() as f64;
    let (mx, my) = (
        points.iter().map(|p| p.0).sum::<f64>() / n,
        points.iter().map(|p| p.1).sum::<f64>() / n,
    );
    points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
        / points.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>()
}

#[test]
fn independent_error_falls_as_one_over_root_n_on_an_analytic_scene() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "furnace.toml", FURNACE);
    let out = strata(
        dir.path(),
        &[
            "study",
            "furnace.toml",
            "--device",
            "cpu",
            "--samplers",
            "independent",
            "--strategies",
            "cosine,mis",
            "--max-spp",
            "256",
            "--seeds",
            "8",
            "--out",
            "s",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows = read_csv(&dir.path().join("s/study.csv"));
    for strategy in ["cosine", "mis"] {
        let slope = slope_vs_spp(&rows[&("independent".to_string(), strategy.to_string())]);
        eprintln!("independent / {strategy}: slope {slope:.3}");
        assert!(
            (slope + 0.5).abs() <= 0.1,
            "independent / {strategy}: slope {slope}"
        );
    }
    let report = std::fs::read_to_string(dir.path().join("s/report.md")).unwrap();
    assert!(report.contains("the scene's exact value"), "{report}");
    // At 1 spp a film has no variance estimate: the report says so rather than predicting 0.
    assert!(
        report.contains("| independent | mis | 1 |") && report.contains("| not estimated |"),
        "{report}"
    );
    assert!(!report.contains("| 0.000e0 |"), "{report}");
}

#[test]
fn stratified_and_sobol_converge_faster_on_a_smooth_integrand() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "sky.toml", SKY_FLOOR);
    let out = strata(
        dir.path(),
        &[
            "study",
            "sky.toml",
            "--device",
            "cpu",
            "--strategies",
            "uniform",
            "--max-spp",
            "256",
            "--seeds",
            "4",
            "--out",
            "s",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows = read_csv(&dir.path().join("s/study.csv"));
    let slope = |s: &str| slope_vs_spp(&rows[&(s.to_string(), "uniform".to_string())]);
    let (independent, stratified, sobol) =
        (slope("independent"), slope("stratified"), slope("sobol"));
    eprintln!("slopes: independent {independent:.2}, stratified {stratified:.2}, sobol {sobol:.2}");
    assert!(
        (independent + 0.5).abs() <= 0.1,
        "independent {independent}"
    );
    assert!(stratified < -0.8, "stratified {stratified}");
    assert!(sobol < -0.8, "sobol {sobol}");
}

#[test]
fn csv_holds_every_configuration_and_the_report_ranks_as_it_says() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "furnace.toml", FURNACE);
    let out = strata(
        dir.path(),
        &[
            "study",
            "furnace.toml",
            "--device",
            "cpu",
            "--max-spp",
            "4",
            "--seeds",
            "2",
            "--out",
            "s",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for file in [
        "study.csv",
        "error-vs-time.svg",
        "error-vs-time.png",
        "error-vs-spp.svg",
        "error-vs-spp.png",
        "report.md",
    ] {
        assert!(dir.path().join("s").join(file).is_file(), "{file} missing");
    }
    let rows = read_csv(&dir.path().join("s/study.csv"));
    // 3 samplers × 5 strategies, each at 1, 2, 4 spp × 2 seeds.
    assert_eq!(rows.len(), 15);
    assert!(rows.values().all(|r| r.len() == 6));
    // Efficiency 1/(MSE·s) from the CSV at 4 spp: relMSE here is MSE / (ref² + 0.01), a constant
    // factor, so the ranking by 1/(relMSE·s) is the same.
    let mut from_csv: Vec<((String, String), f64)> = rows
        .iter()
        .map(|(k, r)| {
            let at: Vec<_> = r.iter().filter(|r| r.0 == 4).collect();
            let n = at.len() as f64;
            let (s, e) = (
                at.iter().map(|r| r.2).sum::<f64>() / n,
                at.iter().map(|r| r.3).sum::<f64>() / n,
            );
            (k.clone(), 1.0 / (e * s))
        })
        .collect();
    from_csv.sort_by(|a, b| b.1.total_cmp(&a.1));
    let report = std::fs::read_to_string(dir.path().join("s/report.md")).unwrap();
    let ranked: Vec<(String, String)> = report
        .lines()
        .filter(|l| {
            l.starts_with("| ")
                && l.split('|')
                    .nth(1)
                    .is_some_and(|c| c.trim().parse::<u32>().is_ok())
        })
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            (cells[2].to_string(), cells[3].to_string())
        })
        .collect();
    assert_eq!(ranked.len(), 15, "{report}");
    // Equal efficiencies (deterministic estimators) may tie in any order: compare the values.
    let efficiency: HashMap<_, _> = from_csv.iter().cloned().collect();
    for pair in ranked.windows(2) {
        let (a, b) = (efficiency[&pair[0]], efficiency[&pair[1]]);
        assert!(
            a >= b * (1.0 - 1e-6),
            "{:?} ({a}) ranked above {:?} ({b})",
            pair[0],
            pair[1]
        );
    }
}

#[test]
fn wrong_size_reference_is_a_clear_error_and_renders_nothing() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "furnace.toml", FURNACE);
    // A real EXR of the wrong size: an 8×8 render.
    let out = strata(
        dir.path(),
        &[
            "render",
            "furnace.toml",
            "--size",
            "8x8",
            "--spp",
            "2",
            "--device",
            "cpu",
            "-o",
            "small.exr",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = strata(
        dir.path(),
        &[
            "study",
            "furnace.toml",
            "--device",
            "cpu",
            "--reference",
            "small.exr",
            "--out",
            "s",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("small.exr") && stderr.contains("8×8") && stderr.contains("16×16"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!dir.path().join("s").exists(), "nothing is written");
    // Not an EXR at all.
    std::fs::write(dir.path().join("bogus.exr"), b"not an image").unwrap();
    let out = strata(
        dir.path(),
        &[
            "study",
            "furnace.toml",
            "--device",
            "cpu",
            "--reference",
            "bogus.exr",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("bogus.exr") && stderr.contains("not a readable EXR"),
        "{stderr}"
    );
}

#[test]
fn ctrl_c_during_a_study_keeps_what_was_measured() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "furnace.toml", FURNACE);
    // Interrupt once the study's first level is measured (its `measured:` line).
    let (status, rest) = interrupted_after(
        dir.path(),
        &[
            "study",
            "furnace.toml",
            "--device",
            "cpu",
            "--max-spp",
            "1000000",
            "--seeds",
            "2",
            "--size",
            "64x64",
            "--out",
            "s",
        ],
        "device: CPU",
        "measured:",
    );
    assert_eq!(status.code(), Some(130), "{rest}");
    assert!(rest.contains("interrupted"), "{rest}");
    let rows = read_csv(&dir.path().join("s/study.csv"));
    assert!(!rows.is_empty(), "{rest}");
    let report = std::fs::read_to_string(dir.path().join("s/report.md")).unwrap();
    assert!(report.contains("Stopped early: interrupted"), "{report}");
}

#[test]
fn render_to_a_target_error_and_to_a_time_limit() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "furnace.toml", FURNACE);
    let out = strata(
        dir.path(),
        &[
            "render",
            "furnace.toml",
            "--device",
            "cpu",
            "--target-error",
            "0.005",
            "-o",
            "t.exr",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("stopped at the target"), "{stderr}");
    let out = strata(
        dir.path(),
        &[
            "render",
            "furnace.toml",
            "--device",
            "cpu",
            "--time-limit",
            "1s",
            "--size",
            "64x64",
            "-o",
            "l.exr",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("stopped before the time limit"), "{stderr}");
    for bad in [["--time-limit", "soon"], ["--target-error", "2"]] {
        let out = strata(
            dir.path(),
            &["render", "furnace.toml", "--device", "cpu", bad[0], bad[1]],
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(bad[0]), "{stderr}");
    }
}

/// A lit triangle from `tri.obj` beside the scene, no exact answer: a study renders its
/// reference.
const MESH_SCENE: &str = r#"
[camera]
eye = [0.3, 0.3, -3]
look_at = [0.3, 0.3, 0]
fov = 40
[film]
width = 8
height = 8
[render]
max_depth = 2
[materials.lit]
type = "diffuse"
albedo = 0.5
emission = 1
[[shapes]]
type = "mesh"
file = "tri.obj"
material = "lit"
"#;

/// The reference cache follows what the scene reads, not only its file's text: a study run
/// again reuses its reference, and after the mesh file the scene names is edited (the scene file
/// untouched) it renders a new one.
#[test]
fn an_edited_mesh_renders_a_new_reference() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "mesh.toml", MESH_SCENE);
    let triangle = |top: f64| format!("v 0 0 0\nv 1 0 0\nv 0 {top} 0\nf 1 2 3\n");
    std::fs::write(dir.path().join("tri.obj"), triangle(1.0)).unwrap();
    let study = || {
        let out = strata(
            dir.path(),
            &[
                "study",
                "mesh.toml",
                "--device",
                "cpu",
                "--samplers",
                "independent",
                "--strategies",
                "mis",
                "--max-spp",
                "1",
                "--seeds",
                "1",
                "--reference-spp",
                "4",
                "--out",
                "s",
            ],
        );
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{stderr}");
        stderr
    };
    let references = || {
        std::fs::read_dir(dir.path().join("s"))
            .unwrap()
            .filter(|e| {
                let name = e.as_ref().unwrap().file_name();
                name.to_string_lossy().starts_with("reference-")
            })
            .count()
    };
    assert!(study().contains("rendering the reference"));
    assert!(study().contains("reusing the reference"));
    assert_eq!(references(), 1);
    std::fs::write(dir.path().join("tri.obj"), triangle(1.5)).unwrap();
    let after = study();
    assert!(after.contains("rendering the reference"), "{after}");
    assert_eq!(references(), 2);
}

/// On a scene the eight-lane CPU renderer covers (sobol / mis only), a study of configurations it
/// does not cover still runs: `auto` weighs lavapipe against the CPU reference and renders on a
/// device that serves every configuration; a study of sobol / mis alone may take eight lanes.
#[test]
fn auto_picks_a_device_for_every_configuration_of_the_study() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mitsuba/cornell-box.toml");
    let scene = scene.to_str().unwrap();
    let common = [
        "--max-spp",
        "2",
        "--seeds",
        "1",
        "--size",
        "16x16",
        "--reference-spp",
        "4",
    ];
    let study = |out: &str, configs: &[&str]| {
        let args = [&["study", scene, "--out", out][..], &common, configs].concat();
        strata(dir.path(), &args)
    };
    let out = study(
        "mixed",
        &["--samplers", "independent,sobol", "--strategies", "mis"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("eight lanes"), "{stderr}");
    let out = study("sobol", &["--samplers", "sobol", "--strategies", "mis"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
