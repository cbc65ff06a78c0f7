//! The probe behind `--device auto` on a machine whose only GPU adapter is lavapipe: render the
//! scene small on lavapipe and on the CPU reference, and compare samples per second. Measured
//! once per machine (CPU model and threads), adapter (name and driver) and scene (what the
//! renderers read of it, [`FlatScene::content_hash`], and the settings), and cached in
//! `$XDG_CACHE_HOME/strata/device-probes.tsv` (else `~/.cache/…`), so later renders of the same
//! scene choose at once.

use super::choice::CpuKind;
use super::Device;
use std::path::PathBuf;
use std::time::Instant;
use stratapt_film::Render;
use stratapt_scene::{FlatScene, RenderSettings};

/// Film width of a probe render (the height keeps the scene's aspect), and its spp.
const PROBE_WIDTH: u32 = 128;
const PROBE_SPP: u32 = 8;
/// Timed runs per renderer (the fastest counts).
const PROBE_RUNS: u32 = 3;

/// lavapipe's samples per second over the CPU renderer `cpu`'s on `scene` (cached, or measured
/// now and cached); `None` if the probe could not run. `device` is the opened lavapipe renderer.
/// The probe renders `scene` at a small size, and gives it its own size back.
pub fn ratio(
    device: &Device,
    scene: &mut FlatScene,
    settings: &RenderSettings,
    cpu: CpuKind,
) -> Option<f64> {
    let Device::Gpu { gpu, renderer } = device else {
        return None;
    };
    let info = gpu.adapter.get_info();
    let key = key(
        &format!("{} | {}", info.name, info.driver_info),
        scene,
        settings,
    );
    // Figures against the reference keep their old keys; those against the eight-lane
    // renderer have their own.
    let key = match cpu {
        CpuKind::Reference => key,
        CpuKind::EightLanes => format!("{key} | against eight lanes"),
    };
    if let Some(ratio) = cached(&key) {
        return Some(ratio);
    }
    let size = (scene.camera.width, scene.camera.height);
    let (w, h) = (size.0.max(1), size.1.max(1));
    let probe_w = PROBE_WIDTH.min(w);
    let probe_h = (h as u64 * probe_w as u64 / w as u64).max(1) as u32;
    (scene.camera.width, scene.camera.height) = (probe_w, probe_h);
    let measured = time_both(renderer, scene, settings, cpu);
    (scene.camera.width, scene.camera.height) = size;
    let (gpu_seconds, cpu_seconds) = measured?;
    let ratio = cpu_seconds / gpu_seconds.max(1e-9);
    eprintln!(
        "probe: {} renders this scene at {ratio:.2}× {}'s speed ({probe_w}×{probe_h}, \
         {PROBE_SPP} spp: {gpu_seconds:.3} s against {cpu_seconds:.3} s); cached for later renders",
        info.name,
        cpu.name()
    );
    store(&key, ratio);
    Some(ratio)
}

/// Seconds of the probe render of `probe` on lavapipe (`renderer`) and on the CPU renderer
/// `cpu`.
fn time_both(
    renderer: &stratapt_gpu::Renderer,
    probe: &FlatScene,
    settings: &RenderSettings,
    cpu: CpuKind,
) -> Option<(f64, f64)> {
    let settings = RenderSettings {
        pattern_spp: PROBE_SPP,
        ..*settings
    };
    // lavapipe compiles its JIT code on the first dispatch: warm it off the clock, then take
    // the best of a few runs (the machine's other work only ever slows a run down).
    let time = |r: &dyn Render| -> Option<f64> {
        r.render(probe, &settings, &|_| {}, None).ok()?;
        let mut best = f64::INFINITY;
        for _ in 0..PROBE_RUNS {
            let start = Instant::now();
            r.render(probe, &settings, &|_| {}, None).ok()?;
            best = best.min(start.elapsed().as_secs_f64());
        }
        Some(best)
    };
    let cpu: &dyn Render = match cpu {
        CpuKind::Reference => &stratapt_cpu::CpuRenderer,
        CpuKind::EightLanes => &stratapt_cpu::Cpu8Renderer,
    };
    Some((time(renderer)?, time(cpu)?))
}

