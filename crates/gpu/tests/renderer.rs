//! The renderer's host side on lavapipe: batching and cancellation, ray counts against the CPU
//! reference, and clear refusals of devices that cannot run the kernel.

use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use stratapt_film::Render;
use stratapt_gpu::{
    testing::software_device, BvhLayout, GpuError, Renderer, SceneBinding, MAX_UNIFORM_SCENE_WORDS,
    MIN_UNIFORM_SCENE_WORDS,
};
use stratapt_scene::{FlatScene, RenderSettings};

fn cornell(size: u32) -> FlatScene {
    let mut scene =
        stratapt_import::scene_file::load(Path::new("../../scenes/cornell-box.toml")).unwrap();
    (scene.camera.width, scene.camera.height) = (size, size);
    scene
}

fn renderer() -> Renderer {
    let (device, queue) = software_device().unwrap_or_else(|e| panic!("{e}"));
    Renderer::new(&device, &queue).map(with_cpu_twins).unwrap()
}

#[test]
fn every_pixel_gets_every_sample_across_batches() {
    let scene = cornell(24);
    let settings = RenderSettings {
        pattern_spp: 37,
        ..scene.settings
    };
    let reported = AtomicU64::new(0);
    let (film, stats) = renderer()
        .render(
            &scene,
            &settings,
            &|n| {
                reported.fetch_add(n, Ordering::Relaxed);
            },
            None,
        )
        .unwrap();
    assert!(stats.dispatches > 1, "37 spp should take several batches");
    assert!(film.count.iter().all(|&c| c == 37));
    assert_eq!(stats.samples, 24 * 24 * 37);
    assert_eq!(reported.into_inner(), stats.samples, "progress adds up");
    assert!(!stats.cancelled);
    assert_eq!(stats.non_finite, 0);
}

#[test]
fn cancel_keeps_whole_batches() {
    let scene = cornell(16);
    let settings = RenderSettings {
        pattern_spp: 1000,
        ..scene.settings
    };
    let cancel = AtomicBool::new(false);
    // Cancel as soon as the first batch is in.
    let (film, stats) = renderer()
        .render(
            &scene,
            &settings,
            &|_| cancel.store(true, Ordering::Relaxed),
            Some(&cancel),
        )
        .unwrap();
    assert!(stats.cancelled);
    assert_eq!(stats.dispatches, 1);
    let spp = film.held_spp();
    assert!((1..1000).contains(&spp), "spp {spp}");
    assert!(
        film.count.iter().all(|&c| c == spp),
        "same count everywhere"
    );
    assert_eq!(stats.samples, 16 * 16 * spp as u64);
}

/// A Ctrl-C in the middle of a batch of several bands (each dispatched while the last one's
/// sums are read back) drops that batch's bands: the film keeps whole batches only.
#[test]
fn cancel_in_the_middle_of_a_batch_drops_its_bands() {
    let scene = cornell(16);
    let settings = RenderSettings {
        pattern_spp: 1000,
        ..scene.settings
    };
    let mut banded = renderer();
    // Bands of 2 rows: every batch is 8 dispatches or more (twins' rows too).
    banded.set_max_dispatch_pixels(Some(16 * 2));
    let first_batch = 16 * 16; // 1 spp of the film's pixels
    let done = AtomicU64::new(0);
    let cancel = AtomicBool::new(false);
    // Cancel once the second batch's first band is in.
    let (film, stats) = banded
        .render(
            &scene,
            &settings,
            &|n| {
                if done.fetch_add(n, Ordering::Relaxed) + n > first_batch {
                    cancel.store(true, Ordering::Relaxed);
                }
            },
            Some(&cancel),
        )
        .unwrap();
    assert!(stats.cancelled);
    assert!(stats.dispatches > 8, "{} dispatches", stats.dispatches);
    assert_eq!(film.held_spp(), 1, "only the first batch is whole");
    assert!(film.count.iter().all(|&c| c == 1), "same count everywhere");
    assert_eq!(stats.samples, first_batch);
    // Its sums are the first batch's alone: the first sample of the same render.
    let mut alone = stratapt_film::Film::for_render(&scene, &settings);
    banded
        .render_into(&scene, &settings, &mut alone, 1, &|_| {}, None)
        .unwrap();
    assert_eq!(film.sum, alone.sum);
}

