//! `shaders/sampler.wgsl` against `stratapt_sampling::Sampler`: every value (1D, 2D and the joint
//! 1D + 2D domain) bit for bit, for every sampler kind, over seeds, sample counts, pixels, sample
//! indices (later passes and huge values included) and dimensions. Runs on lavapipe.

use std::path::Path;

use stratapt_gpu::testing;
use stratapt_sampling::hash::lowbias32;
use stratapt_sampling::{Sampler, SamplerKind};
use stratapt_scene::{FlatScene, RenderSettings};

/// Sampler kind as the shader codes it (`SAMPLER_*`).
fn code(kind: SamplerKind) -> u32 {
    kind.id()
}

fn scene() -> FlatScene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn device() -> (wgpu::Device, wgpu::Queue) {
    testing::software_device().unwrap_or_else(|e| panic!("{e}"))
}

/// What a query asks for (its code in the probe's input).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Domain {
    /// `sample_1d` at `dim`.
    One = 0,
    /// `sample_2d` at `dim`.
    Two = 1,
    /// `sample_1d_2d`, the choice at `dim` and the point at `dim + 1`.
    Joint = 2,
}

/// One query: sampler settings, pixel, index, dim, and the domain.
#[derive(Clone, Copy, Debug)]
struct Query {
    kind: SamplerKind,
    spp: u32,
    seed: u32,
    pixel: [u32; 2],
    index: u32,
    dim: u32,
    domain: Domain,
}

impl Query {
    /// The Rust sampler's values, as bits (1D: value, 0, 0; 2D: both coordinates, 0; joint:
    /// the choice and the point).
    fn expected(&self) -> [u32; 3] {
        let s = Sampler {
            kind: self.kind,
            spp: self.spp,
            seed: self.seed,
        };
        let (pixel, index, dim) = (self.pixel, self.index, self.dim);
        match self.domain {
            Domain::One => [s.sample_1d(pixel, index, dim).to_bits(), 0, 0],
            Domain::Two => {
                let v = s.sample_2d(pixel, index, dim);
                [v.x.to_bits(), v.y.to_bits(), 0]
            }
            Domain::Joint => {
                let (c, p) = s.sample_1d_2d(pixel, index, dim, dim.wrapping_add(1));
                [c.to_bits(), p.x.to_bits(), p.y.to_bits()]
            }
        }
    }
}

/// Pixels: the corner, neighbours, a film-sized one, and large / hashed coordinates.
fn pixels() -> Vec<[u32; 2]> {
    vec![
        [0, 0],
        [1, 0],
        [255, 191],
        [4095, 17],
        [lowbias32(7), lowbias32(8)],
        [u32::MAX, 3],
    ]
}

/// Indices for `spp` samples per pass: first pass, pass boundaries, later passes, huge values.
fn indices(spp: u32) -> Vec<u32> {
    let n = spp.max(1);
    let mut v = vec![
        0,
        1,
        n / 2,
        n - 1,
        n,
        n + 1,
        2 * n + 3,
        7 * n + 5,
        123_456_789,
        0x7fff_ffff,
        u32::MAX,
        lowbias32(n),
    ];
    v.sort_unstable();
    v.dedup();
    v
}

/// Dimensions 0..40 plus the top of the range (2D wraps `dim + 1`).
fn dims() -> impl Iterator<Item = u32> {
    (0..40).chain([1000, u32::MAX - 1, u32::MAX])
}

/// Every query of the sweep for `kind`, `spp`, `seed`.
fn sweep(kind: SamplerKind, spp: u32, seed: u32, out: &mut Vec<Query>) {
    for pixel in pixels() {
        for index in indices(spp) {
            for dim in dims() {
                for domain in [Domain::One, Domain::Two, Domain::Joint] {
                    out.push(Query {
                        kind,
                        spp,
                        seed,
                        pixel,
                        index,
                        dim,
                        domain,
                    });
                }
            }
        }
    }
}

/// Compare the GPU's bits with the Rust sampler's; panics listing the first mismatches.
fn check(queries: &[Query], got: &[u32]) {
    let mut bad = Vec::new();
    for (q, g) in queries.iter().zip(got.chunks_exact(3)) {
        let want = q.expected();
        if g != want {
            bad.push(format!("{q:?}: gpu {g:08x?} cpu {want:08x?}"));
        }
    }
    assert!(
        bad.is_empty(),
        "{} of {} samples differ, first: \n{}",
        bad.len(),
        queries.len(),
        bad[..bad.len().min(20)].join("\n")
    );
}

