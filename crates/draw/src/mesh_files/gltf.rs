//! glTF 2.0 loading through `gltf` (`.gltf` with external or `data:` URI buffers, and `.glb`).
//!
//! What is drawn: the default scene if the file names one, otherwise every scene; if the file
//! has no scenes, every root node (a node that is nobody's child); if it has no nodes either,
//! every mesh once, untransformed. Node transforms are composed down the hierarchy
//! (parent · child, from `node.transform().matrix()`), and a mesh used by several nodes is drawn
//! at each. Per primitive mode:
//!
//! * `TRIANGLES`, `TRIANGLE_STRIP`, `TRIANGLE_FAN`: the three edges of each triangle,
//! * `LINES`, `LINE_STRIP`, `LINE_LOOP`: the lines themselves,
//! * `POINTS`: ignored,
//!
//! indexed or not. Shared edges are drawn once (see [`EdgeMeshBuilder`]). Materials, textures
//! (images are never loaded, so a missing texture file does not stop the model from loading),
//! skins and morph targets are ignored.
//!
//! **Axes.** Positions are used as the file has them, with no change of axes. glTF's own
//! convention is +Y up, +Z forward (right-handed); the viewer's body frame is nose **+X**, left
//! wing **+Y**, up **+Z**. We deliberately do not convert: a file exported from the viewer
//! (`assets/plane.gltf`, written by `cargo run --example export_plane`, which stores body axes
//! directly and says so in `asset.extras`) must round-trip exactly. A model authored in glTF's
//! convention will therefore show nose along the wrong axis; re-export it in body axes, or give
//! it a root node whose rotation maps glTF axes to body axes (+X nose ← glTF +Z,
//! +Y left ← glTF +X, +Z up ← glTF +Y: the matrix with columns (0,1,0), (0,0,1), (1,0,0)).

use std::path::Path;