/// What the probe's result depends on, as one line: the `adapter` (name and driver), this
/// machine and build, what the renderers read of the scene (an edited mesh or texture changes
/// it, not only the scene file's text) and the settings.
fn key(adapter: &str, scene: &FlatScene, settings: &RenderSettings) -> String {
    format!(
        "{adapter} | {} | {} threads | {} build {} | scene {:016x} | {} {} depth {}",
        super::cpu_model().unwrap_or_default(),
        rayon::current_num_threads(),
        if cfg!(debug_assertions) {
            "debug"
        } else {
            "release"
        },
        build_stamp(),
        scene.content_hash(),
        settings.sampler,
        settings.strategy,
        settings.max_depth
    )
    .replace('\t', " ")
}

/// This executable's size and modification time: a rebuilt strata (a faster CPU reference or
/// kernel) measures again instead of trusting the figure of the build before it.
fn build_stamp() -> String {
    let meta = std::env::current_exe().and_then(std::fs::metadata);
    let modified = meta
        .as_ref()
        .ok()
        .and_then(|m| m.modified().ok())
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok());
    match (meta.as_ref().map(|m| m.len()), modified) {
        (Ok(len), Some(t)) => format!("{len}@{}.{:09}", t.as_secs(), t.subsec_nanos()),
        _ => "unknown".to_string(),
    }
}

fn cache_file() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .filter(|p| p.is_absolute())
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("strata").join("device-probes.tsv"))
}

fn cached(key: &str) -> Option<f64> {
    let text = std::fs::read_to_string(cache_file()?).ok()?;
    // The latest figure for the key wins.
    text.lines()
        .rev()
        .filter_map(|l| l.split_once('\t'))
        .filter(|(k, _)| *k == key)
        .find_map(|(_, v)| v.trim().parse::<f64>().ok())
}

/// Append the figure (a cache that cannot be written only costs a probe next time).
fn store(key: &str, ratio: f64) {
    let Some(path) = cache_file() else { return };
    if let Some(dir) = path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    use std::io::Write;
    if let Ok(mut f) = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&path)
    {
        let _ = writeln!(f, "{key}\t{ratio}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stamp in the cache key is this executable's size and modification time, so a rebuilt
    /// strata (another size or time) cannot find the figure an earlier build cached.
    #[test]
    fn build_stamp_is_the_executables_size_and_time() {
        let meta = std::fs::metadata(std::env::current_exe().unwrap()).unwrap();
        let since = meta
            .modified()
            .unwrap()
            .duration_since(std::time::UNIX_EPOCH);
        let t = since.unwrap();
        let want = format!("{}@{}.{:09}", meta.len(), t.as_secs(), t.subsec_nanos());
        assert_eq!(build_stamp(), want);
    }

    /// The key follows what the scene's mesh file holds: the same file text with an edited mesh
    /// beside it is another key, so a probe is measured again rather than served stale.
    #[test]
    fn the_key_changes_with_a_mesh_the_scene_reads() {
        let dir = std::env::temp_dir().join(format!("strata-probe-key-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene_path = dir.join("s.toml");
        std::fs::write(
            &scene_path,
            "[camera]\neye = [0, 0, -3]\nlook_at = [0, 0, 0]\nfov = 40\n\
             [materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\nemission = 1\n\
             [[shapes]]\ntype = \"mesh\"\nfile = \"t.obj\"\nmaterial = \"m\"\n",
        )
        .unwrap();
        let key_with = |obj: &str| {
            std::fs::write(dir.join("t.obj"), obj).unwrap();
            let scene = stratapt_import::scene_file::load(&scene_path).unwrap();
            key("lavapipe | Mesa", &scene, &scene.settings)
        };
        let a = key_with("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let same = key_with("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let moved = key_with("v 0 0 0\nv 1 0 0\nv 0 2 0\nf 1 2 3\n");
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(a, same);
        assert_ne!(a, moved);
    }
}
