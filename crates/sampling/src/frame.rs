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
    pub fn from_normal(n: Vec3) -> Self {
        unimplemented!("sampling helper: Duff et al. 2017 {n}")
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
