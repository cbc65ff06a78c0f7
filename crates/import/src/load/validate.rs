//! Validation helpers: each checks one value and, when it is wrong, returns a [`SceneError`] at
//! that value's line and column with a reason that names the key.

use crate::desc::{Pair, Sources, Spanned, Triple};
use glam::Vec3;
use std::ops::Range;
use stratapt_scene::{SceneError, SourceLocation};

/// The files a description was read from (for errors: spans index them).
#[derive(Clone, Copy)]
pub struct Ctx<'a> {
    pub sources: &'a Sources,
}

pub type Result<T> = std::result::Result<T, SceneError>;

impl<'a> Ctx<'a> {
    pub fn new(sources: &'a Sources) -> Self {
        Self { sources }
    }

    /// An error at the start of `span`, in whichever file it lies.
    pub fn err(&self, span: Range<usize>, reason: impl Into<String>) -> SceneError {
        SceneError::new(self.sources.location(span.start), reason)
    }

    /// An error about the whole scene file (no position known).
    pub fn file_err(&self, reason: impl Into<String>) -> SceneError {
        SceneError::new(SourceLocation::file(self.sources.main()), reason)
    }

    /// A TOML syntax or schema error, at its span.
    pub fn toml(&self, e: toml::de::Error) -> SceneError {
        // serde speaks of fields; a TOML file has keys.
        let reason = e
            .message()
            .trim()
            .replace("unknown field", "unknown key")
            .replace("missing field", "missing key");
        match e.span() {
            Some(span) => self.err(span, reason),
            None => self.file_err(reason),
        }
    }

    /// A finite number that fits in `f32`.
    pub fn finite(&self, v: &Spanned<f64>, key: &str) -> Result<f32> {
        let x = *v.get_ref();
        if x.is_finite() && x.abs() <= f32::MAX as f64 {
            Ok(x as f32)
        } else {
            Err(self.err(
                v.span(),
                format!("`{key}` must be a finite number, got {x}"),
            ))
        }
    }

    /// A number `> 0`.
    pub fn positive(&self, v: &Spanned<f64>, key: &str) -> Result<f32> {
        let x = self.finite(v, key)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(
                v.span(),
                format!("`{key}` must be positive, got {}", v.get_ref()),
            ))
        }
    }

    /// A number `≥ 0`.
    pub fn non_negative(&self, v: &Spanned<f64>, key: &str) -> Result<f32> {
        let x = self.finite(v, key)?;
        if x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(
                v.span(),
                format!("`{key}` must not be negative, got {}", v.get_ref()),
            ))
        }
    }

    /// Three finite numbers.
    pub fn finite3(&self, v: [f64; 3], span: Range<usize>, key: &str) -> Result<Vec3> {
        let mut out = [0.0f32; 3];
        for (o, x) in out.iter_mut().zip(v) {
            if !(x.is_finite() && x.abs() <= f32::MAX as f64) {
                return Err(self.err(span, format!("`{key}` must be finite, got {v:?}")));
            }
            *o = x as f32;
        }
        Ok(Vec3::from_array(out))
    }

    /// A point (or any vector that may be zero).
    pub fn point(&self, v: &Spanned<[f64; 3]>, key: &str) -> Result<Vec3> {
        self.finite3(*v.get_ref(), v.span(), key)
    }

    /// A direction: non-zero, returned normalized.
    pub fn direction(&self, v: &Spanned<[f64; 3]>, key: &str) -> Result<Vec3> {
        let d = self.point(v, key)?;
        let n = d.normalize_or_zero();
        if n == Vec3::ZERO || !n.is_finite() {
            return Err(self.err(v.span(), format!("`{key}` must be a non-zero vector")));
        }
        Ok(n)
    }

    /// A reflectance-like colour: every component in `[0, 1]` (more would create energy).
    pub fn unit_color(&self, v: &Spanned<Triple>, key: &str) -> Result<[f32; 3]> {
        let c = self.finite3(v.get_ref().0, v.span(), key)?;
        if c.min_element() < 0.0 || c.max_element() > 1.0 {
            return Err(self.err(
                v.span(),
                format!(
                    "`{key}` components must lie in [0, 1] (above 1 the surface would create \
                     energy), got {:?}",
                    v.get_ref().0
                ),
            ));
        }
        Ok(c.to_array())
    }

    /// An emitted quantity (radiance, intensity, irradiance): every component `≥ 0`.
    pub fn emitted(&self, v: &Spanned<Triple>, key: &str) -> Result<[f32; 3]> {
        self.non_negative3(v, key)
    }

    /// Three numbers, each `≥ 0`.
    pub fn non_negative3(&self, v: &Spanned<Triple>, key: &str) -> Result<[f32; 3]> {
        let c = self.finite3(v.get_ref().0, v.span(), key)?;
        if c.min_element() < 0.0 {
            return Err(self.err(
                v.span(),
                format!("`{key}` must not be negative, got {:?}", v.get_ref().0),
            ));
        }
        Ok(c.to_array())
    }

    /// Three numbers, each `> 0`.
    pub fn positive3(&self, v: &Spanned<Triple>, key: &str) -> Result<[f32; 3]> {
        let c = self.finite3(v.get_ref().0, v.span(), key)?;
        if c.min_element() <= 0.0 {
            return Err(self.err(
                v.span(),
                format!(
                    "`{key}` components must be positive, got {:?}",
                    v.get_ref().0
                ),
            ));
        }
        Ok(c.to_array())
    }

    /// Two finite numbers, each `≥ 0`.
    pub fn non_negative2(&self, v: &Spanned<Pair>, key: &str) -> Result<[f32; 2]> {
        let [a, b] = v.get_ref().0;
        let c = self.finite3([a, b, 0.0], v.span(), key)?;
        if c.min_element() < 0.0 {
            return Err(self.err(
                v.span(),
                format!("`{key}` must not be negative, got {:?}", v.get_ref().0),
            ));
        }
        Ok([c.x, c.y])
    }

    /// An integer in `1..=max`.
    pub fn count(&self, v: &Spanned<i64>, key: &str, max: u32) -> Result<u32> {
        let x = *v.get_ref();
        if x < 1 || x > max as i64 {
            return Err(self.err(v.span(), format!("`{key}` must be in 1..={max}, got {x}")));
        }
        Ok(x as u32)
    }

    /// A name from a fixed list.
    pub fn one_of<T>(
        &self,
        v: &Spanned<String>,
        key: &str,
        valid: &[&str],
        parse: impl Fn(&str) -> Option<T>,
    ) -> Result<T> {
        parse(v.get_ref()).ok_or_else(|| {
            self.err(
                v.span(),
                format!(
                    "unknown {key} `{}`; expected one of: {}",
                    v.get_ref(),
                    valid.join(", ")
                ),
            )
        })
    }
}
