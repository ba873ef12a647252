//! Wireframe models from files: OBJ (tobj) and glTF (gltf), chosen by extension. Every file
//! is read through `wireflight_fsio` (bounded, regular files only), and every mesh is built
//! by [`EdgeMeshBuilder`](wireflight_geometry::mesh::EdgeMeshBuilder), so a loaded model obeys the same rules as the
//! built-in plane.

pub mod gltf;
pub mod obj;

use std::path::{Path, PathBuf};

use wireflight_geometry::mesh::{plane, EdgeMesh, MeshProblem, MAX_RADIUS_M, MIN_RADIUS_M};

/// A model file could not be used. Always names the file.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read. (The I/O error is in the message, not a `source`, so that an
    /// error chain prints it once.)
    #[error("{path}: cannot read: {error}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// The file's extension names no supported format.
    #[error("{path}: unknown model format (expected .obj, .gltf or .glb)")]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The file is malformed; `detail` says where (line, element) and what.
    #[error("{path}: {detail}")]
    Malformed {
        /// The file.
        path: PathBuf,
        /// Where and what, e.g. "line 12: face index 9 out of range (8 vertices)".
        detail: String,
    },
    /// The file parsed but its content is unusable.
    #[error("{path}: {problem}")]
    Content {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        problem: MeshProblem,
    },
}

/// Load a model, choosing the format by extension (`.obj`, `.gltf`, `.glb`; case-insensitive).
///
/// # Errors
/// A [`MeshError`] naming the file and the problem.
pub fn load(path: &Path) -> Result<EdgeMesh, MeshError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let mesh = match ext.as_deref() {
        Some("obj") => obj::load(path),
        Some("gltf") | Some("glb") => gltf::load(path),
        _ => Err(MeshError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }?;
    let (_, radius) = mesh.bounding_sphere();
    if !(MIN_RADIUS_M..=MAX_RADIUS_M).contains(&radius) {
        return Err(MeshError::Content {
            path: path.to_path_buf(),
            problem: MeshProblem::OutOfScale(radius),
        });
    }
    Ok(mesh)
}

/// The mesh named on the command line: `plane` is the built-in aircraft, anything else a
/// file (see [`load`]).
///
/// # Errors
/// Loading errors naming the file.
pub fn load_named(name: &str) -> Result<EdgeMesh, MeshError> {
    if name == "plane" {
        return Ok(plane::builtin_plane());
    }
    load(Path::new(name))
}
