//! pbrt-v4's transformation state (its `BasicSceneBuilder`): the current transformation matrix
//! (CTM) that `Translate`, `Scale`, `Rotate`, `LookAt`, `Transform` and `ConcatTransform` change,
//! `Identity`, named coordinate systems (`CoordinateSystem`, `CoordSysTransform`, and `"camera"`
//! and `"world"`, which `Camera` and `WorldBegin` name), `ReverseOrientation`, and the stacks of
//! `AttributeBegin` / `AttributeEnd` (everything) and `TransformBegin` / `TransformEnd` (the CTM
//! only). Matrices are kept in f64 and applied as pbrt-v4 applies them: each directive multiplies
//! the CTM on the right, so the last one written acts first on an object's points.
//!
//! pbrt's matrices are those of a left-handed world; they are only numbers here. What the
//! handedness means for the image is the camera's business (a `Scale -1 1 1` before `LookAt` is
//! how many scenes make pbrt's image match a right-handed renderer's).
//!
//! A singular CTM (`Scale 0 1 1`, a `ConcatTransform` with a zero column) is taken as pbrt-v4
//! takes it (its `Transform` keeps a NaN inverse): it flattens what comes next, and the state
//! remembers which directive made it singular ([`Attributes::flattened_at`]), so that what it
//! does to the shapes under it is warned about once, there.

use super::include::Parsed;
use super::parse::{Arg, Directive};
use glam::{DMat3, DMat4, DVec3, DVec4};
use std::collections::HashMap;
use stratapt_scene::error::SceneError;

pub use crate::desc::Warning;

/// The part of pbrt's graphics state that `AttributeBegin` saves.
#[derive(Clone, Debug, PartialEq)]
pub struct Attributes {
    /// Object → world (after `WorldBegin`) or → camera (before it) of what comes next.
    pub ctm: DMat4,
    /// `ReverseOrientation` flips the normals of what comes next.
    pub reverse_orientation: bool,
    /// Where the directive that made `ctm` singular is (source, offset); `None` while it is
    /// invertible.
    pub flattened_at: Option<(usize, usize)>,
}

/// The transformation state while the directives are read in order.
#[derive(Clone, Debug)]
pub struct State {
    pub attributes: Attributes,
    /// Saved by `AttributeBegin`, `ObjectBegin` or `TransformBegin` (its name), with where it
    /// was pushed (source, offset).
    stack: Vec<(Attributes, &'static str, usize, usize)>,
    /// Named coordinate systems: the CTM, and where it became singular.
    named: HashMap<String, (DMat4, Option<(usize, usize)>)>,
    /// `Camera`'s CTM: camera from world.
    pub camera_from_world: Option<DMat4>,
    pub warnings: Vec<Warning>,
}

impl Default for State {
    fn default() -> Self {
        Self {
            attributes: Attributes {
                ctm: DMat4::IDENTITY,
                reverse_orientation: false,
                flattened_at: None,
            },
            stack: Vec::new(),
            named: HashMap::new(),
            camera_from_world: None,
            warnings: Vec::new(),
        }
    }
}

/// The numbers of a directive's arguments (the parser has checked their count).
fn numbers(d: &Directive) -> Vec<f64> {
    d.args
        .iter()
        .map(|a| match a {
            Arg::Number(x) => *x,
            Arg::Str(_) => unreachable!("{} takes numbers", d.name),
        })
        .collect()
}

fn string(d: &Directive) -> &str {
    match d.args.first() {
        Some(Arg::Str(s)) => s,
        _ => unreachable!("{} takes a string", d.name),
    }
}

/// pbrt-v4's `Rotate(θ, axis)`: θ in degrees about the (normalized) axis, counter-clockwise
/// seen from the axis' tip in a right-handed frame (Rodrigues' formula).
pub fn rotate(degrees: f64, axis: DVec3) -> DMat4 {
    DMat4::from_axis_angle(axis.normalize(), degrees.to_radians())
}

/// pbrt-v4's `LookAt`: camera from world, the camera at `eye` looking at `look` along its +z,
/// its +y towards `up` and its +x = `up × direction` (pbrt's left-handed camera space); `None`
/// when `up` is parallel to the direction or `eye` = `look`.
pub fn look_at(eye: DVec3, look: DVec3, up: DVec3) -> Option<DMat4> {
    let dir = (look - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        eye.extend(1.0),
    );
    Some(world_from_camera.inverse())
}

/// Whether `m` flattens space (its linear part's determinant is 0): pbrt-v4 cannot invert it.
pub fn singular(m: &DMat4) -> bool {
    DMat3::from_mat4(*m).determinant() == 0.0
}

/// A matrix from pbrt's 16 numbers, which list it column by column.
pub fn matrix(m: &[f64]) -> DMat4 {
    let col = |i: usize| DVec4::new(m[4 * i], m[4 * i + 1], m[4 * i + 2], m[4 * i + 3]);
    DMat4::from_cols(col(0), col(1), col(2), col(3))
}

/// The directives that change the CTM (after which [`Attributes::flattened_at`] is brought up to
/// date; `Identity` and `WorldBegin` make it invertible).
const CTM_DIRECTIVES: &[&str] = &[
    "Identity",
    "Translate",
    "Scale",
    "Rotate",
    "LookAt",
    "Transform",
    "ConcatTransform",
    "CoordSysTransform",
    "WorldBegin",
];

impl State {
    /// Apply `d` (of source `source`) if it is a transformation or attribute directive; `false`
    /// for any other directive (left to the caller).
    pub fn apply(
        &mut self,
        parsed: &Parsed,
        source: usize,
        d: &Directive,
    ) -> Result<bool, SceneError> {
        let handled = self.apply_directive(parsed, source, d)?;
        if handled && CTM_DIRECTIVES.contains(&d.name.as_str()) {
            let a = &mut self.attributes;
            a.flattened_at = match singular(&a.ctm) {
                true => a.flattened_at.or(Some((source, d.at))),
                false => None,
            };
        }
        Ok(handled)
    }

