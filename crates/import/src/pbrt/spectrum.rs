//! Spectra pbrt-v4 scenes give where strata takes RGB: `blackbody` emission, as the linear sRGB
//! colour of a black body of that temperature with luminance 1 (pbrt-v4 divides a light's
//! `scale` by its spectrum's luminance, so `"blackbody L" 3000` is a light of luminance `scale`
//! whatever the temperature; strata's `[r, g, b]` emission is then that colour times `scale`).
//!
//! The colour is Planck's law integrated against the CIE 1931 2° colour-matching functions, as
//! Wyman, Sloan and Shirley's multi-lobe Gaussian fit gives them ("Simple Analytic
//! Approximations to the CIE XYZ Color Matching Functions", JCGT 2013), from 360 to 830 nm in
//! 1 nm steps, then XYZ to linear sRGB (D65). The tests hold it to the published chromaticities
//! of CIE illuminant A and of the Planckian locus.
//!
//! Other spectra (wavelength–value pairs written inline or in an `.spd` file, and pbrt's named
//! spectra, [`super::named`]) become RGB by [`sampled_rgb`] as what they describe: a
//! reflectance, an index of refraction, or an emission.

/// One lobe of the fit: a Gaussian of mean `mu` with widths `s1` below and `s2` above it.
fn lobe(lambda: f64, mu: f64, s1: f64, s2: f64) -> f64 {
    let s = if lambda < mu { s1 } else { s2 };
    (-0.5 * ((lambda - mu) / s).powi(2)).exp()
}

/// The CIE 1931 colour-matching functions x̄, ȳ, z̄ at `lambda` nm (Wyman et al.'s fit).
pub fn cie_xyz(lambda: f64) -> [f64; 3] {
    let l = lambda;
    [
        1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7)
            - 0.065 * lobe(l, 501.1, 20.4, 26.2),
        0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1),
        1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8),
    ]
}

/// Planck's spectral radiance at `lambda` nm and `kelvin` (any unit: only ratios are used).
fn planck(lambda: f64, kelvin: f64) -> f64 {
    const C2: f64 = 1.438_776_877e-2; // h c / k, m·K
    let l = lambda * 1e-9;
    1.0 / (l.powi(5) * ((C2 / (l * kelvin)).exp() - 1.0))
}

/// The XYZ of a black body at `kelvin`, unnormalized.
pub fn blackbody_xyz(kelvin: f64) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    for nm in 360..=830 {
        let (b, cmf) = (planck(nm as f64, kelvin), cie_xyz(nm as f64));
        for k in 0..3 {
            xyz[k] += b * cmf[k];
        }
    }
    xyz
}

/// Linear sRGB (D65 white) of CIE XYZ.
pub fn xyz_to_srgb([x, y, z]: [f64; 3]) -> [f64; 3] {
    [
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    ]
}

/// The linear sRGB colour of a black body at `kelvin` with luminance 1; `None` for a
/// temperature that is not above 0 (pbrt-v4 refuses those too). Below about 1900 K the colour
/// lies outside the sRGB gamut (its blue is negative): emission cannot be, so the negative part
/// is clamped to 0 and the rest scaled back to luminance 1.
pub fn blackbody_rgb(kelvin: f64) -> Option<[f64; 3]> {
    if !(kelvin > 0.0 && kelvin.is_finite()) {
        return None;
    }
    let xyz = blackbody_xyz(kelvin);
    let rgb = xyz_to_srgb(xyz.map(|c| c / xyz[1])).map(|c| c.max(0.0));
    let luminance = 0.212_672_9 * rgb[0] + 0.715_152_2 * rgb[1] + 0.072_175_0 * rgb[2];
    Some(rgb.map(|c| c / luminance))
}

/// Whether a spectrum is a reflectance (bounded, seen under pbrt's D65-like light) or not
/// (an index of refraction, an emission).
#[derive(Clone, Copy, PartialEq)]
pub enum SpectrumKind {
    Reflectance,
    Unbounded,
    /// An emission spectrum: its colour at luminance 1.
    Illuminant,
}

