//! pbrt-v4's directives (its `parse()`): each directive's positional arguments, then, where it
//! takes them, its typed parameters `"type name" value` or `"type name" [values]`, checked
//! against the type (a `point3` takes a multiple of three numbers, an `integer` whole ones, a
//! `bool` `true` or `false`, a `string` or `texture` strings, a `spectrum` numbers or a name).
//! What the directives mean is the importer's; this reads only their shape, and every error
//! names the file, line and column.

use super::lexer::{tokens, At, Token};
use std::path::Path;
use stratapt_scene::error::{SceneError, SourceLocation};

/// A positional argument.
#[derive(Clone, Debug, PartialEq)]
pub enum Arg {
    Number(f64),
    Str(String),
}

/// The type of a parameter, by its declared name (`point` is `point3`, `color` is `rgb`, ...).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    Integer,
    Float,
    Point2,
    Vector2,
    Point3,
    Vector3,
    Normal,
    Rgb,
    Spectrum,
    Blackbody,
    Bool,
    String,
    Texture,
}

impl ParamType {
    fn of(name: &str) -> Option<Self> {
        Some(match name {
            "integer" => Self::Integer,
            "float" => Self::Float,
            "point2" => Self::Point2,
            "vector2" => Self::Vector2,
            "point3" | "point" => Self::Point3,
            "vector3" | "vector" => Self::Vector3,
            "normal" | "normal3" => Self::Normal,
            "rgb" | "color" => Self::Rgb,
            "spectrum" => Self::Spectrum,
            "blackbody" => Self::Blackbody,
            "bool" => Self::Bool,
            "string" => Self::String,
            "texture" => Self::Texture,
            _ => return None,
        })
    }

    /// Numbers per value of a numeric type (`None`: not numeric).
    fn arity(self) -> Option<usize> {
        match self {
            Self::Integer | Self::Float | Self::Blackbody => Some(1),
            Self::Point2 | Self::Vector2 => Some(2),
            Self::Point3 | Self::Vector3 | Self::Normal | Self::Rgb => Some(3),
            // Wavelength–value pairs.
            Self::Spectrum => Some(2),
            Self::Bool | Self::String | Self::Texture => None,
        }
    }
}

/// A parameter's values.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Numbers(Vec<f64>),
    Strings(Vec<String>),
    Bools(Vec<bool>),
}

/// One parameter of a directive.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub ty: ParamType,
    pub name: String,
    pub values: Values,
    /// Byte offset of its declaration.
    pub at: usize,
}

/// One directive: its name, positional arguments and parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Directive {
    pub name: String,
    pub args: Vec<Arg>,
    pub params: Vec<Param>,
    /// Byte offset of its name.
    pub at: usize,
}

/// What follows a directive's name.
#[derive(Clone, Copy)]
enum Shape {
    /// Nothing.
    Bare,
    /// `n` numbers.
    Numbers(usize),
    /// `[` 16 numbers `]` (pbrt-v4 asks for the brackets; 16 bare numbers are read too).
    Matrix,
    /// `n` strings, then parameters when `params`.
    Strings(usize, bool),
    /// One or two strings (`MediumInterface`).
    OneOrTwoStrings,
    /// A bare word (`ActiveTransform StartTime`).
    Word,
    /// A single parameter (`Option "bool disablepixeljitter" true`).
    Option,
}

fn shape(name: &str) -> Option<Shape> {
    use Shape::*;
    Some(match name {
        "AttributeBegin" | "AttributeEnd" | "TransformBegin" | "TransformEnd" | "WorldBegin"
        | "ObjectEnd" | "ReverseOrientation" | "Identity" => Bare,
        "Translate" | "Scale" => Numbers(3),
        "Rotate" => Numbers(4),
        "LookAt" => Numbers(9),
        "TransformTimes" => Numbers(2),
        "Transform" | "ConcatTransform" => Matrix,
        "Camera" | "Film" | "Sampler" | "Integrator" | "PixelFilter" | "Accelerator" | "Shape"
        | "Material" | "LightSource" | "AreaLightSource" | "MakeNamedMaterial"
        | "MakeNamedMedium" | "Attribute" => Strings(1, true),
        "Texture" => Strings(3, true),
        "NamedMaterial" | "CoordinateSystem" | "CoordSysTransform" | "Include" | "Import"
        | "ObjectBegin" | "ObjectInstance" | "ColorSpace" => Strings(1, false),
        "MediumInterface" => OneOrTwoStrings,
        "ActiveTransform" => Word,
        "Option" => Option,
        _ => return None,
    })
}

