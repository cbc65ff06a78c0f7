//! strata's scene files, read into the scene model.
//!
//! Owns: the scene description ([`desc`]) that every reader makes, each value spanned by the
//! file, line and column it was read from: strata's TOML (with OBJ/MTL meshes through tobj and
//! PLY through ply-rs-bw) in [`load`](mod@load), pbrt-v4 in [`pbrt`], either by [`scene_file`];
//! validation of a description into a [`stratapt_scene::FlatScene`] with errors at those
//! locations ([`load::build`]); the description written back as TOML ([`desc::write`], `strata
//! convert`).
//! Must not know: films and how anything is rendered.

pub mod desc;
pub mod export;
pub mod load;
pub mod pbrt;
pub mod scene_file;

pub use scene_file::load;