/// Both renderers trace the same paths (same samples, same decisions), so they trace the same
/// number of rays, up to the rare path whose f32 results differ in the last bits.
#[test]
fn traces_as_many_rays_as_the_cpu_reference() {
    let scene = cornell(32);
    let settings = RenderSettings {
        pattern_spp: 8,
        ..scene.settings
    };
    let (_, gpu) = renderer().render(&scene, &settings, &|_| {}, None).unwrap();
    let (_, cpu) = stratapt_cpu::render(&scene, &settings, &|_| {}, None);
    let per_path = cpu.rays as f64 / cpu.samples as f64;
    assert!(
        per_path > 2.0,
        "a Cornell path with NEE traces several rays: {per_path}"
    );
    let diff = (gpu.rays as f64 - cpu.rays as f64).abs() / cpu.rays as f64;
    assert!(diff < 1e-3, "gpu {} rays, cpu {} rays", gpu.rays, cpu.rays);
}

/// Either BVH layout can be forced; both render the same image (the same samples, traversals
/// that differ only at exact ties), and the specialization follows the layout.
#[test]
fn both_bvh_layouts_render_the_same_image() {
    let scene = cornell(32);
    let settings = RenderSettings {
        pattern_spp: 4,
        ..scene.settings
    };
    let mut renderer = renderer();
    assert_eq!(
        renderer.bvh_layout(),
        BvhLayout::for_adapter(wgpu::DeviceType::Cpu),
        "lavapipe gets the software default"
    );
    let films = BvhLayout::ALL.map(|bvh| {
        renderer.set_bvh_layout(bvh);
        assert_eq!(renderer.specialize(&scene, &settings).bvh, bvh);
        renderer.render(&scene, &settings, &|_| {}, None).unwrap().0
    });
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-5 * a.abs().max(b.abs()) + 1e-7;
    let same = (0..films[0].sum.len())
        .filter(|&i| (0..3).all(|c| close(films[0].sum[i][c], films[1].sum[i][c])))
        .count();
    assert!(
        same * 100 >= films[0].sum.len() * 99,
        "{same} of {} pixels agree to rounding",
        films[0].sum.len()
    );
}

