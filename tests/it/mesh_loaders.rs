//! OBJ and glTF loaders: the shipped plane assets round-trip to the built-in plane, faces and
//! primitives become the right edges, node transforms apply, and broken files give errors that
//! name the file and the problem (never a panic).

use std::path::{Path, PathBuf};

use glam::Vec3;
use serde_json::json;
use wireflight::draw::mesh_files;
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::mesh::EdgeMesh;

use crate::support::cli::{ok, wireflight};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
}

/// The edges as unordered pairs of positions.
fn segments(m: &EdgeMesh) -> Vec<[Vec3; 2]> {
    m.edges()
        .iter()
        .map(|&[a, b]| [m.positions()[a as usize], m.positions()[b as usize]])
        .collect()
}

fn same_segment(s: &[Vec3; 2], t: &[Vec3; 2], tol: f32) -> bool {
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= tol;
    (close(s[0], t[0]) && close(s[1], t[1])) || (close(s[0], t[1]) && close(s[1], t[0]))
}

/// Same set of unordered position pairs, within `tol` per coordinate.
fn assert_same_edges(got: &EdgeMesh, want: &EdgeMesh, tol: f32) {
    let (g, w) = (segments(got), segments(want));
    assert_eq!(g.len(), w.len(), "edge counts differ");
    for s in &w {
        assert!(
            g.iter().any(|t| same_segment(s, t, tol)),
            "missing edge {s:?}"
        );
    }
    for s in &g {
        assert!(
            w.iter().any(|t| same_segment(s, t, tol)),
            "extra edge {s:?}"
        );
    }
}

fn write(dir: &Path, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, contents).unwrap();
    path
}

/// Load, expect an error, and check it names the file and contains every hint.
fn assert_load_error(path: &Path, hints: &[&str]) -> String {
    let err = match mesh_files::load(path) {
        Ok(m) => panic!("{} loaded ({} edges)", path.display(), m.edges().len()),
        Err(e) => e.to_string(),
    };
    let name = path.file_name().unwrap().to_str().unwrap();
    assert!(err.contains(name), "error does not name {name}: {err}");
    for hint in hints {
        assert!(err.contains(hint), "error lacks '{hint}': {err}");
    }
    err
}

// ---------------------------------------------------------------------------------- glTF helpers

fn le_bytes(positions: &[[f32; 3]], indices: &[u32]) -> Vec<u8> {
    let mut bin: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    bin
}

/// A one-mesh, one-primitive glTF document whose buffer is `uri` (or the GLB chunk if `None`),
/// holding `positions` then `indices` (if any) as in [`le_bytes`].
fn gltf_json(
    positions: &[[f32; 3]],
    indices: &[u32],
    mode: u32,
    uri: Option<&str>,
    nodes: serde_json::Value,
    scenes: serde_json::Value,
) -> serde_json::Value {
    let pos_len = 12 * positions.len();
    let idx_len = 4 * indices.len();
    let mut primitive = json!({ "attributes": { "POSITION": 0 }, "mode": mode });
    let mut accessors = vec![json!({
        "bufferView": 0, "componentType": 5126, "count": positions.len(), "type": "VEC3",
    })];
    let mut views = vec![json!({ "buffer": 0, "byteOffset": 0, "byteLength": pos_len })];
    if !indices.is_empty() {
        primitive["indices"] = json!(1);
        accessors.push(json!({
            "bufferView": 1, "componentType": 5125, "count": indices.len(), "type": "SCALAR",
        }));
        views.push(json!({ "buffer": 0, "byteOffset": pos_len, "byteLength": idx_len }));
    }
    let mut buffer = json!({ "byteLength": pos_len + idx_len });
    if let Some(uri) = uri {
        buffer["uri"] = json!(uri);
    }
    let mut doc = json!({
        "asset": { "version": "2.0" },
        "nodes": nodes,
        "meshes": [{ "primitives": [primitive] }],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [buffer],
    });
    if !scenes.is_null() {
        doc["scenes"] = scenes;
        doc["scene"] = json!(0);
    }
    doc
}

