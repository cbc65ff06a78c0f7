//! `strata render --part-from-env` as a job array runs it (one process per index, the index in
//! the environment, one command line for all), then `strata merge`: the merged image is the
//! single render's; bad part sets are refused with a message and no output.

mod common;

use common::scene_file;
use std::path::Path;
use std::process::Command;

/// A small lit room seen from inside (see the facade's `tests/parts.rs`).
const ROOM: &str = r#"
[camera]
eye = [0, 1, 0.9]
look_at = [0, 1, 0]
fov = 70
[film]
width = 24
height = 16
[render]
spp = 16
max_depth = 5
[materials.white]
type = "diffuse"
albedo = 0.7
[materials.lamp]
type = "diffuse"
albedo = 0
emission = 8
[[shapes]]
type = "box"
min = [-1, 0, -1]
max = [1, 2, 1]
material = "white"
[[shapes]]
type = "rectangle"
corner = [-0.3, 1.99, -0.3]
edge_u = [0.6, 0, 0]
edge_v = [0, 0, 0.6]
material = "lamp"
"#;

/// `strata ARGS` (split at spaces) in `dir`, with `env` added to its environment (a job
/// array's variables) and no job-array variables of the test's own.
fn run(dir: &Path, args: &str, env: &[(&str, String)]) -> std::process::Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_strata"));
    command.args(args.split(' ')).current_dir(dir);
    for var in [
        "SLURM_ARRAY_TASK_ID",
        "SLURM_ARRAY_TASK_MIN",
        "SLURM_ARRAY_TASK_COUNT",
        "JOB_COMPLETION_INDEX",
    ] {
        command.env_remove(var);
    }
    command.envs(env.iter().map(|(k, v)| (k, v)));
    command.output().expect("the strata binary runs")
}

/// The `R, G, B` channels of an EXR.
fn rgb(path: &Path) -> Vec<Vec<f32>> {
    let image = exr::prelude::read_all_flat_layers_from_file(path).unwrap();
    let layer = image
        .layer_data
        .iter()
        .find(|l| l.channel_data.list.iter().any(|c| c.name.eq("R")))
        .unwrap();
    ["R", "G", "B"]
        .map(|name| {
            let c = layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name.eq(name))
                .unwrap();
            c.sample_data.values_as_f32().collect()
        })
        .into()
}

/// Largest relative difference between two images' channels.
fn max_difference(a: &[Vec<f32>], b: &[Vec<f32>]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(&x, &y)| ((x - y).abs() / x.abs().max(y.abs()).max(1e-30)) as f64)
        .fold(0.0, f64::max)
}

fn ok(out: &std::process::Output) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{stderr}");
    stderr
}

