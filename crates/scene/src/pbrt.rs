//! pbrt-v4 scene files (issue 26, first steps): the tokens ([`lexer`]), the directives with
//! their typed parameters ([`parse`]), and a scene's files read with their `Include`s and
//! `Import`s spliced in ([`include`]), with errors that name the file, line and column. What
//! the directives mean, and a [`crate::FlatScene`] from them, come next.

pub mod include;
pub mod lexer;
pub mod parse;
