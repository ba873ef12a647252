//! PX4 ULog files: a small reader of the binary format
//! (<https://docs.px4.io/main/en/dev_log/ulog_file_format.html>), enough to pull topics out.
//!
//! A ULog file is a 16-byte header (`ULog` magic, version, start time in µs) followed by
//! messages, each `u16 size, u8 type, payload`: in the *definitions* section the flag bits
//! (`B`), the message formats (`F`, `name:type field;…`), info (`I`, `M`) and parameters (`P`,
//! `Q`); in the *data* section subscriptions (`A`: a topic instance gets a message id), data
//! (`D`: id + the packed fields), log text (`L`, `C`), dropouts (`O`), sync markers (`S`) and
//! parameter changes. Fields are packed little-endian with no alignment; nested formats are
//! flattened to names such as `q[0]` or `esc[2].rpm`; `_padding` fields take room but are not
//! fields, and trailing padding may be left out of a data message.
//!
//! [`UlogFile::parse`] reads a whole file held in memory ([`UlogFile::read`] reads it through
//! `wireflight_fsio`, so `--max-input-mb` bounds it; larger files are refused before they are
//! read), keeping the data of the wanted topics only, so memory is
//! bounded by what is used. It never panics: every length is checked before it is used, and
//! layouts are bounded ([`MAX_NESTING`], [`MAX_FIELDS`], messages ≤ 65 535 bytes).
//!
//! What is an error and what is a note:
//! * errors ([`UlogError`], naming the file, the byte offset and the topic or field): no `ULog`
//!   magic, a header or definitions section cut short, incompatible flag bits this reader does
//!   not know, a malformed format, a subscription to a wanted topic with no format;
//! * notes (counted in [`UlogFile`]): a data section cut short (a log from a vehicle that lost
//!   power ends mid-message; what came before is kept, [`UlogFile::truncated_at`]), data
//!   messages of the wrong size or for an unknown id (skipped, [`UlogFile::corrupt_messages`];
//!   after an unknown message type the reader resynchronises at the next sync marker),
//!   dropouts ([`UlogFile::dropouts`]).
//!
//! Data appended after a crash (flag bit `DATA_APPENDED`) is read as PX4 writes it: the main
//! data up to the first appended offset, then each appended block.
//!
//! Turning PX4 topics into a [`super::FlightData`] is [`super::px4`]'s job.

use std::fmt;
use std::path::Path;

mod parser;
use parser::Parser;

/// The default largest file read, bytes (1 GiB, `--max-input-mb`'s default; the option
/// governs, [`UlogFile::read`]). PX4 logs of a long flight at high rates are a few hundred MB.
pub const MAX_ULOG_BYTES: u64 = 1 << 30;

/// Deepest nesting of formats inside formats.
pub const MAX_NESTING: usize = 16;

/// Most fields (after flattening arrays and nested formats) of one topic.
pub const MAX_FIELDS: usize = 8192;

/// The file magic: `ULog` then 0x01 0x12 0x35.
pub const MAGIC: [u8; 7] = *b"ULog\x01\x12\x35";

/// The payload of a sync message.
const SYNC_MAGIC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];

/// True when `bytes` start with the ULog magic.
pub fn is_ulog(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC)
}

// ---------------------------------------------------------------------------------------------
// Errors

/// A ULog file that cannot be read: the file, where, and the problem.
///
/// Displays as `FILE: byte N: topic `T`, field `F`: PROBLEM` (the parts that are known).
#[derive(Debug)]
pub struct UlogError {
    /// The file (or the name given to [`UlogFile::parse`]).
    pub file: String,
    /// Byte offset in the file of the message involved, if any.
    pub offset: Option<usize>,
    /// The topic involved, if any.
    pub topic: Option<String>,
    /// The field involved, if any.
    pub field: Option<String>,
    /// The problem (boxed: errors travel in `Result`s that should stay small).
    pub kind: Box<UlogErrorKind>,
}

/// What is wrong, in a [`UlogError`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum UlogErrorKind {
    /// The file could not be read.
    #[error("cannot read the file: {0}")]
    Unreadable(std::io::Error),
    /// The file is larger than [`MAX_ULOG_BYTES`].
    #[error("{size} bytes is more than the {max} a ULog file may have here")]
    TooLarge {
        /// The file's size.
        size: u64,
        /// The limit.
        max: u64,
    },
    /// No ULog magic at the start.
    #[error("not a ULog file (it does not start with `ULog` and bytes 01 12 35)")]
    NotUlog,
    /// The file ends inside the header or the definitions section.
    #[error(
        "the file is cut short in the {section}: {what} needs {needed} bytes, {present} are left"
    )]
    Truncated {
        /// `header` or `definitions section`.
        section: &'static str,
        /// What was being read.
        what: String,
        /// Bytes needed.
        needed: usize,
        /// Bytes left in the file.
        present: usize,
    },
    /// Incompatible flag bits this reader does not know.
    #[error("incompatible flag bits {bits} in byte {byte} are not known to this reader: the file cannot be read safely")]
    UnknownIncompatible {
        /// The flag byte (0..8).
        byte: usize,
        /// Its unknown bits, as hex.
        bits: String,
    },
    /// A format definition that cannot be used.
    #[error("bad format: {0}")]
    BadFormat(String),
    /// A topic the caller needs is not in the file (or has no samples).
    #[error("{0}")]
    Missing(String),
    /// Values that cannot be used.
    #[error("{0}")]
    BadValues(String),
}

