//! One function per loader fuzz target: feed it bytes, it must return (an error is fine) and
//! never panic, hang or allocate without bound; what loads must keep the type's promises.
//!
//! Shared by the fuzz targets (`fuzz_targets/*.rs`, whose library this file is) and the corpus
//! replay test (`tests/it/fuzz_corpus.rs`, stable), which includes it by path. It names the
//! library crates by their own names (`wireflight_data`, `wireflight_flight`,
//! `wireflight_draw`, `wireflight_geometry`) and `glam`: both the fuzz crate and the root
//! package depend on them, so the same paths resolve in both.

use std::path::Path;

use wireflight_data::parse as parse_flight_data;
use wireflight_draw::flythrough::script::parse as parse_script;
use wireflight_draw::mesh_files::{gltf::parse as parse_gltf, obj::parse as parse_obj};
use wireflight_flight::effects::Origin;
use wireflight_flight::model::{Model, Vehicle};
use wireflight_flight::params::FixedWingParams;
use wireflight_flight::spec::ModelSpec;
use wireflight_flight::trim::trim_level;
use wireflight_geometry::mesh::EdgeMesh;

/// Text as a loader sees it after reading a file (lossy, as for OBJ; the strict readers reject
/// non-UTF-8 before parsing, so this only widens what the parsers are shown).
fn text(data: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(data)
}

/// Flight-data CSV: parse (derives missing channels); what loads validates.
pub fn csv(data: &[u8]) {
    if let Ok(d) = parse_flight_data(&text(data), "fuzz.csv") {
        assert!(!d.is_empty());
        d.validate().expect("parsed data validate");
        let _ = d.controls_at(d.duration() * 0.5);
    }
}

/// An edge mesh keeps its promises: at least one edge, finite positions, indices in range.
fn check_mesh(m: &EdgeMesh) {
    assert!(!m.edges().is_empty());
    assert!(m.positions().iter().all(|p| p.is_finite()));
    let n = m.positions().len() as u32;
    assert!(m.edges().iter().all(|&[a, b]| a < n && b < n && a != b));
}

/// Wavefront OBJ.
pub fn obj(data: &[u8]) {
    if let Ok(m) = parse_obj(data, Path::new("fuzz.obj")) {
        check_mesh(&m);
    }
}

/// glTF (JSON) or GLB; external URIs resolve under a directory that does not exist.
pub fn gltf(data: &[u8]) {
    let path = Path::new("/nonexistent-wireflight-fuzz/model.gltf");
    if let Ok(m) = parse_gltf(data, path) {
        check_mesh(&m);
    }
}

/// A model file (TOML): parse, then build (which loads a named parameter set and checks every
/// effect parameter).
pub fn model_toml(data: &[u8]) {
    if let Ok(spec) = ModelSpec::from_toml(&text(data)) {
        let _ = spec.build(Origin::default());
    }
}

/// A fixed-wing parameter set (TOML): parse, then trim the aircraft in level flight.
pub fn params_toml(data: &[u8]) {
    if let Ok(p) = FixedWingParams::from_toml(&text(data), "fuzz.toml") {
        let model = Model::new(Vehicle::FixedWing(Box::new(p)), Origin::default());
        let _ = trim_level(&model, 25.0, 0.0, glam::DVec3::new(0.0, 0.0, -100.0));
    }
}

/// The fly-through window's control script.
pub fn script(data: &[u8]) {
    let _ = parse_script(&text(data), "fuzz.txt");
}

