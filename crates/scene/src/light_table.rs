//! Light power and the alias tables that pick a light in proportion to it.
//!
//! Power (luminance of the RGB, Rec. 709 weights) is only used to choose lights, so it needs to
//! be proportional to each light's contribution, not exact: area lights `π · A · L`, line lights
//! `π² · I · length`, point lights `4π · I`, distant lights `π R² E` and the sky and an
//! environment map `π R² · π L̄`
//! with `R` the radius of the scene's bounding sphere. Tables follow Vose (1991), "A linear
//! algorithm for generating random numbers with a given distribution".

use crate::records::{light_kind, AliasEntry, Light, Motion, Pose, NONE};
use glam::Vec3;
use std::f64::consts::PI;

/// Rec. 709 luminance of a linear RGB colour.
pub fn luminance(rgb: [f32; 3]) -> f64 {
    0.2126 * rgb[0] as f64 + 0.7152 * rgb[1] as f64 + 0.0722 * rgb[2] as f64
}

/// Whether no sampled direction can ever hit the light (point, line, delta distant): such lights
/// are reached only by next-event estimation, through [`crate::FlatScene::unhittable_table`].
pub fn is_unhittable(light: &Light) -> bool {
    match light.kind {
        light_kind::POINT | light_kind::LINE | light_kind::SPOT => true,
        light_kind::DISTANT => light.p2[0] >= 1.0,
        _ => false,
    }
}

/// Emitted power of `light` (arbitrary common unit), `scene_radius` the radius of the scene's
/// bounding sphere. A moving area light counts the mean of its areas at shutter open and close.
pub fn power(light: &Light, motions: &[Motion], scene_radius: f64) -> f64 {
    let l = luminance(light.radiance);
    let [p0, p1, p2] = [light.p0, light.p1, light.p2].map(Vec3::from_array);
    let area_at = |pose: &Pose| -> f64 {
        let v = |p: Vec3| pose.vector_to_world(p);
        let s = pose.scale[0] as f64; // disks and spheres scale uniformly
        match light.kind {
            light_kind::TRIANGLE => 0.5 * v(p1 - p0).cross(v(p2 - p0)).length() as f64,
            light_kind::RECTANGLE => v(p1).cross(v(p2)).length() as f64,
            light_kind::DISK => PI * (p2.x as f64 * s).powi(2),
            light_kind::SPHERE => 4.0 * PI * (p2.x as f64 * s).powi(2),
            _ => 0.0,
        }
    };
    let area = match motions.get(light.motion as usize) {
        Some(m) if light.motion != NONE => 0.5 * (area_at(&m.open) + area_at(&m.close)),
        _ => area_at(&Pose::IDENTITY),
    };
    let disk_of_scene = PI * scene_radius * scene_radius;
    match light.kind {
        light_kind::TRIANGLE | light_kind::RECTANGLE | light_kind::DISK | light_kind::SPHERE => {
            // A two-sided emitter sends as much from its back.
            let sides = if light.has(crate::records::light_flag::TWO_SIDED) {
                2.0
            } else {
                1.0
            };
            sides * PI * area * l
        }
        light_kind::LINE => PI * PI * l * (p1 - p0).length() as f64,
        light_kind::POINT => 4.0 * PI * l,
        // ∫ smoothstep over the sphere: the full cone inside the falloff, half the falloff band.
        light_kind::SPOT => {
            let (end, start) = (light.p2[0] as f64, light.p2[1] as f64);
            2.0 * PI * l * ((1.0 - start) + 0.5 * (start - end))
        }
        light_kind::DISTANT => {
            // A cone stores radiance; what reaches the scene is its irradiance E = L·π·sin²θ.
            let cos_max = (light.p2[0] as f64).min(1.0);
            let e = if cos_max >= 1.0 {
                l
            } else {
                l * PI * (1.0 - cos_max * cos_max)
            };
            disk_of_scene * e
        }
        light_kind::SKY => disk_of_scene * PI * 0.5 * (l + luminance(light.p1)),
        // `radiance` holds the map's mean radiance.
        light_kind::ENVIRONMENT | light_kind::OCTAHEDRAL => disk_of_scene * PI * l,
        _ => 0.0,
    }
}

/// Build a Walker/Vose alias table over `weights` (non-negative; all zero or non-finite sums
/// give a uniform table). Empty in, empty out.
pub fn alias_table(weights: &[f64]) -> Vec<AliasEntry> {
    let n = weights.len();
    let total: f64 = weights.iter().sum();
    let uniform = !(total > 0.0 && total.is_finite());
    let pdf: Vec<f64> = weights
        .iter()
        .map(|&w| if uniform { 1.0 / n as f64 } else { w / total })
        .collect();
    // Scaled probabilities: entries below 1 borrow from entries above 1.
    let mut scaled: Vec<f64> = pdf.iter().map(|p| p * n as f64).collect();
    let mut table: Vec<AliasEntry> = (0..n)
        .map(|i| AliasEntry {
            threshold: 1.0,
            alias: i as u32,
            pdf: pdf[i] as f32,
            _pad: 0,
        })
        .collect();
    let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
    while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
        small.pop();
        table[s].threshold = scaled[s] as f32;
        table[s].alias = l as u32;
        scaled[l] -= 1.0 - scaled[s];
        if scaled[l] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    // Leftovers are 1 up to rounding: they keep themselves.
    table
}