#[test]
fn a_slurm_array_on_the_cpu_and_a_kubernetes_indexed_job_on_the_gpu_merge_into_one_render() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene_file(d, "room.toml", ROOM);
    // ---- Slurm: --array=1-4, the same command line for every task ----------------------------
    ok(&run(
        d,
        "render room.toml --device cpu -o whole-cpu.exr",
        &[],
    ));
    for id in 1..=4 {
        let env = [
            ("SLURM_ARRAY_TASK_ID", id.to_string()),
            ("SLURM_ARRAY_TASK_MIN", "1".to_string()),
            ("SLURM_ARRAY_TASK_COUNT", "4".to_string()),
        ];
        let args = format!("render room.toml --device cpu --part-from-env -o slurm-{id}.exr");
        let stderr = ok(&run(d, &args, &env));
        let k = id - 1;
        let held = format!("(samples {}..{} of 16)", 4 * k, 4 * k + 4);
        assert!(stderr.contains(&held), "task {id}: {stderr}");
    }
    let merge =
        "merge slurm-3.exr slurm-1.exr slurm-4.exr slurm-2.exr -o merged-cpu.exr -o merged-cpu.png";
    let stderr = ok(&run(d, merge, &[]));
    let complete = stderr.contains("merged 4 parts") && stderr.contains("0..16 of 16 (complete)");
    assert!(complete, "{stderr}");
    let worst = max_difference(
        &rgb(&d.join("merged-cpu.exr")),
        &rgb(&d.join("whole-cpu.exr")),
    );
    assert!(
        worst <= 1.2e-7,
        "CPU: merged image {worst:e} off the single render"
    );
    assert!(d.join("merged-cpu.png").is_file());
    // ---- Kubernetes: an Indexed Job of 3 completions, on the GPU -----------------------------
    ok(&run(
        d,
        "render room.toml --device gpu -o whole-gpu.exr",
        &[],
    ));
    for index in 0..3 {
        let env = [("JOB_COMPLETION_INDEX", index.to_string())];
        let args =
            format!("render room.toml --device gpu --part-from-env --parts 3 -o k8s-{index}.exr");
        ok(&run(d, &args, &env));
    }
    ok(&run(
        d,
        "merge k8s-0.exr k8s-1.exr k8s-2.exr -o merged-gpu.exr",
        &[],
    ));
    let worst = max_difference(
        &rgb(&d.join("merged-gpu.exr")),
        &rgb(&d.join("whole-gpu.exr")),
    );
    assert!(
        worst <= 1e-6,
        "GPU: merged image {worst:e} off the single render"
    );
    // Parts of either device are samples of one estimator: CPU and GPU parts merge too.
    ok(&run(
        d,
        "render room.toml --device cpu --samples 5..16 -o rest.exr",
        &[],
    ));
    let stderr = ok(&run(d, "merge k8s-0.exr rest.exr -o mixed.exr", &[]));
    assert!(stderr.contains("(complete)"), "{stderr}");
}

#[test]
fn bad_part_sets_are_refused_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene_file(d, "room.toml", ROOM);
    let cpu = |args: &str| run(d, &format!("render room.toml --device cpu {args}"), &[]);
    ok(&cpu("--part 0/2 -o a.exr"));
    ok(&cpu("--part 1/2 -o b.exr"));
    ok(&cpu("--samples 4..12 -o middle.exr"));
    ok(&cpu("--part 1/2 --seed 7 -o seed7.exr"));
    ok(&cpu("-o whole.exr"));
    std::fs::write(d.join("junk.exr"), "not an image").unwrap();
    let refused = [
        (vec!["a.exr", "middle.exr"], "both hold samples 4..8"),
        (vec!["a.exr"], "samples 8..16 of 16 are in no part"),
        (vec!["a.exr", "seed7.exr"], "seed differs"),
        (vec!["a.exr", "whole.exr"], "whole.exr: not a strata part"),
        (vec!["a.exr", "junk.exr"], "junk.exr: not a readable EXR"),
    ];
    for (parts, says) in refused {
        let out = run(
            d,
            &format!("merge {} -o out.exr -o out.png", parts.join(" ")),
            &[],
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{parts:?} merged");
        assert!(stderr.contains(says), "{parts:?}: {stderr}");
        assert!(
            !d.join("out.exr").exists() && !d.join("out.png").exists(),
            "{parts:?} wrote"
        );
    }
    // Merging what is there, saying what is missing; the result merges on with the rest.
    let stderr = ok(&run(d, "merge a.exr --allow-partial -o half.exr", &[]));
    assert!(stderr.contains("missing 8..16"), "{stderr}");
    let stderr = ok(&run(d, "merge half.exr b.exr -o all.exr", &[]));
    assert!(stderr.contains("(complete)"), "{stderr}");
    let worst = max_difference(&rgb(&d.join("all.exr")), &rgb(&d.join("whole.exr")));
    assert!(worst <= 1.2e-7, "merged in two steps: {worst:e} off");
    // A part is an EXR; a part range must lie within the render.
    for (args, says) in [
        ("--part 0/2 -o p.png", "a part is written as EXR"),
        ("--samples 8..20", "16 samples per pixel"),
        ("--part 2/2", "numbered 0 to 1"),
        ("--part 0/2 --time-limit 5s", "do not combine"),
    ] {
        let out = cpu(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && stderr.contains(says),
            "{args}: {stderr}"
        );
    }
    assert!(!d.join("p.png").exists());
}
