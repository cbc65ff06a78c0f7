#!/usr/bin/env python3
"""Print crates/import/src/pbrt/named.rs: RGB values for pbrt-v4's named spectra.

pbrt-v4 scenes may name a built-in spectrum where strata takes RGB ("spectrum eta"
"metal-Au-eta", "spectrum L" "stdillum-F4", "spectrum eta" "glass-BK7"). This script computes one
RGB triple (or one index of refraction) per name and prints it as Rust source. The spectral data
are not committed: the script reads them from a pbrt-v4 checkout's src/pbrt/util/spectrum.cpp,
the arrays (Au_eta, CIE_Illum_F4, GlassBK7_eta, ..., and the CIE 1931 2° colour-matching
functions CIE_X/Y/Z at 1 nm, 360-830 nm) and the name table in Spectra::Init (namedSpectra).
Only the derived numbers are committed.

Run (numpy needed; mitsuba only for --check-mitsuba):
    git clone https://github.com/mmp/pbrt-v4 /tmp/pbrt-v4
    python3 scripts/pbrt-named-spectra.py /tmp/pbrt-v4/src/pbrt/util/spectrum.cpp \
        > crates/import/src/pbrt/named.rs
    rustfmt --edition 2021 --check crates/import/src/pbrt/named.rs   # already formatted
    # cross-check against Mitsuba 3 (prints to stderr, output unchanged):
    /tmp/mi/bin/python scripts/pbrt-named-spectra.py --check-mitsuba <spectrum.cpp> > /dev/null

Every spectrum is first made what pbrt-v4 makes it (PiecewiseLinearSpectrum::FromInterleaved):
(lambda, value) samples, interpolated linearly, extended at constant value to 359 and 831 nm
where the data stop short of 360-830 nm, and zero beyond.

Conversion, by kind of name:

* metal-*-eta, metal-*-k (Ag, Al, Au, Cu, CuZn, MgO, TiO2): exactly what Mitsuba 3's RGB variants
  do to an IOR spectrum (conductor material="Au": include/mitsuba/render/ior.h ior_from_file ->
  src/core/spectrum.cpp spectrum_list_to_srgb(bounded=false, d65=false)), since strata is
  compared against Mitsuba's RGB mode: 1000 wavelengths evenly spaced over [360, 830] nm
  (endpoints included), XYZ = sum(value * cmf) * 470 / 1000 / 106.7502593994140625, with the
  CIE 1931 2° functions tabulated at 5 nm and interpolated linearly (Mitsuba's table is the 1 nm
  table taken every 5 nm, as read here from pbrt's file), then Mitsuba's XYZ-to-linear-sRGB
  matrix, negative components clamped to 0. No illuminant weights the integral, so this is the
  colour of the spectrum under an equal-energy light: a constant spectrum c comes out as
  c * (1.205, 0.948, 0.909), not grey. That is Mitsuba's behaviour, kept on purpose.

* stdillum-* and illum-acesD60 (light spectra): pbrt-v4 divides a light's scale by its
  spectrum's luminance, so the light's luminance is `scale` whatever the spectrum. The value is
  the linear sRGB colour with luminance Y = 1, computed as pbrt does: the sum over integer
  wavelengths 360..830 nm of spectrum * CIE 1931 (1 nm table from pbrt's file), divided by Y,
  then the sRGB (D65) matrix strata's spectrum.rs uses for black bodies. Through that matrix
  pbrt's D65 is (1, 1, 1) to within 5e-6 (pbrt's own sRGB space maps it to exactly white).

* glass-* (BK7, BAF10, FK51A, LASF9, F5, F10, F11; F5/F10/F11 are pbrt's names for Schott SF5,
  SF10, SF11): one index of refraction, the y-bar-weighted mean of eta(lambda) over 360..830 nm
  at 1 nm, sum(eta * y) / sum(y). strata refracts all three channels with one index, whereas
  pbrt-v4 disperses (one wavelength per path once a dispersive interface is hit); the
  luminance-weighted mean is the single index that the image's luminance sees on average; it is
  the Y of the spectrum, close to what Mitsuba's monochrome variants take (the luminance of the
  metal conversion above). It lies 2e-4 to
  9e-4 below eta(550 nm) for these glasses (printed with --check-mitsuba).

Camera sensor curves (canon_eos_*, nikon_*, sony_*, hasselblad_*) are not covered.
"""
import argparse
import re
import sys

