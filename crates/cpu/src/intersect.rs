//! Ray–primitive intersection and the surface geometry at a hit.
//!
//! Static primitives are tested in world space. A moving primitive (`Prim::motion != NONE`) is
//! stored in object space: the ray is taken there by the pose at the ray's time (ray parameters
//! `t` are preserved because directions are not renormalized), and the hit geometry is brought
//! back to world space (points by the pose, normals by its inverse transpose).

pub mod disk;
pub mod sphere;
pub mod triangle;

use glam::{Vec2, Vec3};
use stratapt_sampling::atan::atan2;
use stratapt_sampling::Frame;
use stratapt_scene::records::{alpha_passes, prim_kind, Motion, Pose, NONE};
use stratapt_scene::shared::{EDGE_BARY, GAMMA_3, GAMMA_5, GAMMA_7, GAMMA_8};
use stratapt_scene::{texture, Alpha, Prim};

/// A ray segment `origin + t·dir`, `t ∈ (tmin, tmax)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    /// Unit length for world-space rays.
    pub dir: Vec3,
    pub tmin: f32,
    pub tmax: f32,
}

impl Ray {
    /// A ray over `(0, tmax)`.
    pub fn new(origin: Vec3, dir: Vec3, tmax: f32) -> Self {
        Self {
            origin,
            dir,
            tmin: 0.0,
            tmax,
        }
    }

    /// The same ray in the object space of `pose` (`t` unchanged).
    pub fn to_object(&self, pose: &Pose) -> Self {
        Self {
            origin: pose.point_to_object(self.origin),
            dir: pose.vector_to_object(self.dir),
            ..*self
        }
    }
}

/// Surface geometry at a ray hit, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) ray direction.
    pub t: f32,
    /// Index into `FlatScene::geometry`'s primitives.
    pub prim: u32,
    /// The hit point, recomputed from the surface (barycentrics / reprojection) rather than
    /// `o + t·d`, for accurate ray origins.
    pub p: Vec3,
    /// Bound on the absolute rounding error of each coordinate of `p` (its distance from the
    /// true surface is at most `|n| · err`): how far [`crate::offset`] moves ray origins.
    pub err: Vec3,
    /// Unit geometric normal on the primitive's front side (not flipped towards the ray).
    pub ng: Vec3,
    /// Unit shading normal (interpolated vertex normals, else `ng`); not flipped either.
    pub ns: Vec3,
    /// Texture coordinates, on textured surfaces only (else zero): a triangle's interpolated
    /// (or its barycentrics), [`sphere_uv`], [`disk_uv`].
    pub uv: Vec2,
}

/// The pose of a primitive or light at normalized shutter time `time`, if it moves.
pub fn pose_at(motions: &[Motion], motion: u32, time: f32) -> Option<Pose> {
    (motion != NONE).then(|| motions[motion as usize].at(time))
}

/// Distance to `prim` along `ray` within `(tmin, tmax)`, or `f32::INFINITY` on a miss (or
/// where the primitive's alpha lets the ray through: [`alpha_passes`]; `tables` hold an alpha
/// texture).
pub fn intersect_prim(
    prim: &Prim,
    motions: &[Motion],
    tables: &[f32],
    ray: &Ray,
    time: f32,
) -> f32 {
    intersect_prim_sheared(
        prim,
        motions,
        tables,
        ray,
        &triangle::Shear::new(ray.dir),
        time,
    )
}

/// [`intersect_prim`] with the world ray's triangle [`triangle::Shear`] precomputed (traversal
/// computes it once per ray; a moving primitive computes its own in object space).
pub fn intersect_prim_sheared(
    prim: &Prim,
    motions: &[Motion],
    tables: &[f32],
    ray: &Ray,
    shear: &triangle::Shear,
    time: f32,
) -> f32 {
    let (local, hit) = match pose_at(motions, prim.motion, time) {
        Some(pose) => {
            let local = ray.to_object(&pose);
            (
                local,
                intersect_local(prim, &local, &triangle::Shear::new(local.dir)),
            )
        }
        None => (*ray, intersect_local(prim, ray, shear)),
    };
    let Some((t, bary)) = hit else {
        return f32::INFINITY;
    };
    let alpha = match prim.alpha {
        Alpha::Opaque => return t,
        Alpha::Constant(a) => a,
        Alpha::Texture(i) => {
            texture::eval_scalar(tables, i, hit_uv(prim, &local, t, bary).to_array())
        }
    };
    match alpha_passes(alpha, ray.origin.to_array(), ray.dir.to_array(), prim.a) {
        true => f32::INFINITY,
        false => t,
    }
}

