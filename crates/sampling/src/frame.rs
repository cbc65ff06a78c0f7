//! Orthonormal frame around a unit normal.

use glam::Vec3;

/// Right-handed orthonormal basis `(s, t, n)`; local `z` is `n`.
///
/// Built branchlessly by Duff et al. 2017, "Building an Orthonormal Basis, Revisited" (JCGT 6(1)),
/// so that the WGSL mirror produces the same tangents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// Frame whose `z` axis is the unit vector `n`.
    ///
    /// The sign is `n.z >= 0 ? 1 : -1` (so `-0.0` counts as positive, as WGSL's
    /// `select(-1.0, 1.0, n.z >= 0.0)` does; `copysign` would differ there).
    pub fn from_normal(n: Vec3) -> Self {
        let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Self { s, t, n }
    }
    /// World → local coordinates.
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }
    /// Local → world coordinates.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}
