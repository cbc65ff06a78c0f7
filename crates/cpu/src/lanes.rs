//! Eight lanes of f32 as AVX2 vectors (`wide`): three-vectors in SoA form, masks, and the
//! ray-origin offset of [`crate::offset`] per lane.

use bytemuck::cast;
use glam::Vec3;
use std::ops::{Add, Mul, Neg, Sub};
use stratapt_scene::shared::{GAMMA_5, OFFSET_INT_SCALE};
use wide::{f32x8, i32x8, CmpEq, CmpGt, CmpLt};

/// Lanes per vector.
pub const LANES: usize = 8;

/// A number in the lanes one routine runs in, written once for all: one (`f32`), four
/// (glam's `Vec4`) or eight (`f32x8`); each lane runs the scalar operations, so the same
/// inputs give the same bits whatever the width.
pub trait Lane: Copy + std::ops::Add<Output = Self> + std::ops::Mul<Output = Self> {
    fn splat(x: f32) -> Self;
    fn abs(self) -> Self;
}

impl Lane for f32 {
    fn splat(x: f32) -> Self {
        x
    }
    fn abs(self) -> Self {
        f32::abs(self)
    }
}

impl Lane for glam::Vec4 {
    fn splat(x: f32) -> Self {
        glam::Vec4::splat(x)
    }
    fn abs(self) -> Self {
        glam::Vec4::abs(self)
    }
}

impl Lane for f32x8 {
    fn splat(x: f32) -> Self {
        f32x8::splat(x)
    }
    fn abs(self) -> Self {
        f32x8::abs(self)
    }
}

/// A lane mask: all bits set in a lane that is on (what `wide`'s comparisons return).
pub type Mask = f32x8;

/// Eight three-vectors, one coordinate per register.
#[derive(Clone, Copy, Debug, Default)]
pub struct V3 {
    pub x: f32x8,
    pub y: f32x8,
    pub z: f32x8,
}

impl V3 {
    pub fn splat(v: Vec3) -> Self {
        Self {
            x: f32x8::splat(v.x),
            y: f32x8::splat(v.y),
            z: f32x8::splat(v.z),
        }
    }

    /// Lane `i` of each coordinate.
    pub fn from_lanes(v: &[Vec3; LANES]) -> Self {
        Self {
            x: f32x8::from(std::array::from_fn::<f32, LANES, _>(|i| v[i].x)),
            y: f32x8::from(std::array::from_fn::<f32, LANES, _>(|i| v[i].y)),
            z: f32x8::from(std::array::from_fn::<f32, LANES, _>(|i| v[i].z)),
        }
    }

    pub fn lane(&self, i: usize) -> Vec3 {
        Vec3::new(
            self.x.as_array_ref()[i],
            self.y.as_array_ref()[i],
            self.z.as_array_ref()[i],
        )
    }

    pub fn dot(self, o: Self) -> f32x8 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// glam's `cross`, operation for operation.
    pub fn cross(self, o: Self) -> Self {
        Self {
            x: self.y * o.z - o.y * self.z,
            y: self.z * o.x - o.z * self.x,
            z: self.x * o.y - o.x * self.y,
        }
    }

    pub fn length(self) -> f32x8 {
        self.dot(self).sqrt()
    }

    /// `self / |self|`, as glam's `normalize` (times the reciprocal).
    pub fn normalize(self) -> Self {
        self * (f32x8::ONE / self.length())
    }

    /// `self / s` per coordinate (a division, as glam's `Vec3 / f32`).
    pub fn div(self, s: f32x8) -> Self {
        Self {
            x: self.x / s,
            y: self.y / s,
            z: self.z / s,
        }
    }

    pub fn abs(self) -> Self {
        Self {
            x: self.x.abs(),
            y: self.y.abs(),
            z: self.z.abs(),
        }
    }

    pub fn max_element(self) -> f32x8 {
        self.x.max(self.y).max(self.z)
    }

    /// `mask ? t : f` per lane.
    pub fn select(mask: Mask, t: Self, f: Self) -> Self {
        Self {
            x: mask.blend(t.x, f.x),
            y: mask.blend(t.y, f.y),
            z: mask.blend(t.z, f.z),
        }
    }

    /// `self` where `mask`, zero elsewhere.
    pub fn keep(self, mask: Mask) -> Self {
        Self {
            x: self.x & mask,
            y: self.y & mask,
            z: self.z & mask,
        }
    }
}

impl Add for V3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for V3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl Mul for V3 {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self {
            x: self.x * o.x,
            y: self.y * o.y,
            z: self.z * o.z,
        }
    }
}