/// CSV through a column map, as `--columns` reads it: the bytes before the first NUL are the
/// map (TOML when they hold a `[columns]` table, else the inline form), the rest the CSV. What
/// loads validates, keeps the documented ranges (times ±1e9 s; positions ±1e8 m, or a
/// flat-earth conversion of in-range latitudes, longitudes and altitudes), and reports.
pub fn column_map(data: &[u8]) {
    use wireflight_data::mapped::{parse as parse_mapped, ColumnMap};
    let (map, csv) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[][..]),
    };
    let map = text(map);
    let map = if map.contains("[columns]") {
        ColumnMap::from_toml(&map)
    } else {
        ColumnMap::parse(&map)
    };
    let Ok(map) = map else { return };
    if let Ok((d, report)) = parse_mapped(&text(csv), "fuzz.csv", &map) {
        assert!(!d.is_empty());
        d.validate().expect("column-mapped data validate");
        assert_within_ranges(&d);
        let _ = d.controls_at(d.duration() * 0.5);
        let _ = report.to_string();
    }
}

/// PX4 ULog, as `import` reads it (`UlogFile::parse` keeping the PX4 topics, then
/// `px4::from_ulog`, which `px4::read` and `data::load` run on the file's bytes). What loads
/// validates, keeps the documented ranges, is not longer than the bound derived from the
/// input (100 samples per position or attitude sample, each at least a 13-byte message, or
/// 10 000), writes as CSV that reads back, and reports with no control characters.
pub fn ulog(data: &[u8]) {
    use wireflight_data::px4::{self, UlogOptions};
    use wireflight_data::ulog::UlogFile;
    let Ok(log) = UlogFile::parse(data, "fuzz.ulg", |t| px4::TOPICS.contains(&t)) else {
        return;
    };
    let Ok((d, report)) = px4::from_ulog(&log, "fuzz.ulg", &UlogOptions::default()) else {
        return;
    };
    assert!(d.len() >= 2);
    d.validate().expect("ULog data validate");
    let bound = (px4::MAX_SAMPLES_PER_SAMPLE * (data.len() / 13)).max(px4::MIN_SAMPLES_BOUND);
    assert!(
        d.len() <= bound,
        "{} samples from {} bytes",
        d.len(),
        data.len()
    );
    assert_within_ranges(&d);
    let _ = d.controls_at(d.duration() * 0.5);
    // `import --out` writes what was read: the CSV reader takes it back.
    let csv = wireflight_data::to_csv_string(&d);
    if let Err(e) = parse_flight_data(&csv, "fuzz.csv") {
        panic!("ULog data that would not read back: {e}");
    }
    let text = report.to_string();
    assert!(
        !text.chars().any(|c| c.is_control() && c != '\n'),
        "{text:?}"
    );
}

/// A structure-aware ULog: the fuzzer's bytes choose a valid header, flag bits, format
/// definitions (the PX4 topics the reader wants, and hostile nested and empty formats with
/// array lengths from the input), info and parameters, subscriptions, then data messages
/// whose time stamps step forward, repeat, go back or jump, with sane, special (NaN, ∞, 1e30,
/// 0) or raw values, among dropouts, sync markers, log text, unknown or cut messages and
/// unsubscriptions; then [`ulog`] reads it.
pub fn ulog_structured(data: &[u8]) {
    ulog(&ulog_from_bytes(data));
}

/// The fuzzer's bytes as a stream of choices (zeros when they run out).
struct Choices<'a>(&'a [u8]);

impl Choices<'_> {
    fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    fn u64(&mut self) -> u64 {
        u64::from(self.u32()) | (u64::from(self.u32()) << 32)
    }
    fn take(&mut self, n: usize) -> &[u8] {
        let n = n.min(self.0.len());
        let (a, b) = self.0.split_at(n);
        self.0 = b;
        a
    }
    fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// The ULog built from `data` by [`ulog_structured`] (public for seeds and tests).
