//! The `strata` binary as a user meets it: renders write images, bad input gives a clear
//! error, a non-zero exit and no output file.

mod common;

use common::{interrupted_after, scene_file, strata};
use std::path::Path;
use std::process::Command;
use stratapt_sampling::testing::TestRng;

const TINY_SCENE: &str = r#"
[camera]
eye = [0, 1, -3]
look_at = [0, 1, 0]
fov = 40

[film]
width = 8
height = 6

[render]
spp = 2
max_depth = 3

[materials.white]
type = "diffuse"
albedo = [0.7, 0.7, 0.7]

[materials.lamp]
type = "diffuse"
albedo = [0, 0, 0]
emission = [5, 5, 5]

[[shapes]]
type = "rectangle"
corner = [-2, 0, -2]
edge_u = [0, 0, 4]
edge_v = [4, 0, 0]
material = "white"

[[shapes]]
type = "sphere"
center = [0, 2.5, 0]
radius = 0.5
material = "lamp"
"#;

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn render_writes_exr_and_png_named_after_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    let out = strata(dir.path(), &["render", "tiny.toml", "--device", "cpu"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "render failed: {stderr}");
    assert_eq!(files_in(dir.path()), ["tiny.exr", "tiny.png", "tiny.toml"]);
    assert!(
        stderr.contains("CPU reference renderer"),
        "names the device: {stderr}"
    );
    assert!(
        stderr.contains("2 spp") && stderr.contains("samples/s"),
        "closing line: {stderr}"
    );
    let png = std::fs::read(dir.path().join("tiny.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let exr = std::fs::read(dir.path().join("tiny.exr")).unwrap();
    assert_eq!(&exr[..4], &[0x76, 0x2f, 0x31, 0x01], "OpenEXR magic number");
}

/// `--device cpu8` renders a scene it covers to the reference's image, byte for byte, and
/// refuses one it does not with the reason, a non-zero exit and no output file.
#[test]
fn the_eight_lane_prototype_renders_the_references_image_or_says_why_not() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mitsuba/cornell-box.toml");
    let scene = scene.to_str().unwrap();
    for device in ["cpu", "cpu8"] {
        let args = [
            "render", scene, "--device", device, "--size", "24x20", "--spp", "8",
        ];
        let out = strata(
            dir.path(),
            &[&args[..], &["-o", &format!("{device}.exr")]].concat(),
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert!(read("cpu.exr") == read("cpu8.exr"), "the two EXRs differ");
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    let out = strata(
        dir.path(),
        &["render", "tiny.toml", "--device", "cpu8", "-o", "no.exr"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains("eight lanes") && stderr.contains("does not cover"),
        "{stderr}"
    );
    assert_eq!(files_in(dir.path()), ["cpu.exr", "cpu8.exr", "tiny.toml"]);
}

/// `--traversal ray-query` where it cannot be used is an error that says why, and writes
/// nothing: on the CPU, and on a scene with a sphere (or a device without ray queries).
#[test]
fn ray_queries_where_they_cannot_be_used_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    for (device, says) in [("cpu", "needs a GPU"), ("gpu", "ray")] {
        let args = [
            "render",
            "tiny.toml",
            "--device",
            device,
            "--traversal",
            "ray-query",
        ];
        let out = strata(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{device}: {stderr}");
        assert!(
            stderr.contains("--traversal ray-query") && stderr.contains(says),
            "{device}: {stderr}"
        );
    }
    assert_eq!(files_in(dir.path()), ["tiny.toml"]);
}

#[test]
fn auto_device_says_which_renderer_it_fell_back_to() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    let out = strata(
        dir.path(),
        &["render", "tiny.toml", "-o", "x.png", "--spp", "1"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("device: "), "{stderr}");
    assert_eq!(files_in(dir.path()), ["tiny.toml", "x.png"]);
}

#[test]
fn command_line_overrides_the_scene_settings() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    let args = [
        "render",
        "tiny.toml",
        "-o",
        "o.exr",
        "--spp",
        "3",
        "--sampler",
        "stratified",
        "--strategy",
        "light",
        "--max-depth",
        "2",
        "--seed",
        "7",
        "--device",
        "cpu",
    ];
    let out = strata(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("3 spp, stratified / light, depth 2"),
        "{stderr}"
    );
}

#[test]
fn malformed_scene_names_file_line_and_column_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bad = TINY_SCENE.replace("radius = 0.5", "radius = -0.5");
    scene_file(dir.path(), "bad.toml", &bad);
    let line = bad
        .lines()
        .position(|l| l.contains("radius = -0.5"))
        .unwrap()
        + 1;
    let out = strata(dir.path(), &["render", "bad.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains(&format!("bad.toml:{line}:")),
        "names file and line: {stderr}"
    );
    assert!(stderr.contains("radius"), "says why: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(files_in(dir.path()), ["bad.toml"]);
}

#[test]
fn missing_scene_file_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = strata(dir.path(), &["render", "nope.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("nope.toml"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn bad_output_path_fails_before_rendering_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    std::fs::create_dir(dir.path().join("folder.exr")).unwrap();
    for (output, reason) in [
        ("out.jpg", ".exr or .png"),
        ("no/such/dir/o.exr", "does not exist"),
        ("folder.exr", "is a folder"),
        // Read-only even for root (the tests may run as root, who may write anywhere else).
        ("/proc/strata-test.exr", "cannot write to folder /proc"),
    ] {
        let out = strata(dir.path(), &["render", "tiny.toml", "-o", output]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{output}");
        assert!(stderr.contains(reason), "{output}: {stderr}");
        // Refused before rendering: no effects line, no device chosen.
        assert!(!stderr.contains("effects:"), "{output}: {stderr}");
    }
    assert_eq!(files_in(dir.path()), ["folder.exr", "tiny.toml"]);
    assert!(files_in(&dir.path().join("folder.exr")).is_empty());
}

/// Every other bad input of the command line, and a mesh the OBJ parser panics on: a clear error
/// naming what is wrong, a non-zero exit, no panic message and no output file.
#[test]
fn bad_arguments_devices_and_meshes_are_refused_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    let cases: &[(&[&str], &str)] = &[
        (&["--size", "12x"], "--size"),
        (&["--size", "axb"], "--size"),
        (&["--size", "0x5"], "--size"),
        (&["--size=-4x4"], "--size"),
        (&["--size", "100000x100000"], "16384"),
        (&["--max-depth", "5000"], "1024"),
        (&["--max-depth", "0"], "--max-depth"),
        (
            &["--adapter", "no-such-adapter"],
            "no adapter named like `no-such-adapter`",
        ),
        (&["--device", "cpu", "--adapter", "x"], "--adapter"),
        (
            &["--kernel-checks", "bounds,speed"],
            "unknown check `speed`",
        ),
    ];
    for (args, reason) in cases {
        let mut all = vec!["render", "tiny.toml", "-o", "t.exr"];
        all.extend_from_slice(args);
        let out = strata(dir.path(), &all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}: {stderr}");
        assert!(stderr.contains(reason), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    // No GPU at all: no Vulkan driver, no EGL vendor for GL.
    let out = Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(["render", "tiny.toml", "-o", "t.exr", "--device", "gpu"])
        .env("VK_ICD_FILENAMES", "/nonexistent")
        .env("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent")
        .current_dir(dir.path())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(stderr.contains("no Vulkan or GL adapter found"), "{stderr}");
    assert!(stderr.contains("--device cpu"), "{stderr}");
    // A face whose normal index overflows tobj's arithmetic (a panic in builds with overflow
    // checks, an out-of-range error without): the mesh is reported malformed, quietly.
    std::fs::write(
        dir.path().join("bad.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//6148914691236517206\n",
    )
    .unwrap();
    let mesh_scene = TINY_SCENE.replace(
        "[[shapes]]\ntype = \"sphere\"",
        "[[shapes]]\ntype = \"mesh\"\nfile = \"bad.obj\"\nmaterial = \"white\"\n\n[[shapes]]\ntype = \"sphere\"",
    );
    scene_file(dir.path(), "mesh.toml", &mesh_scene);
    let out = strata(
        dir.path(),
        &["render", "mesh.toml", "-o", "m.exr", "--device", "cpu"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains("mesh.toml:") && stderr.contains("bad.obj"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(files_in(dir.path()), ["bad.obj", "mesh.toml", "tiny.toml"]);
}

/// `--kernel-checks` compiles the GPU kernel with the checks asked for, says which, warns when
/// they leave out the bounds checks, and every set writes the same image bits; a forced
/// `--sample-split` says it split.
#[test]
fn kernel_checks_and_sample_split_are_applied_and_said() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    // A GPU render of the tiny scene with `extra` arguments: its stderr, having succeeded.
    let render = |extra: &[&str]| {
        let mut args = vec!["render", "tiny.toml", "-o", "t.exr", "--device", "gpu"];
        args.extend_from_slice(extra);
        let out = strata(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{extra:?}: {stderr}");
        stderr
    };
    let mut images = Vec::new();
    for (checks, line, warns) in [
        ("default", "checks: bounds,loops)", false),
        ("audited", "checks: bounds)", false),
        ("all", "checks: bounds,loops,int-division)", false),
        ("none", "checks: none)", true),
    ] {
        let stderr = render(&["--kernel-checks", checks]);
        assert!(stderr.contains(line), "{checks}: {stderr}");
        assert_eq!(
            stderr.contains("warning: --kernel-checks"),
            warns,
            "{checks}: {stderr}"
        );
        images.push(std::fs::read(dir.path().join("t.exr")).unwrap());
    }
    assert!(images.windows(2).all(|w| w[0] == w[1]), "the images differ");
    // A forced split says so (lavapipe is never split by `auto`).
    let stderr = render(&["--spp", "16", "--sample-split", "4"]);
    assert!(stderr.contains("samples in up to 4 slices"), "{stderr}");
}

/// Mutated scenes through the binary (the loader's mutation corpus checks thousands in
/// process, `crates/scene/tests/corpus.rs`): each renders and writes its image, or fails with
/// the scene file named and writes nothing.
#[test]
fn mutated_scenes_render_or_fail_writing_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = TestRng(99);
    let lines: Vec<&str> = TINY_SCENE.lines().collect();
    let (mut rendered, mut refused) = (0, 0);
    for k in 0..24 {
        // Delete, duplicate or corrupt a line.
        let mut mutated: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        let i = rng.below(mutated.len());
        match k % 3 {
            0 => {
                mutated.remove(i);
            }
            1 => {
                let line = mutated[i].clone();
                mutated.insert(rng.below(mutated.len()), line);
            }
            _ => mutated[i] = mutated[i].replace('0', "-1e39").replace('=', "= ["),
        }
        let name = format!("m{k}.toml");
        scene_file(dir.path(), &name, &mutated.join("\n"));
        let image = format!("m{k}.exr");
        let out = strata(
            dir.path(),
            &[
                "render", &name, "-o", &image, "--device", "cpu", "--spp", "1",
            ],
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        let written = dir.path().join(&image).exists();
        if out.status.success() {
            assert!(written, "{name}: succeeded without an image");
            rendered += 1;
        } else {
            assert!(!written, "{name}: failed but wrote {image}");
            assert!(
                stderr.contains(&name),
                "{name}: the error does not name it: {stderr}"
            );
            refused += 1;
        }
    }
    assert!(
        rendered > 0 && refused > 0,
        "{rendered} rendered, {refused} refused"
    );
}

/// One sample per pixel gives no variance estimate: the closing line says so instead of
/// claiming a zero error; from two samples on it reports one.
#[test]
fn one_spp_says_its_error_is_not_estimated() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    for (spp, expect) in [
        ("1", "error: not estimated"),
        ("2", "relative standard error"),
    ] {
        let out = strata(
            dir.path(),
            &[
                "render",
                "tiny.toml",
                "-o",
                "o.exr",
                "--spp",
                spp,
                "--device",
                "cpu",
            ],
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(stderr.contains(expect), "{spp} spp: {stderr}");
        assert!(!stderr.contains("0.000 %"), "{spp} spp: {stderr}");
    }
}

/// The closing lines give the image mean and its standard error: a closed furnace (albedo ½,
/// emission 1, every radiance 2) reads 2 within its error on every channel, and a furnace
/// whose emission is 0.5 % higher (2.01) is told apart from it.
#[test]
fn the_image_mean_is_reported_with_its_error() {
    let dir = tempfile::tempdir().unwrap();
    let furnace = |emission: &str| {
        format!(
            "[camera]\neye = [0.1, -0.2, 0.15]\nlook_at = [0.5, 0.3, 1]\nfov = 70\n\
             [film]\nwidth = 8\nheight = 8\n[render]\nmax_depth = 64\n\
             [materials.shell]\ntype = \"diffuse\"\nalbedo = 0.5\nemission = {emission}\n\
             [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"shell\"\n"
        )
    };
    let mean = |name: &str, toml: &str| -> Vec<(f64, f64)> {
        scene_file(dir.path(), name, toml);
        let args = [
            "render",
            name,
            "-o",
            "o.exr",
            "--spp",
            "4096",
            "--strategy",
            "light",
            "--sampler",
            "independent",
            "--device",
            "cpu",
        ];
        let out = strata(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        let line = stderr
            .lines()
            .find_map(|l| l.strip_prefix("mean: "))
            .unwrap_or_else(|| panic!("no mean line: {stderr}"));
        let numbers: Vec<f64> = line
            .split(|c: char| c == ' ' || c == '(' || c == ')' || c == '±')
            .filter_map(|w| w.parse().ok())
            .collect();
        assert_eq!(numbers.len(), 6, "{line}");
        (0..3).map(|c| (numbers[c], numbers[3 + c])).collect()
    };
    for (m, se) in mean("furnace.toml", &furnace("1")) {
        assert!(se > 0.0 && (m - 2.0).abs() <= 4.5 * se, "{m} ± {se} vs 2");
    }
    let off = mean("brighter.toml", &furnace("1.005"));
    assert!(
        off.iter().any(|&(m, se)| (m - 2.0).abs() > 4.5 * se),
        "a 0.5 % brighter furnace passed for 2: {off:?}"
    );
}

#[test]
fn zero_spp_is_rejected_by_the_argument_parser() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    let out = strata(dir.path(), &["render", "tiny.toml", "--spp", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(files_in(dir.path()), ["tiny.toml"]);
}

#[test]
fn info_reports_effects_and_dimension_layout() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    let out = strata(dir.path(), &["info", "tiny.toml"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A static pinhole scene spends no dimension on lens or time.
    assert!(stdout.contains("lens no, time no"), "{stdout}");
    assert!(
        stdout.contains("dimensions pixel 0, lens —, time —"),
        "{stdout}"
    );
    assert!(stdout.contains("sphere"), "{stdout}");
}

#[test]
fn bench_prints_a_row_per_scene_and_renderer() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    let out = strata(
        dir.path(),
        &["bench", "tiny.toml", "--size", "16x8", "--spp", "2"],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("M paths/s") && stdout.contains("M rays/s"),
        "{stdout}"
    );
    for renderer in ["gpu", "cpu"] {
        let row = stdout
            .lines()
            .find(|l| {
                l.starts_with("tiny")
                    && l.split_whitespace()
                        .nth(1)
                        .is_some_and(|on| on.starts_with(renderer))
            })
            .unwrap_or_else(|| panic!("no {renderer} row: {stdout}"));
        // spp, seconds, ms/spp, M paths/s, M rays/s, rays/path: the rates are measured and
        // positive (the times may round to zero on a film this small).
        let numbers: Vec<f64> = row
            .split_whitespace()
            .skip(2)
            .take(6)
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(numbers[0], 2.0, "spp: {row}");
        assert!(numbers[3..].iter().all(|v| *v > 0.0), "{row}");
    }
    assert_eq!(
        files_in(dir.path()),
        ["tiny.toml"],
        "bench writes no images"
    );
}

#[test]
fn bench_refuses_a_bad_scene_before_timing_anything() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "bad.toml", "[camera]\nfov = -3\n");
    let out = strata(dir.path(), &["bench", "bad.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("bad.toml:"), "{stderr}");
    assert!(out.stdout.is_empty(), "no table for a bad scene");
}

#[test]
fn adapters_lists_the_software_adapter() {
    let dir = tempfile::tempdir().unwrap();
    let out = strata(dir.path(), &["adapters"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout
            .lines()
            .any(|l| l.contains("llvmpipe") || l.contains("lavapipe")),
        "{stdout}"
    );
}

/// Ctrl-C (SIGINT) during a GPU render: the batch in flight finishes, and the images hold the
/// samples taken so far, the EXR saying how many.
#[cfg(unix)]
#[test]
fn ctrl_c_writes_the_samples_taken_so_far() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    // Interrupt once the first batch has landed (its progress line), however fast the device.
    let (status, rest) = interrupted_after(
        dir.path(),
        &[
            "render",
            "tiny.toml",
            "-o",
            "cut.exr",
            "--spp",
            "1000000",
            "--size",
            "32x24",
            "--device",
            "gpu",
        ],
        "device: GPU",
        "progress:",
    );
    // Written, and said to scripts with the shell's code for SIGINT.
    assert_eq!(status.code(), Some(130), "{rest}");
    assert!(rest.contains("(interrupted)"), "{rest}");
    assert_eq!(files_in(dir.path()), ["cut.exr", "tiny.toml"]);

    let image = exr::prelude::read_all_data_from_file(dir.path().join("cut.exr")).unwrap();
    let spp = match image.layer_data[0]
        .attributes
        .other
        .get(&exr::prelude::Text::from("spp"))
    {
        Some(exr::prelude::AttributeValue::I32(n)) => *n,
        other => panic!("spp attribute: {other:?}"),
    };
    assert!((1..1_000_000).contains(&spp), "spp {spp}");
    assert!(rest.contains(&format!("{spp} spp (interrupted)")), "{rest}");
}

/// Without a Vulkan driver (only Mesa's GL llvmpipe, or nothing), `auto` renders on the CPU
/// reference and says why on its device line; `--device gpu` still takes GL when asked.
#[test]
fn auto_never_picks_gl_llvmpipe() {
    let dir = tempfile::tempdir().unwrap();
    scene_file(dir.path(), "tiny.toml", TINY_SCENE);
    let out = Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(["render", "tiny.toml", "-o", "t.exr"])
        .env("VK_ICD_FILENAMES", "/nonexistent")
        .current_dir(dir.path())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let device = stderr
        .lines()
        .find(|l| l.starts_with("device:"))
        .unwrap_or_default();
    assert!(device.starts_with("device: CPU reference"), "{stderr}");
    assert!(
        device.contains("GL llvmpipe") || device.contains("no GPU adapter"),
        "{device}"
    );
    // What the scene calls for, in one line.
    assert!(
        stderr.contains("effects: pinhole, static, sphere lights, diffuse, NEE\n"),
        "{stderr}"
    );
}