impl Mul<f32x8> for V3 {
    type Output = Self;
    fn mul(self, s: f32x8) -> Self {
        Self {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl Neg for V3 {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

/// `v` with its sign flipped where `mask` is on.
pub fn flip(v: V3, mask: Mask) -> V3 {
    let sign = mask & f32x8::splat(-0.0);
    V3 {
        x: v.x ^ sign,
        y: v.y ^ sign,
        z: v.z ^ sign,
    }
}

/// Lanes of a mask as bits (lane `i` → bit `i`).
pub fn bits(mask: Mask) -> u32 {
    mask.move_mask() as u32
}

/// The mask of the lanes whose bit is set in `bits`.
pub fn mask_of(bits: u32) -> Mask {
    let lane_bits = i32x8::from([1, 2, 4, 8, 16, 32, 64, 128]);
    cast((i32x8::splat(bits as i32) & lane_bits).cmp_eq(lane_bits))
}

/// [`crate::offset::offset_ray_origin`] per lane: `p` (coordinates within `err` of the
/// surface) moved off the surface to the side of the unit normal `n`, by the same steps along
/// the number line.
pub fn offset_ray_origin(p: V3, err: V3, n: V3) -> V3 {
    let q = p + n * (n.abs().dot(err) * f32x8::splat(1.0 + GAMMA_5));
    V3 {
        x: step(q.x, n.x),
        y: step(q.y, n.y),
        z: step(q.z, n.z),
    }
}

/// [`offset_ray_origin`]'s move of one coordinate `x` by `OFFSET_INT_SCALE · |n|` (at least
/// one) representable floats in the direction of `n`'s sign; `x` itself where `n` is zero.
fn step(x: f32x8, n: f32x8) -> f32x8 {
    let count = (n.abs() * f32x8::splat(OFFSET_INT_SCALE))
        .trunc_int()
        .max(i32x8::splat(1));
    let positive: i32x8 = cast(n.cmp_gt(f32x8::ZERO));
    let negative: i32x8 = cast(n.cmp_lt(f32x8::ZERO));
    let steps = positive.blend(count, negative.blend(-count, i32x8::ZERO));
    let bits: i32x8 = cast(x);
    let ordered = bits
        .cmp_lt(i32x8::ZERO)
        .blend(-(bits & i32x8::splat(i32::MAX)), bits);
    let moved = ordered + steps;
    let out = moved
        .cmp_lt(i32x8::ZERO)
        .blend(-moved | i32x8::splat(i32::MIN), moved);
    let keep: f32x8 = cast(steps.cmp_eq(i32x8::ZERO));
    keep.blend(x, cast(out))
}

/// [`crate::offset::spawn_origin`] per lane: `p` offset to the side of `ng` that `dir` points to.
pub fn spawn_origin(p: V3, err: V3, ng: V3, dir: V3) -> V3 {
    offset_ray_origin(p, err, flip(ng, ng.dot(dir).cmp_lt(f32x8::ZERO)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use stratapt_sampling::testing::TestRng;

    #[test]
    fn masks_and_bits_round_trip() {
        for b in 0..256u32 {
            assert_eq!(bits(mask_of(b)), b);
        }
    }

    /// Every lane's offset is the one-lane function's, bit for bit, over points near and far
    /// from the origin, zero and negative coordinates and axis-aligned normals.
    #[test]
    fn offsets_are_the_reference_offsets() {
        let mut rng = TestRng(7);
        for round in 0..2000 {
            let scale = [1e-3f32, 1.0, 1e5][round % 3];
            let pick = |rng: &mut TestRng| {
                let v = Vec3::new(rng.f32() - 0.5, rng.f32() - 0.5, rng.f32() - 0.5);
                if rng.f32() < 0.2 {
                    Vec3::new(v.x, 0.0, -0.0)
                } else {
                    v
                }
            };
            let p: [Vec3; LANES] = std::array::from_fn(|_| pick(&mut rng) * scale);
            let err: [Vec3; LANES] = std::array::from_fn(|_| pick(&mut rng).abs() * 1e-6 * scale);
            let n: [Vec3; LANES] = std::array::from_fn(|i| match i {
                0 => Vec3::Y,
                1 => -Vec3::X,
                _ => pick(&mut rng).normalize_or(Vec3::Z),
            });
            let got =
                offset_ray_origin(V3::from_lanes(&p), V3::from_lanes(&err), V3::from_lanes(&n));
            for i in 0..LANES {
                let want = crate::offset::offset_ray_origin(p[i], err[i], n[i]);
                assert_eq!(
                    got.lane(i).to_array().map(f32::to_bits),
                    want.to_array().map(f32::to_bits)
                );
            }
        }
    }
}
