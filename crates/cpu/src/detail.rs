//! Surface detail: pbrt-v4's bump maps (`BumpMap`, a height texture's finite differences) and
//! normal maps (`NormalMap`, a tangent-space normal from a texture), which tilt a hit's shading
//! normal before its material is placed there ([`material_kind::BUMP`],
//! [`material_kind::NORMAL_MAP`]). The geometric normal is left alone, so the shading point's
//! guard ([`crate::bsdf::ShadingPoint::eval`]) still refuses light that a tilted normal would let
//! through the surface. Mirrored in `shaders/detail.wgsl`.

use crate::intersect::{pose_at, Hit};
use glam::{Vec2, Vec3};
use stratapt_sampling::frame::Frame;
use stratapt_scene::records::{material_flag, prim_kind, Material, Motion, BUMP_DELTA};
use stratapt_scene::{texture, Prim};

/// The shading geometry's partial derivatives at a hit, in world space: pbrt-v4's
/// `shading.dpdu`, `shading.dpdv`, `shading.dndu`, `shading.dndv` for strata's `(u, v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tangents {
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    pub dndu: Vec3,
    pub dndv: Vec3,
}

/// The [`Tangents`] of `hit` on `prim` (placed at shutter time `time` if it moves).
///
/// Triangles as pbrt-v4's `Triangle::InteractionFromIntersection`: `∂p/∂u`, `∂p/∂v` from the
/// vertices' texture coordinates (strata's barycentric ones when the mesh has none), an
/// arbitrary tangent pair where those are degenerate; with vertex normals, `∂p/∂u` made
/// perpendicular to the shading normal and `∂p/∂v = n × ∂p/∂u` (pbrt's `ss`, `ts`), and the
/// normals' own derivatives. Spheres and disks from strata's parametrizations
/// ([`crate::intersect::sphere_uv`], [`crate::intersect::disk_uv`]).
pub fn tangents(prim: &Prim, motions: &[Motion], hit: &Hit, time: f32) -> Tangents {
    let pose = pose_at(motions, prim.motion, time);
    // Object-space hit point and shading normal (the tangents are found there).
    let (p, ns) = match &pose {
        // Normals go back by the transpose of the world map's inverse transpose: S R⁻¹.
        Some(pose) => (
            pose.point_to_object(hit.p),
            (pose.scale() * (pose.rotation().inverse() * hit.ns)).normalize_or(hit.ns),
        ),
        None => (hit.p, hit.ns),
    };
    let [a, b, c] = [prim.a, prim.b, prim.c].map(Vec3::from_array);
    let local = match prim.kind {
        prim_kind::TRIANGLE => triangle(prim, a, b, c, ns),
        prim_kind::SPHERE => sphere(a, b.x, p),
        _ => disk(a, b, c.x, p),
    };
    match pose {
        None => local,
        // Tangents by R S, the normal's derivatives as normals (R S⁻¹, its normalization's
        // own derivative neglected).
        Some(pose) => Tangents {
            dpdu: pose.vector_to_world(local.dpdu),
            dpdv: pose.vector_to_world(local.dpdv),
            dndu: pose.rotation() * (local.dndu / pose.scale()),
            dndv: pose.rotation() * (local.dndv / pose.scale()),
        },
    }
}

/// A triangle's tangents (pbrt-v4), `ns` its shading normal at the hit.
fn triangle(prim: &Prim, a: Vec3, b: Vec3, c: Vec3, ns: Vec3) -> Tangents {
    let [uv0, uv1, uv2] = match prim.uvs {
        Some(uvs) => uvs.map(Vec2::from_array),
        None => [Vec2::ZERO, Vec2::X, Vec2::Y],
    };
    let (duv02, duv12) = (uv0 - uv2, uv1 - uv2);
    let (dp02, dp12) = (a - c, b - c);
    let det = duv02.x * duv12.y - duv02.y * duv12.x;
    let inv = 1.0 / det;
    let mut dpdu = (dp02 * duv12.y - dp12 * duv02.y) * inv;
    let mut dpdv = (dp12 * duv02.x - dp02 * duv12.x) * inv;
    let degenerate = det.abs() < 1e-9 || dpdu.cross(dpdv).length_squared() == 0.0;
    if degenerate {
        let f = Frame::from_normal(dp12.cross(dp02).normalize_or(Vec3::Z));
        (dpdu, dpdv) = (f.s, f.t);
    }
    let Some(normals) = prim.normals else {
        // Flat: the shading geometry is the triangle's own.
        return Tangents {
            dpdu,
            dpdv,
            dndu: Vec3::ZERO,
            dndv: Vec3::ZERO,
        };
    };
    // pbrt's shading tangents: ∂p/∂u without its component along ns, and ns × ∂p/∂u.
    let mut ts = ns.cross(dpdu);
    let ss = if ts.length_squared() > 0.0 {
        ts.cross(ns)
    } else {
        let f = Frame::from_normal(ns);
        ts = f.t;
        f.s
    };
    // The vertex normals' derivatives (zero where the coordinates are degenerate: pbrt takes
    // an arbitrary pair there, which only its ray differentials use).
    let [n0, n1, n2] = normals.map(Vec3::from_array);
    let (dn1, dn2) = (n0 - n2, n1 - n2);
    let (dndu, dndv) = match degenerate {
        true => (Vec3::ZERO, Vec3::ZERO),
        false => (
            (dn1 * duv12.y - dn2 * duv02.y) * inv,
            (dn2 * duv02.x - dn1 * duv12.x) * inv,
        ),
    };
    Tangents {
        dpdu: ss,
        dpdv: ts,
        dndu,
        dndv,
    }
}

