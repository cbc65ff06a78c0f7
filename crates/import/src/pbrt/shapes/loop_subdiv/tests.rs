//! Loop subdivision against what it must give: four triangles for one per level, limit
//! positions that do not move from level to level, the hand-computed limits of a regular
//! tetrahedron's, an octahedron's and a valence-6 vertex, planes that stay planes, normals on
//! pbrt's side; and meshes pbrt-v4 has no answer for, told rather than panicked on.

use super::level::{next, Level};
use super::rules::{beta, loop_gamma, weigh_boundary};
use super::*;
use std::collections::HashMap;
use std::f64::consts::PI;

/// Faces of a convex mesh round the origin wound counter-clockwise seen from outside.
fn outward(points: &[DVec3], faces: &[[u32; 3]]) -> Vec<[u32; 3]> {
    faces
        .iter()
        .map(|&[a, b, c]| {
            let p = |i: u32| points[i as usize];
            let n = (p(b) - p(a)).cross(p(c) - p(a));
            match n.dot(p(a) + p(b) + p(c)) > 0.0 {
                true => [a, b, c],
                false => [a, c, b],
            }
        })
        .collect()
}

/// The unit octahedron (vertices ±x, ±y, ±z in that order), wound outward.
fn octahedron() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let points = vec![
        DVec3::X,
        -DVec3::X,
        DVec3::Y,
        -DVec3::Y,
        DVec3::Z,
        -DVec3::Z,
    ];
    let faces: Vec<[u32; 3]> = (0..8)
        .map(|i| [i & 1, 2 + (i >> 1 & 1), 4 + (i >> 2 & 1)])
        .collect();
    let faces = outward(&points, &faces);
    (points, faces)
}

/// A regular tetrahedron centred on the origin, wound outward.
fn tetrahedron() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let points = vec![
        DVec3::new(1.0, 1.0, 1.0),
        DVec3::new(1.0, -1.0, -1.0),
        DVec3::new(-1.0, 1.0, -1.0),
        DVec3::new(-1.0, -1.0, 1.0),
    ];
    let faces = outward(&points, &[[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]);
    (points, faces)
}

/// A `side` × `side` grid of unit squares in the plane z = 0, each two triangles wound
/// counter-clockwise seen from +z.
fn grid(side: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let at = |x: u32, y: u32| y * (side + 1) + x;
    let points = (0..=side)
        .flat_map(|y| (0..=side).map(move |x| DVec3::new(x as f64, y as f64, 0.0)))
        .collect();
    let faces = (0..side)
        .flat_map(|y| (0..side).map(move |x| (x, y)))
        .flat_map(|(x, y)| {
            let (a, b, c, d) = (at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1));
            [[a, b, c], [a, c, d]]
        })
        .collect();
    (points, faces)
}

fn subdivided(mesh: &(Vec<DVec3>, Vec<[u32; 3]>), levels: u32) -> Subdivided {
    subdivide(&mesh.0, &mesh.1, levels).expect("a manifold mesh")
}

/// The unit normal of triangle `t` by its winding.
fn winding_normal(s: &Subdivided, t: [u32; 3]) -> DVec3 {
    let p = |i: u32| s.positions[i as usize];
    (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).normalize()
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol
}

#[test]
fn each_level_makes_four_triangles_of_one_and_a_closed_mesh_stays_closed() {
    for (mesh, faces) in [(octahedron(), 8), (tetrahedron(), 4)] {
        for levels in 0..=4 {
            let s = subdivided(&mesh, levels);
            let triangles = faces * 4usize.pow(levels);
            assert_eq!(s.triangles.len(), triangles);
            // Euler: a closed genus-0 mesh of F triangles has 2 + F/2 vertices.
            assert_eq!(s.positions.len(), 2 + triangles / 2);
            assert_eq!(s.normals.len(), s.positions.len());
        }
    }
}