use glam::{Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::MeshError;
use wireflight_geometry::mesh::{EdgeMesh, EdgeMeshBuilder, MeshProblem};

/// Extensions that change how geometry is stored; files that require them cannot be read.
const GEOMETRY_EXTENSIONS: [&str; 3] = [
    "KHR_draco_mesh_compression",
    "EXT_meshopt_compression",
    "KHR_mesh_quantization",
];

/// Deepest node nesting accepted (the loader recurses).
const MAX_DEPTH: usize = 1024;

/// Load a glTF file's meshes as edges.
///
/// # Errors
/// A [`MeshError`] naming the file and the problem: unreadable file, invalid JSON/GLB or glTF,
/// a buffer that cannot be read (naming it), accessors out of range, non-finite positions, or
/// nothing to draw.
pub fn load(path: &Path) -> Result<EdgeMesh, MeshError> {
    let bytes = wireflight_fsio::read_bytes(path).map_err(|error| MeshError::Io {
        path: path.to_path_buf(),
        error,
    })?;
    parse(&bytes, path)
}

/// Load glTF (JSON) or GLB bytes already read from `path`; buffers named by URI are read from
/// `path`'s directory, and only from there unless [`wireflight_fsio::InputLimits`] allow external
/// URIs (`--allow-external-uris`).
///
/// # Errors
/// As [`load`].
pub fn parse(bytes: &[u8], path: &Path) -> Result<EdgeMesh, MeshError> {
    let malformed = |detail: String| MeshError::Malformed {
        path: path.to_path_buf(),
        detail,
    };
    check_glb_header(bytes, path).map_err(malformed)?;
    let gltf::Gltf { document, mut blob } = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| malformed(describe_parse_error(bytes, e)))?;
    let root = document.into_json();
    for ext in &root.extensions_required {
        if GEOMETRY_EXTENSIONS.contains(&ext.as_str()) {
            return Err(malformed(format!(
                "requires the extension {ext}, which is not supported"
            )));
        }
    }
    validate(&root).map_err(malformed)?;
    let document = gltf::Document::from_json_without_validation(root);

    // What `gltf::import` does, minus the images, confined to the model's directory, bounded
    // in size, and naming the buffer that fails.
    let base = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let declared = buffer.length();
        let (data, what) = match buffer.source() {
            gltf::buffer::Source::Bin => {
                let data = blob.take().ok_or_else(|| {
                    malformed(format!(
                        "buffer {} is the GLB binary chunk, but the file has none",
                        buffer.index()
                    ))
                })?;
                // The chunk is padded to 4 bytes.
                if data.len() < declared || data.len() > declared.saturating_add(3) {
                    return Err(malformed(format!(
                        "buffer {} is the GLB binary chunk of {} bytes, but its byteLength \
                         says {declared}",
                        buffer.index(),
                        data.len()
                    )));
                }
                (data, "the GLB binary chunk".to_string())
            }
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let mut none = None;
                let data = gltf::buffer::Data::from_source_and_blob(
                    buffer.source(),
                    Some(base),
                    &mut none,
                )
                .map_err(|e| {
                    malformed(format!(
                        "buffer {} cannot be read from its data URI: {e}",
                        buffer.index()
                    ))
                })?;
                (data.0, "its data URI".to_string())
            }
            gltf::buffer::Source::Uri(uri) => {
                let file = resolve_uri(base, uri).map_err(|why| {
                    malformed(format!(
                        "buffer {} has the URI '{uri}': {why}",
                        buffer.index()
                    ))
                })?;
                let data = wireflight_fsio::read_bytes(&file).map_err(|e| {
                    malformed(format!(
                        "buffer {} cannot be read from '{}': {e}",
                        buffer.index(),
                        file.display()
                    ))
                })?;
                (data, format!("'{}'", file.display()))
            }
        };
        if data.len() < declared {
            return Err(malformed(format!(
                "buffer {} is {} bytes long ({what}), but the file says {declared}",
                buffer.index(),
                data.len(),
            )));
        }
        let mut data = data;
        // Accessors may use the declared bytes only.
        data.truncate(declared);
        buffers.push(gltf::buffer::Data(data));
    }

    // glTF nodes form trees: a node with two parents would be drawn twice per path (and a
    // crafted file could make that exponential), so reject it.
    let mut parents = vec![0u32; document.nodes().len()];
    for node in document.nodes() {
        for child in node.children() {
            parents[child.index()] += 1;
            if parents[child.index()] > 1 {
                return Err(malformed(format!(
                    "invalid glTF: node {} has more than one parent",
                    child.index()
                )));
            }
        }
    }

    let mut loader = Loader {
        buffers: &buffers,
        builder: EdgeMeshBuilder::new(),
    };
    let result = if let Some(scene) = document.default_scene() {
        scene
            .nodes()
            .try_for_each(|n| loader.node(&n, Mat4::IDENTITY, &mut Vec::new()))
    } else if document.scenes().len() > 0 {
        document
            .scenes()
            .flat_map(|s| s.nodes())
            .try_for_each(|n| loader.node(&n, Mat4::IDENTITY, &mut Vec::new()))
    } else if document.nodes().len() > 0 {
        document
            .nodes()
            .filter(|n| parents[n.index()] == 0)
            .try_for_each(|n| loader.node(&n, Mat4::IDENTITY, &mut Vec::new()))
    } else {
        document
            .meshes()
            .try_for_each(|m| loader.mesh(&m, Mat4::IDENTITY))
    };
    result.map_err(malformed)?;
    loader
        .builder
        .build()
        .map_err(|problem| MeshError::Content {
            path: path.to_path_buf(),
            problem,
        })
}

