//! pbrt-v4 scene files (issue 26, first step): the tokens ([`lexer`]) and the directives with
//! their typed parameters ([`parse`]), with errors that name the file, line and column. What the
//! directives mean, and a [`crate::FlatScene`] from them, come next.

pub mod lexer;
pub mod parse;
