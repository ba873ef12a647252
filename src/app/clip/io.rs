//! CSV files of edges for `wireflight clip` (the clipping lab). Not pure: it reads files; the
//! clippers themselves live in [`crate::geometry::clip`].
//!
//! One edge per line, comma-separated: `x0,y0,z0,w0,x1,y1,z1,w1` (homogeneous clip space) or
//! `x0,y0,x1,y1` (2D). A byte-order mark is skipped. Blank lines and lines starting with `#`
//! are skipped; a first line is a header (echoed to the output) only when it has as many fields
//! as an edge, none of them a number and every one like a name (starts with a letter or `_`);
//! any other first
//! line is an edge, and an error naming the line if it is not one. `nan` and `inf`
//! are read as such (the clippers drop and count them); a number beyond the `f32` range is
//! an error. The output has one line per input edge, in order: the clipped edge in the same
//! columns, or an empty line for an edge with nothing visible.

use std::fmt::Write as _;
use std::io::Read;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec4};

/// Names of the homogeneous columns.
pub const HOMOGENEOUS_COLUMNS: [&str; 8] = ["x0", "y0", "z0", "w0", "x1", "y1", "z1", "w1"];
/// Names of the 2D columns.
pub const PLANAR_COLUMNS: [&str; 4] = ["x0", "y0", "x1", "y1"];

/// An input problem, with the file and the line (1-based; 0 for the file as a whole).
#[derive(Debug, thiserror::Error)]
#[error("{}:{line}: {problem}", path.display())]
pub struct CsvError {
    /// The file.
    pub path: PathBuf,
    /// The line, from 1 (0: the file as a whole).
    pub line: usize,
    /// What is wrong.
    pub problem: String,
}

/// The edges of a file, in order, with its header line if it had one.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeFile<E> {
    /// The header line, as written.
    pub header: Option<String>,
    /// The edges, in input order.
    pub edges: Vec<E>,
    /// The line number of each edge (for messages).
    pub lines: Vec<usize>,
}

/// Read a text file of at most `max_bytes` bytes.
///
/// # Errors
/// A [`CsvError`] (line 0) if the file cannot be read, is larger than the limit, or is not
/// UTF-8.
pub fn read_bounded(path: &Path, max_bytes: u64) -> Result<String, CsvError> {
    let whole = |problem: String| CsvError {
        path: path.to_path_buf(),
        line: 0,
        problem,
    };
    // A regular file only: a FIFO would block the open, a device would read without end.
    let file = crate::fsio::open_regular(path).map_err(|e| whole(format!("cannot read: {e}")))?;
    if let Ok(meta) = file.metadata() {
        if meta.is_file() && meta.len() > max_bytes {
            return Err(whole(format!(
                "file is {} bytes, more than the limit of {max_bytes} (--max-bytes)",
                meta.len()
            )));
        }
    }
    // The metadata can lie (a pipe, a growing file): never read more than the limit + 1.
    let mut bytes = Vec::new();
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| whole(format!("cannot read: {e}")))?;
    if bytes.len() as u64 > max_bytes {
        return Err(whole(format!(
            "file is more than the limit of {max_bytes} bytes (--max-bytes)"
        )));
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        CsvError {
            path: path.to_path_buf(),
            line,
            problem: format!("not UTF-8 text (byte {at})"),
        }
    })
}

/// Parse `text` as rows of `N` numbers (`names` for messages), e.g. `N = 8` for homogeneous
/// edges.
///
/// # Errors
/// A [`CsvError`] naming the line and the problem (wrong number of values, a value that is
/// not a number or is out of the `f32` range).
pub fn parse_rows<const N: usize>(
    text: &str,
    path: &Path,
    names: &[&str; N],
) -> Result<EdgeFile<[f32; N]>, CsvError> {
    let mut file = EdgeFile {
        header: None,
        edges: Vec::new(),
        lines: Vec::new(),
    };
    let mut first = true;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let err = |problem: String| CsvError {
            path: path.to_path_buf(),
            line,
            problem,
        };
        let row = raw.trim();
        if row.is_empty() || row.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        // A header names the edge's values: as many fields as an edge has (a line of text of
        // another shape is an error, not a header that leaves the file without edges).
        if std::mem::take(&mut first) && fields.len() == N && is_header(&fields) {
            file.header = Some(row.to_string());
            continue;
        }
        if fields.len() != N {
            let hint = match (N, fields.len()) {
                (8, 4) => " (2D edges: give --window)",
                (4, 8) => " (homogeneous edges: leave out --window)",
                _ if row.contains(';') => " (separate the values with commas, not `;`)",
                _ => "",
            };
            return Err(err(format!(
                "expected {N} values ({}), found {}{hint}",
                names.join(","),
                fields.len()
            )));
        }
        let mut values = [0f32; N];
        for (i, (slot, field)) in values.iter_mut().zip(&fields).enumerate() {
            let v: f64 = field.parse().map_err(|_| {
                err(format!(
                    "column {} ({}): `{field}` is not a number",
                    i + 1,
                    names[i]
                ))
            })?;
            if v.is_finite() && v.abs() > f64::from(f32::MAX) {
                return Err(err(format!(
                    "column {} ({}): {field} is outside the f32 range",
                    i + 1,
                    names[i]
                )));
            }
            *slot = v as f32;
        }
        file.edges.push(values);
        file.lines.push(line);
    }
    Ok(file)
}

/// Whether a first row is a header: no field is a number and every field looks like a name
/// (a letter or `_` first). `0x10`, `1;2;3;4` or a number with a stray character are data,
/// reported as bad data rather than dropped as a header.
fn is_header(fields: &[&str]) -> bool {
    fields.iter().all(|f| {
        f.parse::<f64>().is_err()
            && f.chars()
                .next()
                .is_some_and(|c| c.is_alphabetic() || c == '_')
            && !f.chars().any(char::is_control)
    })
}

/// Homogeneous edges `(A, C)` from rows of eight numbers.
pub fn homogeneous_edges(rows: &[[f32; 8]]) -> Vec<(Vec4, Vec4)> {
    rows.iter()
        .map(|r| {
            (
                Vec4::new(r[0], r[1], r[2], r[3]),
                Vec4::new(r[4], r[5], r[6], r[7]),
            )
        })
        .collect()
}

/// 2D edges `(A, C)` from rows of four numbers.
pub fn planar_edges(rows: &[[f32; 4]]) -> Vec<(Vec2, Vec2)> {
    rows.iter()
        .map(|r| (Vec2::new(r[0], r[1]), Vec2::new(r[2], r[3])))
        .collect()
}

/// The output text: the header (if any), then per edge the clipped coordinates (shortest
/// round-trip formatting) or an empty line.
pub fn format_rows<'a>(
    header: Option<&str>,
    rows: impl IntoIterator<Item = Option<&'a [f32]>>,
) -> String {
    let mut out = String::new();
    if let Some(h) = header {
        out.push_str(h);
        out.push('\n');
    }
    for row in rows {
        if let Some(values) = row {
            for (i, v) in values.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                let _ = write!(out, "{v}");
            }
        }
        out.push('\n');
    }
    out
}