/// The RGB of a spectrum given as wavelength–value pairs (pbrt's `PiecewiseLinearSpectrum`),
/// averaged against the CIE 1931 matching functions: a reflectance normalized so that a
/// constant spectrum is that constant grey, an unbounded spectrum (an index of refraction) as
/// Mitsuba 3's RGB variants convert one (XYZ over ∫ȳ, to linear sRGB, negatives clamped: what
/// [`super::named`]'s metals are), an illuminant as its colour at luminance 1.
pub fn sampled_rgb(pairs: &[f64], kind: SpectrumKind) -> [f64; 3] {
    let value = |lambda: f64| piecewise_linear(pairs, lambda);
    let (mut xyz, mut white) = ([0.0; 3], [0.0; 3]);
    for nm in 360..=830 {
        let cmf = super::spectrum::cie_xyz(nm as f64);
        let v = value(nm as f64);
        for c in 0..3 {
            xyz[c] += v * cmf[c];
            white[c] += cmf[c];
        }
    }
    match kind {
        SpectrumKind::Reflectance => {
            let (rgb, w) = (
                super::spectrum::xyz_to_srgb(xyz),
                super::spectrum::xyz_to_srgb(white),
            );
            [0, 1, 2].map(|c| (rgb[c] / w[c]).max(0.0))
        }
        SpectrumKind::Unbounded => {
            super::spectrum::xyz_to_srgb(xyz.map(|v| v / white[1])).map(|c| c.max(0.0))
        }
        SpectrumKind::Illuminant => {
            let y = xyz[1];
            if y > 0.0 {
                super::spectrum::xyz_to_srgb(xyz.map(|v| v / y)).map(|c| c.max(0.0))
            } else {
                [0.0; 3]
            }
        }
    }
}

/// The mean of a sampled spectrum weighted by the luminance curve ȳ (a dispersive index of
/// refraction as one number, as [`super::named`]'s glasses).
pub fn luminance_mean(pairs: &[f64]) -> f64 {
    let (mut sum, mut weight) = (0.0, 0.0);
    for nm in 360..=830 {
        let y = super::spectrum::cie_xyz(nm as f64)[1];
        sum += y * piecewise_linear(pairs, nm as f64);
        weight += y;
    }
    sum / weight
}

/// pbrt's `PiecewiseLinearSpectrum` of wavelength–value `pairs` at `lambda`, held constant
/// beyond its ends.
fn piecewise_linear(pairs: &[f64], lambda: f64) -> f64 {
    let n = pairs.len() / 2;
    if lambda <= pairs[0] {
        return pairs[1];
    }
    if lambda >= pairs[2 * (n - 1)] {
        return pairs[2 * n - 1];
    }
    let i = (0..n - 1)
        .find(|&i| pairs[2 * (i + 1)] >= lambda)
        .unwrap_or(n - 2);
    let (a, va, b, vb) = (
        pairs[2 * i],
        pairs[2 * i + 1],
        pairs[2 * i + 2],
        pairs[2 * i + 3],
    );
    if b == a {
        return vb;
    }
    va + (vb - va) * (lambda - a) / (b - a)
}

/// The wavelength–value pairs of a spectrum file pbrt-v4 reads (`"spectrum eta"
/// "spds/Au.eta.spd"`): numbers separated by white space, `#` comments to the end of a line.
pub fn read_spd(path: &std::path::Path) -> Result<Vec<f64>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let mut values = Vec::new();
    for line in text.lines() {
        let line = line.split('#').next().unwrap_or("");
        for word in line.split_whitespace() {
            values.push(
                word.parse::<f64>()
                    .map_err(|_| format!("`{word}` is not a number"))?,
            );
        }
    }
    if values.len() < 2 || values.len() % 2 != 0 {
        return Err(format!(
            "{} numbers: wavelength–value pairs, at least one",
            values.len()
        ));
    }
    if values.iter().any(|v| !v.is_finite()) || values.chunks(2).any(|w| w[0] <= 0.0) {
        return Err("a wavelength or value that is not finite, or a wavelength ≤ 0".into());
    }
    Ok(values)
}