struct Parser<'a, 't> {
    tokens: &'t [At<'a>],
    i: usize,
    text: &'a str,
    file: &'a Path,
}

impl<'a> Parser<'a, '_> {
    fn err(&self, at: usize, reason: impl Into<String>) -> SceneError {
        SceneError::new(SourceLocation::at_offset(self.file, self.text, at), reason)
    }

    /// Where the next token starts (the end of the text after the last).
    fn here(&self) -> usize {
        self.tokens.get(self.i).map_or(self.text.len(), |t| t.at)
    }

    fn next(&mut self) -> Option<&At<'a>> {
        let t = self.tokens.get(self.i);
        self.i += 1;
        t
    }

    fn peek(&self) -> Option<&Token<'a>> {
        self.tokens.get(self.i).map(|t| &t.token)
    }

    fn number(&mut self, directive: &str) -> Result<f64, SceneError> {
        let at = self.here();
        match self.next().map(|t| t.token.clone()) {
            Some(Token::Word(w)) => parse_number(w).ok_or_else(|| {
                self.err(at, format!("{directive} takes numbers; `{w}` is not one"))
            }),
            _ => Err(self.err(at, format!("{directive} takes numbers here"))),
        }
    }

    fn string(&mut self, directive: &str) -> Result<String, SceneError> {
        let at = self.here();
        match self.next().map(|t| t.token.clone()) {
            Some(Token::Str(s)) => Ok(s),
            _ => Err(self.err(at, format!("{directive} takes a quoted string here"))),
        }
    }

    fn directive(&mut self) -> Result<Directive, SceneError> {
        let at = self.here();
        let name = match self.next().map(|t| t.token.clone()) {
            Some(Token::Word(w)) => w.to_string(),
            Some(Token::Str(s)) => {
                return Err(self.err(at, format!("a string `\"{s}\"` where a directive belongs")))
            }
            _ => return Err(self.err(at, "a bracket where a directive belongs")),
        };
        let Some(shape) = shape(&name) else {
            return Err(self.err(at, format!("unknown directive `{name}`")));
        };
        let mut d = Directive {
            name,
            args: Vec::new(),
            params: Vec::new(),
            at,
        };
        let name = d.name.clone();
        match shape {
            Shape::Bare => {}
            Shape::Numbers(n) => {
                for _ in 0..n {
                    d.args.push(Arg::Number(self.number(&name)?));
                }
            }
            Shape::Matrix => {
                let bracketed = self.peek() == Some(&Token::Open);
                if bracketed {
                    self.i += 1;
                }
                for _ in 0..16 {
                    d.args.push(Arg::Number(self.number(&name)?));
                }
                if bracketed {
                    let at = self.here();
                    if self.next().map(|t| &t.token) != Some(&Token::Close) {
                        return Err(self.err(at, format!("{name} takes 16 numbers, then `]`")));
                    }
                }
            }
            Shape::Strings(n, params) => {
                for _ in 0..n {
                    d.args.push(Arg::Str(self.string(&name)?));
                }
                if params {
                    d.params = self.params()?;
                }
            }
            Shape::OneOrTwoStrings => {
                d.args.push(Arg::Str(self.string(&name)?));
                if let Some(Token::Str(s)) = self.peek() {
                    d.args.push(Arg::Str(s.clone()));
                    self.i += 1;
                }
            }
            Shape::Word => {
                let at = self.here();
                match self.next().map(|t| t.token.clone()) {
                    Some(Token::Word(w)) => d.args.push(Arg::Str(w.to_string())),
                    _ => return Err(self.err(at, format!("{name} takes a bare word here"))),
                }
            }
            Shape::Option => {
                if !matches!(self.peek(), Some(Token::Str(_))) {
                    return Err(self.err(self.here(), "Option takes \"type name\" and a value"));
                }
                d.params.push(self.param()?);
            }
        }
        Ok(d)
    }

    /// Parameters while the next token is a quoted declaration.
    fn params(&mut self) -> Result<Vec<Param>, SceneError> {
        let mut out = Vec::new();
        while matches!(self.peek(), Some(Token::Str(_))) {
            out.push(self.param()?);
        }
        Ok(out)
    }

    fn param(&mut self) -> Result<Param, SceneError> {
        let at = self.here();
        let Some(Token::Str(decl)) = self.next().map(|t| t.token.clone()) else {
            unreachable!("called at a string");
        };
        let mut parts = decl.split_whitespace();
        let (Some(ty), Some(name), None) = (parts.next(), parts.next(), parts.next()) else {
            return Err(self.err(at, format!("parameter `\"{decl}\"` is not \"type name\"")));
        };
        let Some(ty_kind) = ParamType::of(ty) else {
            return Err(self.err(at, format!("parameter `{name}` has unknown type `{ty}`")));
        };
        // The values: one bare value, or a bracketed list.
        let value_at = self.here();
        let mut raw: Vec<(Token<'a>, usize)> = Vec::new();
        match self.next().cloned() {
            Some(At {
                token: Token::Open, ..
            }) => loop {
                match self.next().cloned() {
                    Some(At {
                        token: Token::Close,
                        ..
                    }) => break,
                    Some(At {
                        token: Token::Open,
                        at,
                    }) => return Err(self.err(at, format!("`[` inside `{name}`'s values"))),
                    Some(t) => raw.push((t.token, t.at)),
                    None => {
                        return Err(self.err(value_at, format!("`{name}`'s `[` is never closed")))
                    }
                }
            },
            Some(At {
                token: Token::Close,
                at,
            }) => return Err(self.err(at, format!("`]` where `{name}`'s value belongs"))),
            Some(t) => raw.push((t.token, t.at)),
            None => return Err(self.err(value_at, format!("`{name}` has no value"))),
        }
        let values = self.values(ty_kind, ty, name, &raw, value_at)?;
        Ok(Param {
            ty: ty_kind,
            name: name.to_string(),
            values,
            at,
        })
    }

    fn values(
        &self,
        ty: ParamType,
        ty_name: &str,
        name: &str,
        raw: &[(Token<'a>, usize)],
        at: usize,
    ) -> Result<Values, SceneError> {
        if raw.is_empty() {
            return Err(self.err(at, format!("`{name}` has no values")));
        }
        let strings = || -> Option<Vec<String>> {
            raw.iter()
                .map(|(t, _)| match t {
                    Token::Str(s) => Some(s.clone()),
                    _ => None,
                })
                .collect()
        };
        match ty {
            ParamType::Bool => raw
                .iter()
                .map(|(t, at)| match t {
                    Token::Word("true") => Ok(true),
                    Token::Word("false") => Ok(false),
                    Token::Str(s) if s == "true" => Ok(true),
                    Token::Str(s) if s == "false" => Ok(false),
                    _ => Err(self.err(*at, format!("bool `{name}` takes true or false"))),
                })
                .collect::<Result<_, _>>()
                .map(Values::Bools),
            ParamType::String | ParamType::Texture => strings()
                .map(Values::Strings)
                .ok_or_else(|| self.err(at, format!("{ty_name} `{name}` takes quoted strings"))),
            ParamType::Spectrum if matches!(raw[0].0, Token::Str(_)) => {
                // A named spectrum or a file of them: one string.
                match strings() {
                    Some(s) if s.len() == 1 => Ok(Values::Strings(s)),
                    _ => Err(self.err(at, format!("spectrum `{name}` takes one name or numbers"))),
                }
            }
            _ => {
                let mut numbers = Vec::with_capacity(raw.len());
                for (t, at) in raw {
                    let x = match t {
                        Token::Word(w) => parse_number(w),
                        _ => None,
                    };
                    let Some(x) = x else {
                        return Err(self.err(*at, format!("{ty_name} `{name}` takes numbers")));
                    };
                    if ty == ParamType::Integer && x.fract() != 0.0 {
                        return Err(self.err(*at, format!("integer `{name}` takes whole numbers")));
                    }
                    numbers.push(x);
                }
                let arity = ty.arity().expect("a numeric type");
                if numbers.len() % arity != 0 {
                    return Err(self.err(
                        at,
                        format!(
                            "{ty_name} `{name}` takes numbers in groups of {arity}, not {}",
                            numbers.len()
                        ),
                    ));
                }
                Ok(Values::Numbers(numbers))
            }
        }
    }
}

/// A number as pbrt-v4 reads one (finite).
fn parse_number(w: &str) -> Option<f64> {
    w.parse::<f64>().ok().filter(|x| x.is_finite())
}

/// The directives of `text`, the contents of `file` (named in errors).
pub fn parse(text: &str, file: &Path) -> Result<Vec<Directive>, SceneError> {
    let tokens = tokens(text, file)?;
    let mut p = Parser {
        tokens: &tokens,
        i: 0,
        text,
        file,
    };
    let mut out = Vec::new();
    while p.i < tokens.len() {
        out.push(p.directive()?);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(text: &str) -> Vec<Directive> {
        parse(text, Path::new("s.pbrt")).unwrap_or_else(|e| panic!("{e}"))
    }

    fn fails(text: &str, at: &str, reason: &str) {
        let e = parse(text, Path::new("s.pbrt")).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!("s.pbrt:{at}:")) && e.contains(reason),
            "`{text}`: {e}"
        );
    }

    fn numbers(p: &Param) -> &[f64] {
        match &p.values {
            Values::Numbers(n) => n,
            other => panic!("{other:?}"),
        }
    }

    /// Every directive's positional arguments, bare and bracketed matrices, and parameters of
    /// every type, a single value with or without brackets.
    #[test]
    fn directives_and_their_arguments() {
        let d = ok(r#"
LookAt 0 1 5  0 0 0  0 1 0
Camera "perspective" "float fov" 45 "float lensradius" [0.1]
Film "rgb" "integer xresolution" [400] "integer yresolution" 300 "string filename" "out.exr"
Sampler "halton" "integer pixelsamples" 64
Integrator "volpath" "integer maxdepth" [ 5 ]
PixelFilter "gaussian" "float sigma" 0.5
Scale -1 1 1
Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1 ]
ConcatTransform 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1
ActiveTransform StartTime
TransformTimes 0 1
ColorSpace "srgb"
Option "bool disablepixeljitter" true
WorldBegin
AttributeBegin
  Translate 1 2 3
  Rotate 90 0 1 0
  CoordinateSystem "here"
  CoordSysTransform "camera"
  ReverseOrientation
  Identity
  Texture "checks" "spectrum" "checkerboard" "float uscale" 8 "rgb tex1" [1 0 0]
  MakeNamedMaterial "gold" "string type" "conductor" "spectrum eta" "metal-Au-eta"
    "spectrum k" [300 3.1 800 5.2] "bool remaproughness" false "float roughness" 0.01
  NamedMaterial "gold"
  Material "diffuse" "texture reflectance" "checks"
  AreaLightSource "diffuse" "blackbody L" 6500 "float scale" 2 "bool twosided" "true"
  Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]
    "normal N" [0 0 1 0 0 1 0 0 1] "point2 uv" [0 0 1 0 0 1] "vector3 dpdu" [1 0 0 1 0 0 1 0 0]
  MediumInterface "fog" ""
  MediumInterface "fog"
AttributeEnd
ObjectBegin "thing"
  Shape "sphere" "float radius" 2 "point p" [1 2 3] "color c" [1 1 1] "vector v" [0 0 1]
ObjectEnd
ObjectInstance "thing"
LightSource "infinite" "string filename" "sky.exr" "float scale" 1.5
Include "more.pbrt"
Import "big.pbrt.gz"
"#);
        let names: Vec<&str> = d.iter().map(|d| d.name.as_str()).collect();
        assert_eq!(names.len(), 37, "{names:?}");
        assert_eq!(d[0].args.len(), 9);
        let camera = &d[1];
        assert_eq!(camera.args, vec![Arg::Str("perspective".into())]);
        assert_eq!(camera.params[0].ty, ParamType::Float);
        assert_eq!(numbers(&camera.params[1]), &[0.1]);
        assert_eq!(numbers(&d[2].params[1]), &[300.0]);
        assert_eq!(
            d[2].params[2].values,
            Values::Strings(vec!["out.exr".into()])
        );
        assert_eq!(d[7].args.len(), 16);
        assert_eq!(d[8].args.len(), 16);
        assert_eq!(d[9].args, vec![Arg::Str("StartTime".into())]);
        assert_eq!(d[12].params[0].values, Values::Bools(vec![true]));
        let texture = &d[21];
        assert_eq!(texture.args.len(), 3);
        assert_eq!(texture.params[1].ty, ParamType::Rgb);
        let gold = &d[22];
        assert_eq!(
            gold.params[1].values,
            Values::Strings(vec!["metal-Au-eta".into()])
        );
        assert_eq!(numbers(&gold.params[2]), &[300.0, 3.1, 800.0, 5.2]);
        assert_eq!(gold.params[3].values, Values::Bools(vec![false]));
        assert_eq!(d[24].params[0].ty, ParamType::Texture);
        let area = &d[25];
        assert_eq!(area.params[0].ty, ParamType::Blackbody);
        assert_eq!(area.params[2].values, Values::Bools(vec![true]));
        let mesh = &d[26];
        let types: Vec<ParamType> = mesh.params.iter().map(|p| p.ty).collect();
        use ParamType::*;
        assert_eq!(types, vec![Point3, Integer, Normal, Point2, Vector3]);
        assert_eq!(d[27].args.len(), 2);
        assert_eq!(d[28].args.len(), 1);
        let sphere = &d[31];
        let types: Vec<ParamType> = sphere.params.iter().map(|p| p.ty).collect();
        assert_eq!(types, vec![Float, Point3, Rgb, Vector3]);
        // Offsets name where each directive and parameter starts.
        let text = "Shape \"sphere\"\n  \"float radius\" 2";
        let d = ok(text);
        assert_eq!((d[0].at, d[0].params[0].at), (0, 17));
    }

    /// Each malformed input is refused at the token that is wrong, with the reason.
    #[test]
    fn errors_name_the_line_column_and_reason() {
        fails("Frobnicate 1", "1:1", "unknown directive `Frobnicate`");
        fails(
            "WorldBegin\n\"sphere\"",
            "2:1",
            "a string `\"sphere\"` where a directive",
        );
        fails("Translate 1 2", "1:14", "Translate takes numbers here");
        fails("Translate 1 x 3", "1:13", "`x` is not one");
        fails("Rotate 90 0 1 nan", "1:15", "`nan` is not one");
        fails("Shape sphere", "1:7", "Shape takes a quoted string");
        fails(
            "Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 1]",
            "1:44",
            "16 numbers, then `]`",
        );
        fails(
            "Shape \"sphere\" \"radius\" 2",
            "1:16",
            "is not \"type name\"",
        );
        fails(
            "Shape \"sphere\" \"floot radius\" 2",
            "1:16",
            "unknown type `floot`",
        );
        fails(
            "Shape \"sphere\"\n \"point3 p\" [1 2]",
            "2:13",
            "groups of 3, not 2",
        );
        fails(
            "Film \"rgb\" \"integer xresolution\" 400.5",
            "1:34",
            "whole numbers",
        );
        fails(
            "Shape \"s\" \"float radius\" \"two\"",
            "1:26",
            "float `radius` takes numbers",
        );
        fails(
            "Shape \"s\" \"string name\" [1]",
            "1:25",
            "string `name` takes quoted strings",
        );
        fails("Shape \"s\" \"bool b\" [yes]", "1:21", "true or false");
        fails("Shape \"s\" \"float r\" [1 2", "1:21", "never closed");
        fails("Shape \"s\" \"float r\" []", "1:21", "has no values");
        fails("Shape \"s\" \"float r\"", "1:20", "has no value");
        fails("Shape \"s\" \"float r\" [[1]]", "1:22", "`[` inside");
        fails(
            "Shape \"s\" \"spectrum s\" [\"a\" \"b\"]",
            "1:24",
            "one name or numbers",
        );
        fails("Option 1", "1:8", "Option takes");
        fails("]", "1:1", "a bracket where a directive belongs");
    }
}
