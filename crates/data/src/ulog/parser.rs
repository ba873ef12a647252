//! The ULog parser: the definitions section (formats flattened, parameters, info), then the
//! data section (subscriptions, data of the wanted topics, appended data), bounded and
//! tolerant of a log cut short. It fills in the types of the parent module ([`UlogFile`],
//! [`Topic`]), whose layout fields only it writes.

use std::collections::HashMap;

use super::{
    is_ulog, Field, Scalar, Topic, UlogError, UlogErrorKind, UlogFile, MAGIC, MAX_FIELDS,
    MAX_NESTING, SYNC_MAGIC,
};

/// One field of a format as written: type name, array length, field name.
#[derive(Clone, Debug)]
struct RawField {
    ty: String,
    array: Option<usize>,
    name: String,
}

/// The state of one parse: the bytes, the formats and subscriptions seen so far, and the
/// [`UlogFile`] being filled in.
pub(super) struct Parser<'a> {
    bytes: &'a [u8],
    file: &'a str,
    keep: &'a dyn Fn(&str) -> bool,
    log: UlogFile,
    /// Formats by name.
    formats: HashMap<String, Vec<RawField>>,
    /// Message id → index into `log.topics`.
    ids: HashMap<u16, usize>,
    /// Whether the data section has begun (the first subscription or data message).
    in_data: bool,
}

impl<'a> Parser<'a> {
    /// A parser of `bytes`, `file` naming them in errors, keeping the samples of the topics
    /// for which `keep` is true.
    pub(super) fn new(bytes: &'a [u8], file: &'a str, keep: &'a dyn Fn(&str) -> bool) -> Self {
        Self {
            bytes,
            file,
            keep,
            log: UlogFile::default(),
            formats: HashMap::new(),
            ids: HashMap::new(),
            in_data: false,
        }
    }

    fn err(&self, offset: usize, kind: UlogErrorKind) -> UlogError {
        UlogError::at(self.file, offset, kind)
    }

    /// Reads the whole file.
    pub(super) fn run(mut self) -> Result<UlogFile, UlogError> {
        let b = self.bytes;
        if b.len() < 16 {
            if !is_ulog(b) && !MAGIC.starts_with(b) {
                return Err(self.err(0, UlogErrorKind::NotUlog));
            }
            return Err(self.err(
                0,
                UlogErrorKind::Truncated {
                    section: "header",
                    what: "the 16-byte header".into(),
                    needed: 16,
                    present: b.len(),
                },
            ));
        }
        if !is_ulog(b) {
            return Err(self.err(0, UlogErrorKind::NotUlog));
        }
        self.log.version = b[7];
        self.log.start_us = u64::from_le_bytes(b[8..16].try_into().unwrap_or([0; 8]));
        let mut appended: Vec<usize> = Vec::new();
        let mut pos = 16;
        while pos < b.len() {
            if b.len() - pos < 3 {
                self.cut(pos, "a message header", 3)?;
                break;
            }
            let size = u16::from_le_bytes([b[pos], b[pos + 1]]) as usize;
            let kind = b[pos + 2];
            let end = pos + 3 + size;
            // Appended data: the main data ends where the first appended block begins.
            if let Some(&next) = appended.first() {
                if pos < next && end > next {
                    pos = next;
                    appended.remove(0);
                    continue;
                }
                if pos >= next {
                    appended.remove(0);
                }
            }
            if end > b.len() {
                self.cut(pos, &format!("a `{}` message", kind as char), 3 + size)?;
                break;
            }
            let payload = &b[pos + 3..end];
            match kind {
                b'B' => appended = self.flag_bits(pos, payload)?,
                b'F' => self.format(pos, payload)?,
                b'I' => {
                    if let Some((k, v)) = key_value(payload) {
                        self.log.info.push((k, v));
                    }
                }
                b'P' if !self.in_data => {
                    if let Some((k, v)) = key_value(payload) {
                        if let Ok(x) = v.parse::<f64>() {
                            self.log.params.push((k, x));
                        }
                    }
                }
                b'A' => {
                    self.in_data = true;
                    self.subscribe(pos, payload)?;
                }
                b'R' => {
                    if payload.len() >= 2 {
                        self.ids
                            .remove(&u16::from_le_bytes([payload[0], payload[1]]));
                    }
                }
                b'D' => {
                    self.in_data = true;
                    self.data(payload);
                }
                b'O' => {
                    self.log.dropouts += 1;
                    if payload.len() >= 2 {
                        self.log.dropout_ms += u16::from_le_bytes([payload[0], payload[1]]) as u64;
                    }
                }
                b'M' | b'Q' | b'L' | b'C' | b'S' | b'P' => {}
                // Unknown message types are skipped (the format may grow); zero bytes are not a
                // message type: resynchronise at the next sync marker.
                k if k.is_ascii_alphabetic() && size > 0 => {}
                _ => match find_sync(b, pos + 1) {
                    Some(next) => {
                        self.log.corrupt_messages += 1;
                        pos = next;
                        continue;
                    }
                    None => {
                        self.log.unreadable_from = Some(pos);
                        break;
                    }
                },
            }
            pos = end;
        }
        self.log.appended = !appended.is_empty() || self.log.appended;
        Ok(self.log)
    }

