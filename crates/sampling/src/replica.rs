//! Independent randomizations ("replicas") of one render, for a calibrated error estimate.
//!
//! One randomization of a stratified or Owen-scrambled Sobol point set says nothing about its own
//! error: its samples are negatively correlated, so their sample variance overstates the error of
//! their mean (5–6× on the Cornell box at 64 spp). Randomized QMC (Owen 1997; L'Ecuyer & Lemieux
//! 2002) estimates it from `R` *independent* randomizations instead: the spread of the `R`
//! replica means is an unbiased estimate of the variance of one replica's mean, whatever the
//! sampler.
//!
//! Sample `index` of a pixel belongs to replica `index % R`, as that replica's sample
//! `index / R`; replica `r` draws from the sampler with seed [`seed`]`(seed, r)` and, for the
//! stratified sampler, `ceil(spp / R)` strata. So every prefix of a progressive render holds
//! each replica's own prefix, and replica 0 of seed `s` is the unreplicated render of seed `s`.
//! Mirrored in `shaders/sampler.wgsl` (`sample_1d`, `sample_2d`).

use crate::hash::hash_combine;
use crate::{Sampler, SamplerKind};
use glam::Vec2;

/// The replica of sample `index` and its index inside that replica.
#[inline]
pub fn split(index: u32, replicas: u32) -> (u32, u32) {
    let replicas = replicas.max(1);
    (index % replicas, index / replicas)
}

/// The sampler seed of replica `replica`: the render's seed for replica 0, else
/// `hash_combine(seed, replica)`.
#[inline]
pub fn seed(seed: u32, replica: u32) -> u32 {
    if replica == 0 {
        seed
    } else {
        hash_combine(seed, replica)
    }
}

/// Samples per pixel of one replica of an `spp`-sample render: `ceil(spp / replicas)`.
#[inline]
pub fn spp(spp: u32, replicas: u32) -> u32 {
    spp.max(1).div_ceil(replicas.max(1))
}

/// How many of a pixel's samples `first .. first + count` fall in replica `replica`.
pub fn count(first: u32, count: u32, replica: u32, replicas: u32) -> u32 {
    let replicas = replicas.max(1);
    // Indices below `n` in replica r: ceil((n - r) / R) for n > r.
    let below = |n: u32| {
        if n > replica {
            (n - replica).div_ceil(replicas)
        } else {
            0
        }
    };
    below(first + count) - below(first)
}

/// A sampler split into `replicas` independent randomizations (see the module docs): the
/// sampler the integrators draw from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReplicatedSampler {
    pub kind: SamplerKind,
    /// Samples per pixel of the whole render.
    pub spp: u32,
    pub seed: u32,
    pub replicas: u32,
}

impl ReplicatedSampler {
    pub fn new(kind: SamplerKind, spp: u32, seed: u32, replicas: u32) -> Self {
        Self {
            kind,
            spp: spp.max(1),
            seed,
            replicas: replicas.max(1),
        }
    }

    /// The plain sampler of `replica`.
    #[inline]
    pub fn replica(&self, replica: u32) -> Sampler {
        Sampler::new(
            self.kind,
            spp(self.spp, self.replicas),
            seed(self.seed, replica),
        )
    }

    /// Value in `[0, 1)` of the 1D domain at `dim` for sample `index`.
    #[inline]
    pub fn sample_1d(&self, pixel: [u32; 2], index: u32, dim: u32) -> f32 {
        let (r, j) = split(index, self.replicas);
        self.replica(r).sample_1d(pixel, j, dim)
    }

    /// Point in `[0, 1)²` of the 2D domain at `dim`, `dim + 1` for sample `index`.
    #[inline]
    pub fn sample_2d(&self, pixel: [u32; 2], index: u32, dim: u32) -> Vec2 {
        let (r, j) = split(index, self.replicas);
        self.replica(r).sample_2d(pixel, j, dim)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_add_up_and_match_split() {
        for replicas in 1..6 {
            for first in 0..9 {
                for n in 0..17 {
                    let mut expect = vec![0; replicas as usize];
                    for i in first..first + n {
                        expect[split(i, replicas).0 as usize] += 1;
                    }
                    for r in 0..replicas {
                        assert_eq!(count(first, n, r, replicas), expect[r as usize]);
                    }
                }
            }
        }
    }

    #[test]
    fn one_replica_is_the_plain_sampler() {
        for kind in SamplerKind::ALL {
            let plain = Sampler::new(kind, 12, 9);
            let replicated = ReplicatedSampler::new(kind, 12, 9, 1);
            for i in 0..40 {
                assert_eq!(
                    plain.sample_2d([3, 4], i, 2),
                    replicated.sample_2d([3, 4], i, 2)
                );
                assert_eq!(
                    plain.sample_1d([3, 4], i, 5).to_bits(),
                    replicated.sample_1d([3, 4], i, 5).to_bits()
                );
            }
        }
    }

    #[test]
    fn each_replica_is_its_own_stratified_pattern() {
        // 16 spp in 4 replicas: replica r's samples r, r+4, r+8, r+12 are one 4-stratum pattern.
        let s = ReplicatedSampler::new(SamplerKind::Stratified, 16, 3, 4);
        for r in 0..4 {
            let mut strata: Vec<u32> = (0..4)
                .map(|j| (s.sample_1d([1, 2], r + 4 * j, 0) * 4.0) as u32)
                .collect();
            strata.sort_unstable();
            assert_eq!(strata, [0, 1, 2, 3], "replica {r}");
        }
    }
}
