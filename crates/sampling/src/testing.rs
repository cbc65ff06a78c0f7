//! Helpers for the workspace's tests: one deterministic generator of random test inputs, and
//! (feature `chi2`) the chi-square test of sampling routines, `chi2`.
//!
//! Not part of the renderer: nothing here runs while rendering. It is public because the other
//! crates' tests (integration tests cannot see `#[cfg(test)]` items) and the test suites of
//! embedders need it, and this is the lowest crate all of them depend on.

use glam::{Vec2, Vec3};

use crate::warp;

#[cfg(feature = "chi2")]
pub mod chi2;

/// The generator of random test inputs: a 64-bit linear congruential generator (Knuth's MMIX
/// constants, as in PCG), read from its top bits.
///
/// Tests build random scenes, rays and probe inputs from it, so its streams are part of what the
/// tests check: every method consumes a documented number of steps and computes its value with
/// the float operations written here, and changing either changes the tests' inputs. Tests must
/// not depend on a sampler's or a crate's random stream (those may change); this one stays.
///
/// The field is the state; `TestRng(seed)` starts a stream.
#[derive(Clone, Debug)]
pub struct TestRng(pub u64);

impl TestRng {
    /// Advances one step and returns the whole new state (its low bits are weak; prefer the
    /// methods below, which read the top bits).
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0
    }

    /// The top 32 bits of one step.
    pub fn u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }

    /// An index in `0..n` (`0` when `n` is 0) from the top 31 bits of one step (modulo, so
    /// slightly biased for large `n`, which tests do not care about).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() >> 33) % n.max(1) as u64) as usize
    }

    /// One element of a non-empty slice, chosen by [`below`](Self::below).
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }

    /// A float in `[0, 1)`, every multiple of 2⁻²⁴ equally likely (the top 24 bits of one step).
    pub fn f32(&mut self) -> f32 {
        ((self.next_u64() >> 40) as f32) / (1u64 << 24) as f32
    }

    /// A float in `[lo, hi)`: `lo + (hi − lo)·u`, one step.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }

    /// A float between `lo` and `hi` (both positive), uniform in its logarithm, one step.
    pub fn log_range(&mut self, lo: f32, hi: f32) -> f32 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.f32()).exp()
    }

    /// A point of `[0, 1)²`, two steps (x first).
    pub fn u2(&mut self) -> Vec2 {
        Vec2::new(self.f32(), self.f32())
    }

    /// A point of the cube `[−r, r)³`, three [`range`](Self::range) steps (x, y, z).
    pub fn point(&mut self, r: f32) -> Vec3 {
        Vec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }

    /// A uniform unit vector by the sphere warp, exactly two steps.
    pub fn sphere(&mut self) -> Vec3 {
        warp::uniform_sphere(self.u2())
    }

    /// [`sphere`](Self::sphere) folded onto the upper hemisphere (`z ≥ 0`), two steps.
    pub fn upper(&mut self) -> Vec3 {
        let v = self.sphere();
        Vec3::new(v.x, v.y, v.z.abs())
    }

    /// A uniform unit vector by rejection from the cube `[−1, 1)³` (three steps per try, about
    /// 1.9 tries). Kept beside [`sphere`](Self::sphere) because tests built on each rely on its
    /// stream; it reaches every float direction, not only those of the warp's two floats.
    pub fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.f32(), self.f32(), self.f32()) * 2.0 - 1.0;
            let l2 = v.length_squared();
            if l2 > 1e-4 && l2 <= 1.0 {
                return v / l2.sqrt();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stream is part of the tests' inputs: its first steps from seed 7, and each reader's
    /// bits of them.
    #[test]
    fn stream_is_pinned() {
        let mut rng = TestRng(7);
        assert_eq!(rng.next_u64(), 0x7e43_28bc_0f7d_fb8a);
        assert_eq!(rng.u32(), 0xf4a6_1a7f);
        assert_eq!(rng.f32(), 15_209_818.0 / 16_777_216.0);
        let mut rng = TestRng(7);
        assert_eq!(
            rng.below(1000),
            (0x7e43_28bc_0f7d_fb8a_u64 >> 33) as usize % 1000
        );
        assert_eq!(TestRng(7).f32(), 8_274_728.0 / 16_777_216.0);
        assert_eq!(TestRng(7).below(0), 0);
    }

    #[test]
    fn values_stay_in_range() {
        let mut rng = TestRng(1);
        for _ in 0..10_000 {
            let u = rng.f32();
            assert!((0.0..1.0).contains(&u));
            assert!(rng.below(3) < 3);
            let l = rng.log_range(1e-3, 1e3);
            assert!((0.99e-3..=1.01e3).contains(&l));
            assert!((rng.unit().length() - 1.0).abs() < 1e-6);
            assert!(rng.upper().z >= 0.0);
        }
    }
}