    /// A message cut short at `pos`: an error in the definitions section, a note in the data.
    fn cut(&mut self, pos: usize, what: &str, needed: usize) -> Result<(), UlogError> {
        if self.in_data {
            self.log.truncated_at = Some(pos);
            return Ok(());
        }
        Err(self.err(
            pos,
            UlogErrorKind::Truncated {
                section: "definitions section",
                what: what.to_string(),
                needed,
                present: self.bytes.len() - pos,
            },
        ))
    }

    /// `B`: compat[8], incompat[8], appended offsets u64[3]. Returns the appended offsets.
    fn flag_bits(&mut self, pos: usize, p: &[u8]) -> Result<Vec<usize>, UlogError> {
        if p.len() < 40 {
            return Err(self.err(
                pos,
                UlogErrorKind::BadFormat(format!(
                    "the flag-bits message has {} bytes, not 40",
                    p.len()
                )),
            ));
        }
        for (byte, &bits) in p[8..16].iter().enumerate() {
            let unknown = if byte == 0 { bits & !1 } else { bits };
            if unknown != 0 {
                return Err(self.err(
                    pos,
                    UlogErrorKind::UnknownIncompatible {
                        byte,
                        bits: format!("{unknown:#04x}"),
                    },
                ));
            }
        }
        if p[8] & 1 == 0 {
            return Ok(Vec::new());
        }
        self.log.appended = true;
        let mut offsets: Vec<usize> = p[16..40]
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
            .filter(|&o| o > pos as u64 && o < self.bytes.len() as u64)
            .map(|o| o as usize)
            .collect();
        offsets.sort_unstable();
        Ok(offsets)
    }

    /// `F`: `name:type field;type field;…`.
    fn format(&mut self, pos: usize, p: &[u8]) -> Result<(), UlogError> {
        let bad = |why: String| self.err(pos, UlogErrorKind::BadFormat(why));
        let text = std::str::from_utf8(p).map_err(|_| bad("not ASCII text".into()))?;
        let (name, body) = text
            .split_once(':')
            .ok_or_else(|| bad(format!("`{}` has no `name:`", clip(text))))?;
        let mut fields = Vec::new();
        for f in body.split(';').map(str::trim).filter(|f| !f.is_empty()) {
            let (ty, fname) = f.split_once(' ').ok_or_else(|| {
                bad(format!(
                    "`{}`: field `{}` is not `type name`",
                    clip(name),
                    clip(f)
                ))
            })?;
            let (ty, array) = match ty.split_once('[') {
                Some((t, rest)) => {
                    let n = rest
                        .strip_suffix(']')
                        .and_then(|n| n.parse::<usize>().ok())
                        .filter(|&n| n <= u16::MAX as usize)
                        .ok_or_else(|| {
                            bad(format!(
                                "`{}`: field `{}` has a bad array length `{}`",
                                clip(name),
                                clip(fname),
                                clip(ty)
                            ))
                        })?;
                    (t, Some(n))
                }
                None => (ty, None),
            };
            fields.push(RawField {
                ty: ty.to_string(),
                array,
                name: fname.trim().to_string(),
            });
        }
        self.formats.insert(name.to_string(), fields);
        Ok(())
    }