/// The `gltf` crate's validation (indices in range, enums known, …), with two relaxations and
/// one guard:
///
/// * a `POSITION` accessor without `min`/`max` (required by the spec, but only a culling hint)
///   is accepted;
/// * a required extension that the `gltf` crate does not know is accepted unless it changes how
///   geometry is stored ([`GEOMETRY_EXTENSIONS`], rejected by the caller with a clear message):
///   materials, textures and lights do not matter to a wireframe;
/// * a `POSITION` attribute naming a missing accessor is reported here, because gltf-json 1.4's
///   validation indexes the accessor list with it unchecked (and would panic).
fn validate(root: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::mesh::Semantic;
    use gltf::json::validation::{Checked, Validate};
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(i) = primitive
                .attributes
                .get(&Checked::Valid(Semantic::Positions))
            {
                if i.value() >= root.accessors.len() {
                    return Err(format!(
                        "invalid glTF: meshes[{m}].primitives[{p}].attributes[\"POSITION\"]: \
                         accessor {} does not exist ({} accessors)",
                        i.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    let mut errors = String::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        let p = path.as_str();
        let ignored = p.ends_with("[\"POSITION\"].min")
            || p.ends_with("[\"POSITION\"].max")
            || (p.starts_with("extensionsRequired[")
                && !GEOMETRY_EXTENSIONS.iter().any(|ext| p.contains(ext)));
        if !ignored {
            errors += &format!(" {p}: {error};");
        }
    });
    if errors.is_empty() {
        Ok(())
    } else {
        Err(format!("invalid glTF:{errors}"))
    }
}

/// A GLB file's 12-byte header: magic `glTF`, version 2, and a length equal to the file's. A
/// file named `.glb` must have it; a JSON file (starting with `{` after white space) is
/// anything else.
fn check_glb_header(bytes: &[u8], path: &Path) -> Result<(), String> {
    let named_glb = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    if !bytes.starts_with(b"glTF") {
        if named_glb {
            let shown: String = bytes
                .iter()
                .take(4)
                .map(|b| format!("{b:02x}"))
                .collect::<Vec<_>>()
                .join(" ");
            return Err(format!(
                "not a glTF file: a GLB (binary glTF) file starts with the magic `glTF`, this \
                 one with the bytes [{shown}]"
            ));
        }
        return Ok(());
    }
    if bytes.len() < 12 {
        return Err(format!(
            "not a valid GLB file: {} bytes, shorter than the 12-byte header",
            bytes.len()
        ));
    }
    let word = |k: usize| u32::from_le_bytes([bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]]);
    let (version, length) = (word(4), word(8));
    if version != 2 {
        return Err(format!(
            "not a valid GLB file: version {version} (only glTF 2 is read)"
        ));
    }
    if u64::from(length) != bytes.len() as u64 {
        return Err(format!(
            "not a valid GLB file: the header says {length} bytes, but the file has {}",
            bytes.len()
        ));
    }
    Ok(())
}

/// The file a buffer URI names: relative to `base` (percent-decoded), and inside it unless
/// external URIs are allowed (`--allow-external-uris`): no absolute path, no `file:` URI, no
/// `..` and no symbolic link leading out.
fn resolve_uri(base: &Path, uri: &str) -> Result<std::path::PathBuf, String> {
    let allow_external = wireflight_fsio::input_limits().allow_external_uris;
    let refuse = |what: &str| {
        Err(format!(
            "{what} outside the model's directory is not read (allow it with \
             --allow-external-uris)"
        ))
    };
    let (decoded, is_file_uri) = match uri.strip_prefix("file://").or(uri.strip_prefix("file:")) {
        Some(rest) => (percent_decode(rest)?, true),
        None if uri.contains(':') => {
            return Err("only relative paths, `file:` and `data:` URIs are supported".into())
        }
        None => (percent_decode(uri)?, false),
    };
    let rel = Path::new(&decoded);
    if !allow_external {
        if is_file_uri || rel.is_absolute() {
            return refuse("a file");
        }
        if rel.components().any(|c| {
            !matches!(
                c,
                std::path::Component::Normal(_) | std::path::Component::CurDir
            )
        }) {
            return refuse("a path with `..`, naming a file");
        }
    }
    let file = if rel.is_absolute() {
        rel.to_path_buf()
    } else {
        base.join(rel)
    };
    if !allow_external {
        // A symbolic link inside the directory may still lead out of it.
        if let (Ok(dir), Ok(target)) = (std::fs::canonicalize(base), std::fs::canonicalize(&file)) {
            if !target.starts_with(&dir) {
                return refuse("a file (through a symbolic link)");
            }
        }
    }
    Ok(file)
}

/// `%XX` escapes decoded (the rest kept as it is); the result must be UTF-8.
fn percent_decode(s: &str) -> Result<String, String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = b
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("bad percent escape at byte {i}"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| "the decoded URI is not UTF-8".to_string())
}