#[test]
fn limit_positions_do_not_move_from_level_to_level() {
    for mesh in [octahedron(), tetrahedron()] {
        let (coarse, fine) = (subdivided(&mesh, 3), subdivided(&mesh, 4));
        let control = subdivided(&mesh, 0);
        // A vertex keeps its number: the first ones of level 4 are level 3's, and the first
        // of those the control mesh's.
        for (i, p) in coarse.positions.iter().enumerate() {
            assert!(close(*p, fine.positions[i], 1e-13), "vertex {i}");
        }
        for (i, p) in control.positions.iter().enumerate() {
            assert!(close(*p, fine.positions[i], 1e-13), "vertex {i}");
        }
    }
}

/// The control grid's boundary vertices after `levels` levels, moved by `(1 − 2w) p + w` of
/// each boundary neighbour.
fn grid_boundary_limits(levels: u32, w: f64) -> Vec<DVec3> {
    let (points, faces) = grid(3);
    let mut mesh = Level::new(&points, &faces).unwrap();
    for _ in 0..levels {
        mesh = mesh.refine();
    }
    let mut ring = Vec::new();
    (0..points.len() as u32)
        .filter(|&v| mesh.boundary[v as usize])
        .map(|v| {
            mesh.ring(v, &mut ring);
            weigh_boundary(&mesh.p, v, &ring, w)
        })
        .collect()
}

#[test]
fn the_level_to_level_check_catches_a_wrong_limit_rule_as_pbrts_boundary_one() {
    // The boundary rules (1/8, 3/4, 1/8 and 1/2, 1/2) refine the cubic B-spline of the
    // boundary polygon, whose limit weights are 1/6, 2/3, 1/6: with them the limits do not
    // move. pbrt's 1/5, 3/5, 1/5 moves the rounded corners' vertices from level to level
    // (5.5 · 10⁻⁴ of a grid cell from level 3 to 4), and strata keeps pbrt's.
    let gap = |w: f64| {
        let (a, b) = (grid_boundary_limits(3, w), grid_boundary_limits(4, w));
        a.iter()
            .zip(&b)
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max)
    };
    assert_eq!(grid_boundary_limits(0, 0.2).len(), 12);
    assert!(gap(1.0 / 6.0) < 1e-13, "{}", gap(1.0 / 6.0));
    assert!(gap(1.0 / 5.0) > 1e-4, "{}", gap(1.0 / 5.0));
}

#[test]
fn a_regular_tetrahedrons_corner_limits_at_a_fifth_of_itself() {
    // Valence 3: β = 3/16, γ = 1 / (3 + 3 / (8 · 3/16)) = 1/5, so the limit is 2/5 p + 1/5 of
    // the other three corners, which sum to −p: p/5.
    assert_eq!(loop_gamma(3), 1.0 / 5.0);
    let mesh = tetrahedron();
    for levels in [0, 3] {
        let s = subdivided(&mesh, levels);
        for (i, p) in mesh.0.iter().enumerate() {
            assert!(close(s.positions[i], *p / 5.0, 1e-14), "level {levels}");
        }
    }
}

#[test]
fn an_octahedrons_corner_limits_halfway_to_the_centre() {
    // Valence 4: β = 3/32, γ = 1 / (4 + 4) = 1/8; the four neighbours sum to 0.
    assert_eq!(loop_gamma(4), 1.0 / 8.0);
    let mesh = octahedron();
    let s = subdivided(&mesh, 2);
    for (i, p) in mesh.0.iter().enumerate() {
        assert!(close(s.positions[i], *p / 2.0, 1e-14));
    }
}

/// A hexagon of six triangles round vertex 0 at `centre`, its rim vertices 1 to 6 at unit
/// distance, at heights `z`, wound counter-clockwise seen from +z.
fn hexagon(centre: DVec3, z: [f64; 6]) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut points = vec![centre];
    for (j, z) in z.iter().enumerate() {
        let (sin, cos) = (PI / 3.0 * j as f64).sin_cos();
        points.push(DVec3::new(cos, sin, *z));
    }
    let faces = (0..6).map(|j| [0, 1 + j, 1 + (j + 1) % 6]).collect();
    (points, faces)
}