/// Every kind, seed and spp, through `sampler_sample_{1,2}d_with` (explicit settings, one
/// dispatch).
#[test]
fn samples_match_rust_bit_for_bit() {
    let mut queries = Vec::new();
    // 0 and 2^25 check the clamp of the stratum count; 2^24 - 1 is the largest count.
    let spps = [1, 2, 7, 16, 64, 100, 1000, 12_345, 0xff_ffff, 0, 0x200_0000];
    for kind in SamplerKind::ALL {
        for seed in [0, 1, 0xdead_beef] {
            for spp in spps {
                sweep(kind, spp, seed, &mut queries);
            }
        }
    }
    let input: Vec<u32> = queries
        .iter()
        .flat_map(|q| {
            [
                code(q.kind),
                q.spp,
                q.seed,
                q.pixel[0],
                q.pixel[1],
                q.index,
                q.dim,
                q.domain as u32,
            ]
        })
        .collect();
    let probe = r#"
fn probe(i: u32) {
    let b = 8u * i;
    let kind = probe_in[b];
    let spp = probe_in[b + 1u];
    let seed = probe_in[b + 2u];
    let pixel = vec2u(probe_in[b + 3u], probe_in[b + 4u]);
    let index = probe_in[b + 5u];
    let dim = probe_in[b + 6u];
    var v = vec3f(0.0);
    switch probe_in[b + 7u] {
        case 0u: {
            v.x = sampler_sample_1d_with(kind, spp, seed, pixel, index, dim);
        }
        case 1u: {
            v = vec3f(sampler_sample_2d_with(kind, spp, seed, pixel, index, dim), 0.0);
        }
        default: {
            v = sampler_sample_1d_2d_with(kind, spp, seed, pixel, index, dim, dim + 1u);
        }
    }
    probe_out[3u * i] = bitcast<u32>(v.x);
    probe_out[3u * i + 1u] = bitcast<u32>(v.y);
    probe_out[3u * i + 2u] = bitcast<u32>(v.z);
}
"#;
    let (device, queue) = device();
    let scene = scene();
    let n = queries.len();
    let got = testing::run_probe(
        &device,
        &queue,
        &scene,
        &RenderSettings::default(),
        &["sampler"],
        probe,
        &input,
        3 * n,
        n as u32,
    );
    check(&queries, &got);
    println!("sampler: {n} samples (1D, 2D and joint 1D + 2D) equal bit for bit");
}

/// The fixed entry points `sampler_sample_1d` / `sampler_sample_2d` / `sampler_sample_1d_2d` read kind, spp and seed from
/// `params`, and the pixel from `sampler_begin_pixel`.
#[test]
fn entry_points_read_params() {
    let (device, queue) = device();
    let scene = scene();
    let probe = r#"
fn probe(i: u32) {
    let b = 5u * i;
    let pixel = vec2u(probe_in[b], probe_in[b + 1u]);
    let index = probe_in[b + 2u];
    let dim = probe_in[b + 3u];
    sampler_begin_pixel(pixel);
    var v = vec3f(0.0);
    switch probe_in[b + 4u] {
        case 0u: {
            v.x = sampler_sample_1d(index, dim);
        }
        case 1u: {
            v = vec3f(sampler_sample_2d(index, dim), 0.0);
        }
        default: {
            v = sampler_sample_1d_2d(index, dim, dim + 1u);
        }
    }
    probe_out[3u * i] = bitcast<u32>(v.x);
    probe_out[3u * i + 1u] = bitcast<u32>(v.y);
    probe_out[3u * i + 2u] = bitcast<u32>(v.z);
}
"#;
    let mut total = 0;
    for kind in SamplerKind::ALL {
        for (spp, seed) in [(7, 3), (64, 0x1234_5678)] {
            let settings = RenderSettings {
                sampler: kind,
                pattern_spp: spp,
                seed,
                ..RenderSettings::default()
            };
            let mut queries = Vec::new();
            sweep(kind, spp, seed, &mut queries);
            let input: Vec<u32> = queries
                .iter()
                .flat_map(|q| [q.pixel[0], q.pixel[1], q.index, q.dim, q.domain as u32])
                .collect();
            let n = queries.len();
            let got = testing::run_probe(
                &device,
                &queue,
                &scene,
                &settings,
                &["sampler"],
                probe,
                &input,
                3 * n,
                n as u32,
            );
            check(&queries, &got);
            total += n;
        }
    }
    println!("sampler_sample_1d / sampler_sample_2d / sampler_sample_1d_2d: {total} samples equal bit for bit");
}

/// The module parses and validates alone, and with the modules the camera needs (no device).
#[test]
fn modules_validate() {
    for modules in [&["sampler"][..], &["sampler", "filter"]] {
        if let Err(e) = testing::compose(modules, "") {
            panic!("{modules:?}: {e}");
        }
    }
}