    /// [`State::apply`], but for noting where the CTM became singular.
    fn apply_directive(
        &mut self,
        parsed: &Parsed,
        source: usize,
        d: &Directive,
    ) -> Result<bool, SceneError> {
        let ctm = &mut self.attributes.ctm;
        match d.name.as_str() {
            "Identity" => *ctm = DMat4::IDENTITY,
            "Translate" => {
                let n = numbers(d);
                *ctm *= DMat4::from_translation(DVec3::new(n[0], n[1], n[2]));
            }
            "Scale" => {
                let n = numbers(d);
                *ctm *= DMat4::from_scale(DVec3::new(n[0], n[1], n[2]));
            }
            "Rotate" => {
                let n = numbers(d);
                let axis = DVec3::new(n[1], n[2], n[3]);
                if axis.length_squared() == 0.0 {
                    return Err(parsed.err(source, d.at, "Rotate about a zero axis"));
                }
                *ctm *= rotate(n[0], axis);
            }
            "LookAt" => {
                let n = numbers(d);
                let v = |i: usize| DVec3::new(n[i], n[i + 1], n[i + 2]);
                let Some(m) = look_at(v(0), v(3), v(6)) else {
                    return Err(parsed.err(
                        source,
                        d.at,
                        "LookAt with the eye at the point looked at, or up along the view",
                    ));
                };
                *ctm *= m;
            }
            "Transform" | "ConcatTransform" => {
                // A singular matrix is taken (pbrt-v4 keeps a NaN inverse): what it flattens to
                // nothing is dropped when the shapes are baked, warned at this directive.
                let m = matrix(&numbers(d));
                if d.name == "Transform" {
                    *ctm = m;
                    self.attributes.flattened_at = None;
                } else {
                    *ctm *= m;
                }
            }
            "CoordinateSystem" => {
                let system = (*ctm, self.attributes.flattened_at);
                self.named.insert(string(d).to_string(), system);
            }
            "CoordSysTransform" => match self.named.get(string(d)) {
                Some(&(m, at)) => (*ctm, self.attributes.flattened_at) = (m, at),
                None => self.warn(
                    parsed,
                    source,
                    d,
                    format!(
                        "no coordinate system `{}`: the transform is left as it was",
                        string(d)
                    ),
                ),
            },
            "Camera" => {
                self.camera_from_world = Some(*ctm);
                // A singular camera transform is refused where the camera is made.
                self.named.insert("camera".into(), (ctm.inverse(), None));
            }
            "WorldBegin" => {
                *ctm = DMat4::IDENTITY;
                self.named.insert("world".into(), (DMat4::IDENTITY, None));
            }
            "ReverseOrientation" => {
                self.attributes.reverse_orientation = !self.attributes.reverse_orientation
            }
            "AttributeBegin" | "ObjectBegin" | "TransformBegin" => {
                let begin = match d.name.as_str() {
                    "AttributeBegin" => "AttributeBegin",
                    "ObjectBegin" => "ObjectBegin",
                    _ => "TransformBegin",
                };
                self.stack
                    .push((self.attributes.clone(), begin, source, d.at));
                // ObjectBegin also names an object: the caller's.
                return Ok(d.name != "ObjectBegin");
            }
            "AttributeEnd" | "ObjectEnd" | "TransformEnd" => {
                let begin = d.name.replace("End", "Begin");
                match self.stack.pop() {
                    Some((saved, opened, _, _)) if opened == begin => {
                        if d.name == "TransformEnd" {
                            self.attributes.ctm = saved.ctm;
                            self.attributes.flattened_at = saved.flattened_at;
                        } else {
                            self.attributes = saved;
                        }
                    }
                    Some((_, opened, s, at)) => {
                        let there = parsed.location(s, at);
                        return Err(parsed.err(
                            source,
                            d.at,
                            format!("{} closes the {opened} at {there}", d.name),
                        ));
                    }
                    None => {
                        return Err(parsed.err(
                            source,
                            d.at,
                            format!("{} without a matching begin", d.name),
                        ))
                    }
                }
                return Ok(d.name != "ObjectEnd");
            }
            "ActiveTransform" | "TransformTimes" => {
                self.warn(
                    parsed,
                    source,
                    d,
                    format!(
                        "{}: strata imports no motion; every transform is the start time's",
                        d.name
                    ),
                );
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// A warning at directive `d`.
    fn warn(&mut self, parsed: &Parsed, source: usize, d: &Directive, message: String) {
        self.warnings.push(Warning {
            at: parsed.location(source, d.at).to_string(),
            message,
        });
    }

    /// At the end of the file: an `AttributeBegin` or `TransformBegin` left open is an error.
    pub fn finish(&self, parsed: &Parsed) -> Result<(), SceneError> {
        match self.stack.last() {
            Some((_, _, s, at)) => Err(parsed.err(*s, *at, "never closed")),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// The state after `text`, or the first error.
    fn run(text: &str) -> Result<State, SceneError> {
        let parsed = Parsed::from_text(text, Path::new("s.pbrt"))?;
        let mut state = State::default();
        for (s, d) in &parsed.directives {
            state.apply(&parsed, *s, d)?;
        }
        state.finish(&parsed)?;
        Ok(state)
    }

    fn ctm(text: &str) -> DMat4 {
        run(text).unwrap_or_else(|e| panic!("{e}")).attributes.ctm
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    /// Each directive multiplies on the right: the last written acts first on a point.
    #[test]
    fn transforms_compose_as_pbrt_composes_them() {
        let m = ctm("Translate 1 0 0 Scale 2 2 2");
        assert!(close(
            m.transform_point3(DVec3::X),
            DVec3::new(3.0, 0.0, 0.0)
        ));
        let m = ctm("Scale 2 2 2 Translate 1 0 0");
        assert!(close(
            m.transform_point3(DVec3::X),
            DVec3::new(4.0, 0.0, 0.0)
        ));
        // Rotate 90 about z takes x to y; about a non-unit axis alike.
        let m = ctm("Rotate 90 0 0 5");
        assert!(close(m.transform_vector3(DVec3::X), DVec3::Y));
        // Transform lists the columns: the translation is the last four numbers.
        let m = ctm("Transform [1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1]");
        assert!(close(
            m.transform_point3(DVec3::ZERO),
            DVec3::new(5.0, 6.0, 7.0)
        ));
        let m = ctm("Translate 1 0 0 ConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1]");
        assert!(close(
            m.transform_point3(DVec3::ONE),
            DVec3::new(3.0, 2.0, 2.0)
        ));
        assert_eq!(ctm("Translate 1 2 3 Identity"), DMat4::IDENTITY);
    }

    /// LookAt is camera from world: the eye goes to the origin, the point looked at onto +z, up
    /// onto +y, and +x is `up × direction` (left-handed: looking along world +z with y up, camera
    /// +x is world +x, where a right-handed camera's right would be world −x).
    #[test]
    fn look_at_is_pbrts_left_handed_camera() {
        let m = ctm("LookAt 1 2 3  1 2 10  0 1 0");
        assert!(close(
            m.transform_point3(DVec3::new(1.0, 2.0, 3.0)),
            DVec3::ZERO
        ));
        assert!(close(
            m.transform_point3(DVec3::new(1.0, 2.0, 10.0)),
            DVec3::new(0.0, 0.0, 7.0)
        ));
        assert!(close(m.transform_vector3(DVec3::Y), DVec3::Y));
        assert!(close(m.transform_vector3(DVec3::X), DVec3::X));
        // Mirrored first: world +x is camera −x.
        let m = ctm("Scale -1 1 1 LookAt 0 0 0  0 0 1  0 1 0");
        assert!(close(m.transform_vector3(DVec3::X), -DVec3::X));
        assert!(m.determinant() < 0.0);
    }

    /// Named systems: Camera names "camera" (world from camera), WorldBegin resets the CTM and
    /// names "world"; AttributeBegin saves everything, TransformBegin the CTM only.
    #[test]
    fn named_systems_and_stacks() {
        let s = run(
            "LookAt 0 0 0  0 0 1  0 1 0 Translate 0 0 -5\nCamera \"perspective\"\nWorldBegin\n\
                     CoordSysTransform \"camera\"",
        )
        .unwrap();
        // The camera sits at z = 5 in the world... seen from the camera, the world origin is at
        // z = -5: world from camera takes the camera's origin to (0, 0, 5).
        assert!(close(
            s.attributes.ctm.transform_point3(DVec3::ZERO),
            DVec3::new(0.0, 0.0, 5.0)
        ));
        let camera = s.camera_from_world.unwrap();
        assert!(close(
            camera.transform_point3(DVec3::new(0.0, 0.0, 5.0)),
            DVec3::ZERO
        ));
        let s = run(
            "WorldBegin Translate 1 0 0 CoordinateSystem \"a\" Identity\n\
                     AttributeBegin ReverseOrientation Translate 0 1 0 AttributeEnd\n\
                     TransformBegin ReverseOrientation Scale 2 2 2 TransformEnd\n\
                     CoordSysTransform \"a\"",
        )
        .unwrap();
        assert!(close(
            s.attributes.ctm.transform_point3(DVec3::ZERO),
            DVec3::X
        ));
        // ReverseOrientation survives TransformEnd (which restores the CTM only), not AttributeEnd.
        assert!(s.attributes.reverse_orientation);
    }

    #[test]
    fn unbalanced_and_degenerate_transforms_are_refused_where_written() {
        for (text, words) in [
            (
                "AttributeBegin\nAttributeEnd\nAttributeEnd",
                &["s.pbrt:3:1:", "without a matching begin"][..],
            ),
            (
                "TransformBegin\nAttributeEnd",
                &["s.pbrt:2:1:", "closes the TransformBegin at s.pbrt:1:1"],
            ),
            (
                "AttributeBegin ObjectEnd",
                &["s.pbrt:1:16:", "closes the AttributeBegin"],
            ),
            (
                "WorldBegin\n  AttributeBegin\n",
                &["s.pbrt:2:3:", "never closed"],
            ),
            ("Rotate 10 0 0 0", &["s.pbrt:1:1:", "zero axis"]),
            ("LookAt 1 1 1  1 1 1  0 1 0", &["s.pbrt:1:1:", "LookAt"]),
            (
                "LookAt 0 0 0  0 1 0  0 1 0",
                &["s.pbrt:1:1:", "up along the view"],
            ),
        ] {
            let e = run(text).unwrap_err().to_string();
            for w in words {
                assert!(e.contains(w), "`{text}`: `{w}` not in: {e}");
            }
        }
        // An unknown coordinate system and motion are warnings, with where they are.
        let s = run("WorldBegin\n CoordSysTransform \"nowhere\"\nActiveTransform EndTime").unwrap();
        let w: Vec<String> = s
            .warnings
            .iter()
            .map(|w| format!("{}: {}", w.at, w.message))
            .collect();
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].starts_with("s.pbrt:2:2: no coordinate system `nowhere`"),
            "{w:?}"
        );
        assert!(w[1].starts_with("s.pbrt:3:1: ActiveTransform"), "{w:?}");
    }

    /// A singular transform is taken, as pbrt-v4 takes it, and the state remembers the directive
    /// that made the CTM singular until one makes it invertible again or a stack restores it.
    #[test]
    fn singular_transforms_are_taken_and_remembered_where_written() {
        let flat = "ConcatTransform [1 0 0 0  0 0 0 0  0 0 1 0  0 0 0 1]";
        for (text, culprit) in [
            (
                format!("Translate 1 0 0 {flat} Scale 0 1 1 Rotate 30 0 0 1"),
                Some(flat),
            ),
            ("Translate 1 0 0 Scale 0 1 1".into(), Some("Scale")),
            (
                "Scale 0 1 1 Transform [0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0]".into(),
                Some("Transform"),
            ),
            (
                format!("{flat} Transform [1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1]"),
                None,
            ),
            (format!("{flat} Identity"), None),
            (format!("TransformBegin {flat} TransformEnd"), None),
            (format!("AttributeBegin {flat} AttributeEnd"), None),
            (
                format!("{flat} CoordinateSystem \"f\" Identity CoordSysTransform \"f\""),
                Some(flat),
            ),
            (format!("{flat} WorldBegin"), None),
        ] {
            let s = run(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
            let expected = culprit.map(|c| (0, text.find(c).unwrap()));
            assert_eq!(s.attributes.flattened_at, expected, "{text}");
            assert_eq!(singular(&s.attributes.ctm), culprit.is_some(), "{text}");
        }
    }
}