#[test]
fn a_regular_vertex_limits_at_half_itself_and_a_twelfth_of_each_neighbour() {
    // Valence 6: β = 1/16, γ = 1 / (6 + 3 / (8/16)) = 1/12 and 1 − 6γ = 1/2.
    assert_eq!(loop_gamma(6), 1.0 / 12.0);
    let z = [0.3, -0.2, 0.7, 0.1, -0.5, 0.25];
    let mesh = hexagon(DVec3::new(0.1, -0.2, 1.0), z);
    let sum: DVec3 = mesh.0[1..].iter().sum();
    let centre = 0.5 * mesh.0[0] + sum / 12.0;
    // A rim vertex is on the boundary: 3/5 of itself and 1/5 of each rim neighbour.
    let rim = |j: usize| 0.6 * mesh.0[j] + 0.2 * (mesh.0[1 + j % 6] + mesh.0[1 + (j + 4) % 6]);
    let s = subdivided(&mesh, 0);
    assert!(close(s.positions[0], centre, 1e-15));
    for j in 1..=6 {
        assert!(close(s.positions[j], rim(j), 1e-15), "rim vertex {j}");
    }
    // The interior vertex's limit stays where it is through the levels.
    assert!(close(subdivided(&mesh, 3).positions[0], centre, 1e-14));
}

#[test]
fn a_symmetric_regular_vertex_has_the_axis_as_normal_facing_away_from_the_winding() {
    let mesh = hexagon(DVec3::new(0.0, 0.0, 0.8), [0.0; 6]);
    for levels in [0, 2] {
        let s = subdivided(&mesh, levels);
        assert!(close(s.normals[0], -DVec3::Z, 1e-14), "{:?}", s.normals[0]);
    }
}

/// The widest angle, in degrees, between a vertex's normal and a triangle round it (its
/// winding's normal reversed, the side pbrt's normals face); every normal checked unit.
fn widest_angle(s: &Subdivided) -> f64 {
    let mut widest = 0.0f64;
    for &t in &s.triangles {
        let face = -winding_normal(s, t);
        for v in t {
            let n = s.normals[v as usize];
            assert!((n.length() - 1.0).abs() < 1e-12, "vertex {v}: {n}");
            widest = widest.max(n.dot(face).clamp(-1.0, 1.0).acos().to_degrees());
        }
    }
    widest
}

#[test]
fn normals_are_unit_and_their_triangles_turn_towards_them_level_by_level() {
    // The widest angles are next to the control corners, extraordinary vertices (valence 3
    // and 4) of a sharply curved limit surface; there the triangles' normals close in on the
    // limit normal by the ratio of the subdivision matrix's eigenvalues, 1/4 : 1/8 for valence
    // 3 and 3/8 : 1/4 for valence 4: 2 and 1.5 each level, approached from below (from level
    // 2 to 5, 1.40 to 1.47 measured for valence 4, 1.68 to 1.93 for valence 3).
    for (mesh, ratio) in [(octahedron(), 1.35), (tetrahedron(), 1.6)] {
        let widest: Vec<f64> = (2..=5)
            .map(|l| widest_angle(&subdivided(&mesh, l)))
            .collect();
        assert!(widest[1] < 25.0, "{widest:?}");
        for w in widest.windows(2) {
            assert!(w[1] * ratio < w[0], "{widest:?}");
        }
        let s = subdivided(&mesh, 3);
        for (p, n) in s.positions.iter().zip(&s.normals) {
            assert!(
                n.dot(*p) < 0.0,
                "the mesh winds outward, so its normals point in"
            );
        }
    }
}