/// The scene's arrays read from their uniform copy render the same image, bit for bit, as read
/// from their storage buffers (the same words, loaded another way): the Cornell box in either
/// BVH layout, and the scenes that read what it does not (shading normals, conductors and
/// dielectrics, triangle and disk lights, a sky, motions). lavapipe reads the copy by default, and
/// a scene too large for it from storage.
#[test]
fn both_scene_bindings_render_the_same_image() {
    let mut renderer = renderer();
    assert_eq!(
        renderer.scene_binding(),
        SceneBinding::for_adapter(wgpu::DeviceType::Cpu)
    );
    assert_eq!(renderer.scene_binding(), SceneBinding::Uniform);
    let bits = |f: &stratapt_film::Film| {
        f.sum
            .iter()
            .chain(&f.sum_sq)
            .flatten()
            .map(|x| x.to_bits())
            .collect::<Vec<_>>()
    };
    let mut same = |name: &str, scene: &FlatScene, bvh| {
        renderer.set_bvh_layout(bvh);
        let settings = RenderSettings {
            pattern_spp: 4,
            ..scene.settings
        };
        let films = SceneBinding::ALL.map(|binding| {
            renderer.set_scene_binding(binding);
            let spec = renderer.specialize(scene, &settings);
            assert_eq!(
                spec.uniform_scene,
                binding == SceneBinding::Uniform,
                "{name}"
            );
            let (film, stats) = renderer.render(scene, &settings, &|_| {}, None).unwrap();
            assert_eq!(
                stats.uniform_scene, spec.uniform_scene,
                "{name}: the stats say so"
            );
            film
        });
        assert!(films[0].sum.iter().flatten().any(|&x| x > 0.0), "{name}");
        let (a, b) = (bits(&films[0]), bits(&films[1]));
        let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert_eq!(
            differ,
            0,
            "{name}, {bvh}: {differ} of {} sums differ",
            a.len()
        );
    };
    let cornell = cornell(24);
    for bvh in BvhLayout::ALL {
        same("cornell-box", &cornell, bvh);
    }
    for name in ["mesh", "glass", "motion-blur-object"] {
        let mut scene = stratapt_import::scene_file::load(
            &Path::new("../../scenes").join(format!("{name}.toml")),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        (scene.camera.width, scene.camera.height) = (24, 16);
        same(name, &scene, BvhLayout::default());
    }
    // The copy is as large as the device binds uniforms, up to 64 KiB (lavapipe binds that):
    // 256 triangles (1024 words with their points, and their nodes) fit it, 1024 do not and
    // are read from storage whatever the renderer prefers.
    renderer.set_scene_binding(SceneBinding::Uniform);
    let fits = |renderer: &Renderer, n| {
        let scene = triangles(n);
        renderer.specialize(&scene, &scene.settings).uniform_scene
    };
    let words = renderer.uniform_scene_words();
    assert_eq!(words, MAX_UNIFORM_SCENE_WORDS);
    assert!(fits(&renderer, words / 16) && !fits(&renderer, words / 4));
    let big = facing_triangles(words / 16);
    assert!(fits(&renderer, words / 16));
    let (film, stats) = renderer.render(&big, &big.settings, &|_| {}, None).unwrap();
    assert!(stats.uniform_scene);
    // A device that binds WebGPU's downlevel 16 KiB gets a kernel composed with a 16 KiB copy:
    // the same triangles read storage there, and render the same image; 64 still fit.
    let gpu = stratapt_gpu::adapter::open(&stratapt_gpu::adapter::AdapterChoice::Software)
        .unwrap_or_else(|e| panic!("{e}"));
    let limits = wgpu::Limits {
        max_uniform_buffer_binding_size: 16 << 10,
        ..Renderer::required_limits(&gpu.adapter).unwrap()
    };
    let (device, queue) = pollster::block_on(gpu.adapter.request_device(&wgpu::DeviceDescriptor {
        required_limits: limits,
        ..Default::default()
    }))
    .expect("a device binding 16 KiB of uniforms");
    let mut small = Renderer::new(&device, &queue).map(with_cpu_twins).unwrap();
    small.set_scene_binding(SceneBinding::Uniform);
    assert_eq!(small.uniform_scene_words(), MIN_UNIFORM_SCENE_WORDS);
    assert!(fits(&small, 64) && !fits(&small, words / 16));
    let (storage, stats) = small.render(&big, &big.settings, &|_| {}, None).unwrap();
    assert!(!stats.uniform_scene);
    assert!(film.sum.iter().flatten().any(|&x| x > 0.0));
    assert_eq!(
        bits(&film),
        bits(&storage),
        "256 triangles, 64 KiB copy vs storage"
    );
}

/// A device opened with the WebGPU default limits (8 storage buffers per stage) cannot bind
/// the kernel: the error says so and how to fix it, rather than a validation panic later.
#[test]
fn default_limits_are_refused_with_the_fix() {
    let gpu = stratapt_gpu::adapter::open(&stratapt_gpu::adapter::AdapterChoice::Software)
        .unwrap_or_else(|e| panic!("{e}"));
    let (device, queue) = pollster::block_on(gpu.adapter.request_device(&Default::default()))
        .expect("a device with default limits");
    match Renderer::new(&device, &queue) {
        Err(GpuError::Unsupported(message)) => {
            assert!(message.contains("storage buffers"), "{message}");
            assert!(message.contains("adapter.limits()"), "{message}");
        }
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("the default limits allow only 8 storage buffers"),
    }
}

/// Twin pixels (virtual rows after the film) sample the same pixels with the same independent
/// randomization as the CPU's: every twin's sum agrees with the CPU's to f32 rounding, in films
/// whose twins span several rows and bands (2×2 blocks at 40×40; 4×4 blocks with clamped
/// partial blocks at the edges at 66×66), and so does the calibration. The peak twins, which
/// the CPU reference renders for both, go to nearly the same pixels and agree bit for bit.
#[test]
fn twins_match_the_cpu() {
    for side in [40, 66] {
        let scene = cornell(side);
        let settings = RenderSettings {
            pattern_spp: 12,
            ..scene.settings
        };
        assert!(settings.twins());
        let mut renderer = renderer();
        renderer.set_max_dispatch_pixels(Some(side * 7));
        let (gpu, _) = renderer.render(&scene, &settings, &|_| {}, None).unwrap();
        let cpu = stratapt_cpu::render(&scene, &settings, &|_| {}, None).0;
        assert_eq!(gpu.twin_sum.len(), cpu.twin_sum.len());
        assert!(gpu.twin_layout().rows() > 1);
        let mut close = 0;
        for (g, c) in gpu.twin_sum.iter().zip(&cpu.twin_sum) {
            let tol = |v: f64| 1e-4 * v.abs().max(1e-3);
            if (0..3).all(|k| (g[k] - c[k]).abs() <= tol(c[k])) {
                close += 1;
            }
        }
        // Shared samples: all but the rare one whose path flips on an f32 rounding.
        assert!(
            close * 100 >= 97 * cpu.twin_sum.len(),
            "{side}²: {close} of {} twins close",
            cpu.twin_sum.len()
        );
        // Peak twins: chosen from each film's own variances (nearly the same pixels), rendered
        // by the CPU reference for both, so the same pixel's peak twin is the same bits.
        assert!(!cpu.peaks.is_empty());
        assert_eq!(gpu.peaks.len(), cpu.peaks.len());
        let shared: Vec<_> = gpu
            .peaks
            .iter()
            .filter_map(|g| {
                cpu.peaks
                    .iter()
                    .find(|c| (c.pixel, c.replica) == (g.pixel, g.replica))
                    .map(|c| (g, c))
            })
            .collect();
        assert!(
            shared.len() * 10 >= 9 * cpu.peaks.len(),
            "{side}²: {} of {} peak pixels shared",
            shared.len(),
            cpu.peaks.len()
        );
        assert!(
            shared.iter().all(|(g, c)| g == c),
            "{side}²: peak twins differ"
        );
        let (kg, kc) = (gpu.calibration().film, cpu.calibration().film);
        for k in 0..3 {
            assert!(
                (kg[k] - kc[k]).abs() <= 0.05 * kc[k],
                "{side}²: κ gpu {kg:?} cpu {kc:?}"
            );
        }
    }
}

/// A device requested with `Renderer::required_limits` runs the kernel: an embedding tool
/// asks for what the renderer needs up front, and the render matches the CPU's.
#[test]
fn required_limits_open_a_device_that_renders() {
    let gpu = stratapt_gpu::adapter::open(&stratapt_gpu::adapter::AdapterChoice::Software)
        .unwrap_or_else(|e| panic!("{e}"));
    let limits = Renderer::required_limits(&gpu.adapter).unwrap();
    assert_eq!(limits.max_storage_buffers_per_shader_stage, 14);
    let desc = wgpu::DeviceDescriptor {
        required_limits: limits,
        ..Default::default()
    };
    let (device, queue) = pollster::block_on(gpu.adapter.request_device(&desc)).unwrap();
    let renderer = Renderer::new(&device, &queue).map(with_cpu_twins).unwrap();
    let scene = cornell(8);
    let settings = RenderSettings {
        pattern_spp: 8,
        ..scene.settings
    };
    let film = renderer.render(&scene, &settings, &|_| {}, None).unwrap().0;
    let cpu = stratapt_cpu::render(&scene, &settings, &|_| {}, None).0;
    let (g, c) = (film.image_mean().0, cpu.image_mean().0);
    for k in 0..3 {
        assert!((g[k] - c[k]).abs() <= 1e-4 * c[k].abs(), "{g:?} vs {c:?}");
    }
}

/// 100 000 samples per pixel of a constant sky: every sample is the same f32, so the mean must
/// come back to within the rounding of one batch's f32 sum (≤ 256 samples: 256 · 2⁻²⁴ ≈ 1.5e-5),
/// not drift as a 100k-term f32 sum would (≈ 6e-3). Batches fold into f64 on the host.
#[test]
fn a_hundred_thousand_samples_stay_accurate() {
    let toml = r#"
[camera]
eye = [0, 0, 0]
look_at = [0, 0, 1]
fov = 40
[film]
width = 4
height = 4
[render]
spp = 100000
[sky]
color = [0.1, 0.3, 0.7]
"#;
    let scene = stratapt_import::load::load_str(toml, Path::new("sky.toml")).unwrap();
    let (film, stats) = renderer()
        .render(&scene, &scene.settings, &|_| {}, None)
        .unwrap();
    assert_eq!(film.held_spp(), 100_000);
    assert!(stats.dispatches > 1);
    let sky = [0.1f32, 0.3, 0.7];
    for i in 0..16 {
        let mean = film.mean(i);
        for c in 0..3 {
            let exact = sky[c] as f64;
            let rel = (mean[c] - exact).abs() / exact;
            assert!(
                rel < 2e-5,
                "pixel {i} channel {c}: {} vs {exact} ({rel:.1e})",
                mean[c]
            );
        }
    }
}

/// A film dispatched in bands of a few rows (as large films are, to fit the accumulator and the
/// time a dispatch may take) gets every sample once, the same image as in one dispatch.
#[test]
fn bands_of_rows_cover_the_film_once() {
    let mut scene = cornell(16);
    (scene.camera.width, scene.camera.height) = (40, 30);
    let settings = RenderSettings {
        pattern_spp: 6,
        ..scene.settings
    };
    let (whole, _) = renderer().render(&scene, &settings, &|_| {}, None).unwrap();
    let mut banded = renderer();
    // Two rows per dispatch, 15 bands per batch (the last one cut by the film's edge with 7).
    banded.set_max_dispatch_pixels(Some(100));
    let (film, stats) = banded.render(&scene, &settings, &|_| {}, None).unwrap();
    assert!(stats.dispatches >= 15, "{} dispatches", stats.dispatches);
    assert!(film.count.iter().all(|&c| c == 6));
    // Per-batch f32 sums round differently when batches split differently: 1e-5 covers it.
    for i in 0..film.count.len() {
        let (a, b) = (film.mean(i), whole.mean(i));
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-5 * b[c].abs() + 1e-7,
                "pixel {i}: {a:?} vs {b:?}"
            );
        }
    }
}