    /// `A`: u8 multi id, u16 message id, topic name.
    fn subscribe(&mut self, pos: usize, p: &[u8]) -> Result<(), UlogError> {
        if p.len() < 4 {
            self.log.corrupt_messages += 1;
            return Ok(());
        }
        let multi_id = p[0];
        let id = u16::from_le_bytes([p[1], p[2]]);
        let name = String::from_utf8_lossy(&p[3..])
            .trim_end_matches('\0')
            .to_string();
        // The same instance subscribed again (appended data): keep adding to it.
        if let Some(i) = self
            .log
            .topics
            .iter()
            .position(|t| t.name == name && t.multi_id == multi_id)
        {
            self.ids.insert(id, i);
            return Ok(());
        }
        let kept = (self.keep)(&name);
        let mut fields = Vec::new();
        let layout = flatten(&self.formats, &name, "", 0, &mut fields);
        let (min_size, full_size) = match layout {
            Ok(sizes) => sizes,
            // A topic that is not kept needs no layout.
            Err(_) if !kept => {
                self.ids.remove(&id);
                return Ok(());
            }
            Err(kind) => {
                return Err(self.err(pos, kind).in_topic(&name));
            }
        };
        self.log.topics.push(Topic {
            name,
            multi_id,
            fields,
            min_size,
            full_size,
            count: 0,
            kept: kept && min_size > 0,
            data: Vec::new(),
        });
        self.ids.insert(id, self.log.topics.len() - 1);
        Ok(())
    }

    /// `D`: u16 message id, then the packed fields.
    fn data(&mut self, p: &[u8]) {
        let Some(&i) = (p.len() >= 2)
            .then(|| u16::from_le_bytes([p[0], p[1]]))
            .and_then(|id| self.ids.get(&id))
        else {
            self.log.corrupt_messages += 1;
            return;
        };
        let t = &mut self.log.topics[i];
        let body = &p[2..];
        if body.len() < t.min_size || body.len() > t.full_size {
            self.log.corrupt_messages += 1;
            return;
        }
        t.count += 1;
        if t.kept {
            t.data.extend_from_slice(&body[..t.min_size]);
        }
    }
}

/// Flattens format `name` into `out` (names prefixed by `prefix`, offsets from the start of
/// the sample). Returns the sizes without and with trailing padding.
///
/// # Errors
/// [`UlogErrorKind::BadFormat`]: formats nested too deep, a missing format, too many fields, a
/// sample larger than a message.
fn flatten(
    formats: &HashMap<String, Vec<RawField>>,
    name: &str,
    prefix: &str,
    depth: usize,
    out: &mut Vec<Field>,
) -> Result<(usize, usize), UlogErrorKind> {
    let mut size = 0;
    let mut min = 0;
    flatten_into(formats, name, prefix, depth, out, &mut size, &mut min)?;
    Ok((min, size))
}

/// [`flatten`]'s work: adds the fields of format `name` to `out`, `size` and `min` growing.
fn flatten_into(
    formats: &HashMap<String, Vec<RawField>>,
    name: &str,
    prefix: &str,
    depth: usize,
    out: &mut Vec<Field>,
    size: &mut usize,
    min: &mut usize,
) -> Result<(), UlogErrorKind> {
    let bad = UlogErrorKind::BadFormat;
    if depth > MAX_NESTING {
        return Err(bad(format!(
            "formats nested more than {MAX_NESTING} deep (a format inside itself?)"
        )));
    }
    let fields = formats
        .get(name)
        .ok_or_else(|| bad(format!("no format definition `{}`", clip(name))))?;
    for f in fields {
        let count = f.array.unwrap_or(1);
        let padding = f.name.starts_with("_padding");
        for k in 0..count {
            let full = match f.array {
                Some(_) => format!("{prefix}{}[{k}]", f.name),
                None => format!("{prefix}{}", f.name),
            };
            match Scalar::of(&f.ty) {
                Some(ty) => {
                    if !padding {
                        if out.len() >= MAX_FIELDS {
                            return Err(bad(format!("more than {MAX_FIELDS} fields")));
                        }
                        out.push(Field {
                            name: full,
                            ty,
                            offset: *size,
                        });
                    }
                    *size += ty.size();
                    if !padding {
                        *min = *size;
                    }
                }
                None => {
                    let nested = format!("{full}.");
                    let before = *size;
                    flatten_into(formats, &f.ty, &nested, depth + 1, out, size, min)?;
                    // A format of no bytes (no fields) takes no room: in an array it would
                    // make work without input (65 535 × 65 535 empty elements); refused.
                    if *size == before {
                        return Err(bad(format!(
                            "`{name}`: field `{}` is of format `{}`, which has no bytes",
                            clip(&f.name),
                            clip(&f.ty)
                        )));
                    }
                    *min = *size;
                }
            }
            if *size > u16::MAX as usize {
                return Err(bad(format!(
                    "`{}` is larger than a message can be",
                    clip(name)
                )));
            }
        }
    }
    Ok(())
}