#[test]
fn reversing_the_winding_reverses_the_normals() {
    let (points, faces) = octahedron();
    let reversed: Vec<[u32; 3]> = faces.iter().map(|&[a, b, c]| [a, c, b]).collect();
    let (s, r) = (
        subdivided(&(points.clone(), faces), 2),
        subdivided(&(points, reversed), 2),
    );
    // The same vertices, numbered otherwise (the faces meet their edges in another order).
    assert_eq!(s.positions.len(), r.positions.len());
    for (p, n) in s.positions.iter().zip(&s.normals) {
        let same = r.positions.iter().position(|q| close(*p, *q, 1e-14));
        let same = same.unwrap_or_else(|| panic!("{p} not in the reversed mesh"));
        assert!(close(*n, -r.normals[same], 1e-12), "at {p}");
    }
}

#[test]
fn a_flat_grid_stays_on_its_plane_with_the_planes_normal() {
    let mesh = grid(3);
    let s = subdivided(&mesh, 3);
    assert_eq!(s.triangles.len(), 18 * 64);
    for (p, n) in s.positions.iter().zip(&s.normals) {
        assert_eq!(p.z, 0.0);
        // Along −z exactly; unit to the rounding of its normalization.
        assert!(
            n.x == 0.0 && n.y == 0.0 && (n.z + 1.0).abs() < 1e-15,
            "{n} at {p}"
        );
        assert!(p.x >= 0.0 && p.x <= 3.0 && p.y >= 0.0 && p.y <= 3.0, "{p}");
    }
    // The boundary: each vertex on it has its limit on the B-spline of the control polygon;
    // corners are rounded, but the middle of each side (from 1 to 2) depends on that side's
    // control points alone and stays on it.
    let boundary = boundary_vertices(&s.triangles);
    assert_eq!(boundary.len(), 12 * 8);
    for &v in &boundary {
        let p = s.positions[v as usize];
        let side = [p.y, p.x, 3.0 - p.y, 3.0 - p.x];
        let along = [p.x, p.y, p.x, p.y];
        for (d, a) in side.iter().zip(along) {
            if *d < 0.5 && (1.0..=2.0).contains(&a) {
                assert_eq!(*d, 0.0, "{p}");
            }
        }
    }
}

/// The vertices on the edges only one of `triangles` has.
fn boundary_vertices(triangles: &[[u32; 3]]) -> std::collections::BTreeSet<u32> {
    let mut edges = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[next(k)]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    edges
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .flat_map(|((a, b), _)| [a, b])
        .collect()
}

#[test]
fn a_tilted_grid_stays_on_its_plane() {
    let (points, faces) = grid(3);
    let rotation = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -0.9, 1.3);
    let offset = DVec3::new(10.0, -4.0, 7.0);
    let points: Vec<DVec3> = points.iter().map(|&p| rotation * p + offset).collect();
    let normal = rotation * -DVec3::Z;
    let s = subdivided(&(points, faces), 3);
    for (p, n) in s.positions.iter().zip(&s.normals) {
        assert!((*p - offset).dot(normal).abs() < 1e-12, "{p}");
        assert!(close(*n, normal, 1e-12), "{n}");
    }
}