/// Intersection in the primitive's own space: the distance, and a triangle's barycentrics.
fn intersect_local(prim: &Prim, r: &Ray, shear: &triangle::Shear) -> Option<(f32, Vec3)> {
    let (a, b, c) = vertices(prim);
    match prim.kind {
        prim_kind::TRIANGLE => {
            triangle::intersect_sheared(a, b, c, r.origin, shear, r.tmin, r.tmax)
                .map(|h| (h.t, h.bary))
        }
        prim_kind::SPHERE => {
            sphere::intersect(a, b.x, r.origin, r.dir, r.tmin, r.tmax).map(|t| (t, Vec3::ZERO))
        }
        prim_kind::DISK => {
            disk::intersect(a, b, c.x, r.origin, r.dir, r.tmin, r.tmax).map(|t| (t, Vec3::ZERO))
        }
        _ => None,
    }
}

/// The texture coordinates of the hit at `t` along the object-space ray `r` (a triangle's at
/// `bary`), as [`surface`] computes them.
fn hit_uv(prim: &Prim, r: &Ray, t: f32, bary: Vec3) -> Vec2 {
    let (a, b, c) = vertices(prim);
    match prim.kind {
        prim_kind::TRIANGLE => triangle_uv(prim, bary),
        prim_kind::SPHERE => sphere_uv((r.origin + t * r.dir - a).normalize()),
        _ => disk_uv(a, b, c.x, disk::project(a, b, r.origin + t * r.dir)),
    }
}

/// A triangle's texture coordinates at `bary`: its vertices' interpolated, else the
/// barycentrics of the second and third vertex.
fn triangle_uv(prim: &Prim, bary: Vec3) -> Vec2 {
    match prim.uvs {
        Some([u0, u1, u2]) => {
            let [u0, u1, u2] = [u0, u1, u2].map(Vec2::from_array);
            u0 * bary.x + u1 * bary.y + u2 * bary.z
        }
        None => Vec2::new(bary.y, bary.z),
    }
}

/// Full surface geometry for a hit on `prim` at distance `t` along `ray` (as found by
/// [`intersect_prim`]). `bary`: a static triangle's barycentrics as the hit's own triangle test
/// found them (the test below computes the same bits again), else `None`.
#[allow(clippy::too_many_arguments)]
pub fn surface(
    prim_index: u32,
    prim: &Prim,
    motions: &[Motion],
    ray: &Ray,
    t: f32,
    time: f32,
    bary: Option<Vec3>,
) -> Hit {
    let pose = pose_at(motions, prim.motion, time);
    let r = match &pose {
        Some(pose) => ray.to_object(pose),
        None => *ray,
    };
    let (a, b, c) = vertices(prim);
    // Object-space point, its error bound, normals and texture coordinates.
    let (p, err, ng, ns, uv) = match prim.kind {
        prim_kind::TRIANGLE => {
            let bary = bary.unwrap_or_else(|| {
                triangle::intersect(a, b, c, r.origin, r.dir, f32::MIN, f32::MAX)
                    .map_or(Vec3::splat(1.0 / 3.0), |h| h.bary)
            });
            // The point, moved off the edges by `EDGE_BARY` (rays leave from it: see there).
            let w = bary.max(Vec3::splat(EDGE_BARY));
            let w = w / (w.x + w.y + w.z);
            let p = a * w.x + b * w.y + c * w.z;
            // The barycentrics' own error moves p within the plane; its interpolation rounds
            // by at most γ₇ Σ|bᵢ pᵢ| off it (pbrt-v4 `Triangle::InteractionFromIntersection`),
            // taken on every axis at its largest: an axis the triangle's plane is exact in (a
            // floor at y = 0) would otherwise get no offset but a few denormal ULPs, and every
            // ray from it computed in denormals, much slower on both renderers (measured:
            // docs/measurements/performance.md#ray-origins-in-denormals).
            let sum = (a * w.x).abs() + (b * w.y).abs() + (c * w.z).abs();
            let err = Vec3::splat(GAMMA_7 * sum.max_element());
            // A sliver hit edge-on has no normal: face the ray.
            let ng = triangle::normal(a, b, c).normalize_or(-r.dir.normalize());
            let uv = match prim.textured {
                false => Vec2::ZERO,
                true => triangle_uv(prim, bary),
            };
            (p, err, ng, shading_normal(prim, bary, ng), uv)
        }
        prim_kind::SPHERE => {
            // Reproject onto the sphere: the normalization and the sum round by a few ULPs of
            // the centre and the radius.
            let n = (r.origin + t * r.dir - a).normalize();
            let rn = b.x * n;
            // (On every axis at its largest, as for triangles.)
            let err = GAMMA_5 * (a.abs() + rn.abs()).max_element();
            let uv = if prim.textured {
                sphere_uv(n)
            } else {
                Vec2::ZERO
            };
            (a + rn, Vec3::splat(err), n, n, uv)
        }
        _ => {
            // Projection onto the plane: the distance to it rounds relative to the point's and
            // the centre's magnitudes.
            let q = r.origin + t * r.dir;
            let err = Vec3::splat(GAMMA_7 * (a.abs() + q.abs()).max_element());
            let p = disk::project(a, b, q);
            let uv = match prim.textured {
                true => disk_uv(a, b, c.x, p),
                false => Vec2::ZERO,
            };
            (p, err, b, b, uv)
        }
    };
    match pose {
        Some(pose) => Hit {
            t,
            prim: prim_index,
            p: pose.point_to_world(p),
            err: pose_error(&pose, p, err),
            ng: pose.normal_to_world(ng),
            ns: pose.normal_to_world(ns),
            uv,
        },
        None => Hit {
            t,
            prim: prim_index,
            p,
            err,
            ng,
            ns,
            uv,
        },
    }
}

