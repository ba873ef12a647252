//! Wavefront OBJ loading through `tobj`.
//!
//! Polygon faces (`f`) become their boundary edges — faces are **not** triangulated, so a quad
//! gives four edges, not five — and line elements (`l`) become the segments between
//! consecutive points. Shared edges are drawn once (see [`EdgeMeshBuilder`]). Points (`p`, and
//! one-vertex faces/lines), normals, texture coordinates, groups and materials are ignored;
//! `mtllib` files are never opened.
//!
//! Coordinates are taken as the file has them, with no change of axes: the viewer's body frame
//! is nose **+X**, left wing **+Y**, up **+Z**, and an OBJ exported from it (for example
//! `assets/plane.obj`, written by `cargo run --example export_plane`) round-trips exactly. A
//! model authored Y-up (the usual OBJ habit) will show lying on its side.
//!
//! # Why there is a pre-pass before `tobj`
//!
//! tobj 4 parses `l` records with the same code as `f` records: a two-point `l a b` comes back
//! as a face of arity 2 (which we draw as one edge), but a polyline `l a b c …` with three or
//! more points is indistinguishable from a polygon, and would be drawn *closed*, with an
//! extra edge from the last point back to the first. tobj also reports errors without a line
//! number, and accepts `nan`/`inf` coordinates. So a small pre-pass over the text
//!
//! * splits every `l` polyline into two-point `l` records (which tobj keeps as lines),
//! * checks `v` coordinates (three numbers, finite) and every `f`/`l` index (in range, not 0),
//!   reporting the line number,
//!
//! and tobj (`load_obj_buf`, the parser behind `load_obj`, fed the rewritten text) does the rest.
//! Line continuations (`\` at the end of a line) are not supported, by tobj or here.

use std::io::Cursor;
use std::path::Path;

use glam::Vec3;

use super::MeshError;
use wireflight_geometry::mesh::{EdgeMesh, EdgeMeshBuilder, MeshProblem};

/// Load an OBJ file's faces and line elements as edges.
///
/// # Errors
/// A [`MeshError`] naming the file and the problem: unreadable file, malformed record (with its
/// line number), index out of range, non-finite vertex, or nothing to draw.
pub fn load(path: &Path) -> Result<EdgeMesh, MeshError> {
    let bytes = wireflight_fsio::read_bytes(path).map_err(|error| MeshError::Io {
        path: path.to_path_buf(),
        error,
    })?;
    parse(&bytes, path)
}

/// Load OBJ text already read; `path` names it in errors. A UTF-8 byte-order mark at the start
/// is skipped (it would otherwise hide the first record: every index would shift by one).
///
/// # Errors
/// As [`load`], without the I/O errors.
pub fn parse(bytes: &[u8], path: &Path) -> Result<EdgeMesh, MeshError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    // OBJ is ASCII in practice; object and material names may be in any 8-bit encoding, and
    // we ignore them, so decode leniently rather than reject the file.
    let text = String::from_utf8_lossy(bytes);
    let malformed = |detail: String| MeshError::Malformed {
        path: path.to_path_buf(),
        detail,
    };
    let rewritten = prepass(&text).map_err(malformed)?;

    // `..Default::default()` covers the fields that tobj's optional `merging`/`reordering`
    // features add, should another crate in the build turn them on.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: false,
        ignore_points: true,
        ignore_lines: false,
        ..Default::default()
    };
    let (models, _materials) =
        tobj::load_obj_buf(&mut Cursor::new(rewritten.as_bytes()), &options, |_| {
            Ok(Default::default())
        })
        .map_err(|e| malformed(format!("not a valid OBJ file ({e})")))?;

    let mut builder = EdgeMeshBuilder::new();
    let content = |problem: MeshProblem| MeshError::Content {
        path: path.to_path_buf(),
        problem,
    };
    for model in &models {
        add_mesh(&mut builder, &model.mesh).map_err(|e| match e {
            AddError::Problem(problem) => content(problem),
            AddError::Index(detail) => malformed(format!("object '{}': {detail}", model.name)),
        })?;
    }
    builder.build().map_err(content)
}

enum AddError {
    Problem(MeshProblem),
    Index(String),
}

/// Add one tobj mesh's faces (arity ≥ 3: closed polygons) and lines (arity 2).
fn add_mesh(builder: &mut EdgeMeshBuilder, mesh: &tobj::Mesh) -> Result<(), AddError> {
    let vertex_count = mesh.positions.len() / 3;
    let position = |i: u32| -> Result<Vec3, AddError> {
        let i = i as usize;
        if i >= vertex_count {
            return Err(AddError::Index(format!(
                "index {i} out of range ({vertex_count} vertices)"
            )));
        }
        Ok(Vec3::from_slice(&mesh.positions[3 * i..3 * i + 3]))
    };
    // An empty `face_arities` means every face is a triangle.
    let arities: Box<dyn Iterator<Item = usize>> = if mesh.face_arities.is_empty() {
        Box::new(std::iter::repeat_n(3, mesh.indices.len() / 3))
    } else {
        Box::new(mesh.face_arities.iter().map(|&n| n as usize))
    };
    let mut start = 0;
    let mut corners = Vec::new();
    for arity in arities {
        let Some(face) = mesh.indices.get(start..start + arity) else {
            return Err(AddError::Index(
                "face list shorter than its arities".to_string(),
            ));
        };
        start += arity;
        corners.clear();
        for &i in face {
            corners.push(position(i)?);
        }
        match arity {
            0 | 1 => {}
            2 => {
                builder
                    .edge_between(corners[0], corners[1])
                    .map_err(AddError::Problem)?;
            }
            // A polygon: its edges, and the face for hidden-line drawing.
            _ => builder.face(&corners).map_err(AddError::Problem)?,
        }
    }
    Ok(())
}