import numpy as np

# Mitsuba 3: include/mitsuba/core/spectrum.h (MI_CIE_MIN/MAX, MI_CIE_Y_NORMALIZATION, xyz_to_srgb)
MI_CIE_MIN, MI_CIE_MAX = 360.0, 830.0
MI_CIE_Y_INTEGRAL = 106.7502593994140625
MI_XYZ_TO_SRGB = np.array([[3.240479, -1.537150, -0.498535],
                           [-0.969256, 1.875991, 0.041556],
                           [0.055648, -0.204043, 1.057311]])
# strata: crates/import/src/pbrt/spectrum.rs xyz_to_srgb (sRGB primaries, D65 white)
XYZ_TO_SRGB = np.array([[3.2404542, -1.5371385, -0.4985314],
                        [-0.9692660, 1.8760108, 0.0415560],
                        [0.0556434, -0.2040259, 1.0572252]])
# pbrt-v4: src/pbrt/util/spectrum.h
LAMBDA_MIN, LAMBDA_MAX = 360.0, 830.0

PREFIXES = ("metal-", "glass-", "stdillum-", "illum-")


def read_arrays(text):
    """Every `const Float NAME[...] = { ... };` in spectrum.cpp, as float arrays."""
    arrays = {}
    for m in re.finditer(r"const\s+Float\s+(\w+)\s*\[[^\]]*\]\s*=\s*\{(.*?)\};", text, re.S):
        body = re.sub(r"//[^\n]*", "", m.group(2))
        arrays[m.group(1)] = np.array([float(v) for v in body.replace("\n", " ").split(",")
                                       if v.strip()])
    return arrays


def read_names(text):
    """The named spectra of Spectra::Init: name -> (array name, normalize flag)."""
    variables = {m.group(1): (m.group(2), m.group(3) == "true") for m in re.finditer(
        r"Spectrum\s+(\w+)\s*=\s*PiecewiseLinearSpectrum::FromInterleaved\(\s*(\w+)\s*,"
        r"\s*(true|false)", text)}
    table = re.search(r"namedSpectra\s*=\s*\{(.*?)\n\s*\};", text, re.S).group(1)
    names = {}
    for name, var in re.findall(r'\{\s*"([^"]+)"\s*,\s*(\w+)\s*\}', table):
        if name.startswith(PREFIXES):
            names[name] = variables[var]
    return names


def from_interleaved(samples):
    """pbrt-v4 PiecewiseLinearSpectrum::FromInterleaved (without normalizing): (lambdas, values)
    extended at constant value to 359 / 831 nm where the samples stop short of 360-830."""
    lam, val = list(samples[0::2]), list(samples[1::2])
    if lam[0] > LAMBDA_MIN:
        lam.insert(0, LAMBDA_MIN - 1)
        val.insert(0, val[0])
    if lam[-1] < LAMBDA_MAX:
        lam.append(LAMBDA_MAX + 1)
        val.append(val[-1])
    return np.array(lam), np.array(val)


def piecewise_linear(lam, val, at):
    """pbrt-v4 PiecewiseLinearSpectrum::operator(): linear inside, zero outside."""
    return np.where((at < lam[0]) | (at > lam[-1]), 0.0, np.interp(at, lam, val))


def mitsuba_srgb(lam, val, cie_lambda, cmf):
    """Mitsuba 3 spectrum_list_to_srgb(bounded=false, d65=false) with its 5 nm CIE table."""
    five = (cie_lambda % 5 == 0)
    w = MI_CIE_MIN + np.arange(1000) / 999.0 * (MI_CIE_MAX - MI_CIE_MIN)
    inside = (w >= lam[0]) & (w <= lam[-1])
    v = np.interp(w, lam, val) * inside
    cmf_w = np.array([np.interp(w, cie_lambda[five], c[five]) for c in cmf])
    xyz = (cmf_w * v).sum(axis=1) * (MI_CIE_MAX - MI_CIE_MIN) / MI_CIE_Y_INTEGRAL / 1000
    return np.maximum(MI_XYZ_TO_SRGB @ xyz, 0.0), xyz


