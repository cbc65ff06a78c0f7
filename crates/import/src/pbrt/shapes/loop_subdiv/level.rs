//! One level of the subdivision, held as pbrt's `SDFace` and `SDVertex` hold it, in arrays:
//! built from the control mesh (faces paired across their edges, each vertex's fan walked) and
//! refined by Loop's rules into the next.

use super::rules::{beta, weigh_boundary, weigh_ring};
use super::Unsupported;
use glam::DVec3;
use std::collections::hash_map::{Entry, HashMap};

/// No face: across a boundary edge, or not yet known.
const NONE: u32 = u32::MAX;

/// The corner after `k` in a triangle, and the one before (pbrt's `NEXT` and `PREV`).
pub(super) fn next(k: usize) -> usize {
    (k + 1) % 3
}
fn prev(k: usize) -> usize {
    (k + 2) % 3
}

/// One level of the subdivision: pbrt's `SDVertex` and `SDFace` as arrays.
#[derive(Clone, Debug, Default)]
pub(super) struct Level {
    pub p: Vec<DVec3>,
    /// Per vertex, a face around it (pbrt's `startFace`).
    start: Vec<u32>,
    pub boundary: Vec<bool>,
    /// Per face, its corners.
    pub faces: Vec<[u32; 3]>,
    /// Per face, the face across edge `k` (corner `k` to corner `k + 1`), or [`NONE`].
    adj: Vec<[u32; 3]>,
}

impl Level {
    /// The control mesh, checked: adjacency, start faces, boundary vertices.
    pub fn new(points: &[DVec3], triangles: &[[u32; 3]]) -> Result<Self, Unsupported> {
        let kept: Vec<[u32; 3]> = triangles
            .iter()
            .copied()
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
            .collect();
        let (faces, old) = renumber(&kept, points.len());
        let renamed = |a: u32| old[a as usize];
        let adj = adjacency(&faces).map_err(|e| match e {
            Unsupported::SharedEdge(a, b) => Unsupported::SharedEdge(renamed(a), renamed(b)),
            Unsupported::Winding(a, b) => Unsupported::Winding(renamed(a), renamed(b)),
            Unsupported::Pinched(v) => Unsupported::Pinched(renamed(v)),
        })?;
        let mut mesh = Level {
            p: old.iter().map(|&i| points[i as usize]).collect(),
            faces,
            adj,
            ..Default::default()
        };
        mesh.find_boundary()
            .map_err(|v| Unsupported::Pinched(renamed(v)))?;
        Ok(mesh)
    }

    /// Each vertex's start face (the last face to name it, as pbrt's) and whether it is on the
    /// boundary; the first vertex whose faces do not all lie in one fan around it is an error.
    fn find_boundary(&mut self) -> Result<(), u32> {
        let mut faces_at = vec![0u32; self.p.len()];
        self.start = vec![NONE; self.p.len()];
        for (f, t) in self.faces.iter().enumerate() {
            for &v in t {
                faces_at[v as usize] += 1;
                self.start[v as usize] = f as u32;
            }
        }
        self.boundary = vec![false; self.p.len()];
        for v in 0..self.p.len() as u32 {
            let (fan, open) = self.fan(v);
            if fan != faces_at[v as usize] {
                return Err(v);
            }
            self.boundary[v as usize] = open;
        }
        Ok(())
    }

    /// The faces of the fan round `v` from its start face, and whether the fan is open. Each
    /// face has one successor round `v` and is the successor of one (edges are manifold and
    /// consistently wound), so the walk ends, back at the start or at the boundary.
    fn fan(&self, v: u32) -> (u32, bool) {
        let start = self.start[v as usize];
        let (mut f, mut n) = (self.next_face(start, v), 1);
        while f != NONE && f != start {
            (f, n) = (self.next_face(f, v), n + 1);
        }
        if f == start {
            return (n, false);
        }
        f = self.prev_face(start, v);
        while f != NONE {
            (f, n) = (self.prev_face(f, v), n + 1);
        }
        (n, true)
    }

