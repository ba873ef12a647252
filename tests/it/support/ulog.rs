//! A minimal ULog writer for tests: formats, subscriptions, data, in file order, with no
//! validation (so broken files can be made too).

/// Bytes of a ULog file under construction.
pub struct UlogWriter {
    /// The file so far.
    pub bytes: Vec<u8>,
    next_id: u16,
}

impl UlogWriter {
    /// A header (magic, version 1, start time 0) and, if `flags`, a flag-bits message with
    /// these incompatible flags.
    pub fn new(incompat: Option<[u8; 8]>) -> Self {
        let mut bytes = b"ULog\x01\x12\x35\x01".to_vec();
        bytes.extend_from_slice(&0u64.to_le_bytes());
        let mut w = Self { bytes, next_id: 0 };
        if let Some(flags) = incompat {
            let mut p = vec![0u8; 8];
            p.extend_from_slice(&flags);
            p.extend_from_slice(&[0u8; 24]);
            w.message(b'B', &p);
        }
        w
    }

    /// One message of `kind` with `payload`.
    pub fn message(&mut self, kind: u8, payload: &[u8]) {
        self.bytes
            .extend_from_slice(&(payload.len() as u16).to_le_bytes());
        self.bytes.push(kind);
        self.bytes.extend_from_slice(payload);
    }

    /// A format: `name:type field;…`.
    pub fn format(&mut self, def: &str) {
        self.message(b'F', def.as_bytes());
    }

    /// An int32 parameter.
    pub fn param_i32(&mut self, name: &str, v: i32) {
        let key = format!("int32_t {name}");
        let mut p = vec![key.len() as u8];
        p.extend_from_slice(key.as_bytes());
        p.extend_from_slice(&v.to_le_bytes());
        self.message(b'P', &p);
    }

    /// A string info message (`I`, `char[N] key`).
    pub fn info_str(&mut self, key: &str, value: &str) {
        let k = format!("char[{}] {key}", value.len());
        let mut p = vec![k.len() as u8];
        p.extend_from_slice(k.as_bytes());
        p.extend_from_slice(value.as_bytes());
        self.message(b'I', &p);
    }

    /// Subscribes instance 0 of `topic`; returns its message id.
    pub fn subscribe(&mut self, topic: &str) -> u16 {
        let id = self.next_id;
        self.next_id += 1;
        let mut p = vec![0u8];
        p.extend_from_slice(&id.to_le_bytes());
        p.extend_from_slice(topic.as_bytes());
        self.message(b'A', &p);
        id
    }

    /// A data message: the time stamp (µs) then f32 fields.
    pub fn data_f32(&mut self, id: u16, t_us: u64, fields: &[f32]) {
        let mut p = id.to_le_bytes().to_vec();
        p.extend_from_slice(&t_us.to_le_bytes());
        for f in fields {
            p.extend_from_slice(&f.to_le_bytes());
        }
        self.message(b'D', &p);
    }

    /// A data message: the time stamp (µs) then f64 fields.
    pub fn data_f64(&mut self, id: u16, t_us: u64, fields: &[f64]) {
        let mut p = id.to_le_bytes().to_vec();
        p.extend_from_slice(&t_us.to_le_bytes());
        for f in fields {
            p.extend_from_slice(&f.to_le_bytes());
        }
        self.message(b'D', &p);
    }
}