/// Run only as a child of `gpu_tests_refuse_gl_unless_allowed`: opens the tests' device.
#[test]
#[ignore = "run by gpu_tests_refuse_gl_unless_allowed in a process without Vulkan"]
fn child_opens_the_test_device() {
    software_device().unwrap_or_else(|e| panic!("{e}"));
}

/// Without a Vulkan driver (the ICD list pointed nowhere) the GPU tests fail, saying so,
/// instead of passing on Mesa's GL llvmpipe; with `STRATA_TESTS_ALLOW_GL=1` they may use it.
#[test]
fn gpu_tests_refuse_gl_unless_allowed() {
    let run = |allow: bool| {
        let mut child = std::process::Command::new(std::env::current_exe().unwrap());
        child
            .args([
                "--exact",
                "child_opens_the_test_device",
                "--include-ignored",
            ])
            .env("VK_ICD_FILENAMES", "/nonexistent")
            .env_remove(stratapt_gpu::testing::ALLOW_GL);
        if allow {
            child.env(stratapt_gpu::testing::ALLOW_GL, "1");
        }
        let out = child.output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string()
            + &String::from_utf8_lossy(&out.stderr);
        (out.status.success(), text)
    };
    let (ok, text) = run(false);
    assert!(!ok, "passed without Vulkan:\n{text}");
    assert!(
        text.contains("no software Vulkan adapter") || text.contains("no software adapter"),
        "{text}"
    );
    // With permission it runs on GL llvmpipe, where this machine has one, and says so.
    let (ok, text) = run(true);
    if text.contains("llvmpipe") {
        assert!(ok, "{text}");
        assert!(
            text.contains("GPU tests on") && text.contains("Gl"),
            "{text}"
        );
    }
}