def illuminant_srgb(lam, val, cie_lambda, cmf):
    """pbrt-v4's XYZ of a spectrum (inner product at integer wavelengths), scaled to Y = 1,
    then linear sRGB."""
    xyz = (cmf * piecewise_linear(lam, val, cie_lambda)).sum(axis=1)
    return XYZ_TO_SRGB @ (xyz / xyz[1])


def luminance_mean(lam, val, cie_lambda, ybar):
    """The y-bar-weighted mean of a spectrum over pbrt's 1 nm wavelengths."""
    return (piecewise_linear(lam, val, cie_lambda) * ybar).sum() / ybar.sum()


def compute(path):
    text = open(path).read()
    arrays, names = read_arrays(text), read_names(text)
    cie_lambda = arrays["CIE_lambda"]
    cmf = np.array([arrays["CIE_X"], arrays["CIE_Y"], arrays["CIE_Z"]])
    assert cie_lambda[0] == LAMBDA_MIN and cie_lambda[-1] == LAMBDA_MAX and len(cie_lambda) == 471
    table = {}
    for name, (array, normalize) in names.items():
        lam, val = from_interleaved(arrays[array])
        if name.startswith("metal-"):
            table[name] = ("Rgb", mitsuba_srgb(lam, val, cie_lambda, cmf)[0], array)
        elif name.startswith("glass-"):
            table[name] = ("Ior", luminance_mean(lam, val, cie_lambda, cmf[1]), array)
        else:
            assert normalize, name
            table[name] = ("Rgb", illuminant_srgb(lam, val, cie_lambda, cmf), array)
    kinds = [n.split("-")[0] for n in table]
    assert kinds.count("metal") >= 14 and kinds.count("glass") >= 7, table.keys()
    assert kinds.count("stdillum") >= 15, table.keys()
    return table, arrays, cie_lambda, cmf


# Rust literals clippy's approx_constant lint would take for std::f64::consts.
CONSTS = [np.pi, np.e, 1 / np.pi, 2 / np.pi, np.pi / 2, np.pi / 3, np.pi / 4, np.pi / 6,
          np.pi / 8, 2 * np.pi, np.log(2), np.log(10), np.log10(np.e), np.log2(np.e),
          np.log2(10), np.log10(2), np.sqrt(2), 1 / np.sqrt(2), 2 / np.sqrt(np.pi)]


def literal(x):
    s = f"{x:.6f}"
    for c in CONSTS:
        if s == f"{c:.6f}":
            s = f"{x:.5f}"
    return s


HEADER = """\
//! pbrt-v4's named spectra (`"spectrum eta" "metal-Au-eta"`, `"spectrum L" "stdillum-F4"`,
//! `"spectrum eta" "glass-BK7"`) as the RGB or the single index of refraction strata takes.
//!
//! Generated by `scripts/pbrt-named-spectra.py` from pbrt-v4's `src/pbrt/util/spectrum.cpp`
//! (its tabulated spectra, the `Spectra::Init` name table and its CIE 1931 2° colour-matching
//! functions at 1 nm); rerun the script rather than editing the numbers. Each spectrum is taken
//! as pbrt-v4 takes it: its samples interpolated linearly, extended at constant value over
//! 360-830 nm where the data stop short.
//!
//! - `metal-*-eta` / `metal-*-k`: linear sRGB of the spectrum exactly as Mitsuba 3's RGB
//!   variants convert an IOR spectrum (`spectrum_list_to_srgb`, no illuminant, negatives
//!   clamped to 0), since strata is compared against Mitsuba's RGB mode. These are unbounded
//!   optical constants, not reflectances; as in Mitsuba, a constant spectrum c comes out as
//!   about c·(1.205, 0.948, 0.909), not grey.
//! - `stdillum-*`, `illum-acesD60`: linear sRGB of the light with luminance Y = 1, because
//!   pbrt-v4 divides a light's `scale` by its spectrum's luminance (as `spectrum::blackbody_rgb`
//!   does for black bodies, with the same XYZ-to-sRGB matrix). D65 comes out as (1, 1, 1) to
//!   within 5e-6.
//! - `glass-*`: one index of refraction, the ȳ-weighted mean of η(λ) over 360-830 nm (the Y of
//!   the spectrum): strata refracts every channel with one index where pbrt-v4 disperses.
//!   `glass-F5`, `-F10`, `-F11` are pbrt's names for Schott SF5, SF10, SF11.
//!
//! pbrt-v4's camera sensor curves (`canon_eos_100d_r`, ...) are not here.

/// The value strata uses for one of pbrt-v4's named spectra.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NamedSpectrum {
    /// Linear sRGB: a metal's η or k, or an illuminant's colour with luminance 1.
    Rgb([f64; 3]),
    /// A glass's index of refraction (the luminance-weighted mean over the visible range).
    Ior(f64),
}

impl NamedSpectrum {
    /// The value as RGB: a glass's index repeated in all three channels.
    pub fn rgb(self) -> [f64; 3] {
        match self {
            NamedSpectrum::Rgb(rgb) => rgb,
            NamedSpectrum::Ior(eta) => [eta; 3],
        }
    }
}

/// The value of pbrt-v4's named spectrum `name` (`"metal-Au-eta"`, `"stdillum-D65"`,
/// `"glass-BK7"`, ...); `None` for a name pbrt-v4 does not define or this table leaves out.
pub fn named_spectrum(name: &str) -> Option<NamedSpectrum> {
    use NamedSpectrum::{Ior, Rgb};
    Some(match name {
"""

