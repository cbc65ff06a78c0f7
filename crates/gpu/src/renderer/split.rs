//! Splitting each pixel's samples over several invocations, so that a small image still fills
//! a large GPU.
//!
//! One invocation renders one pixel's samples, so a 256² render dispatches 65 536 invocations,
//! while an H100- or H200-class GPU keeps about 270 000 resident (132 streaming multiprocessors ×
//! 2 048 threads). A batch may split each pixel's samples into slices of consecutive samples,
//! one invocation each, each writing its own tile of the accumulator; the host adds the slices
//! to the film in order, so a batch split into k slices of n samples gives the film that k
//! batches of n samples would (`tests/agreement.rs` checks split renders against the CPU).

use super::MAX_BATCH_SPP;

/// Most slices a pixel's samples are split into.
pub const MAX_SPLIT: u32 = 64;

/// How a batch spreads each pixel's samples over invocations ([`crate::Renderer::set_sample_split`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SampleSplit {
    /// As many slices as bring a dispatch to the invocations the adapter keeps resident
    /// ([`SampleSplit::resident_invocations`]); none on a CPU adapter, which a dispatch of a few
    /// thousand pixels fills already.
    #[default]
    Auto,
    /// This many slices (1: one invocation per pixel), at most [`MAX_SPLIT`], as the batch's
    /// samples and the accumulator allow.
    Fixed(u32),
}

impl SampleSplit {
    /// The invocations a dispatch aims at on an adapter of this type, to fill it: 2¹⁸ on a
    /// discrete GPU (an H100/H200 keeps 270 336 threads resident; a smaller GPU gets a few
    /// slices more than it needs, which costs only accumulator memory and readback), 2¹⁶ on an
    /// integrated or virtual one, and none on a CPU (lavapipe's few threads of 8 lanes).
    pub fn resident_invocations(device_type: wgpu::DeviceType) -> u32 {
        match device_type {
            wgpu::DeviceType::DiscreteGpu => 1 << 18,
            wgpu::DeviceType::Cpu => 0,
            _ => 1 << 16,
        }
    }

    /// The slices wanted for a dispatch of `pixels` pixels on an adapter of `device_type`.
    pub fn slices(self, device_type: wgpu::DeviceType, pixels: u32) -> u32 {
        match self {
            SampleSplit::Fixed(k) => k.clamp(1, MAX_SPLIT),
            SampleSplit::Auto => Self::resident_invocations(device_type)
                .div_ceil(pixels.max(1))
                .clamp(1, MAX_SPLIT),
        }
    }

    /// `auto` or the number of slices, as `--sample-split` takes them.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s.trim() {
            "auto" => Ok(SampleSplit::Auto),
            n => match n.parse::<u32>() {
                Ok(k) if (1..=MAX_SPLIT).contains(&k) => Ok(SampleSplit::Fixed(k)),
                _ => Err(format!(
                    "expected `auto` or a number of slices from 1 to {MAX_SPLIT}"
                )),
            },
        }
    }
}

impl std::fmt::Display for SampleSplit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SampleSplit::Auto => f.write_str("auto"),
            SampleSplit::Fixed(k) => write!(f, "{k}"),
        }
    }
}

/// A batch of up to `total` samples per pixel over bands of `band_pixels`, with `wanted` slices
/// and an accumulator of `capacity` pixels: `(slices, samples per slice)`. Every slice has the
/// same number of samples, at least 1 and at most [`MAX_BATCH_SPP`] (f32 sums), so the batch
/// renders `slices · n ≤ total` samples (at least 1).
pub(super) fn plan(total: u32, wanted: u32, band_pixels: u32, capacity: u32) -> (u32, u32) {
    let fits = capacity / band_pixels.max(1);
    let slices = wanted.min(fits).min(total).clamp(1, MAX_SPLIT);
    let n = (total / slices).clamp(1, MAX_BATCH_SPP);
    (slices, n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plan_never_renders_more_than_asked_nor_overfills_a_slice_or_the_accumulator() {
        for total in [1, 2, 3, 7, 64, 255, 256, 1000, 100_000] {
            for wanted in [1, 2, 3, 5, 16, 64] {
                for (band, capacity) in [(100, 100), (100, 350), (4096, 1 << 20), (1, 1 << 20)] {
                    let (slices, n) = plan(total, wanted, band, capacity);
                    assert!(slices >= 1 && n >= 1, "{total} {wanted} {band}");
                    assert!(slices * n <= total, "{total} {wanted} {band}: {slices}×{n}");
                    assert!(n <= MAX_BATCH_SPP);
                    assert!(slices * band <= capacity.max(band));
                    assert!(slices <= wanted);
                    // No slice is wasted: as many as asked for, unless samples or room run out.
                    assert_eq!(slices, wanted.min(total).min(capacity / band).max(1));
                }
            }
        }
    }

    #[test]
    fn auto_fills_a_discrete_gpu_and_leaves_a_cpu_adapter_alone() {
        let discrete = wgpu::DeviceType::DiscreteGpu;
        assert_eq!(SampleSplit::Auto.slices(discrete, 256 * 256), 4);
        assert_eq!(SampleSplit::Auto.slices(discrete, 1024 * 1024), 1);
        assert_eq!(SampleSplit::Auto.slices(discrete, 16), MAX_SPLIT);
        assert_eq!(SampleSplit::Auto.slices(wgpu::DeviceType::Cpu, 16), 1);
        assert_eq!(SampleSplit::Fixed(3).slices(wgpu::DeviceType::Cpu, 16), 3);
        assert_eq!(SampleSplit::parse("auto"), Ok(SampleSplit::Auto));
        assert_eq!(SampleSplit::parse("8"), Ok(SampleSplit::Fixed(8)));
        assert!(SampleSplit::parse("0").is_err() && SampleSplit::parse("65").is_err());
    }
}