/// `n` small triangles side by side.
fn triangles(n: u32) -> FlatScene {
    let mut toml = String::from(
        "[camera]\neye = [0, 0, -3]\nlook_at = [0, 0, 0]\nfov = 40\n[film]\nwidth = 4\nheight = 4\n\
         [materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\n",
    );
    for k in 0..n {
        let x = k as f64 * 1e-3;
        toml += &format!(
            "[[shapes]]\ntype = \"triangle\"\nvertices = [[{x}, 0, 0], [{x}, 1, 0], [{x}, 0, 1]]\n\
             material = \"m\"\n"
        );
    }
    stratapt_import::load::load_str(&toml, std::path::Path::new("triangles.toml")).unwrap()
}

/// `n` small triangles facing the camera, in a grid with rows at different depths, lit by a sky:
/// an image every triangle shows in.
fn facing_triangles(n: u32) -> FlatScene {
    let mut toml = String::from(
        "[camera]\neye = [0, 0, -4]\nlook_at = [0, 0, 0]\nfov = 40\n[film]\nwidth = 24\nheight = 24\n\
         [render]\nspp = 4\n[materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\n\
         [sky]\ncolor = [0.5, 0.6, 0.7]\n",
    );
    let side = (n as f64).sqrt().ceil() as u32;
    for k in 0..n {
        let (i, j) = (k % side, k / side);
        let (x, y) = (i as f64 / side as f64 - 0.5, j as f64 / side as f64 - 0.5);
        let (z, s) = (i as f64 * 0.01, 1.2 / side as f64);
        toml += &format!(
            "[[shapes]]\ntype = \"triangle\"\nvertices = [[{x}, {y}, {z}], [{}, {y}, {z}], [{x}, {}, {z}]]\n\
             material = \"m\"\n",
            x + s,
            y + s
        );
    }
    stratapt_import::load::load_str(&toml, std::path::Path::new("facing.toml")).unwrap()
}