/// Binary glTF: header, JSON chunk (space-padded), BIN chunk (zero-padded).
fn glb(doc: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut json = serde_json::to_vec(doc).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// A unit cube's 8 corners and its 12 triangles (two per face, each face's diagonal shared).
fn cube() -> (Vec<[f32; 3]>, Vec<u32>) {
    let corners: Vec<[f32; 3]> = (0..8)
        .map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32])
        .collect();
    let quads = [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ];
    let tris = quads
        .iter()
        .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
        .collect();
    (corners, tris)
}

fn one_node() -> serde_json::Value {
    json!([{ "mesh": 0 }])
}

// ------------------------------------------------------------------------------------ the assets

#[test]
fn plane_obj_is_the_builtin_plane() {
    let m = mesh_files::load(&asset("plane.obj")).unwrap();
    assert_same_edges(&m, &builtin_plane(), 1e-6);
}

#[test]
fn plane_gltf_is_the_builtin_plane() {
    let m = mesh_files::load(&asset("plane.gltf")).unwrap();
    assert_same_edges(&m, &builtin_plane(), 1e-6);
    // No transform and f32 data: bit-exact, so even the welded vertex count agrees.
    assert_eq!(m.positions().len(), builtin_plane().positions().len());
}

#[test]
fn load_named_dispatches_plane_and_files() {
    use wireflight::draw::mesh_files::load_named as load_model;
    assert_eq!(load_model("plane").unwrap(), builtin_plane());
    let m = load_model(asset("plane.obj").to_str().unwrap()).unwrap();
    assert_same_edges(&m, &builtin_plane(), 1e-6);
    let err = format!("{:#}", load_model("model.stl").unwrap_err());
    assert!(
        err.contains("model.stl") && err.contains("unknown model format"),
        "{err}"
    );
}

// ------------------------------------------------------------------------------------------- OBJ

#[test]
fn obj_quad_cube_has_twelve_edges() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("# unit cube, quads\n");
    for i in 0..8 {
        text += &format!("v {} {} {}\n", i & 1, (i >> 1) & 1, (i >> 2) & 1);
    }
    text += "vn 0 0 1\nvt 0 0\n";
    text += "f 1 2 4 3\nf 5 7 8 6\nf 1/1/1 5/1/1 6/1/1 2/1/1\nf 3//1 4//1 8//1 7//1\n";
    text += "g second\nf -8 -6 -2 -4\nf 2 6 8 4\n"; // relative indices, a new group
    let m = mesh_files::load(&write(dir.path(), "cube.obj", text)).unwrap();
    assert_eq!(m.edges().len(), 12, "no diagonals, shared edges once");
    assert_eq!(m.positions().len(), 8);
}

#[test]
fn obj_lines_and_polylines_stay_open() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nl 1 2 3 4\nl 4 1\np 1\nl 2\n";
    let m = mesh_files::load(&write(dir.path(), "lines.obj", text)).unwrap();
    // 1-2, 2-3, 3-4 from the polyline (no closing 4-1 from it), 4-1 from the second line.
    assert_eq!(m.edges().len(), 4);
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\n";
    let m = mesh_files::load(&write(dir.path(), "open.obj", text)).unwrap();
    assert_eq!(m.edges().len(), 2, "a 3-point polyline is not a triangle");
}