#[test]
fn one_level_moves_vertices_and_makes_edge_vertices_by_loops_rules() {
    // Two triangles sharing the diagonal 0–2 of a square, z varying: every vertex on the
    // boundary, the diagonal the one interior edge.
    let points = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.5),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, -0.5),
    ];
    let mesh = Level::new(&points, &[[0, 1, 2], [0, 2, 3]]).unwrap();
    let fine = mesh.refine();
    assert_eq!((fine.p.len(), fine.faces.len()), (4 + 5, 8));
    // Even, on the boundary: 3/4 of itself, 1/8 of each boundary neighbour.
    let even = |v: usize, a: usize, b: usize| 0.75 * points[v] + (points[a] + points[b]) / 8.0;
    assert!(close(fine.p[0], even(0, 1, 3), 1e-15));
    assert!(close(fine.p[1], even(1, 0, 2), 1e-15));
    // Odd: the edges of face 0 first (0–1, 1–2, 2–0), then face 1's new ones (2–3, 3–0).
    let mid = |a: usize, b: usize| (points[a] + points[b]) / 2.0;
    assert!(close(fine.p[4], mid(0, 1), 1e-15));
    assert!(close(fine.p[5], mid(1, 2), 1e-15));
    let inner = 3.0 / 8.0 * (points[0] + points[2]) + (points[1] + points[3]) / 8.0;
    assert!(close(fine.p[6], inner, 1e-15));
    assert!(close(fine.p[7], mid(2, 3), 1e-15));
    assert!(close(fine.p[8], mid(3, 0), 1e-15));
    assert!(!fine.boundary[6] && fine.boundary[4]);
}

#[test]
fn an_interior_vertex_moves_by_warrens_beta() {
    // The octahedron's corners have four neighbours: β = 3/32, (1 − 4β) = 5/8.
    let (points, faces) = octahedron();
    let fine = Level::new(&points, &faces).unwrap().refine();
    assert!(close(fine.p[0], 5.0 / 8.0 * points[0], 1e-15));
    assert_eq!(beta(6), 1.0 / 16.0);
}

#[test]
fn meshes_pbrt_cannot_subdivide_are_told_by_their_control_vertices() {
    let points = vec![DVec3::ZERO; 8];
    // Vertex 0 unused: the numbers told are the control mesh's, not the renumbered ones.
    let three = [[1, 2, 3], [2, 1, 4], [1, 2, 5]];
    assert_eq!(
        subdivide(&points, &three, 1).unwrap_err(),
        Unsupported::SharedEdge(1, 2)
    );
    let same_way = [[1, 2, 3], [1, 2, 4]];
    assert_eq!(
        subdivide(&points, &same_way, 1).unwrap_err(),
        Unsupported::Winding(1, 2)
    );
    let bowtie = [[1, 2, 3], [1, 4, 5]];
    assert_eq!(
        subdivide(&points, &bowtie, 1).unwrap_err(),
        Unsupported::Pinched(1)
    );
    let why = Unsupported::SharedEdge(1, 2).to_string();
    assert!(why.contains("between vertices 1 and 2"), "{why}");
}

#[test]
fn degenerate_meshes_do_not_panic() {
    let empty = subdivide(&[], &[], 3).unwrap();
    assert!(empty.positions.is_empty() && empty.triangles.is_empty());
    let points = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    // Triangles that repeat a corner are left out.
    let s = subdivide(&points, &[[0, 0, 1], [1, 2, 2]], 3).unwrap();
    assert!(s.positions.is_empty() && s.triangles.is_empty());
    // One triangle (boundary vertices of valence 2), vertex 3 unused and left out.
    let s = subdivide(&points, &[[0, 1, 2], [1, 1, 3]], 2).unwrap();
    assert_eq!((s.triangles.len(), s.positions.len()), (16, 15));
    assert!(s.normals.iter().all(|n| close(*n, -DVec3::Z, 1e-15)));
    // Two triangles back to back: interior vertices of valence 2, whose tangents are
    // parallel; normals unit or zero, never NaN.
    let s = subdivide(&points, &[[0, 1, 2], [0, 2, 1]], 2).unwrap();
    assert_eq!(s.triangles.len(), 32);
    for n in &s.normals {
        assert!(n.is_finite() && (n.length() == 0.0 || (n.length() - 1.0).abs() < 1e-12));
    }
}

#[test]
fn level_zero_keeps_the_control_triangles_on_the_limit_surface() {
    let mesh = octahedron();
    let s = subdivided(&mesh, 0);
    assert_eq!(s.triangles, mesh.1);
    assert!(close(s.positions[4], DVec3::Z / 2.0, 1e-15));
}
