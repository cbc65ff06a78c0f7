//! pbrt-v4 scene files (issue 26, first steps): the tokens ([`lexer`]), the directives with
//! their typed parameters ([`parse`]), a scene's files read with their `Include`s and `Import`s
//! spliced in ([`include`](mod@include)), and the transformation state the directives change ([`state`]),
//! with errors that name the file, line and column. Cameras, shapes, materials and lights, and
//! a [`crate::FlatScene`] from them, come next.

pub mod include;
pub mod lexer;
pub mod parse;
pub mod state;
