//! Environment map ([`stratapt_scene::environment`]): radiance by Mitsuba's bilinear lookup
//! (latitude–longitude) or pbrt-v4's nearest texel (equal-area octahedral), directions
//! importance-sampled by the map's piecewise-constant distribution.

use super::LightSample;
use glam::{Mat3, Vec2, Vec3};
use stratapt_scene::environment::{self, octahedral};
use stratapt_scene::records::{light_kind, Light};

/// A placed environment map: its data in the scene's tables, its layout and its frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Environment<'a> {
    /// Texels then distribution ([`environment::EnvironmentMap::data`]).
    pub data: &'a [f32],
    pub width: usize,
    pub height: usize,
    /// pbrt-v4's equal-area octahedral layout ([`light_kind::OCTAHEDRAL`]), not
    /// latitude–longitude.
    pub octahedral: bool,
    /// World → map directions.
    pub to_map: Mat3,
}

impl<'a> Environment<'a> {
    /// The map of `light` in `tables`; `None` when the tables do not hold it.
    pub fn of(light: &Light, tables: &'a [f32]) -> Option<Self> {
        let [w, h, offset] = light.p2.map(|x| x as usize);
        let data = tables.get(offset..offset + environment::data_len(w, h))?;
        let (r0, r1) = (Vec3::from_array(light.p0), Vec3::from_array(light.p1));
        Some(Self {
            data,
            width: w,
            height: h,
            octahedral: light.kind == light_kind::OCTAHEDRAL,
            to_map: Mat3::from_cols(r0, r1, r0.cross(r1)).transpose(),
        })
    }

    pub fn sample(&self, u: Vec2) -> Option<LightSample> {
        let (d, pdf, radiance) = if self.octahedral {
            octahedral::sample(self.data, self.width, u)?
        } else {
            let (d, pdf) = environment::sample(self.data, self.width, self.height, u)?;
            (
                d,
                pdf,
                environment::radiance(self.data, self.width, self.height, d),
            )
        };
        // Map → world: the transpose of world → map.
        let wi = self.to_map.transpose() * d;
        Some(LightSample::unoffset(
            wi,
            f32::INFINITY,
            radiance,
            pdf,
            false,
        ))
    }

    pub fn pdf(&self, wi: Vec3) -> f32 {
        let d = self.to_map * wi;
        if self.octahedral {
            octahedral::pdf(self.data, self.width, d)
        } else {
            environment::pdf(self.data, self.width, self.height, d)
        }
    }

    pub fn radiance(&self, wi: Vec3) -> Vec3 {
        let d = self.to_map * wi;
        if self.octahedral {
            octahedral::radiance(self.data, self.width, d)
        } else {
            environment::radiance(self.data, self.width, self.height, d)
        }
    }
}