/// The RGB of one of pbrt's named spectra (a glass's index in all three channels).
pub fn named_rgb(name: &str) -> Option<[f64; 3]> {
    super::named::named_spectrum(name).map(|n| n.rgb())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chromaticity(kelvin: f64) -> (f64, f64) {
        let [x, y, z] = blackbody_xyz(kelvin);
        (x / (x + y + z), y / (x + y + z))
    }

    /// CIE illuminant A (a black body at 2856 K) is x 0.44757, y 0.40745; the Planckian locus at
    /// 6500 K is x 0.3135, y 0.3237, at 4000 K 0.3805, 0.3768 (CIE 15:2004). The fit is good to
    /// a few thousandths there.
    #[test]
    fn chromaticities_are_the_cie_ones() {
        for (kelvin, x, y) in [
            (2856.0, 0.44757, 0.40745),
            (4000.0, 0.3805, 0.3768),
            (6500.0, 0.3135, 0.3237),
        ] {
            let (cx, cy) = chromaticity(kelvin);
            println!("{kelvin} K: ({cx:.4}, {cy:.4}) against ({x}, {y})");
            assert!(
                (cx - x).abs() < 3e-3 && (cy - y).abs() < 3e-3,
                "{kelvin} K: ({cx}, {cy})"
            );
        }
        // A shift of the luminosity lobe by 10 nm moves illuminant A outside that tolerance: the
        // check can tell a wrong fit.
        let shifted = |kelvin: f64| {
            let mut xyz = [0.0; 3];
            for nm in 360..=830 {
                let l = nm as f64;
                let mut cmf = cie_xyz(l);
                cmf[1] = 0.821 * lobe(l, 578.8, 46.9, 40.5) + 0.286 * lobe(l, 540.9, 16.3, 31.1);
                for k in 0..3 {
                    xyz[k] += planck(l, kelvin) * cmf[k];
                }
            }
            let s: f64 = xyz.iter().sum();
            (xyz[0] / s, xyz[1] / s)
        };
        let (sx, sy) = shifted(2856.0);
        assert!(
            (sx - 0.44757).abs() > 3e-3 || (sy - 0.40745).abs() > 3e-3,
            "({sx}, {sy})"
        );
    }

    /// Luminance 1, warm at low temperatures and blue at high ones, and nothing for 0 K.
    #[test]
    fn colours_have_luminance_one_and_shift_with_temperature() {
        let mut last_ratio = -1.0;
        for kelvin in [1500.0, 2700.0, 4000.0, 6500.0, 10000.0, 20000.0] {
            let [r, g, b] = blackbody_rgb(kelvin).unwrap();
            let luminance = 0.212_672_9 * r + 0.715_152_2 * g + 0.072_175_0 * b;
            assert!((luminance - 1.0).abs() < 1e-6, "{kelvin} K: {luminance}");
            assert!(r >= 0.0 && g >= 0.0 && b >= 0.0, "{kelvin} K: {r} {g} {b}");
            assert!(b / r > last_ratio, "{kelvin} K: not bluer");
            last_ratio = b / r;
        }
        // 1500 K is outside the gamut: its blue is clamped to 0.
        assert_eq!(blackbody_rgb(1500.0).unwrap()[2], 0.0);
        let [r, g, b] = blackbody_rgb(6500.0).unwrap();
        assert!(
            (r - 1.0).abs() < 0.1 && (g - 1.0).abs() < 0.1 && (b - 1.0).abs() < 0.15,
            "{r} {g} {b}"
        );
        assert_eq!(blackbody_rgb(0.0), None);
        assert_eq!(blackbody_rgb(f64::NAN), None);
    }
}
