//! A directive's parameters as the importer reads them: by name and type, as pbrt-v4's
//! `ParameterDictionary` looks them up (a `"integer fov"` is not the `"float fov"` a camera
//! reads), each read recorded, so that every parameter left unread becomes one warning naming
//! it and where it is: nothing in a scene file is dropped silently.

use super::include::Parsed;
use super::parse::{Directive, Param, ParamType, Values};
use super::state::Warning;
use std::cell::Cell;
use stratapt_scene::error::SceneError;

/// The parameters of directive `d` (in source `source` of `parsed`).
pub struct Params<'a> {
    parsed: &'a Parsed,
    source: usize,
    d: &'a Directive,
    used: Vec<Cell<bool>>,
}

impl<'a> Params<'a> {
    pub fn new(parsed: &'a Parsed, source: usize, d: &'a Directive) -> Self {
        Self {
            parsed,
            source,
            d,
            used: d.params.iter().map(|_| Cell::new(false)).collect(),
        }
    }

    /// The error `reason` at parameter `p`.
    pub fn err(&self, p: &Param, reason: impl Into<String>) -> SceneError {
        self.parsed.err(self.source, p.at, reason)
    }

    /// Where the directive is: (source, byte offset).
    pub fn location(&self) -> (usize, usize) {
        (self.source, self.d.at)
    }

    /// The span of parameter `p` in the description's sources.
    pub fn span(&self, p: &Param) -> std::ops::Range<usize> {
        self.parsed.span(self.source, p.at)
    }

    /// The span of the last parameter called `name` (of any type), or of the directive when it
    /// has none: where a value read from it is written.
    pub fn span_of(&self, name: &str) -> std::ops::Range<usize> {
        let at = self
            .d
            .params
            .iter()
            .rfind(|p| p.name == name)
            .map_or(self.d.at, |p| p.at);
        self.parsed.span(self.source, at)
    }

    /// Whether the directive has a parameter `name` (of any type); it is not marked as read.
    pub fn has(&self, name: &str) -> bool {
        self.d.params.iter().any(|p| p.name == name)
    }

    /// The span of the directive.
    pub fn directive_span(&self) -> std::ops::Range<usize> {
        self.parsed.span(self.source, self.d.at)
    }

    /// The error `reason` at the directive.
    pub fn directive_err(&self, reason: impl Into<String>) -> SceneError {
        self.parsed.err(self.source, self.d.at, reason)
    }

    /// The parameter `name` of type `ty`, marked as read (the last one when it is repeated, as
    /// pbrt-v4 takes it).
    pub fn find(&self, ty: ParamType, name: &str) -> Option<&'a Param> {
        let i = self
            .d
            .params
            .iter()
            .rposition(|p| p.ty == ty && p.name == name)?;
        self.used[i].set(true);
        Some(&self.d.params[i])
    }

    /// One number of type `ty` (float, integer, blackbody), or `default`.
    pub fn number(&self, ty: ParamType, name: &str, default: f64) -> Result<f64, SceneError> {
        let Some(p) = self.find(ty, name) else {
            return Ok(default);
        };
        match &p.values {
            Values::Numbers(n) if n.len() == 1 => Ok(n[0]),
            _ => Err(self.err(p, format!("`{name}` takes one number"))),
        }
    }

    pub fn float(&self, name: &str, default: f64) -> Result<f64, SceneError> {
        self.number(ParamType::Float, name, default)
    }

    pub fn integer(&self, name: &str, default: i64) -> Result<i64, SceneError> {
        Ok(self.number(ParamType::Integer, name, default as f64)? as i64)
    }

    pub fn string(&self, name: &str) -> Result<Option<&'a str>, SceneError> {
        let Some(p) = self.find(ParamType::String, name) else {
            return Ok(None);
        };
        match &p.values {
            Values::Strings(s) if s.len() == 1 => Ok(Some(&s[0])),
            _ => Err(self.err(p, format!("`{name}` takes one string"))),
        }
    }

    pub fn bool(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        let Some(p) = self.find(ParamType::Bool, name) else {
            return Ok(default);
        };
        match &p.values {
            Values::Bools(b) if b.len() == 1 => Ok(b[0]),
            _ => Err(self.err(p, format!("`{name}` takes one bool"))),
        }
    }

    /// A warning at the directive.
    pub fn warning(&self, message: impl Into<String>) -> Warning {
        self.warning_at(self.d.at, message)
    }

    /// A warning at byte offset `at` of the directive's source (a parameter's `at`).
    pub fn warning_at(&self, at: usize, message: impl Into<String>) -> Warning {
        Warning {
            at: self.parsed.location(self.source, at).to_string(),
            message: format!("{} \"{}\": {}", self.d.name, self.kind(), message.into()),
        }
    }

    /// The directive's type argument (`"perspective"`, `"sphere"`, …), "" if none.
    pub fn kind(&self) -> &str {
        match self.d.args.first() {
            Some(super::parse::Arg::Str(s)) => s,
            _ => "",
        }
    }

    /// One warning per parameter nothing read, at the parameter.
    pub fn unused(&self) -> Vec<Warning> {
        self.d
            .params
            .iter()
            .zip(&self.used)
            .filter(|(_, used)| !used.get())
            .map(|(p, _)| Warning {
                at: self.parsed.location(self.source, p.at).to_string(),
                message: format!(
                    "{} \"{}\": parameter \"{} {}\" ignored (strata does not read it)",
                    self.d.name,
                    self.kind(),
                    type_name(p.ty),
                    p.name
                ),
            })
            .collect()
    }
}

/// pbrt's name of a type.
pub fn type_name(ty: ParamType) -> &'static str {
    match ty {
        ParamType::Integer => "integer",
        ParamType::Float => "float",
        ParamType::Point2 => "point2",
        ParamType::Vector2 => "vector2",
        ParamType::Point3 => "point3",
        ParamType::Vector3 => "vector3",
        ParamType::Normal => "normal",
        ParamType::Rgb => "rgb",
        ParamType::Spectrum => "spectrum",
        ParamType::Blackbody => "blackbody",
        ParamType::Bool => "bool",
        ParamType::String => "string",
        ParamType::Texture => "texture",
    }
}
