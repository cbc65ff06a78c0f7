//! pbrt-v4 scene files (issue 26, first steps): the tokens ([`lexer`]), the directives with
//! their typed parameters ([`parse`]), a scene's files read with their `Include`s and `Import`s
//! spliced in ([`include`](mod@include)), the transformation state the directives change
//! ([`state`]), the perspective camera with its handedness ([`camera`]), and the film, sampler,
//! integrator and filter as strata's settings ([`settings`]), reading parameters by name and type
//! so that every one left unread is a warning ([`params`]), and blackbody emission as RGB
//! ([`spectrum`]); errors name the file, line and column. Shapes, materials and lights, and a
//! [`crate::FlatScene`] from them, come next.

pub mod camera;
pub mod include;
pub mod lexer;
pub mod params;
pub mod parse;
pub mod settings;
pub mod spectrum;
pub mod state;