    /// The corner of face `f` that is vertex `v`.
    fn vnum(&self, f: u32, v: u32) -> usize {
        let t = self.faces[f as usize];
        (0..3).find(|&k| t[k] == v).expect("v is a corner of f")
    }

    /// Round `v` from face `f`: the face across the edge to the next corner (turning clockwise
    /// about the winding's normal), and the face across the edge from the previous corner.
    fn next_face(&self, f: u32, v: u32) -> u32 {
        self.adj[f as usize][self.vnum(f, v)]
    }
    fn prev_face(&self, f: u32, v: u32) -> u32 {
        self.adj[f as usize][prev(self.vnum(f, v))]
    }

    /// `v`'s neighbours in pbrt's order (`SDVertex::oneRing`): inside, the next corner of each
    /// face from its start face on, turning clockwise about the winding's normal; on the
    /// boundary, from the neighbour along one boundary edge round to the other, anticlockwise.
    /// Its length is pbrt's valence.
    pub fn ring(&self, v: u32, out: &mut Vec<u32>) {
        out.clear();
        let corner = |f: u32, step: usize| self.faces[f as usize][(self.vnum(f, v) + step) % 3];
        let start = self.start[v as usize];
        if !self.boundary[v as usize] {
            let mut f = start;
            loop {
                out.push(corner(f, 1));
                f = self.next_face(f, v);
                if f == start {
                    return;
                }
            }
        }
        let mut f = start;
        while self.next_face(f, v) != NONE {
            f = self.next_face(f, v);
        }
        out.push(corner(f, 1));
        while f != NONE {
            out.push(corner(f, 2));
            f = self.prev_face(f, v);
        }
    }

    /// The next level: each face into four, pbrt's numbering (the even vertices keep theirs,
    /// the odd ones follow in the order the faces meet their edges; face `f`'s children are
    /// `4f` to `4f + 3`, the one at corner `k` being `4f + k`, the middle one `4f + 3`).
    pub fn refine(&self) -> Level {
        let mut ring = Vec::new();
        let n = self.p.len() as u32;
        let mut fine = Level {
            p: (0..n).map(|v| self.even_point(v, &mut ring)).collect(),
            start: (0..n)
                .map(|v| self.child(self.start[v as usize], v))
                .collect(),
            boundary: self.boundary.clone(),
            faces: Vec::with_capacity(4 * self.faces.len()),
            adj: Vec::with_capacity(4 * self.faces.len()),
        };
        let on_edge = self.odd_vertices(&mut fine);
        self.children(&on_edge, &mut fine);
        fine
    }

    /// The child of face `f` at its corner `v`; [`NONE`] when `f` is.
    fn child(&self, f: u32, v: u32) -> u32 {
        match f {
            NONE => NONE,
            f => 4 * f + self.vnum(f, v) as u32,
        }
    }

    /// Even vertex `v` at the next level: inside, (1 − nβ) p + β Σ ring; on the boundary,
    /// 3/4 p + 1/8 of each boundary neighbour.
    fn even_point(&self, v: u32, ring: &mut Vec<u32>) -> DVec3 {
        self.ring(v, ring);
        match self.boundary[v as usize] {
            true => weigh_boundary(&self.p, v, ring, 1.0 / 8.0),
            false => weigh_ring(&self.p, v, ring, beta(ring.len())),
        }
    }

    /// One odd vertex per edge, appended to `fine`: per face, the number of the one on each
    /// of its edges.
    fn odd_vertices(&self, fine: &mut Level) -> Vec<[u32; 3]> {
        let mut on_edge = vec![[NONE; 3]; self.faces.len()];
        for f in 0..self.faces.len() {
            for k in 0..3 {
                if on_edge[f][k] != NONE {
                    continue;
                }
                let id = fine.p.len() as u32;
                let across = self.across(f, k);
                on_edge[f][k] = id;
                if let Some((g, j)) = across {
                    on_edge[g][j] = id;
                }
                fine.p.push(self.edge_point(f, k, across));
                fine.start.push(4 * f as u32 + 3);
                fine.boundary.push(across.is_none());
            }
        }
        on_edge
    }

