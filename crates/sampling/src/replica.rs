//! Independent randomizations of one render, for a calibrated error estimate.
//!
//! One randomization of a stratified or Owen-scrambled Sobol point set says nothing about its own
//! error: its samples are negatively correlated, so their sample variance overstates the error of
//! their mean many times over (measured:
//! docs/measurements/error-estimate.md#predicted-against-true-error-cornell-box). Randomized QMC
//! (Owen 1997; L'Ecuyer & Lemieux 2002) estimates the error from *independent* randomizations
//! instead. Replica `r` of a render draws every sample from the sampler with seed
//! [`seed`]`(seed, r)`, whose patterns are independent of every other replica's; replica 0 is
//! the render itself.
//! Mirrored in `shaders/sampler.wgsl` (`sampler_replica_seed`).

use crate::hash::hash_combine;

/// The sampler seed of replica `replica` of a render with seed `seed`: `seed` itself for
/// replica 0, else `hash_combine(seed, replica)`.
#[inline]
pub fn seed(seed: u32, replica: u32) -> u32 {
    if replica == 0 {
        seed
    } else {
        hash_combine(seed, replica)
    }
}