TESTS = """\
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb(name: &str) -> [f64; 3] {
        match named_spectrum(name) {
            Some(NamedSpectrum::Rgb(rgb)) => rgb,
            other => panic!("{name}: {other:?}"),
        }
    }

    /// Gold absorbs more strongly towards the red (k grows with wavelength); copper's η is
    /// lower in the red than in the blue, which is what makes both look warm.
    #[test]
    fn metals_have_their_colour() {
        let k = rgb("metal-Au-k");
        assert!(k[0] > k[1] && k[1] > k[2], "{k:?}");
        let eta = rgb("metal-Cu-eta");
        assert!(eta[0] < eta[2], "{eta:?}");
        for metal in ["Ag", "Al", "Au", "Cu", "CuZn", "MgO", "TiO2"] {
            for part in ["eta", "k"] {
                let name = format!("metal-{metal}-{part}");
                assert!(
                    rgb(&name).iter().all(|c| c.is_finite() && *c >= 0.0),
                    "{name}"
                );
            }
        }
    }

    /// Every illuminant has luminance 1; D65 is white.
    #[test]
    fn illuminants_have_luminance_one() {
        let d65 = rgb("stdillum-D65");
        assert!(d65.iter().all(|c| (c - 1.0).abs() < 1e-4), "{d65:?}");
        let a = rgb("stdillum-A");
        assert!(a[0] > a[1] && a[1] > a[2], "illuminant A is reddish: {a:?}");
        for name in [
            "stdillum-A",
            "stdillum-D50",
            "stdillum-F1",
            "stdillum-F12",
            "illum-acesD60",
        ] {
            let [r, g, b] = rgb(name);
            let y = 0.212_672_9 * r + 0.715_152_2 * g + 0.072_175_0 * b;
            assert!((y - 1.0).abs() < 1e-4, "{name}: luminance {y}");
        }
    }

    /// Glasses give one plausible index; BK7's is about 1.52.
    #[test]
    fn glasses_are_one_index() {
        let Some(NamedSpectrum::Ior(bk7)) = named_spectrum("glass-BK7") else {
            panic!("glass-BK7 is an index");
        };
        assert!((bk7 - 1.518).abs() < 0.005, "{bk7}");
        assert_eq!(named_spectrum("glass-BK7").unwrap().rgb(), [bk7; 3]);
        let sf11 = named_spectrum("glass-F11").unwrap().rgb()[0];
        assert!(sf11 > 1.75 && sf11 < 1.8, "{sf11}");
    }

    #[test]
    fn unknown_names_are_none() {
        assert_eq!(named_spectrum("metal-Unobtainium-eta"), None);
        assert_eq!(named_spectrum("canon_eos_100d_r"), None);
        assert_eq!(named_spectrum(""), None);
    }
}
"""


