//! strata scene model.
//!
//! Owns: the scene description ([`desc`]) that every reader makes (strata's TOML, with OBJ/MTL
//! meshes through tobj and PLY through ply-rs-bw, in [`load`]; pbrt-v4 in [`pbrt`]; either by
//! [`scene_file`]) and its validation with file:line:column errors in the file the user wrote; the [`Effects`] a scene calls
//! for and the sample-dimension layout derived from them; flattening into the records both
//! renderers read ([`records`], in the GPU's layout) and the BVH (obvhs); the [`Film`] both renderers produce and its EXR/PNG
//! output.
//! Must not know: how anything is rendered (no integrator, no wgpu).

pub mod bvh;
pub mod coating;
pub mod content_hash;
pub mod desc;
pub mod dims;
pub mod effects;
pub mod environment;
pub mod error;
pub mod film;
pub mod flat;
pub mod geometry;
pub mod light_table;
pub mod load;
pub mod motion;
pub mod pbrt;
pub mod records;
pub mod render;
pub mod scene_file;
pub mod settings;
pub mod shared;
pub mod texture;

pub use dims::DimLayout;
pub use effects::Effects;
pub use error::{SceneError, SourceLocation};
pub use film::Film;
pub use flat::FlatScene;
pub use geometry::{Geometry, Prim};
pub use render::{Render, RenderError, RenderStats};
pub use settings::{RenderSettings, Strategy};
pub use stratapt_sampling::SamplerKind;

/// A loaded, validated scene ready for either renderer.
pub type Scene = FlatScene;