impl UlogError {
    /// An error about the whole file.
    pub fn file(file: &str, kind: UlogErrorKind) -> Self {
        Self {
            file: file.to_string(),
            offset: None,
            topic: None,
            field: None,
            kind: Box::new(kind),
        }
    }

    /// The same error, naming a topic.
    pub fn in_topic(mut self, topic: &str) -> Self {
        self.topic = Some(topic.to_string());
        self
    }

    /// The same error, naming a field.
    pub fn in_field(mut self, field: &str) -> Self {
        self.field = Some(field.to_string());
        self
    }

    fn at(file: &str, offset: usize, kind: UlogErrorKind) -> Self {
        Self {
            offset: Some(offset),
            ..Self::file(file, kind)
        }
    }
}

impl fmt::Display for UlogError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.file)?;
        if let Some(o) = self.offset {
            write!(f, "byte {o}: ")?;
        }
        // Topic and field names come from the file: control characters escaped.
        let esc = |s: &Option<String>| s.as_deref().map(super::report::escape);
        match (esc(&self.topic), esc(&self.field)) {
            (Some(t), Some(x)) => write!(f, "topic `{t}`, field `{x}`: ")?,
            (Some(t), None) => write!(f, "topic `{t}`: ")?,
            (None, Some(x)) => write!(f, "field `{x}`: ")?,
            (None, None) => {}
        }
        write!(f, "{}", self.kind)
    }
}

impl std::error::Error for UlogError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &*self.kind {
            UlogErrorKind::Unreadable(e) => Some(e),
            _ => None,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Types

/// The scalar types of ULog fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scalar {
    /// `int8_t`
    I8,
    /// `uint8_t`
    U8,
    /// `int16_t`
    I16,
    /// `uint16_t`
    U16,
    /// `int32_t`
    I32,
    /// `uint32_t`
    U32,
    /// `int64_t`
    I64,
    /// `uint64_t`
    U64,
    /// `float`
    F32,
    /// `double`
    F64,
    /// `bool`
    Bool,
    /// `char`
    Char,
}

impl Scalar {
    /// The scalar type of a ULog type name.
    pub fn of(name: &str) -> Option<Self> {
        Some(match name {
            "int8_t" => Self::I8,
            "uint8_t" => Self::U8,
            "int16_t" => Self::I16,
            "uint16_t" => Self::U16,
            "int32_t" => Self::I32,
            "uint32_t" => Self::U32,
            "int64_t" => Self::I64,
            "uint64_t" => Self::U64,
            "float" => Self::F32,
            "double" => Self::F64,
            "bool" => Self::Bool,
            "char" => Self::Char,
            _ => return None,
        })
    }

    /// Size in bytes.
    pub fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 | Self::Bool | Self::Char => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::I64 | Self::U64 | Self::F64 => 8,
        }
    }

    /// The value at the start of `b` (which holds at least [`size`](Self::size) bytes) as f64.
    fn read(self, b: &[u8]) -> f64 {
        let a = |n: usize| -> [u8; 8] {
            let mut x = [0u8; 8];
            x[..n].copy_from_slice(&b[..n]);
            x
        };
        match self {
            Self::I8 => b[0] as i8 as f64,
            Self::U8 | Self::Char => b[0] as f64,
            Self::Bool => (b[0] != 0) as u8 as f64,
            Self::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Self::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Self::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Self::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Self::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Self::I64 => i64::from_le_bytes(a(8)) as f64,
            Self::U64 => u64::from_le_bytes(a(8)) as f64,
            Self::F64 => f64::from_le_bytes(a(8)),
        }
    }
}

/// One field of a topic after flattening: its full name, type and byte offset.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Field {
    /// Flattened name, e.g. `q[0]`, `esc[1].rpm`.
    pub name: String,
    /// Scalar type.
    pub ty: Scalar,
    /// Byte offset in a data message's payload (after the message id).
    pub offset: usize,
}