/// Check `v`, `f` and `l` records and split `l` polylines into two-point lines; see the module
/// docs. Returns the text for tobj, or `"line N: …"`.
fn prepass(text: &str) -> Result<String, String> {
    // Absolute indices are checked against the whole file's counts (tobj resolves them when an
    // object ends, so it accepts forward references); relative (negative) ones against the
    // counts so far, as tobj resolves them at once.
    let mut total = [0usize; 3]; // v, vt, vn
    for line in text.lines() {
        match line.split_whitespace().next() {
            Some("v") => total[0] += 1,
            Some("vt") => total[1] += 1,
            Some("vn") => total[2] += 1,
            _ => {}
        }
    }

    if total[0] == 0 {
        return Err(
            "no vertices (no `v` records): the file is empty or not a Wavefront OBJ file"
                .to_string(),
        );
    }

    let mut so_far = [0usize; 3];
    let mut out = String::with_capacity(text.len() + 16);
    for (n, line) in text.lines().enumerate() {
        let n = n + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                so_far[0] += 1;
                let coords: Vec<&str> = words.by_ref().take(3).collect();
                let parsed: Option<Vec<f32>> = coords.iter().map(|w| w.parse().ok()).collect();
                match parsed {
                    Some(c) if c.len() == 3 => {
                        if !c.iter().all(|x| x.is_finite()) {
                            return Err(format!(
                                "line {n}: vertex {} is not finite ({} {} {})",
                                so_far[0], c[0], c[1], c[2]
                            ));
                        }
                        // `v x y z w` (tobj divides by w); `v x y z r g b` is a colour.
                        let rest: Vec<&str> = words.collect();
                        if let [w] = rest[..] {
                            if w.parse::<f32>().is_ok_and(|w| w == 0.0 || !w.is_finite()) {
                                return Err(format!(
                                    "line {n}: vertex {} has weight w = {w}",
                                    so_far[0]
                                ));
                            }
                        }
                    }
                    _ => {
                        return Err(format!(
                            "line {n}: vertex {}: expected three numbers after 'v', found '{}'",
                            so_far[0],
                            coords.join(" ")
                        ))
                    }
                }
            }
            Some("vt") => so_far[1] += 1,
            Some("vn") => so_far[2] += 1,
            Some(kind @ ("f" | "l")) => {
                let element = if kind == "f" { "face" } else { "line" };
                let refs: Vec<&str> = words.collect();
                for r in &refs {
                    check_vertex_ref(r, &total, &so_far)
                        .map_err(|e| format!("line {n}: {element} {e}"))?;
                }
                if kind == "l" && refs.len() > 2 {
                    for pair in refs.windows(2) {
                        out.push_str("l ");
                        out.push_str(pair[0]);
                        out.push(' ');
                        out.push_str(pair[1]);
                        out.push('\n');
                    }
                    continue;
                }
            }
            _ => {}
        }
        out.push_str(line);
        out.push('\n');
    }
    Ok(out)
}

/// Check one `v`, `v/vt`, `v//vn` or `v/vt/vn` reference against the counts.
fn check_vertex_ref(r: &str, total: &[usize; 3], so_far: &[usize; 3]) -> Result<(), String> {
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    const WHATS: [&str; 3] = ["vertices", "texture coordinates", "normals"];
    let parts: Vec<&str> = r.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(format!("reference '{r}' is not v, v/vt, v//vn or v/vt/vn"));
    }
    for (k, part) in parts.iter().enumerate() {
        if part.is_empty() {
            continue;
        }
        let Ok(i) = part.parse::<i64>() else {
            return Err(format!("reference '{r}': '{part}' is not an index"));
        };
        let ok = match i {
            0 => false,
            i if i > 0 => i as u64 <= total[k] as u64,
            i => i.unsigned_abs() <= so_far[k] as u64,
        };
        if !ok {
            let count = if i < 0 { so_far[k] } else { total[k] };
            let known = if i < 0 { " so far" } else { "" };
            return Err(format!(
                "{} index {i} out of range ({count} {}{known}; OBJ indices start at 1)",
                WHAT[k], WHATS[k]
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polyline_is_split_and_checked() {
        let out = prepass("v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\n").unwrap();
        assert!(out.contains("l 1 2\nl 2 3\n"), "{out}");
        let e = prepass("v 0 0 0\nf 1 2 3\n").unwrap_err();
        assert!(
            e.starts_with("line 2: face vertex index 2 out of range"),
            "{e}"
        );
        let e = prepass("v 0 0 0\nl 1 -2\n").unwrap_err();
        assert!(e.contains("index -2 out of range"), "{e}");
        let e = prepass("v 0 nan 0\n").unwrap_err();
        assert!(e.contains("line 1: vertex 1 is not finite"), "{e}");
        let e = prepass("v 0 0 0 0\n").unwrap_err();
        assert!(e.contains("line 1: vertex 1 has weight w = 0"), "{e}");
        let e = prepass("# nothing\n").unwrap_err();
        assert!(e.contains("no vertices"), "{e}");
        let e = prepass("v 0 0\n").unwrap_err();
        assert!(e.contains("expected three numbers"), "{e}");
        assert!(prepass("v 0 0 0\nvt 0 0\nf 1/1 1/1 -1/-1\n").is_ok());
        assert!(prepass("v 0 0 0\nf 1/2 1 1\n").is_err());
    }
}