pub fn ulog_from_bytes(data: &[u8]) -> Vec<u8> {
    // (format, the types of the fields after `timestamp`: b'f' f32, b'd' f64, b'i' i32, b'b' u8)
    const TOPICS: [(&str, &[u8]); 10] = [
        (
            "vehicle_local_position:uint64_t timestamp;float x;float y;float z;float vx;float vy;\
             float vz;double ref_lat;double ref_lon;float ref_alt;bool xy_global;bool xy_valid;\
             uint8_t xy_reset_counter;uint8_t[5] _padding0;",
            b"ffffffddfbbb",
        ),
        ("vehicle_attitude:uint64_t timestamp;float[4] q;", b"ffff"),
        (
            "vehicle_global_position:uint64_t timestamp;double lat;double lon;float alt;",
            b"ddf",
        ),
        (
            "vehicle_gps_position:uint64_t timestamp;int32_t lat;int32_t lon;int32_t alt;",
            b"iii",
        ),
        (
            "vehicle_angular_velocity:uint64_t timestamp;float[3] xyz;",
            b"fff",
        ),
        ("airspeed:uint64_t timestamp;float true_airspeed_m_s;", b"f"),
        (
            "actuator_controls_0:uint64_t timestamp;float[8] control;",
            b"ffffffff",
        ),
        (
            "vehicle_torque_setpoint:uint64_t timestamp;float[3] xyz;",
            b"fff",
        ),
        (
            "vehicle_thrust_setpoint:uint64_t timestamp;float[3] xyz;",
            b"fff",
        ),
        (
            "actuator_outputs:uint64_t timestamp;float[4] output;",
            b"ffff",
        ),
    ];
    let mut c = Choices(data);
    let mut out = b"ULog\x01\x12\x35".to_vec();
    out.push(c.u8() & 1);
    let start = match c.u8() % 4 {
        0 => 0,
        1 => 1_000_000,
        2 => u64::from(c.u32()),
        _ => c.u64(),
    };
    out.extend_from_slice(&start.to_le_bytes());
    let msg = |out: &mut Vec<u8>, kind: u8, p: &[u8]| {
        let p = &p[..p.len().min(usize::from(u16::MAX))];
        out.extend_from_slice(&(p.len() as u16).to_le_bytes());
        out.push(kind);
        out.extend_from_slice(p);
    };
    let flags = c.u8();
    if flags & 1 != 0 {
        let mut p = vec![0u8; 40];
        p[8] = flags >> 7; // DATA_APPENDED, sometimes
        if flags & 2 != 0 {
            p[8 + usize::from(c.u8() % 8)] |= c.u8(); // unknown incompatible bits
        }
        let off = u64::from(c.u16()) * 4;
        p[16..24].copy_from_slice(&off.to_le_bytes());
        msg(&mut out, b'B', &p);
    }
    // Info and parameters.
    if flags & 4 != 0 {
        let n = usize::from(c.u8() % 24);
        let name = c.take(n).to_vec();
        let key = format!("char[{}] sys_name", name.len());
        let mut p = vec![key.len() as u8];
        p.extend_from_slice(key.as_bytes());
        p.extend_from_slice(&name);
        msg(&mut out, b'I', &p);
    }
    if flags & 8 != 0 {
        let key = b"int32_t MAV_TYPE";
        let mut p = vec![key.len() as u8];
        p.extend_from_slice(key);
        p.extend_from_slice(&i32::from(c.u8() % 24).to_le_bytes());
        msg(&mut out, b'P', &p);
    }
    // Formats: which PX4 topics, then hostile nested ones.
    let wanted = c.u16();
    let mut topics: Vec<(String, Vec<u8>)> = Vec::new();
    for (i, (def, types)) in TOPICS.iter().enumerate() {
        if wanted & (1 << i) != 0 {
            msg(&mut out, b'F', def.as_bytes());
            let name = def.split(':').next().unwrap_or_default().to_string();
            topics.push((name, types.to_vec()));
        }
    }
    for k in 0..usize::from(c.u8() % 4) {
        let def = match c.u8() % 4 {
            0 => format!("n{k}:"),
            1 => format!("n{k}:float a;n{}[{}] b;", k.wrapping_sub(1), c.u16()),
            2 => format!("n{k}:n{}[{}] a;", k.wrapping_sub(1), c.u16()),
            _ => format!("n{k}:uint8_t[{}] a;n{k} self;", c.u16()),
        };
        msg(&mut out, b'F', def.as_bytes());
        if c.u8() & 1 != 0 {
            topics.push((format!("n{k}"), Vec::new()));
        }
    }
    // Subscriptions.
    for (id, (name, _)) in topics.iter().enumerate() {
        let mut p = vec![0u8];
        p.extend_from_slice(&(id as u16).to_le_bytes());
        p.extend_from_slice(name.as_bytes());
        msg(&mut out, b'A', &p);
    }
    if topics.is_empty() {
        return out;
    }
    // Data.
    let mut time: Vec<u64> = vec![start.wrapping_add(1_000_000); topics.len()];
    let mut steps = 0;
    while !c.is_empty() && steps < 20_000 {
        steps += 1;
        let op = c.u8();
        let id = usize::from(c.u8()) % topics.len();
        match op % 16 {
            0..=10 => {
                let dt: i64 = match c.u8() % 16 {
                    0 => 0,
                    1 => -i64::from(c.u16()),
                    2 => i64::from(c.u32()) << 8,
                    3 => c.u64() as i64,
                    _ => 10_000 + i64::from(c.u8()) * 100,
                };
                time[id] = time[id].wrapping_add(dt as u64);
                let mut p = (id as u16).to_le_bytes().to_vec();
                p.extend_from_slice(&time[id].to_le_bytes());
                let special = c.u8();
                for (j, ty) in topics[id].1.iter().enumerate() {
                    let sane = f64::from(c.u8() as i8) / 16.0 + j as f64 * 0.01;
                    let v = match (special >> (j % 8)) & 1 {
                        0 => sane,
                        _ => match c.u8() % 6 {
                            0 => f64::NAN,
                            1 => f64::INFINITY,
                            2 => 1e30,
                            3 => 0.0,
                            4 => -1e250,
                            _ => f64::from(f32::from_bits(c.u32())),
                        },
                    };
                    match ty {
                        b'f' => p.extend_from_slice(&(v as f32).to_le_bytes()),
                        b'd' => p.extend_from_slice(&(v * 1000.0).to_le_bytes()),
                        b'i' => p.extend_from_slice(&((v * 1e7) as i32).to_le_bytes()),
                        _ => p.push(v as u8),
                    }
                }
                if op & 0x80 != 0 {
                    p.truncate(p.len().saturating_sub(usize::from(c.u8() % 4)));
                }
                msg(&mut out, b'D', &p);
            }
            11 => msg(&mut out, b'O', &c.u16().to_le_bytes()),
            12 => msg(
                &mut out,
                b'S',
                &[0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12],
            ),
            13 => {
                let n = usize::from(c.u8() % 32);
                let mut p = vec![6u8];
                p.extend_from_slice(&c.u64().to_le_bytes());
                p.extend_from_slice(c.take(n));
                msg(&mut out, b'L', &p);
            }
            14 => {
                let kind = c.u8();
                let n = usize::from(c.u8() % 16);
                let p = c.take(n).to_vec();
                msg(&mut out, kind, &p);
            }
            _ => {
                // Unsubscribe, or a message cut short at the end.
                if op & 0x80 != 0 {
                    msg(&mut out, b'R', &(id as u16).to_le_bytes());
                } else {
                    out.extend_from_slice(&[0xff, 0x00, b'D', 0]);
                    break;
                }
            }
        }
    }
    out
}

/// What every reader promises of the data it lets through: times within ±1e9 s, positions
/// within ±2e8 m, commands within their ranges (throttle 0..1, surfaces ±90°).
fn assert_within_ranges(d: &wireflight_data::FlightData) {
    assert!(d.time.iter().all(|t| t.abs() <= 1e9), "time out of range");
    assert!(
        d.pos_ned.iter().all(|p| p.abs().max_element() <= 2e8),
        "position out of range"
    );
    if let Some(c) = &d.controls {
        assert!(c.iter().all(|c| (0.0..=1.0).contains(&c.throttle)
            && [c.elevator, c.aileron, c.rudder]
                .iter()
                .all(|s| s.abs() <= std::f64::consts::FRAC_PI_2)));
    }
}