#[test]
fn obj_errors_name_the_file_and_problem() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    assert_load_error(&d.join("missing.obj"), &["cannot read"]);
    assert_load_error(
        &write(d, "garbage.obj", "this is not a model\nat all }{\n"),
        &["no vertices", "not a Wavefront OBJ"],
    );
    assert_load_error(
        &write(d, "binary.obj", [0u8, 159, 146, 150, 255, 0, 1, 2]),
        &["no vertices"],
    );
    assert_load_error(&write(d, "empty.obj", ""), &["empty"]);
    assert_load_error(
        &write(d, "nofaces.obj", "v 0 0 0\nv 1 0 0\n"),
        &["no edges"],
    );
    assert_load_error(
        &write(d, "w0.obj", "v 0 0 0\nv 1 0 0 0\nl 1 2\n"),
        &["line 2", "w = 0"],
    );
    assert_load_error(
        &write(d, "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
        &["line 4", "index 9 out of range", "3 vertices"],
    );
    assert_load_error(
        &write(d, "zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
        &["line 4", "index 0 out of range"],
    );
    assert_load_error(
        &write(d, "nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"),
        &["line 2", "vertex 2", "not finite"],
    );
    assert_load_error(
        &write(d, "inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 inf\nl 1 3\n"),
        &["line 3", "vertex 3", "not finite"],
    );
    assert_load_error(
        &write(d, "short.obj", "v 0 0\nv 1 0 0\nl 1 2\n"),
        &["line 1", "expected three numbers"],
    );
    assert_load_error(
        &write(d, "badref.obj", "v 0 0 0\nv 1 0 0\nl 1 x\n"),
        &["line 3", "'x' is not an index"],
    );
    assert_load_error(
        &write(d, "points.obj", "v 0 0 0\nv 1 0 0\np 1 2\nf 1 1 1\n"),
        &["no edges"],
    );
}

// ------------------------------------------------------------------------------------------ glTF

#[test]
fn gltf_triangle_cube_external_buffer() {
    let dir = tempfile::tempdir().unwrap();
    let (pos, tri) = cube();
    write(dir.path(), "cube.bin", le_bytes(&pos, &tri));
    let doc = gltf_json(
        &pos,
        &tri,
        4,
        Some("cube.bin"),
        one_node(),
        json!([{ "nodes": [0] }]),
    );
    let m = mesh_files::load(&write(dir.path(), "cube.gltf", doc.to_string())).unwrap();
    // 12 cube edges + one diagonal per face.
    assert_eq!(m.edges().len(), 18);
}

#[test]
fn gltf_primitive_modes_and_non_indexed() {
    let dir = tempfile::tempdir().unwrap();
    let square = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    // (mode, indices, expected edges); empty indices = non-indexed.
    let cases: [(u32, &[u32], usize); 10] = [
        (0, &[], 0),           // POINTS → nothing → error checked below
        (1, &[], 2),           // LINES 0-1, 2-3
        (1, &[0, 1, 1, 2], 2), // LINES indexed
        (2, &[], 4),           // LINE_LOOP
        (3, &[], 3),           // LINE_STRIP
        (3, &[3, 0, 1], 2),    // LINE_STRIP indexed
        (4, &[0, 1, 2, 0, 2, 3], 5),
        (4, &[], 3), // TRIANGLES non-indexed: one triangle, the 4th vertex left over
        (5, &[], 5), // TRIANGLE_STRIP 012, 123
        (6, &[], 5), // TRIANGLE_FAN 012, 023
    ];
    for (k, (mode, idx, want)) in cases.into_iter().enumerate() {
        let uri = format!("m{k}.bin");
        write(dir.path(), &uri, le_bytes(&square, idx));
        let doc = gltf_json(&square, idx, mode, Some(&uri), one_node(), json!(null));
        let path = write(dir.path(), &format!("m{k}.gltf"), doc.to_string());
        if want == 0 {
            assert_load_error(&path, &["no edges"]);
        } else {
            let m = mesh_files::load(&path).unwrap();
            assert_eq!(m.edges().len(), want, "mode {mode} indices {idx:?}");
        }
    }
}

#[test]
fn gltf_node_transforms_compose() {
    let dir = tempfile::tempdir().unwrap();
    let seg = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    write(dir.path(), "seg.bin", le_bytes(&seg, &[]));
    // Root translated by (10, 0, 0); child scaled by 2 and translated by (0, 5, 0) in the
    // root's frame; the mesh on both. A third node, not in the scene, is not drawn.
    let nodes = json!([
        { "translation": [10.0, 0.0, 0.0], "children": [1], "mesh": 0 },
        { "translation": [0.0, 5.0, 0.0], "scale": [2.0, 2.0, 2.0], "mesh": 0 },
        { "translation": [100.0, 0.0, 0.0], "mesh": 0 },
    ]);
    let scenes = json!([{ "nodes": [0] }, { "nodes": [2] }]);
    let doc = gltf_json(&seg, &[], 1, Some("seg.bin"), nodes.clone(), scenes);
    let m = mesh_files::load(&write(dir.path(), "nodes.gltf", doc.to_string())).unwrap();
    let want = [
        [Vec3::new(10.0, 0.0, 0.0), Vec3::new(11.0, 0.0, 0.0)],
        [Vec3::new(10.0, 5.0, 0.0), Vec3::new(12.0, 5.0, 0.0)],
    ];
    let got = segments(&m);
    assert_eq!(got.len(), 2, "{got:?}");
    for s in &want {
        assert!(got.iter().any(|t| same_segment(s, t, 1e-6)), "{got:?}");
    }

    // A matrix on the child (column-major): rotate +90° about Z, so +X → +Y.
    let nodes = json!([
        { "children": [1] },
        { "matrix": [0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0,
                     0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 3.0, 1.0], "mesh": 0 },
    ]);
    // No scenes: root nodes are drawn.
    let doc = gltf_json(&seg, &[], 1, Some("seg.bin"), nodes, json!(null));
    let m = mesh_files::load(&write(dir.path(), "matrix.gltf", doc.to_string())).unwrap();
    let s = segments(&m);
    let want = [Vec3::new(0.0, 0.0, 3.0), Vec3::new(0.0, 1.0, 3.0)];
    assert!(s.len() == 1 && same_segment(&s[0], &want, 1e-6), "{s:?}");
}

#[test]
fn glb_loads() {
    let dir = tempfile::tempdir().unwrap();
    let (pos, tri) = cube();
    let doc = gltf_json(&pos, &tri, 4, None, one_node(), json!([{ "nodes": [0] }]));
    let path = write(dir.path(), "cube.glb", glb(&doc, &le_bytes(&pos, &tri)));
    assert_eq!(mesh_files::load(&path).unwrap().edges().len(), 18);

    // The plane asset, repacked as GLB, is still the plane.
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(asset("plane.gltf")).unwrap()).unwrap();
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let bin = decode_base64(uri.split_once(',').unwrap().1);
    doc["buffers"][0].as_object_mut().unwrap().remove("uri");
    let path = write(dir.path(), "plane.glb", glb(&doc, &bin));
    assert_same_edges(&mesh_files::load(&path).unwrap(), &builtin_plane(), 1e-6);
}