/// A parse error with a hint of what kind of file this is not.
fn describe_parse_error(bytes: &[u8], e: gltf::Error) -> String {
    match e {
        gltf::Error::Deserialize(e) if !bytes.starts_with(b"glTF") => {
            format!("not a glTF file (invalid glTF JSON: {e})")
        }
        gltf::Error::Binary(e) => format!("not a valid GLB (binary glTF) file: {e}"),
        e => format!("invalid glTF: {e}"),
    }
}

struct Loader<'b> {
    buffers: &'b [gltf::buffer::Data],
    builder: EdgeMeshBuilder,
}

impl Loader<'_> {
    /// Draw `node` and its descendants; `ancestors` are the nodes above it (for cycles).
    fn node(
        &mut self,
        node: &gltf::Node<'_>,
        parent: Mat4,
        ancestors: &mut Vec<usize>,
    ) -> Result<(), String> {
        if ancestors.contains(&node.index()) {
            return Err(format!(
                "node {} is its own ancestor (a cycle in the node hierarchy)",
                node.index()
            ));
        }
        if ancestors.len() >= MAX_DEPTH {
            return Err(format!(
                "node {} is nested more than {MAX_DEPTH} deep",
                node.index()
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            self.mesh(&mesh, world)?;
        }
        ancestors.push(node.index());
        for child in node.children() {
            self.node(&child, world, ancestors)?;
        }
        ancestors.pop();
        Ok(())
    }

    fn mesh(&mut self, mesh: &gltf::Mesh<'_>, world: Mat4) -> Result<(), String> {
        let name = match mesh.name() {
            Some(name) => format!("mesh {} ('{name}')", mesh.index()),
            None => format!("mesh {}", mesh.index()),
        };
        for primitive in mesh.primitives() {
            let here = format!("{name} primitive {}", primitive.index());
            self.primitive(&primitive, world)
                .map_err(|e| format!("{here}: {e}"))?;
        }
        Ok(())
    }

    fn primitive(&mut self, primitive: &gltf::Primitive<'_>, world: Mat4) -> Result<(), String> {
        let mode = primitive.mode();
        if mode == Mode::Points {
            return Ok(());
        }
        let Some(accessor) = primitive.get(&gltf::Semantic::Positions) else {
            return Err("no POSITION attribute".to_string());
        };
        check_accessor(&accessor, self.buffers, "POSITION", &[DataType::F32], true)?;
        let reader = primitive.reader(|b| self.buffers.get(b.index()).map(|d| &d.0[..]));
        let Some(positions) = reader.read_positions() else {
            return Err("cannot read the POSITION accessor".to_string());
        };
        let positions: Vec<Vec3> = positions.map(Vec3::from_array).collect();
        if positions.len() != accessor.count() {
            return Err("cannot read the POSITION accessor".to_string());
        }

        let indices: Vec<u32> = match primitive.indices() {
            Some(accessor) => {
                check_accessor(
                    &accessor,
                    self.buffers,
                    "indices",
                    &[DataType::U8, DataType::U16, DataType::U32],
                    false,
                )?;
                let read = reader
                    .read_indices()
                    .ok_or("cannot read the indices accessor")?;
                let indices: Vec<u32> = read.into_u32().collect();
                if indices.len() != accessor.count() {
                    return Err("cannot read the indices accessor".to_string());
                }
                if let Some(&bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
                    return Err(format!(
                        "index {bad} out of range ({} vertices)",
                        positions.len()
                    ));
                }
                indices
            }
            None => (0..positions.len() as u32).collect(),
        };

        let identity = world == Mat4::IDENTITY;
        let mut vertex = |i: u32| -> Result<u32, String> {
            let p = positions[i as usize];
            let q = if identity {
                p
            } else {
                world.transform_point3(p)
            };
            self.builder.vertex(q).map_err(|e| match e {
                MeshProblem::NonFinite(_) if p.is_finite() => format!(
                    "vertex {i}: position {p} is not finite after the node transforms ({q})"
                ),
                MeshProblem::NonFinite(_) => format!("vertex {i}: position {p} is not finite"),
                e => e.to_string(),
            })
        };
        let mut ids = Vec::with_capacity(indices.len());
        for &i in &indices {
            ids.push(vertex(i)?);
        }
        let b = &mut self.builder;
        let n = ids.len();
        match mode {
            Mode::Points => {}
            Mode::Lines => {
                for pair in ids.chunks_exact(2) {
                    b.edge(pair[0], pair[1]);
                }
            }
            Mode::LineStrip | Mode::LineLoop => {
                for pair in ids.windows(2) {
                    b.edge(pair[0], pair[1]);
                }
                if mode == Mode::LineLoop && n > 2 {
                    b.edge(ids[n - 1], ids[0]);
                }
            }
            Mode::Triangles => {
                for t in ids.chunks_exact(3) {
                    triangle(b, t[0], t[1], t[2]);
                }
            }
            Mode::TriangleStrip => {
                // Every other triangle of a strip is wound the other way round.
                for (k, t) in ids.windows(3).enumerate() {
                    if k % 2 == 0 {
                        triangle(b, t[0], t[1], t[2]);
                    } else {
                        triangle(b, t[1], t[0], t[2]);
                    }
                }
            }
            Mode::TriangleFan => {
                for k in 1..n.saturating_sub(1) {
                    triangle(b, ids[0], ids[k], ids[k + 1]);
                }
            }
        }
        Ok(())
    }
}

/// A triangle's three edges, and the triangle as a face (hidden-line drawing).
fn triangle(b: &mut EdgeMeshBuilder, i: u32, j: u32, k: u32) {
    b.face_indices(&[i, j, k]);
}

/// Check what the `gltf` reader takes for granted (it debug-asserts element sizes and can
/// overflow on counts of 0), so that a bad file gives an error rather than a panic.
fn check_accessor(
    accessor: &gltf::Accessor<'_>,
    buffers: &[gltf::buffer::Data],
    role: &str,
    types: &[DataType],
    vec3: bool,
) -> Result<(), String> {
    let what = format!("{role} accessor {}", accessor.index());
    let dims_ok = if vec3 {
        accessor.dimensions() == Dimensions::Vec3
    } else {
        accessor.dimensions() == Dimensions::Scalar
    };
    if !dims_ok || !types.contains(&accessor.data_type()) || (vec3 && accessor.normalized()) {
        return Err(format!(
            "{what} is {:?} {:?}{}; expected {}",
            accessor.data_type(),
            accessor.dimensions(),
            if accessor.normalized() {
                " normalized"
            } else {
                ""
            },
            if vec3 {
                "F32 Vec3"
            } else {
                "unsigned integer Scalar"
            }
        ));
    }
    if accessor.count() == 0 {
        return Err(format!("{what} is empty (count 0)"));
    }
    let size = accessor.size();
    if let Some(view) = accessor.view() {
        check_range(
            &view,
            accessor.offset(),
            accessor.count(),
            size,
            buffers,
            &what,
        )?;
    }
    if let Some(sparse) = accessor.sparse() {
        if sparse.count() == 0 {
            return Err(format!("{what} has an empty sparse section"));
        }
        let indices = sparse.indices();
        check_range(
            &indices.view(),
            indices.offset(),
            sparse.count(),
            indices.index_type().size(),
            buffers,
            &what,
        )?;
        let values = sparse.values();
        check_range(
            &values.view(),
            values.offset(),
            sparse.count(),
            size,
            buffers,
            &what,
        )?;
    }
    Ok(())
}

/// `count` elements of `size` bytes at `offset` in `view` (with its stride) lie inside the view,
/// and the view inside its buffer.
fn check_range(
    view: &gltf::buffer::View<'_>,
    offset: usize,
    count: usize,
    size: usize,
    buffers: &[gltf::buffer::Data],
    what: &str,
) -> Result<(), String> {
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "{what}: buffer view {} has stride {stride}, less than the element size {size}",
            view.index()
        ));
    }
    let end = stride
        .checked_mul(count - 1)
        .and_then(|n| n.checked_add(size))
        .and_then(|n| n.checked_add(offset));
    if end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "{what} ({count} elements) runs past the end of buffer view {}",
            view.index()
        ));
    }
    let buffer_len = buffers.get(view.buffer().index()).map_or(0, |d| d.len());
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|end| end > buffer_len)
    {
        return Err(format!(
            "buffer view {} runs past the end of buffer {}",
            view.index(),
            view.buffer().index()
        ));
    }
    Ok(())
}
