//! strata's lights that are not surfaces as Mitsuba 3 emitters: point, spot and directional
//! lights, line lights as thin emitting cylinders, and the sky as a `constant` or `envmap`
//! emitter (gradients and octahedral maps as latitude–longitude images).

use super::xml::Element;
use super::{triple, Writer};
use glam::{Mat3, Mat4, Vec2, Vec3};
use stratapt_scene::environment::{self, octahedral, pfm_bytes};
use stratapt_scene::records::{light_kind as kind, Light};

/// Rows of a baked sky gradient's map (its columns twice as many); its bilinear lookup is within
/// 2·10⁻⁵ of the gradient.
const GRADIENT_ROWS: usize = 256;

impl Writer<'_> {
    /// Every light that is not a surface's.
    pub(super) fn emitters(&mut self) -> Vec<Element> {
        let lights = self.scene.lights.clone();
        let mut out = Vec::new();
        for (i, l) in lights.iter().enumerate() {
            let e = match l.kind {
                kind::POINT => Element::plugin("emitter", "point")
                    .child(Element::point("position", Vec3::from(l.p0)))
                    .child(Element::rgb("intensity", l.radiance)),
                kind::LINE => self.line(l),
                kind::DISTANT => self.distant(l),
                kind::SPOT => self.spot(l),
                kind::SKY => self.gradient(l),
                kind::ENVIRONMENT | kind::OCTAHEDRAL => self.environment(i, l),
                _ => continue,
            };
            out.push(e);
        }
        out
    }

    /// A line light as an open cylinder of radius 10⁻³ of its length whose radiance is the
    /// line's intensity per length over its diameter: a Lambertian tube of diameter d and
    /// radiance L sends `L · d · sin θ` per unit length at angle θ to its axis, as the line does.
    fn line(&mut self, l: &Light) -> Element {
        let (a, b) = (Vec3::from(l.p0), Vec3::from(l.p1));
        let radius = 1e-3 * (b - a).length();
        self.warn(format!(
            "line light: Mitsuba has none; drawn as an emitting cylinder of radius {radius}, which \
             camera rays can also hit"
        ));
        let radiance = l.radiance.map(|i| i / (2.0 * radius));
        Element::plugin("shape", "cylinder")
            .child(Element::point("p0", a))
            .child(Element::point("p1", b))
            .child(Element::float("radius", radius))
            .child(Element::plugin("bsdf", "diffuse").child(Element::rgb("reflectance", [0.0; 3])))
            .child(Element::plugin("emitter", "area").child(Element::rgb("radiance", radiance)))
    }

    /// A distant light; a sun cone as the delta light of the same irradiance, `L π sin²α`.
    fn distant(&mut self, l: &Light) -> Element {
        let cos = l.p2[0];
        let irradiance = match cos < 1.0 {
            true => {
                self.warn(
                    "distant light with an angular diameter: Mitsuba's directional light is a \
                     delta; written with the cone's irradiance (soft shadows become hard)"
                        .into(),
                );
                // sin² α as (1 − cos α)(1 + cos α): 1 − cos² loses digits for a sun's tiny α.
                let solid = std::f32::consts::PI * (1.0 - cos) * (1.0 + cos);
                l.radiance.map(|r| r * solid)
            }
            false => l.radiance,
        };
        Element::plugin("emitter", "directional")
            .child(
                Element::new("vector")
                    .attr("name", "direction")
                    .attr("x", -l.p0[0])
                    .attr("y", -l.p0[1])
                    .attr("z", -l.p0[2]),
            )
            .child(Element::rgb("irradiance", irradiance))
    }

    /// pbrt-v4's spot light as Mitsuba's, whose falloff is linear in angle where pbrt's is a
    /// smoothstep in cosine.
    fn spot(&mut self, l: &Light) -> Element {
        let (position, axis) = (Vec3::from(l.p0), Vec3::from(l.p1));
        let cutoff = l.p2[0].clamp(-1.0, 1.0).acos().to_degrees();
        let mut beam = l.p2[1].clamp(-1.0, 1.0).acos().to_degrees();
        if beam < cutoff {
            self.warn(
                "spot light: Mitsuba's falloff is linear in angle, pbrt-v4's (strata's) a \
                 smoothstep in cosine; they differ inside the falloff ring"
                    .into(),
            );
        } else {
            // A hard edge: Mitsuba divides by the ring's width.
            beam = cutoff * (1.0 - 1e-6);
        }
        let lookat = Element::new("lookat")
            .attr("origin", triple(position))
            .attr("target", triple(position + axis))
            .attr("up", triple(any_perpendicular(axis)));
        Element::plugin("emitter", "spot")
            .child(Element::rgb("intensity", l.radiance))
            .child(Element::float("cutoff_angle", cutoff))
            .child(Element::float("beam_width", beam))
            .child(
                Element::new("transform")
                    .attr("name", "to_world")
                    .child(lookat),
            )
    }

    /// The sky gradient `lerp(bottom, top, ½(1 + ω·up))`: a constant emitter when the two are
    /// equal, else a latitude–longitude map of it whose pole is `up`.
    fn gradient(&mut self, l: &Light) -> Element {
        let (bottom, top) = (l.radiance, l.p1);
        if bottom == top {
            return Element::plugin("emitter", "constant").child(Element::rgb("radiance", top));
        }
        let (w, h) = (2 * GRADIENT_ROWS, GRADIENT_ROWS);
        let mut texels = Vec::with_capacity(3 * w * h);
        for j in 0..h {
            let cos = (std::f64::consts::PI * j as f64 / (h - 1) as f64).cos();
            let t = (0.5 * (1.0 + cos)) as f32;
            let rgb: [f32; 3] = std::array::from_fn(|c| bottom[c] + (top[c] - bottom[c]) * t);
            for _ in 0..w {
                texels.extend(rgb);
            }
        }
        let file = self.file("sky.pfm".into(), pfm_bytes(&texels, w, h));
        // The map's +y (its top row) onto `up`.
        let up = Vec3::from(l.p0);
        let x = any_perpendicular(up).cross(up).normalize();
        let to_world = Mat3::from_cols(x, up, x.cross(up));
        envmap(&file, to_world)
    }

    /// An environment map: its texels (scaled and mirrored at load) as a PFM file, turned into
    /// the world by the inverse of the light's world → map rotation; an octahedral map
    /// resampled into a latitude–longitude one ([`resample_octahedral`]).
    fn environment(&mut self, index: usize, l: &Light) -> Element {
        let (w, h, offset) = (l.p2[0] as usize, l.p2[1] as usize, l.p2[2] as usize);
        let data = &self.scene.tables[offset..];
        let (texels, w, h) = match l.kind {
            kind::OCTAHEDRAL => {
                self.warn(format!(
                    "environment map: Mitsuba has no octahedral layout; resampled into a \
                     {}×{} latitude–longitude map",
                    resampled_width(w),
                    resampled_width(w) / 2
                ));
                resample_octahedral(data, w)
            }
            _ => (data[..3 * w * h].to_vec(), w, h),
        };
        let file = self.file(format!("environment{index}.pfm"), pfm_bytes(&texels, w, h));
        let (r0, r1) = (Vec3::from(l.p0), Vec3::from(l.p1));
        // The rows of the world → map rotation are the columns of its inverse.
        envmap(&file, Mat3::from_cols(r0, r1, r0.cross(r1)))
    }
}