/// A BVH deeper than the traversal stack, and scene arrays larger than the device's
/// storage-buffer limit, are refused with a message saying so (not a device error or a wrong
/// image).
#[test]
fn scenes_beyond_the_device_are_refused_with_a_message() {
    let (device, queue) = stratapt_gpu::testing::software_device().unwrap();
    let mut renderer = Renderer::new(&device, &queue).map(with_cpu_twins).unwrap();
    renderer.set_bvh_layout(stratapt_gpu::BvhLayout::Bvh2);
    // A chain 70 levels deep: inner node 2i has leaf 2i + 1 (triangle i) and node 2i + 2.
    let mut deep = triangles(71);
    let template = deep.bvh.nodes[0];
    deep.bvh.nodes = (0..141u32)
        .map(|i| {
            let leaf = i % 2 == 1 || i == 140;
            obvhs::bvh2::node::Bvh2Node {
                prim_count: leaf as u32,
                first_index: if leaf { i / 2 } else { i + 1 },
                ..template
            }
        })
        .collect();
    let settings = RenderSettings {
        pattern_spp: 1,
        ..deep.settings
    };
    let message = renderer
        .render(&deep, &settings, &|_| {}, None)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("70 levels deep") && message.contains("traversal stack holds 64"),
        "{message}"
    );
    // A device allowing 64 KiB per storage buffer, and 2000 triangles of 64 bytes.
    let gpu = stratapt_gpu::adapter::open(&stratapt_gpu::adapter::AdapterChoice::Software)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut limits = Renderer::required_limits(&gpu.adapter).unwrap();
    limits.max_storage_buffer_binding_size = 64 << 10;
    let desc = wgpu::DeviceDescriptor {
        required_limits: limits,
        ..Default::default()
    };
    let (device, queue) = pollster::block_on(gpu.adapter.request_device(&desc)).unwrap();
    let small = Renderer::new(&device, &queue).map(with_cpu_twins).unwrap();
    let many = triangles(2000);
    let message = small
        .render(&many, &settings, &|_| {}, None)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("storage-buffer limit of 64.0 KiB"),
        "{message}"
    );
}

