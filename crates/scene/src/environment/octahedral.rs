//! pbrt-v4's equal-area octahedral environment maps: a square image of `w × w` texels laid out
//! by Clarberg's equal-area map ([`stratapt_sampling::warp::equal_area`]): the image's centre
//! looks along the map's `+z`, its corners along `−z`, the middle of its right edge along `+x`
//! and of its bottom row along `+y`. A direction's radiance is the texel its point of the
//! square falls in, without filtering (pbrt-v4's `LookupNearest`): column `⌊u·w⌋`, row `⌊v·w⌋`
//! (row 0 the image's top row), clamped into the image.
//!
//! The map is equal-area, so every texel covers the same solid angle `4π / w²`: importance
//! sampling draws a texel in proportion to its luminance ([`piecewise`] over the `w × w` grid,
//! no Jacobian), a point uniformly inside it, and the direction there; the solid-angle density is
//! the texel's density over the square divided by `4π`. As radiance and density are constant
//! over a texel, a sample's radiance over its density is the same for every point of the map
//! with light: in luminance, `4π / w² · Σ luminance`, the map's radiance integrated over the
//! sphere.
//!
//! The data in [`crate::FlatScene::tables`] is laid out as the latitude–longitude map's
//! ([`super::split`], [`super::data_len`] with `h = w`): texels, then the distribution.

use super::{split, EnvironmentMap};
use crate::light_table::luminance;
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::{equal_area, piecewise};

/// The index (`row · w + column`) of the texel holding point `p` of the square.
pub fn texel(w: usize, p: Vec2) -> usize {
    let col = ((p.x * w as f32) as usize).min(w - 1);
    let row = ((p.y * w as f32) as usize).min(w - 1);
    row * w + col
}

/// The sampling weight of each texel: its luminance.
pub fn weights(texels: &[f32]) -> Vec<f32> {
    texels
        .chunks(3)
        .map(|c| luminance([c[0], c[1], c[2]]).max(0.0) as f32)
        .collect()
}

impl EnvironmentMap {
    /// An octahedral map from `texels` (`w × w` RGB, finite, `≥ 0`, `w ≥ 1`); `None` when all
    /// black.
    pub fn octahedral(texels: Vec<f32>, w: usize) -> Option<Self> {
        let tables = piecewise::build(&weights(&texels), w, w)?;
        // Equal areas: the mean over directions is the texels' mean.
        let mut sum = [0.0f64; 3];
        for c in texels.chunks(3) {
            for k in 0..3 {
                sum[k] += f64::from(c[k]);
            }
        }
        let mean_radiance = sum.map(|s| (s / (w * w) as f64) as f32);
        let mut data = texels;
        data.extend(tables);
        Some(Self {
            width: w,
            height: w,
            data,
            mean_radiance,
        })
    }
}

fn texel_rgb(texels: &[f32], i: usize) -> Vec3 {
    Vec3::from_slice(&texels[3 * i..])
}

/// A direction sampled from the map's data (`w × w`), in the map's frame, with its solid-angle
/// density and the radiance of the texel it was drawn in; `None` in a texel of density 0.
pub fn sample(data: &[f32], w: usize, u: Vec2) -> Option<(Vec3, f32, Vec3)> {
    let (texels, tables) = split(data, w, w);
    let (p, density, cell) = piecewise::sample_cell(tables, w, w, u)?;
    let pdf = density * equal_area::pdf();
    Some((
        equal_area::square_to_sphere(p),
        pdf,
        texel_rgb(texels, cell),
    ))
}

/// The solid-angle density of [`sample`] for `d` (unit, in the map's frame).
pub fn pdf(data: &[f32], w: usize, d: Vec3) -> f32 {
    let (_, tables) = split(data, w, w);
    piecewise::pdf(tables, w, w, equal_area::sphere_to_square(d)) * equal_area::pdf()
}

/// The radiance of the map's data along `d` (unit, in the map's frame).
pub fn radiance(data: &[f32], w: usize, d: Vec3) -> Vec3 {
    let (texels, _) = split(data, w, w);
    texel_rgb(texels, texel(w, equal_area::sphere_to_square(d)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A texel's radiance over its density is the same wherever the light is sampled: the map's
    /// total luminance times 4π / w², and the pdf of the sampled direction is the sample's.
    #[test]
    fn samples_carry_radiance_over_pdf_constant_in_luminance() {
        let w = 8;
        let texels: Vec<f32> = (0..w * w)
            .flat_map(|i| match i % 5 {
                0 => [0.0; 3],
                k => [k as f32, 0.5, 0.1 * k as f32],
            })
            .collect();
        let total: f64 = weights(&texels).iter().map(|&x| f64::from(x)).sum();
        let expected = total * 4.0 * std::f64::consts::PI / (w * w) as f64;
        let map = EnvironmentMap::octahedral(texels, w).unwrap();
        let mean: f64 = map.mean_radiance.iter().map(|&x| f64::from(x)).sum::<f64>();
        assert!(mean > 0.0);
        let mut state = 7u32;
        let mut elsewhere = 0;
        for _ in 0..2000 {
            state = stratapt_sampling::hash::lowbias32(state);
            let a = (state >> 8) as f32 / (1 << 24) as f32;
            state = stratapt_sampling::hash::lowbias32(state);
            let b = (state >> 8) as f32 / (1 << 24) as f32;
            let (d, pdf, l) = sample(&map.data, w, Vec2::new(a, b)).unwrap();
            let ratio = luminance(l.to_array()) / f64::from(pdf);
            assert!(
                (ratio / expected - 1.0).abs() < 1e-5,
                "{ratio} vs {expected}"
            );
            // The direction's texel is the one drawn, unless the direction lies within rounding
            // of its edge (the inverse map's polynomial is good to 10⁻⁵ of the square).
            if radiance(&map.data, w, d) != l || self::pdf(&map.data, w, d) != pdf {
                elsewhere += 1;
            }
        }
        assert!(
            elsewhere <= 20,
            "{elsewhere} of 2000 directions left their texel"
        );
    }
}