/// A sphere's tangents at `p` (centre `center`, radius `radius`): `u = φ/2π`, `v = θ/π`, so
/// `∂p/∂u = 2π (−y, x, 0)` and `∂p/∂v = π r (cos θ cos φ, cos θ sin φ, −sin θ)` about the
/// centre, and `∂n/∂· = ∂p/∂· / r`. At a pole, where φ is undefined, a tangent pair.
fn sphere(center: Vec3, radius: f32, p: Vec3) -> Tangents {
    let n = (p - center) / radius;
    let sin_theta = (n.x * n.x + n.y * n.y).sqrt();
    let (dndu, dndv) = if sin_theta > 1e-6 {
        let (cos_phi, sin_phi) = (n.x / sin_theta, n.y / sin_theta);
        (
            Vec3::new(-n.y, n.x, 0.0) * std::f32::consts::TAU,
            Vec3::new(n.z * cos_phi, n.z * sin_phi, -sin_theta) * std::f32::consts::PI,
        )
    } else {
        let f = Frame::from_normal(n);
        (f.s, f.t)
    };
    Tangents {
        dpdu: dndu * radius,
        dpdv: dndv * radius,
        dndu,
        dndv,
    }
}

/// A disk's tangents at `p` (`center`, unit `normal`, `radius`): `u` the distance from the
/// centre over the radius, `v = φ/2π`, so `∂p/∂u = radius · (p − c)/|p − c|` and
/// `∂p/∂v = 2π n × (p − c)`; flat. At the centre, the normal's frame.
fn disk(center: Vec3, normal: Vec3, radius: f32, p: Vec3) -> Tangents {
    let d = p - center;
    let f = Frame::from_normal(normal);
    let len = d.length();
    let (dpdu, dpdv) = if len > 0.0 {
        (d * (radius / len), normal.cross(d) * std::f32::consts::TAU)
    } else {
        (f.s * radius, f.t)
    };
    Tangents {
        dpdu,
        dpdv,
        dndu: Vec3::ZERO,
        dndv: Vec3::ZERO,
    }
}

/// The shading normal that bump map `m` ([`material_kind::BUMP`]) gives a point of shading
/// normal `ns`, tangents `t` and texture coordinates `uv`: pbrt-v4's `BumpMap`, the height `d`
/// read at `uv`, `uv + (δ, 0)` and `uv + (0, δ)` ([`BUMP_DELTA`]), then
/// `∂p′/∂u = ∂p/∂u + (d(u + δ) − d(u))/δ · n + d · ∂n/∂u` (and in `v`), and
/// `n′ = ∂p′/∂u × ∂p′/∂v`, normalized, on `ns`'s side. `ns` itself where that is degenerate.
pub fn bump(m: &Material, tables: &[f32], t: &Tangents, ns: Vec3, uv: Vec2) -> Vec3 {
    let height = |uv: Vec2| match m.has(material_flag::COLOR_TEXTURE) {
        true => texture::eval_scalar(tables, m.color[0] as u32, uv.to_array()),
        false => m.color[0],
    };
    let d = height(uv);
    let du = (height(uv + Vec2::new(BUMP_DELTA, 0.0)) - d) / BUMP_DELTA;
    let dv = (height(uv + Vec2::new(0.0, BUMP_DELTA)) - d) / BUMP_DELTA;
    let dpdu = t.dpdu + ns * du + t.dndu * d;
    let dpdv = t.dpdv + ns * dv + t.dndv * d;
    facing(dpdu.cross(dpdv), ns)
}

/// The shading normal that normal map `m` ([`material_kind::NORMAL_MAP`]) gives a point of
/// shading normal `ns`, tangents `t` and texture coordinates `uv`: pbrt-v4's `NormalMap`, the
/// texel's `2c − 1`, normalized, in the frame of `∂p/∂u` (made perpendicular to `ns`),
/// `ns × ∂p/∂u` and `ns`; on `ns`'s side. `ns` itself where the map or the frame is degenerate.
pub fn normal_map(m: &Material, tables: &[f32], t: &Tangents, ns: Vec3, uv: Vec2) -> Vec3 {
    let c = Vec3::from_array(texture::eval(tables, m.color[0] as u32, uv.to_array()));
    let local = (c * 2.0 - Vec3::ONE).normalize_or_zero();
    let s = (t.dpdu - ns * ns.dot(t.dpdu)).normalize_or_zero();
    if local == Vec3::ZERO || s == Vec3::ZERO {
        return ns;
    }
    let frame = Frame {
        s,
        t: ns.cross(s),
        n: ns,
    };
    facing(frame.to_world(local), ns)
}

/// `n` normalized and turned to the side of `ns`; `ns` if `n` has no direction.
fn facing(n: Vec3, ns: Vec3) -> Vec3 {
    let n = n.normalize_or_zero();
    if n == Vec3::ZERO {
        ns
    } else if n.dot(ns) < 0.0 {
        -n
    } else {
        n
    }
}

#[cfg(test)]
mod tests;