/// Select an index with `u ∈ [0, 1)`: the selection rule documented on [`AliasEntry`]. Returns
/// the index and its probability. The table must not be empty.
pub fn select(table: &[AliasEntry], u: f32) -> (usize, f32) {
    let n = table.len();
    let scaled = u * n as f32;
    let i = (scaled as usize).min(n - 1);
    let v = scaled - i as f32;
    let j = if v < table[i].threshold {
        i
    } else {
        table[i].alias as usize
    };
    (j, table[j].pdf)
}

/// Fill `select_pdf` / `unhittable_select_pdf` of every light and return
/// `(light_table, unhittable_table)`. The unhittable lights must come first in `lights`, so that
/// an index drawn from the unhittable table is also an index into `lights`.
pub fn build_tables(
    lights: &mut [Light],
    motions: &[Motion],
    scene_radius: f64,
) -> (Vec<AliasEntry>, Vec<AliasEntry>) {
    let unhittable = lights.iter().take_while(|l| is_unhittable(l)).count();
    debug_assert!(
        lights[unhittable..].iter().all(|l| !is_unhittable(l)),
        "unhittable lights first"
    );
    let powers: Vec<f64> = lights
        .iter()
        .map(|l| power(l, motions, scene_radius))
        .collect();
    let all = alias_table(&powers);
    let delta = alias_table(&powers[..unhittable]);
    for (i, light) in lights.iter_mut().enumerate() {
        light.select_pdf = all[i].pdf;
        light.unhittable_select_pdf = delta.get(i).map_or(0.0, |e| e.pdf);
    }
    (all, delta)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sampling the table with many stratified `u` reproduces each pdf: the count of index `i`
    /// in `N` draws is binomial(N, pᵢ); accept within 5 standard deviations (plus one draw for
    /// stratification).
    #[test]
    fn alias_frequencies_match_pdfs() {
        let weights = [1.0, 0.0, 3.0, 0.25, 10.0, 2.5, 0.0, 7.0, 0.01];
        let table = alias_table(&weights);
        let total: f64 = weights.iter().sum();
        let n = 1_000_000usize;
        let mut counts = vec![0usize; weights.len()];
        // A scrambled stratified sequence: (k + 0.5)/n in a shuffled order is not needed, every
        // stratum is visited once.
        for k in 0..n {
            let u = ((k as f64 + 0.5) / n as f64) as f32;
            let (i, pdf) = select(&table, u);
            assert_eq!(pdf, table[i].pdf);
            counts[i] += 1;
        }
        for (i, &w) in weights.iter().enumerate() {
            let p = w / total;
            assert!((table[i].pdf as f64 - p).abs() < 1e-6, "pdf {i}");
            let sigma = (n as f64 * p * (1.0 - p)).sqrt();
            let err = (counts[i] as f64 - n as f64 * p).abs();
            assert!(
                err <= 5.0 * sigma + 1.0,
                "index {i}: {} draws, expected {}",
                counts[i],
                n as f64 * p
            );
        }
    }

    /// Independent pseudo-random draws (an LCG) also match, within a variance-derived tolerance.
    #[test]
    fn alias_random_draws_match_pdfs() {
        let weights = [5.0, 1.0, 1.0, 0.5, 2.0];
        let table = alias_table(&weights);
        let total: f64 = weights.iter().sum();
        let n = 200_000usize;
        let mut rng = stratapt_sampling::testing::TestRng(0x2545_f491_4f6c_dd1d);
        let mut counts = vec![0usize; weights.len()];
        for _ in 0..n {
            counts[select(&table, rng.f32()).0] += 1;
        }
        for (i, &w) in weights.iter().enumerate() {
            let p = w / total;
            let sigma = (n as f64 * p * (1.0 - p)).sqrt();
            assert!(
                (counts[i] as f64 - n as f64 * p).abs() <= 5.0 * sigma,
                "index {i}"
            );
        }
    }

    /// A sun's share of the light budget is what it delivers, its irradiance: widening the cone
    /// at fixed irradiance (which lowers the stored radiance) must not change it.
    #[test]
    fn sun_power_is_irradiance_whatever_the_cone() {
        let sun = |cos_max: f32, radiance: f32| Light {
            kind: light_kind::DISTANT,
            p2: [cos_max, 0.0, 0.0],
            radiance: [radiance; 3],
            ..Light::default()
        };
        let delta = power(&sun(1.0, 2.0), &[], 10.0);
        for degrees in [0.53_f64, 5.0, 60.0] {
            // As the loader does: sin² from the f32 cosine the renderers will sample.
            let cos = (degrees.to_radians() / 2.0).cos() as f32;
            let radiance = 2.0 / (PI * (1.0 - (cos as f64).powi(2)));
            let cone = power(&sun(cos, radiance as f32), &[], 10.0);
            assert!(
                (cone / delta - 1.0).abs() < 1e-4,
                "{degrees}°: {cone} vs {delta}"
            );
        }
    }

    #[test]
    fn degenerate_tables() {
        assert!(alias_table(&[]).is_empty());
        let t = alias_table(&[0.0, 0.0]);
        assert_eq!(t.iter().map(|e| e.pdf).collect::<Vec<_>>(), vec![0.5, 0.5]);
        let t = alias_table(&[4.0]);
        assert_eq!((t[0].pdf, t[0].threshold), (1.0, 1.0));
    }
}
