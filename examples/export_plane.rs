//! Write the built-in plane as `assets/plane.obj` and `assets/plane.gltf`.
//!
//! ```text
//! cargo run --example export_plane            # into assets/ of this crate
//! cargo run --example export_plane -- OUTDIR  # somewhere else
//! ```
//!
//! Both files store the viewer's body axes directly — nose **+X**, left wing **+Y**, up **+Z**,
//! metres — not glTF's +Y-up convention, so that loading them back gives exactly the built-in
//! edge set (the loaders take coordinates as the file has them). The OBJ has one `l` element
//! per edge; the glTF has one node, one mesh and one `LINES` primitive (unsigned-int indices),
//! its buffer embedded as a base64 `data:` URI.

use std::path::PathBuf;

use serde_json::json;
use wireflight::geometry::mesh::plane::builtin_plane;
use wireflight::geometry::mesh::EdgeMesh;

const AXES_NOTE: &str = "body axes: +X nose, +Y left wing, +Z up (metres); \
     not glTF's +Y-up convention";

fn main() -> anyhow::Result<()> {
    let dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets"));
    std::fs::create_dir_all(&dir)?;
    let mesh = builtin_plane();

    let obj = dir.join("plane.obj");
    std::fs::write(&obj, to_obj(&mesh))?;
    let gltf = dir.join("plane.gltf");
    std::fs::write(&gltf, to_gltf(&mesh)?)?;
    println!(
        "wrote {} and {} ({} vertices, {} edges)",
        obj.display(),
        gltf.display(),
        mesh.positions().len(),
        mesh.edges().len()
    );
    Ok(())
}

/// OBJ text: the vertices, then one `l` per edge. `{}` prints the shortest decimal that parses
/// back to the same `f32`, so the positions round-trip exactly.
fn to_obj(mesh: &EdgeMesh) -> String {
    let mut s = format!(
        "# wireflight built-in plane ({} vertices, {} edges), written by \
         `cargo run --example export_plane`\n# {AXES_NOTE}\no plane\n",
        mesh.positions().len(),
        mesh.edges().len()
    );
    for p in mesh.positions() {
        s += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for [a, b] in mesh.edges() {
        s += &format!("l {} {}\n", a + 1, b + 1);
    }
    s
}

/// glTF JSON with one `LINES` primitive; the buffer (positions, then `u32` index pairs,
/// little-endian) is embedded as a `data:` URI.
fn to_gltf(mesh: &EdgeMesh) -> anyhow::Result<String> {
    let mut bin = Vec::new();
    for p in mesh.positions() {
        for c in p.to_array() {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    let positions_len = bin.len();
    for i in mesh.edges().iter().flatten() {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let indices_len = bin.len() - positions_len;
    let (min, max) = mesh.bounds();

    let doc = json!({
        "asset": {
            "version": "2.0",
            "generator": "wireflight examples/export_plane.rs",
            "extras": { "axes": AXES_NOTE },
        },
        "scene": 0,
        "scenes": [{ "name": "plane", "nodes": [0] }],
        "nodes": [{ "name": "plane", "mesh": 0 }],
        "meshes": [{
            "name": "plane",
            "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1, "mode": 1 }],
        }],
        "accessors": [
            {
                "bufferView": 0, "componentType": 5126, "count": mesh.positions().len(),
                "type": "VEC3", "min": min.to_array(), "max": max.to_array(),
            },
            {
                "bufferView": 1, "componentType": 5125, "count": 2 * mesh.edges().len(),
                "type": "SCALAR",
            },
        ],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": positions_len, "target": 34962 },
            {
                "buffer": 0, "byteOffset": positions_len, "byteLength": indices_len,
                "target": 34963,
            },
        ],
        "buffers": [{
            "byteLength": bin.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64(&bin)),
        }],
    });
    Ok(serde_json::to_string_pretty(&doc)? + "\n")
}

/// Standard base64 (RFC 4648, with `=` padding).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &b)| n | (u32::from(b) << (16 - 8 * i)));
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}