    /// The face across edge `k` of face `f`, and the number of that edge in it.
    fn across(&self, f: usize, k: usize) -> Option<(usize, usize)> {
        let g = self.adj[f][k];
        if g == NONE {
            return None;
        }
        // Wound the other way there: from corner k + 1 of f to corner k.
        let (a, b) = (self.faces[f][next(k)], self.faces[f][k]);
        let t = self.faces[g as usize];
        let j = (0..3).find(|&j| t[j] == a && t[next(j)] == b);
        Some((g as usize, j.expect("adjacent faces share the edge")))
    }

    /// The odd vertex on edge `k` of face `f`: 3/8 of each end and 1/8 of each corner opposite,
    /// or the midpoint of a boundary edge.
    fn edge_point(&self, f: usize, k: usize, across: Option<(usize, usize)>) -> DVec3 {
        let p = |f: usize, k: usize| self.p[self.faces[f][k] as usize];
        let ends = p(f, k) + p(f, next(k));
        match across {
            None => 0.5 * ends,
            Some((g, j)) => 3.0 / 8.0 * ends + 1.0 / 8.0 * (p(f, prev(k)) + p(g, prev(j))),
        }
    }

    /// Each face's four children and their neighbours, appended to `fine`; `on_edge` numbers
    /// the odd vertex on each edge of each face.
    fn children(&self, on_edge: &[[u32; 3]], fine: &mut Level) {
        for (f, (v, e)) in self.faces.iter().zip(on_edge).enumerate() {
            let middle = 4 * f as u32 + 3;
            for j in 0..3 {
                let mut corners = [v[j]; 3];
                corners[next(j)] = e[j];
                corners[prev(j)] = e[prev(j)];
                let mut adj = [middle; 3];
                adj[j] = self.child(self.adj[f][j], v[j]);
                adj[prev(j)] = self.child(self.adj[f][prev(j)], v[j]);
                fine.faces.push(corners);
                fine.adj.push(adj);
            }
            fine.faces.push(*e);
            fine.adj
                .push([0, 1, 2].map(|j| 4 * f as u32 + next(j) as u32));
        }
    }
}

/// `triangles` with their corners numbered by the points they use, in the points' order; and
/// for each new number, the old one.
fn renumber(triangles: &[[u32; 3]], points: usize) -> (Vec<[u32; 3]>, Vec<u32>) {
    let mut used = vec![false; points];
    for &v in triangles.iter().flatten() {
        used[v as usize] = true;
    }
    let old: Vec<u32> = (0..points as u32).filter(|&v| used[v as usize]).collect();
    let mut new = vec![NONE; points];
    for (i, &v) in old.iter().enumerate() {
        new[v as usize] = i as u32;
    }
    let faces = triangles
        .iter()
        .map(|t| t.map(|v| new[v as usize]))
        .collect();
    (faces, old)
}

/// Per face, the face across each edge ([`NONE`] on the boundary), paired as pbrt pairs them:
/// an error for an edge of a third face, or of a second face wound the same way.
fn adjacency(faces: &[[u32; 3]]) -> Result<Vec<[u32; 3]>, Unsupported> {
    // Per edge (its ends, smaller first): the first face along it, that face's edge number,
    // and whether a second face has joined it.
    let mut edges: HashMap<(u32, u32), (u32, usize, bool)> =
        HashMap::with_capacity(faces.len() * 3 / 2 + 1);
    let mut adj = vec![[NONE; 3]; faces.len()];
    for (f, t) in faces.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[next(k)]);
            match edges.entry((a.min(b), a.max(b))) {
                Entry::Vacant(e) => {
                    e.insert((f as u32, k, false));
                }
                Entry::Occupied(mut e) => {
                    let (g, j, joined) = *e.get();
                    if joined {
                        return Err(Unsupported::SharedEdge(a, b));
                    }
                    if faces[g as usize][j] == a {
                        return Err(Unsupported::Winding(a, b));
                    }
                    adj[g as usize][j] = f as u32;
                    adj[f][k] = g;
                    e.get_mut().2 = true;
                }
            }
        }
    }
    Ok(adj)
}