/// An `I` or `P` payload: u8 key length, key `type name`, value. Returns the name and the
/// value as text (char arrays as strings, numbers printed).
fn key_value(p: &[u8]) -> Option<(String, String)> {
    let n = *p.first()? as usize;
    let key = std::str::from_utf8(p.get(1..1 + n)?).ok()?;
    let value = p.get(1 + n..)?;
    let (ty, name) = key.split_once(' ')?;
    let text = if ty.starts_with("char") {
        String::from_utf8_lossy(value)
            .trim_end_matches('\0')
            .to_string()
    } else {
        let s = Scalar::of(ty.split('[').next().unwrap_or(ty))?;
        if value.len() < s.size() {
            return None;
        }
        let v = s.read(value);
        if matches!(s, Scalar::F32 | Scalar::F64) {
            format!("{v}")
        } else {
            format!("{}", v as i128)
        }
    };
    Some((name.to_string(), text))
}

/// Where reading can resume after unreadable bytes from `from`: just after the next sync
/// marker.
fn find_sync(b: &[u8], from: usize) -> Option<usize> {
    let rest = b.get(from..)?;
    rest.windows(SYNC_MAGIC.len())
        .position(|w| w == SYNC_MAGIC)
        .map(|i| from + i + SYNC_MAGIC.len())
}

/// At most 60 characters of `s`, control characters escaped, for messages.
fn clip(s: &str) -> String {
    let mut out: String = s.chars().take(60).collect();
    if s.chars().count() > 60 {
        out.push('…');
    }
    crate::report::escape(&out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn formats(defs: &[&str]) -> HashMap<String, Vec<RawField>> {
        let mut p = Parser::new(&[], "t.ulg", &|_| true);
        for d in defs {
            p.format(0, d.as_bytes()).unwrap();
        }
        p.formats
    }

    #[test]
    fn nested_formats_flatten_with_offsets_and_padding() {
        let f = formats(&[
            "esc:uint16_t rpm;float volt;uint8_t[2] _padding0;",
            "status:uint64_t timestamp;float[2] q;esc[2] e;uint8_t _padding1;",
        ]);
        let mut out = Vec::new();
        let (min, full) = flatten(&f, "status", "", 0, &mut out).unwrap();
        let names: Vec<_> = out.iter().map(|f| (f.name.as_str(), f.offset)).collect();
        assert_eq!(
            names,
            [
                ("timestamp", 0),
                ("q[0]", 8),
                ("q[1]", 12),
                ("e[0].rpm", 16),
                ("e[0].volt", 18),
                ("e[1].rpm", 24),
                ("e[1].volt", 26),
            ]
        );
        // The nested padding counts inside (the next element starts after it); only the
        // trailing padding of the outer format may be left out.
        assert_eq!((min, full), (32, 33));
    }

    #[test]
    fn bad_formats_are_errors_not_panics() {
        let f = formats(&["loop:loop inner;"]);
        let mut out = Vec::new();
        let e = flatten(&f, "loop", "", 0, &mut out)
            .unwrap_err()
            .to_string();
        assert!(e.contains("nested"), "{e}");
        let e = flatten(&f, "missing", "", 0, &mut out)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no format definition `missing`"), "{e}");
        // Formats of no bytes in arrays: refused at the first element, not 65 535² of them.
        let f = formats(&["e:", "f:e[65535] a;", "t:f[65535] b;"]);
        let start = std::time::Instant::now();
        let e = flatten(&f, "t", "", 0, &mut out).unwrap_err().to_string();
        assert!(
            e.contains("`f`: field `a` is of format `e`, which has no bytes"),
            "{e}"
        );
        assert!(start.elapsed() < std::time::Duration::from_secs(1));
        // Names from the file are escaped in messages.
        let e = flatten(&f, "x\x1b[2J", "", 0, &mut out)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`x\\u{1b}[2J`"), "{e}");
        let mut p = Parser::new(&[], "t.ulg", &|_| true);
        for bad in ["no colon", "x:float", "x:float[zz] a;", "x:float[70000] a;"] {
            let e = p.format(40, bad.as_bytes()).unwrap_err();
            assert!(
                e.to_string().starts_with("t.ulg: byte 40: bad format"),
                "{e}"
            );
        }
    }

    #[test]
    fn info_values() {
        let mut p = vec![12u8];
        p.extend_from_slice(b"char[4] name");
        p.extend_from_slice(b"PX4\0");
        assert_eq!(key_value(&p), Some(("name".into(), "PX4".into())));
        let mut p = vec![16u8];
        p.extend_from_slice(b"int32_t MAV_TYPE");
        p.extend_from_slice(&22i32.to_le_bytes());
        assert_eq!(key_value(&p), Some(("MAV_TYPE".into(), "22".into())));
        assert_eq!(key_value(&[200, 1, 2]), None);
        assert_eq!(key_value(&[]), None);
    }
}
