//! strata scene model and records.
//!
//! Owns: the validated scene both renderers read ([`FlatScene`]): the [`Effects`] a scene calls
//! for and the sample-dimension layout derived from them; the records both renderers read
//! ([`records`], in the GPU's layout) and the BVH (obvhs); environment maps and texture texels
//! as the tables hold them; the render settings; what an import drew differently from its file
//! ([`report`]).
//! Must not know: scene files (`stratapt-import` reads them into this), films and how anything
//! is rendered (`stratapt-film`, the renderers: no integrator, no wgpu).

pub mod bvh;
pub mod coating;
pub mod content_hash;
pub mod dims;
pub mod effects;
pub mod environment;
pub mod error;
pub mod flat;
pub mod geometry;
pub mod light_table;
pub mod motion;
pub mod records;
pub mod report;
pub mod settings;
pub mod shared;
pub mod texture;

pub use dims::DimLayout;
pub use effects::Effects;
pub use error::{SceneError, SourceLocation};
pub use flat::FlatScene;
pub use geometry::{Alpha, Geometry, Prim};
pub use settings::{RenderSettings, Strategy};
pub use stratapt_sampling::SamplerKind;