fn decode_base64(s: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("bad base64 {c}"),
    };
    let digits: Vec<u8> = s.bytes().filter(|&c| c != b'=').map(value).collect();
    let mut out = Vec::new();
    for chunk in digits.chunks(4) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &d)| n | (u32::from(d) << (18 - 6 * i)));
        out.extend_from_slice(&n.to_be_bytes()[1..chunk.len()]);
    }
    out
}

#[test]
fn gltf_errors_name_the_file_and_problem() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (pos, tri) = cube();
    let scenes = json!([{ "nodes": [0] }]);

    assert_load_error(&d.join("missing.gltf"), &["cannot read"]);
    assert_load_error(
        &write(d, "garbage.gltf", "this is not a model"),
        &["not a glTF file"],
    );
    assert_load_error(&write(d, "empty.gltf", ""), &["not a glTF file"]);
    assert_load_error(&write(d, "empty.glb", ""), &["not a glTF file"]);
    assert_load_error(&write(d, "garbage.glb", "glTF\x02\0\0\0junk"), &["GLB"]);
    assert_load_error(&write(d, "json.gltf", "{}"), &["missing field"]);

    // The buffer file is not there: the error names it.
    let doc = gltf_json(&pos, &tri, 4, Some("gone.bin"), one_node(), scenes.clone());
    assert_load_error(
        &write(d, "nobuffer.gltf", doc.to_string()),
        &["buffer 0", "gone.bin"],
    );
    // Buffer too short for its declared length.
    write(d, "short.bin", [0u8; 16]);
    let doc = gltf_json(&pos, &tri, 4, Some("short.bin"), one_node(), scenes.clone());
    assert_load_error(
        &write(d, "shortbuf.gltf", doc.to_string()),
        &["buffer 0", "bytes"],
    );
    // Index out of range.
    let bad: Vec<u32> = tri.iter().map(|&i| if i == 7 { 8 } else { i }).collect();
    write(d, "bad.bin", le_bytes(&pos, &bad));
    let doc = gltf_json(&pos, &bad, 4, Some("bad.bin"), one_node(), scenes.clone());
    assert_load_error(
        &write(d, "badindex.gltf", doc.to_string()),
        &["index 8 out of range", "8 vertices"],
    );
    // NaN position.
    let mut nan = pos.clone();
    nan[3][1] = f32::NAN;
    write(d, "nan.bin", le_bytes(&nan, &tri));
    let doc = gltf_json(&nan, &tri, 4, Some("nan.bin"), one_node(), scenes.clone());
    assert_load_error(
        &write(d, "nan.gltf", doc.to_string()),
        &["vertex 3", "not finite"],
    );
    // An accessor reading past its view, and one of the wrong type: errors, not panics.
    write(d, "cube.bin", le_bytes(&pos, &tri));
    let mut doc = gltf_json(&pos, &tri, 4, Some("cube.bin"), one_node(), scenes.clone());
    doc["accessors"][0]["count"] = json!(9);
    assert_load_error(&write(d, "past.gltf", doc.to_string()), &["runs past"]);
    let mut doc = gltf_json(&pos, &tri, 4, Some("cube.bin"), one_node(), scenes.clone());
    doc["accessors"][0]["type"] = json!("VEC2");
    assert_load_error(
        &write(d, "vec2.gltf", doc.to_string()),
        &["POSITION", "expected F32 Vec3"],
    );
    let mut doc = gltf_json(&pos, &tri, 4, Some("cube.bin"), one_node(), scenes.clone());
    doc["accessors"][0]["count"] = json!(0);
    assert_load_error(&write(d, "count0.gltf", doc.to_string()), &["count 0"]);
    // A POSITION attribute naming a missing accessor (gltf-json's own validation would panic).
    let mut doc = gltf_json(&pos, &tri, 4, Some("cube.bin"), one_node(), scenes.clone());
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(9);
    assert_load_error(
        &write(d, "posindex.gltf", doc.to_string()),
        &["POSITION", "accessor 9 does not exist"],
    );
    // Compressed geometry is refused by name; other required extensions do not matter.
    let mut doc = gltf_json(&pos, &tri, 4, Some("cube.bin"), one_node(), scenes.clone());
    doc["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    assert_load_error(
        &write(d, "draco.gltf", doc.to_string()),
        &["KHR_draco_mesh_compression", "not supported"],
    );
    let mut doc = gltf_json(&pos, &tri, 4, Some("cube.bin"), one_node(), scenes.clone());
    doc["extensionsUsed"] = json!(["KHR_texture_transform"]);
    doc["extensionsRequired"] = json!(["KHR_texture_transform"]);
    let path = write(d, "texture_ext.gltf", doc.to_string());
    assert_eq!(mesh_files::load(&path).unwrap().edges().len(), 18);
    // A node with two parents.
    let nodes = json!([{ "children": [2] }, { "children": [2] }, { "mesh": 0 }]);
    let doc = gltf_json(
        &pos,
        &tri,
        4,
        Some("cube.bin"),
        nodes,
        json!([{ "nodes": [0, 1] }]),
    );
    assert_load_error(
        &write(d, "parents.gltf", doc.to_string()),
        &["node 2", "more than one parent"],
    );
    // A node that is its own child.
    let doc = gltf_json(
        &pos,
        &tri,
        4,
        Some("cube.bin"),
        json!([{ "children": [0] }]),
        scenes,
    );
    assert_load_error(
        &write(d, "cycle.gltf", doc.to_string()),
        &["node 0", "cycle"],
    );
}

// ------------------------------------------------------------------------------------------- CLI

#[test]
fn cli_renders_obj_and_rejects_garbage() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plane.svg");
    let plane = asset("plane.obj");
    ok(&[
        "render",
        "--model",
        plane.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let svg = std::fs::read_to_string(&out).unwrap();
    assert!(svg.contains("<svg"), "{svg}");

    let garbage = write(dir.path(), "garbage.gltf", "not a model at all");
    let never = dir.path().join("never.svg");
    let run = wireflight(&[
        "render",
        "--model",
        garbage.to_str().unwrap(),
        "--out",
        never.to_str().unwrap(),
    ]);
    assert!(!run.status.success());
    assert_ne!(run.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("garbage.gltf"), "{stderr}");
    assert!(!dir.path().join("never.svg").exists());
}
