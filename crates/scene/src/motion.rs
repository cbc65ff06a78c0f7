//! Poses and their interpolation over the shutter.

use crate::records::{Motion, Pose};
use glam::{Mat4, Quat, Vec3};

impl Pose {
    pub fn new(translation: Vec3, rotation: Quat, scale: Vec3) -> Self {
        Self {
            translation: translation.to_array(),
            _pad0: 0,
            rotation: rotation.normalize().to_array(),
            scale: scale.to_array(),
            _pad1: 0,
        }
    }

    pub const IDENTITY: Pose = Pose {
        translation: [0.0; 3],
        _pad0: 0,
        rotation: [0.0, 0.0, 0.0, 1.0],
        scale: [1.0; 3],
        _pad1: 0,
    };

    pub fn translation(&self) -> Vec3 {
        Vec3::from_array(self.translation)
    }
    pub fn rotation(&self) -> Quat {
        Quat::from_array(self.rotation)
    }
    pub fn scale(&self) -> Vec3 {
        Vec3::from_array(self.scale)
    }

    /// Object-to-world matrix `T · R · S`.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale(), self.rotation(), self.translation())
    }

    /// Map an object-space point to world space.
    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        self.rotation() * (self.scale() * p) + self.translation()
    }
    /// Map a world-space point to object space.
    pub fn point_to_object(&self, p: Vec3) -> Vec3 {
        (self.rotation().inverse() * (p - self.translation())) / self.scale()
    }
    /// Map an object-space direction (not normalized) to world space.
    pub fn vector_to_world(&self, v: Vec3) -> Vec3 {
        self.rotation() * (self.scale() * v)
    }
    /// Map a world-space direction to object space (lengths change with scale, so ray
    /// parameters `t` are preserved).
    pub fn vector_to_object(&self, v: Vec3) -> Vec3 {
        (self.rotation().inverse() * v) / self.scale()
    }
    /// Map an object-space normal to world space (inverse transpose), normalized.
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        (self.rotation() * (n / self.scale())).normalize()
    }
}

impl Motion {
    /// The pose at normalized shutter time `t ∈ [0, 1]`: lerp of translation and scale, slerp of
    /// rotation (shortest arc).
    pub fn at(&self, t: f32) -> Pose {
        let (a, b) = (&self.open, &self.close);
        Pose::new(
            a.translation().lerp(b.translation(), t),
            a.rotation().slerp(b.rotation(), t),
            a.scale().lerp(b.scale(), t),
        )
    }

    /// Whether the pose changes at all during the shutter.
    pub fn is_moving(&self) -> bool {
        self.open != self.close
    }
}