/// A scene whose primitives one binding cannot hold continues them in the second binding
/// (`PRIMS_SPLIT`): on a device whose binding limit is below the primitives' bytes, the mesh
/// scene renders the same image, bit for bit, as where they fit one binding.
#[test]
fn primitives_past_the_binding_limit_render_the_same_image() {
    let mut scene = stratapt_import::scene_file::load(Path::new("../../scenes/mesh.toml")).unwrap();
    (scene.camera.width, scene.camera.height) = (16, 12);
    let settings = RenderSettings {
        pattern_spp: 4,
        ..scene.settings
    };
    let sizes = stratapt_gpu::scene_bytes(&scene, BvhLayout::default()).unwrap();
    let prims = sizes.iter().find(|(n, _)| *n == "primitives").unwrap().1;
    // The smallest limit every other array fits, in whole primitives.
    let others = sizes
        .iter()
        .filter(|(n, _)| *n != "primitives" && !n.starts_with("uniform"))
        .map(|(_, b)| *b)
        .max()
        .unwrap();
    let limit = others.next_multiple_of(16);
    assert!(limit < prims, "{limit} B holds all {prims} B of primitives");

    let split = renderer_with_binding_limit(limit);
    assert_eq!(
        split.specialize(&scene, &settings).prims_split as u64,
        limit / 16
    );
    let whole = renderer();
    assert_eq!(whole.specialize(&scene, &settings).prims_split, 0);

    assert_same_film_bits(&split, &whole, &scene, &settings);
}

/// Tables (texture records, texels, coatings) that one binding cannot hold continue in the
/// second binding (`TABLES_SPLIT`): on a device whose binding limit is below the tables' bytes,
/// the textured scene renders the same image, bit for bit, as where they fit one binding.
#[test]
fn tables_past_the_binding_limit_render_the_same_image() {
    let mut scene =
        stratapt_import::scene_file::load(Path::new("../../scenes/textures.toml")).unwrap();
    (scene.camera.width, scene.camera.height) = (16, 10);
    let settings = RenderSettings {
        pattern_spp: 4,
        ..scene.settings
    };
    let sizes = stratapt_gpu::scene_bytes(&scene, BvhLayout::default()).unwrap();
    let is_tables = |n: &str| n.ends_with("environment-map tables");
    let tables = sizes.iter().find(|(n, _)| is_tables(n)).unwrap().1;
    // The smallest limit every other array and half the tables fit.
    let others = sizes
        .iter()
        .filter(|(n, _)| !is_tables(n) && !n.starts_with("uniform"))
        .map(|(_, b)| *b)
        .max()
        .unwrap();
    let limit = others.max(tables.div_ceil(2)).next_multiple_of(16);
    assert!(limit < tables, "{limit} B holds all {tables} B of tables");

    let split = renderer_with_binding_limit(limit);
    assert_eq!(
        split.specialize(&scene, &settings).tables_split as u64,
        limit / 4
    );
    let whole = renderer();
    assert_eq!(whole.specialize(&scene, &settings).tables_split, 0);

    assert_same_film_bits(&split, &whole, &scene, &settings);
}

/// A renderer on the software adapter whose storage bindings hold at most `limit` bytes.
fn renderer_with_binding_limit(limit: u64) -> Renderer {
    let gpu = stratapt_gpu::adapter::open(&stratapt_gpu::adapter::AdapterChoice::Software)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut limits = gpu.adapter.limits();
    limits.max_storage_buffer_binding_size = limit;
    let desc = wgpu::DeviceDescriptor {
        required_limits: limits,
        ..Default::default()
    };
    let (device, queue) = pollster::block_on(gpu.adapter.request_device(&desc)).unwrap();
    Renderer::new(&device, &queue).map(with_cpu_twins).unwrap()
}

/// `a` and `b` render `scene` to films whose sums are the same bits.
fn assert_same_film_bits(a: &Renderer, b: &Renderer, scene: &FlatScene, settings: &RenderSettings) {
    let bits = |f: &stratapt_film::Film| {
        f.sum
            .iter()
            .flatten()
            .map(|x| x.to_bits())
            .collect::<Vec<_>>()
    };
    let fa = a.render(scene, settings, &|_| {}, None).unwrap().0;
    let fb = b.render(scene, settings, &|_| {}, None).unwrap().0;
    assert_eq!(bits(&fa), bits(&fb));
}

/// `renderer` with its films' peak twins rendered by the CPU reference, as the `strata` command
/// builds it.
fn with_cpu_twins(renderer: Renderer) -> Renderer {
    renderer.with_peak_twins(std::sync::Arc::new(stratapt_cpu::render_peak_twins))
}
