//! What an import drew differently from its file: one [`Warning`] each, and what it counted.

/// Something the importer did instead of what the file asked, and where.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// `file:line:column`.
    pub at: String,
    pub message: String,
}

/// What an import made of a scene, besides the scene itself.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    /// What strata draws differently from what the file asks, in reading order.
    pub warnings: Vec<Warning>,
    /// Shapes drawn from `Shape` directives outside object definitions.
    pub shapes: usize,
    /// `ObjectInstance`s flattened, and the shapes their copies added.
    pub instances: usize,
    pub instanced_shapes: usize,
    /// PLY files read (each once, however many instances use it).
    pub ply_files: usize,
    /// Triangles written, after instances are flattened.
    pub triangles: usize,
}