/// One topic instance: its layout and, when kept, its samples.
#[derive(Clone, Debug)]
pub struct Topic {
    /// Topic name, e.g. `vehicle_attitude`.
    pub name: String,
    /// Instance (multi id).
    pub multi_id: u8,
    /// The fields, padding left out.
    pub fields: Vec<Field>,
    /// Bytes of a sample without trailing padding (the least a data message may carry).
    min_size: usize,
    /// Bytes of a sample with trailing padding (the most a data message may carry).
    full_size: usize,
    /// Samples read (kept or not).
    pub count: usize,
    /// Whether samples are kept.
    kept: bool,
    /// The kept samples, `min_size` bytes each.
    data: Vec<u8>,
}

impl Topic {
    /// Number of samples kept.
    pub fn len(&self) -> usize {
        self.data.len().checked_div(self.min_size).unwrap_or(0)
    }

    /// True when no samples are kept.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The field called `name`.
    pub fn field(&self, name: &str) -> Option<&Field> {
        self.fields.iter().find(|f| f.name == name)
    }

    /// Every kept sample's value of field `name`, as f64 (integers above 2⁵³ lose precision;
    /// use [`timestamps`](Self::timestamps) for times).
    pub fn values(&self, name: &str) -> Option<Vec<f64>> {
        let f = self.field(name)?.clone();
        Some(
            self.data
                .chunks_exact(self.min_size)
                .map(|s| f.ty.read(&s[f.offset..]))
                .collect(),
        )
    }

    /// Every kept sample's `timestamp` (µs since boot), exactly.
    pub fn timestamps(&self) -> Option<Vec<u64>> {
        let f = self.field("timestamp")?;
        if f.ty != Scalar::U64 {
            return None;
        }
        let o = f.offset;
        Some(
            self.data
                .chunks_exact(self.min_size)
                .map(|s| {
                    let mut b = [0u8; 8];
                    b.copy_from_slice(&s[o..o + 8]);
                    u64::from_le_bytes(b)
                })
                .collect(),
        )
    }
}

/// A ULog file read: info, parameters, topics, and what was wrong with it.
#[derive(Clone, Debug, Default)]
pub struct UlogFile {
    /// Header time stamp: when logging started, µs since boot.
    pub start_us: u64,
    /// Format version byte of the header.
    pub version: u8,
    /// Info messages (`I`): key name → value as text (strings as written, numbers printed).
    pub info: Vec<(String, String)>,
    /// Parameters (`P`) of the definitions section, with their values.
    pub params: Vec<(String, f64)>,
    /// Every topic instance subscribed, in order of subscription (kept or not).
    pub topics: Vec<Topic>,
    /// Where the data section is cut short (a message that runs past the end), if it is.
    pub truncated_at: Option<usize>,
    /// Data messages skipped: wrong size, or an id with no subscription.
    pub corrupt_messages: usize,
    /// Where reading stopped after unreadable bytes with no sync marker after them, if it did.
    pub unreadable_from: Option<usize>,
    /// Dropout messages (the logger lost data).
    pub dropouts: usize,
    /// Their total duration, ms.
    pub dropout_ms: u64,
    /// Whether data was appended after a crash.
    pub appended: bool,
}

impl UlogFile {
    /// Reads the file at `path` through [`wireflight_fsio::read_bytes`] (a regular file of at
    /// most `--max-input-mb`, [`wireflight_fsio::InputLimits`]), keeping the samples of the
    /// topics for which `keep` is true.
    ///
    /// # Errors
    /// An unreadable or too large file, and everything [`parse`](Self::parse) rejects.
    pub fn read(path: &Path, keep: impl Fn(&str) -> bool) -> Result<Self, UlogError> {
        let name = path.display().to_string();
        let bytes = wireflight_fsio::read_bytes(path)
            .map_err(|e| UlogError::file(&name, UlogErrorKind::Unreadable(e)))?;
        Self::parse(&bytes, &name, keep)
    }

    /// Parses a ULog file held in `bytes`, `file` naming it in errors, keeping the samples of
    /// the topics for which `keep` is true.
    ///
    /// # Errors
    /// See the module documentation.
    pub fn parse(bytes: &[u8], file: &str, keep: impl Fn(&str) -> bool) -> Result<Self, UlogError> {
        Parser::new(bytes, file, &keep).run()
    }

    /// The first instance (lowest multi id) of topic `name` that has samples kept.
    pub fn topic(&self, name: &str) -> Option<&Topic> {
        self.topics
            .iter()
            .filter(|t| t.name == name && !t.is_empty())
            .min_by_key(|t| t.multi_id)
    }

    /// The info value of `key` (e.g. `sys_name`, `ver_hw`).
    pub fn info(&self, key: &str) -> Option<&str> {
        self.info
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The value of parameter `name` (e.g. `MAV_TYPE`).
    pub fn param(&self, name: &str) -> Option<f64> {
        self.params.iter().find(|(k, _)| k == name).map(|(_, v)| *v)
    }
}