def rust(table):
    out = [HEADER]
    group = None
    for name, (kind, value, _) in table.items():
        if name.split("-")[0] != group:
            group = name.split("-")[0]
            out.append({"metal": "        // Metals: Mitsuba's RGB of η and k.\n",
                        "glass": "        // Glasses: luminance-weighted mean index.\n",
                        "stdillum": "        // CIE standard illuminants, luminance 1.\n",
                        "illum": "        // ACES white point (D60), luminance 1.\n"}[group])
        if kind == "Rgb":
            v = ", ".join(literal(c) for c in value)
            out.append(f'        "{name}" => Rgb([{v}]),\n')
        else:
            out.append(f'        "{name}" => Ior({literal(value)}),\n')
    out.append(TESTS)
    return "".join(out)


def order(table):
    """Metals, then glasses, then illuminants, each in pbrt's order."""
    rank = {"metal": 0, "glass": 1, "stdillum": 2, "illum": 3}
    return dict(sorted(table.items(), key=lambda kv: rank[kv[0].split("-")[0]]))


def check_mitsuba(table, arrays, cie_lambda, cmf):
    """To stderr: this script's metal values against Mitsuba's own conversion of the same
    arrays and against Mitsuba's conductor(material=...) from its .spd files; D65; glasses."""
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    log = lambda *a: print(*a, file=sys.stderr)
    fmt = lambda v: "(" + ", ".join(f"{c:.6f}" for c in v) + ")"
    worst = 0.0
    log("metal: this script | mi.spectrum_list_to_srgb(pbrt's data) | Mitsuba's"
        " conductor(material=...) from its own .spd files")
    for name, (kind, value, array) in table.items():
        if kind != "Rgb" or not name.startswith("metal-"):
            continue
        lam, val = from_interleaved(arrays[array])
        theirs = np.array(mi.spectrum_list_to_srgb(list(lam), list(val), bounded=False))
        worst = max(worst, np.abs(theirs - value).max())
        _, metal, part = name.split("-")
        try:
            bsdf = mi.load_dict({"type": "conductor", "material": metal})
            params = mi.traverse(bsdf)
            key = [k for k in params.keys() if k.endswith(part + ".value")][0]
            own = fmt(np.array(params[key]).ravel())
        except Exception:  # Mitsuba has no such material (CuZn)
            own = "n/a (no such material in Mitsuba)"
        log(f"{name:15} {fmt(value)} | {fmt(theirs)} | {own}")
    log(f"largest |script - mi.spectrum_list_to_srgb| over metals: {worst:.2e}")
    d65 = table["stdillum-D65"][1]
    log(f"stdillum-D65: {fmt(d65)}, max |c - 1| = {np.abs(d65 - 1).max():.2e}")
    lam, val = from_interleaved(arrays["CIE_Illum_D6500"])
    mi_d65 = np.array(mi.spectrum_list_to_srgb(list(lam), list(val), bounded=False))
    log(f"  (Mitsuba's conversion of D65, scaled to its green: {fmt(mi_d65 / mi_d65[1])})")
    for name, (kind, value, array) in table.items():
        if kind == "Ior":
            lam, val = from_interleaved(arrays[array])
            at = lambda l: float(piecewise_linear(lam, val, np.array([l]))[0])
            log(f"{name:12} mean {value:.5f}  eta(550) {at(550.0):.5f}  "
                f"eta_d(587.6) {at(587.56):.5f}  eta(450) {at(450.0):.5f}  "
                f"eta(650) {at(650.0):.5f}  mitsuba lookup_ior: {lookup(mi, name)}")


def lookup(mi, name):
    try:
        return f"{mi.lookup_ior(mi.Properties(), 'int_ior', name.split('-')[1].lower()):.4f}"
    except Exception:
        return "n/a"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("spectrum_cpp", help="pbrt-v4's src/pbrt/util/spectrum.cpp")
    parser.add_argument("--check-mitsuba", action="store_true",
                        help="print a cross-check against Mitsuba 3 to stderr")
    args = parser.parse_args()
    table, arrays, cie_lambda, cmf = compute(args.spectrum_cpp)
    table = order(table)
    sys.stdout.write(rust(table))
    if args.check_mitsuba:
        check_mitsuba(table, arrays, cie_lambda, cmf)


if __name__ == "__main__":
    main()