/// Mitsuba's `envmap` of `file`, its frame turned into the world by `to_world`.
fn envmap(file: &str, to_world: Mat3) -> Element {
    Element::plugin("emitter", "envmap")
        .child(Element::string("filename", file))
        .child(Element::matrix("to_world", Mat4::from_mat3(to_world)))
}

/// A unit vector perpendicular to `v`.
fn any_perpendicular(v: Vec3) -> Vec3 {
    v.normalize().any_orthonormal_vector()
}

/// The width of the latitude–longitude map an octahedral map `w` texels a side is resampled
/// into: 4w (twice as fine as the square at the equator: at 2w the bundled studio map's small
/// sun blurred, and the image mean moved by 2.9 % against 0.13 %), at most 4096, at least 4.
fn resampled_width(w: usize) -> usize {
    (4 * w).clamp(4, 4096)
}

/// The octahedral map in `data` (`w × w` texels first) as a latitude–longitude map
/// ([`resampled_width`] × half of it), each texel the mean of 2 × 2 nearest lookups around its
/// centre; with its width and height.
fn resample_octahedral(data: &[f32], w: usize) -> (Vec<f32>, usize, usize) {
    let ww = resampled_width(w);
    let hh = ww / 2;
    let mut out = Vec::with_capacity(3 * ww * hh);
    for j in 0..hh {
        for i in 0..ww {
            let mut sum = Vec3::ZERO;
            for (di, dj) in [(0.25, -0.25), (0.75, -0.25), (0.25, 0.25), (0.75, 0.25)] {
                let u = (i as f32 + di) / ww as f32;
                let v = ((j as f32 + dj) / (hh - 1) as f32).clamp(0.0, 1.0);
                let (d, _) = environment::uv_to_direction(Vec2::new(u, v));
                sum += octahedral::radiance(data, w, d);
            }
            out.extend((sum * 0.25).to_array());
        }
    }
    (out, ww, hh)
}
