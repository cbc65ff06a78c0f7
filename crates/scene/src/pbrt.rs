//! pbrt-v4 scene files (issue 26, first steps): the tokens ([`lexer`]), the directives with
//! their typed parameters ([`parse`]), a scene's files read with their `Include`s and `Import`s
//! spliced in ([`include`](mod@include)), the transformation state the directives change
//! ([`state`]), and the perspective camera with its handedness ([`camera`]), with errors that
//! name the file, line and column. Shapes, materials and lights, and a [`crate::FlatScene`] from
//! them, come next.

pub mod camera;
pub mod include;
pub mod lexer;
pub mod parse;
pub mod state;