/// The `(u, v)` of a sphere's point whose unit offset from the centre is `n` (object space):
/// `u = φ / 2π ∈ [0, 1)` with `φ` from +x towards +y, `v = θ / π` with `θ` from +z (Mitsuba 3's
/// `sphere`; `θ` by `atan2`, as the environment map's, for precision near the poles).
pub fn sphere_uv(n: Vec3) -> Vec2 {
    let u = atan2(n.y, n.x) * (0.5 / std::f32::consts::PI);
    let u = if u < 0.0 { u + 1.0 } else { u };
    let v = atan2((n.x * n.x + n.y * n.y).sqrt(), n.z) * (1.0 / std::f32::consts::PI);
    Vec2::new(u, v)
}

/// The `(u, v)` of point `p` of the disk (`center`, unit `normal`, `radius`): `u` the distance
/// from the centre over the radius, `v = φ / 2π ∈ [0, 1)` with `φ` measured in the plane from
/// the normal's [`Frame`] tangents `s` towards `t` (Mitsuba 3's `disk`, whose frame for
/// `normal = +z` is x, y).
pub fn disk_uv(center: Vec3, normal: Vec3, radius: f32, p: Vec3) -> Vec2 {
    let frame = Frame::from_normal(normal);
    let d = p - center;
    let (x, y) = (d.dot(frame.s), d.dot(frame.t));
    let v = atan2(y, x) * (0.5 / std::f32::consts::PI);
    let v = if v < 0.0 { v + 1.0 } else { v };
    Vec2::new((x * x + y * y).sqrt() / radius, v)
}

/// Error bound of `pose.point_to_world(p)` for an object-space point `p` with error bound `err`:
/// the scaled error rotated (at most its length on any axis), the rotation's and translation's
/// own rounding (a few ULPs of the rotated point and of the result), and the rounding of taking
/// a spawned origin back to object space (`point_to_object`, the same magnitudes again).
fn pose_error(pose: &Pose, p: Vec3, err: Vec3) -> Vec3 {
    let scaled = (pose.scale() * p).length();
    let moved = pose.translation().length();
    let rotated = (pose.scale().abs() * err).length() * (1.0 + GAMMA_3) + GAMMA_8 * scaled;
    Vec3::splat(rotated + GAMMA_8 * (scaled + moved) + GAMMA_3 * rotated)
}

/// Interpolated vertex normal, or `ng` for flat shading (or a degenerate interpolation).
fn shading_normal(prim: &Prim, bary: Vec3, ng: Vec3) -> Vec3 {
    let Some(normals) = prim.normals else {
        return ng;
    };
    let n = |k: usize| Vec3::from_array(normals[k]);
    let ns = (n(0) * bary.x + n(1) * bary.y + n(2) * bary.z).normalize_or_zero();
    if ns == Vec3::ZERO {
        ng
    } else {
        ns
    }
}

fn vertices(prim: &Prim) -> (Vec3, Vec3, Vec3) {
    (
        Vec3::from_array(prim.a),
        Vec3::from_array(prim.b),
        Vec3::from_array(prim.c),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn analytic_shapes_parametrize_as_mitsuba() {
        let close = |a: Vec2, b: [f32; 2]| (a - Vec2::from_array(b)).abs().max_element() < 1e-6;
        // Sphere: u from +x towards +y, v from the +z pole.
        for (n, uv) in [
            (Vec3::X, [0.0, 0.5]),
            (Vec3::Y, [0.25, 0.5]),
            (-Vec3::X, [0.5, 0.5]),
            (-Vec3::Y, [0.75, 0.5]),
            (Vec3::Z, [0.0, 0.0]),
            (Vec3::new(0.0, 0.0, -1.0), [0.0, 1.0]),
            (Vec3::new(1.0, 0.0, 1.0).normalize(), [0.0, 0.25]),
        ] {
            assert!(close(sphere_uv(n), uv), "{n}: {}", sphere_uv(n));
        }
        // Just below the seam u is just below 1.
        assert!(sphere_uv(Vec3::new(1.0, -1e-4, 0.0).normalize()).x > 0.9999);
        // Disk (normal +z: the frame is x, y): u the radius fraction, v the angle.
        let c = Vec3::new(1.0, 2.0, 3.0);
        for (p, uv) in [
            (c, [0.0, 0.0]),
            (c + Vec3::new(1.0, 0.0, 0.0), [0.5, 0.0]),
            (c + Vec3::new(0.0, 2.0, 0.0), [1.0, 0.25]),
            (c + Vec3::new(-1.0, 0.0, 0.0), [0.5, 0.5]),
        ] {
            assert!(close(disk_uv(c, Vec3::Z, 2.0, p), uv), "{p}");
        }
    }
}
