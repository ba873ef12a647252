//! The ranges of flight-data values (docs/flight-data.md: positions ±1e8 m, times ±1e9 s,
//! velocities ±1e5 m/s, rates ±1e4 rad/s, throttle 0..1, surfaces ±90°, latitude ±90°,
//! longitude −180..360°, altitude −1e5..1e8 m) hold in every reader: the project's CSV, a CSV
//! through a column map, JSBSim's CSV and PX4 ULog either refuse a value beyond them (naming
//! the file, line and column where there are lines) or never let it into the [`FlightData`]
//! the model gets. The ranges here are the documented ones, written out again, not the
//! library's table.

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::path::Path;

use proptest::prelude::*;
use wireflight::data::mapped::ColumnMap;
use wireflight::data::px4::UlogOptions;
use wireflight::data::{load, FlightData, LoadOptions};

use super::{assert_ok, assert_refused, flight, run};
use crate::support::ulog::UlogWriter;

/// A documented range.
#[derive(Clone, Copy, Debug, PartialEq)]
enum R {
    Time,
    Position,
    Angle,
    Speed,
    Rate,
    Throttle,
    Surface,
    Lat,
    Lon,
    Alt,
}

impl R {
    /// The range in SI (radians for angles).
    fn range(self) -> (f64, f64) {
        match self {
            R::Time => (-1e9, 1e9),
            R::Position => (-1e8, 1e8),
            R::Angle => (-1e6, 1e6),
            R::Speed => (-1e5, 1e5),
            R::Rate => (-1e4, 1e4),
            R::Throttle => (0.0, 1.0),
            R::Surface | R::Lat => (-FRAC_PI_2, FRAC_PI_2),
            R::Lon => (-PI, TAU),
            R::Alt => (-1e5, 1e8),
        }
    }

    /// A value beyond the range: `excess` times the bound's size (at least 1) past the upper
    /// or the lower bound.
    fn beyond(self, upper: bool, excess: f64) -> f64 {
        let (lo, hi) = self.range();
        if upper {
            hi + excess * hi.abs().max(1.0)
        } else {
            lo - excess * lo.abs().max(1.0)
        }
    }

    /// A value inside the range, `u` of the way from the lower bound to the upper.
    fn inside(self, u: f64) -> f64 {
        let (lo, hi) = self.range();
        lo + u * (hi - lo)
    }
}

/// How far past a bound: just past, a little, a lot, absurdly.
fn excess() -> impl Strategy<Value = f64> {
    prop_oneof![
        1e-3..1.0f64,
        1.0..1e3f64,
        (3..300i32).prop_map(|e| 10f64.powi(e)),
    ]
}

/// Within the documented ranges: every channel the reader read (derived ones are computed
/// from these), and the metadata's origin.
fn within_ranges(d: &FlightData) -> Result<(), String> {
    let ok = |r: R, v: f64| {
        let (lo, hi) = r.range();
        let slack = 1e-9 * hi.abs().max(lo.abs()).max(1.0);
        v.is_finite() && v >= lo - slack && v <= hi + slack
    };
    let check = |what: &str, r: R, vs: &mut dyn Iterator<Item = f64>| -> Result<(), String> {
        for (i, v) in vs.enumerate() {
            if !ok(r, v) {
                return Err(format!("{what}[{i}] = {v} reached the flight data"));
            }
        }
        Ok(())
    };
    check("time", R::Time, &mut d.time.iter().copied())?;
    check(
        "pos_ned",
        R::Position,
        &mut d.pos_ned.iter().flat_map(|p| p.to_array()),
    )?;
    if let Some(a) = &d.attitude {
        check(
            "attitude",
            R::Angle,
            &mut a.iter().flat_map(|e| [e.yaw, e.pitch, e.roll]),
        )?;
    }
    for (name, v) in [("vel_ned", &d.vel_ned), ("vel_body", &d.vel_body)] {
        if let (Some(v), false) = (v, d.is_derived(name)) {
            check(name, R::Speed, &mut v.iter().flat_map(|p| p.to_array()))?;
        }
    }
    if let (Some(v), false) = (&d.rates_body, d.is_derived("rates_body")) {
        check(
            "rates_body",
            R::Rate,
            &mut v.iter().flat_map(|p| p.to_array()),
        )?;
    }
    if let Some(a) = &d.airspeed {
        check("airspeed", R::Speed, &mut a.iter().copied())?;
    }
    if let Some(c) = &d.controls {
        check("throttle", R::Throttle, &mut c.iter().map(|c| c.throttle))?;
        check(
            "surfaces",
            R::Surface,
            &mut c.iter().flat_map(|c| [c.elevator, c.aileron, c.rudder]),
        )?;
    }
    if let Some(la) = d.meta.latitude_deg {
        check("latitude_deg", R::Lat, &mut [la.to_radians()].into_iter())?;
    }
    if let Some(lo) = d.meta.longitude_deg {
        check("longitude_deg", R::Lon, &mut [lo.to_radians()].into_iter())?;
    }
    if let Some(a) = d.meta.altitude_m {
        check("altitude_m", R::Alt, &mut [a].into_iter())?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// The CSV readers

/// One column of a CSV: its header name, its range, and its factor to SI.
struct Col {
    name: &'static str,
    range: R,
    scale: f64,
}

const D: f64 = PI / 180.0;

/// The project's CSV: every column it reads.
fn wireflight_columns() -> Vec<Col> {
    let c = |name, range, scale| Col { name, range, scale };
    vec![
        c("time_s", R::Time, 1.0),
        c("north_m", R::Position, 1.0),
        c("east_m", R::Position, 1.0),
        c("down_m", R::Position, 1.0),
        c("roll_deg", R::Angle, D),
        c("pitch_rad", R::Angle, 1.0),
        c("yaw_deg", R::Angle, D),
        c("vn_mps", R::Speed, 1.0),
        c("ve_mps", R::Speed, 1.0),
        c("vd_mps", R::Speed, 1.0),
        c("u_mps", R::Speed, 1.0),
        c("v_mps", R::Speed, 1.0),
        c("w_mps", R::Speed, 1.0),
        c("p_dps", R::Rate, D),
        c("q_radps", R::Rate, 1.0),
        c("r_dps", R::Rate, D),
        c("airspeed_mps", R::Speed, 1.0),
        c("throttle", R::Throttle, 1.0),
        c("elevator_deg", R::Surface, D),
        c("aileron_rad", R::Surface, 1.0),
        c("rudder_deg", R::Surface, D),
    ]
}

/// JSBSim's CSV output: the columns read, geodetic position included.
fn jsbsim_columns() -> Vec<Col> {
    let ft = 0.3048;
    let c = |name, range, scale| Col { name, range, scale };
    vec![
        c("Time", R::Time, 1.0),
        c("/fdm/jsbsim/position/lat-geod-deg", R::Lat, D),
        c("/fdm/jsbsim/position/long-gc-rad", R::Lon, 1.0),
        c("/fdm/jsbsim/position/h-sl-ft", R::Alt, ft),
        c("/fdm/jsbsim/attitude/phi-rad", R::Angle, 1.0),
        c("/fdm/jsbsim/attitude/theta-deg", R::Angle, D),
        c("/fdm/jsbsim/attitude/psi-rad", R::Angle, 1.0),
        c("/fdm/jsbsim/velocities/p-rad_sec", R::Rate, 1.0),
        c("/fdm/jsbsim/velocities/q-rad_sec", R::Rate, 1.0),
        c("/fdm/jsbsim/velocities/r-rad_sec", R::Rate, 1.0),
        c("/fdm/jsbsim/velocities/u-fps", R::Speed, ft),
        c("/fdm/jsbsim/velocities/v-fps", R::Speed, ft),
        c("/fdm/jsbsim/velocities/w-fps", R::Speed, ft),
        c("/fdm/jsbsim/velocities/v-north-fps", R::Speed, ft),
        c("/fdm/jsbsim/velocities/v-east-fps", R::Speed, ft),
        c("/fdm/jsbsim/velocities/v-down-fps", R::Speed, ft),
        c("/fdm/jsbsim/velocities/vt-fps", R::Speed, ft),
    ]
}

/// Column maps (in units other than SI) and the columns they read, with the scales the map
/// gives them.
fn mapped_columns(geodetic: bool) -> (ColumnMap, Vec<Col>) {
    let spec = if geodetic {
        "time=t:ms,lat=la:1e-7*deg,lon=lo:deg,alt=a:ft,vn=a1:kt,ve=b1:kt,vd=c1:kt"
    } else {
        "time=t:us,north=n:ft,east=e:km,height=h:mm,roll=r:deg,pitch=p,yaw=y:deg,\
         vn=a1:kt,ve=b1,vd=c1:km/h,u=u1:ft/s,v=v1:mph,w=w1,p=pp:deg/s,q=qq,r=rr:deg/s,\
         airspeed=tas:kt,throttle=th:%,elevator=el:deg,aileron=ai,rudder=ru:deg"
    };
    let map = ColumnMap::parse(spec).unwrap();
    let range = |q: &str| match q {
        "time" => R::Time,
        "north" | "east" | "down" | "height" => R::Position,
        "lat" => R::Lat,
        "lon" => R::Lon,
        "alt" => R::Alt,
        "roll" | "pitch" | "yaw" => R::Angle,
        "p" | "q" | "r" => R::Rate,
        "throttle" => R::Throttle,
        "elevator" | "aileron" | "rudder" => R::Surface,
        _ => R::Speed,
    };
    let cols = map
        .entries
        .iter()
        .map(|e| Col {
            name: Box::leak(e.column.clone().into_boxed_str()),
            range: range(e.quantity),
            scale: e.scale,
        })
        .collect();
    (map, cols)
}

const ROWS: usize = 8;

/// A CSV of `ROWS` rows of modest values (times 0, 0.1, …; every other value 0.01 per row in
/// SI) with `cell` (in SI) in column `col`, row `row` (a time goes in the last row).
fn csv_text(cols: &[Col], col: usize, row: usize, value: f64) -> String {
    let row = if col == 0 { ROWS - 1 } else { row % ROWS };
    let mut text = cols.iter().map(|c| c.name).collect::<Vec<_>>().join(",");
    text.push('\n');
    for k in 0..ROWS {
        let cells: Vec<String> = cols
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let si = if i == col && k == row {
                    value
                } else if i == 0 {
                    0.1 * k as f64
                } else {
                    0.01 * k as f64
                };
                format!("{:e}", si / c.scale)
            })
            .collect();
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    text
}

/// Reads `text` as `name` through the loader every command uses.
fn load_text(
    dir: &Path,
    name: &str,
    bytes: &[u8],
    options: &LoadOptions,
) -> Result<FlightData, String> {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    load(&path, options)
        .map(|l| l.data)
        .map_err(|e| e.to_string())
}

/// The property for the CSV readers: a value beyond its range in column `col` is refused with
/// an error naming the file, the line and the column, or does not reach the data.
fn csv_property(
    reader: &str,
    cols: &[Col],
    map: Option<ColumnMap>,
    col: usize,
    row: usize,
    upper: bool,
    excess: f64,
) -> Result<(), TestCaseError> {
    let col = col % cols.len();
    let value = cols[col].range.beyond(upper, excess);
    let text = csv_text(cols, col, row, value);
    let dir = tempfile::tempdir().unwrap();
    let options = LoadOptions {
        columns: map,
        ..LoadOptions::default()
    };
    match load_text(dir.path(), "f.csv", text.as_bytes(), &options) {
        Err(e) => {
            let column = format!("`{}`", cols[col].name);
            prop_assert!(
                e.contains("f.csv: line ") && e.contains(&column),
                "{reader}: {} = {value:e} refused without naming the file, line and column: {e}",
                cols[col].name
            );
        }
        Ok(d) => {
            if let Err(e) = within_ranges(&d) {
                prop_assert!(
                    false,
                    "{reader}: {} = {value:e} (SI) accepted: {e}",
                    cols[col].name
                );
            }
        }
    }
    Ok(())
}

/// Values inside the ranges are read (the ranges refuse nothing a flight can have).
fn csv_inside(
    cols: &[Col],
    map: Option<ColumnMap>,
    col: usize,
    row: usize,
    u: f64,
) -> Result<(), TestCaseError> {
    let col = col % cols.len();
    let r = cols[col].range;
    // A time goes last: after the others (0.6 s), inside the range.
    let value = if col == 0 { 1.0 + u * 1e8 } else { r.inside(u) };
    let text = csv_text(cols, col, row, value);
    let dir = tempfile::tempdir().unwrap();
    let options = LoadOptions {
        columns: map,
        ..LoadOptions::default()
    };
    let result = load_text(dir.path(), "f.csv", text.as_bytes(), &options);
    prop_assert!(
        result.is_ok(),
        "{} = {value:e} (SI) refused: {:?}",
        cols[col].name,
        result.err()
    );
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// PX4 ULog

/// What a hostile ULog value is in.
#[derive(Clone, Copy, Debug)]
enum UlogField {
    /// `vehicle_local_position` x, y, z, vx, vy, vz (0..6).
    Local(usize),
    /// `vehicle_angular_velocity` xyz (0..3).
    Rates(usize),
    /// `airspeed` true_airspeed_m_s.
    Airspeed,
    /// `actuator_controls_0` control[0..4]: roll, pitch, yaw, throttle.
    Control(usize),
    /// The last local position's time stamp.
    Time,
    /// `vehicle_global_position` lat, lon (degrees, f64), alt (f32) (0..3), in a log without
    /// a local position.
    Global(usize),
}

fn ulog_field() -> impl Strategy<Value = UlogField> {
    prop_oneof![
        (0..6usize).prop_map(UlogField::Local),
        (0..3usize).prop_map(UlogField::Rates),
        Just(UlogField::Airspeed),
        (0..4usize).prop_map(UlogField::Control),
        Just(UlogField::Time),
        (0..3usize).prop_map(UlogField::Global),
    ]
}

/// A short fixed-wing log (2 s at 10 Hz of everything) with one hostile value; the value in
/// the field's own unit (f32 fields saturate at 1e30, beyond which f32 has no numbers).
fn hostile_ulog(field: UlogField, row: usize, upper: bool, excess: f64) -> (Vec<u8>, f64) {
    let surface_max = UlogOptions::default().surface_max_deg.to_radians();
    let (range, unit) = match field {
        UlogField::Local(i) if i < 3 => (R::Position, 1.0),
        UlogField::Local(_) | UlogField::Airspeed => (R::Speed, 1.0),
        UlogField::Rates(_) => (R::Rate, 1.0),
        UlogField::Control(3) => (R::Throttle, 1.0),
        UlogField::Control(_) => (R::Surface, surface_max),
        UlogField::Time => (R::Time, 1e-6),
        UlogField::Global(0) => (R::Lat, D),
        UlogField::Global(1) => (R::Lon, D),
        UlogField::Global(_) => (R::Alt, 1.0),
    };
    // Time stamps are unsigned: only past the upper bound.
    let upper = upper || matches!(field, UlogField::Time);
    let value = (range.beyond(upper, excess) / unit).clamp(-1e30, 1e30);
    let row = row % 20;
    // `value` where `f` is the hostile field and `k` its row, else `base`.
    let pick = |k: usize, f: UlogField, base: f64| -> f64 {
        let same = match (f, field) {
            (UlogField::Local(a), UlogField::Local(b))
            | (UlogField::Rates(a), UlogField::Rates(b))
            | (UlogField::Control(a), UlogField::Control(b))
            | (UlogField::Global(a), UlogField::Global(b)) => a == b,
            (UlogField::Airspeed, UlogField::Airspeed) => true,
            _ => false,
        };
        if same && k == row {
            value
        } else {
            base
        }
    };
    let mut w = UlogWriter::new(Some([0; 8]));
    let global = matches!(field, UlogField::Global(_));
    if global {
        w.format("vehicle_global_position:uint64_t timestamp;double lat;double lon;float alt;");
    } else {
        w.format(
            "vehicle_local_position:uint64_t timestamp;float x;float y;float z;float vx;float vy;float vz;",
        );
    }
    w.format("vehicle_attitude:uint64_t timestamp;float[4] q;");
    w.format("vehicle_angular_velocity:uint64_t timestamp;float[3] xyz;");
    w.format("airspeed:uint64_t timestamp;float true_airspeed_m_s;");
    w.format("actuator_controls_0:uint64_t timestamp;float[8] control;");
    w.param_i32("MAV_TYPE", 1);
    let p = w.subscribe(if global {
        "vehicle_global_position"
    } else {
        "vehicle_local_position"
    });
    let a = w.subscribe("vehicle_attitude");
    let g = w.subscribe("vehicle_angular_velocity");
    let s = w.subscribe("airspeed");
    let c = w.subscribe("actuator_controls_0");
    for k in 0..20usize {
        let t = 1_000_000 + k as u64 * 100_000;
        // A hostile time is the last position's (µs; `as` saturates).
        let tp = if matches!(field, UlogField::Time) && k == 19 {
            value as u64
        } else {
            t
        };
        let base = 0.01 * k as f64;
        if global {
            let mut m = p.to_le_bytes().to_vec();
            m.extend_from_slice(&tp.to_le_bytes());
            m.extend_from_slice(&pick(k, UlogField::Global(0), 45.0 + base * 1e-3).to_le_bytes());
            m.extend_from_slice(&pick(k, UlogField::Global(1), 7.0 + base * 1e-3).to_le_bytes());
            m.extend_from_slice(
                &(pick(k, UlogField::Global(2), 100.0 + base) as f32).to_le_bytes(),
            );
            w.message(b'D', &m);
        } else {
            let f: Vec<f32> = (0..6)
                .map(|i| pick(k, UlogField::Local(i), base) as f32)
                .collect();
            w.data_f32(p, tp, &f);
        }
        w.data_f32(a, t, &[1.0, 0.0, 0.0, 0.0]);
        let f: Vec<f32> = (0..3)
            .map(|i| pick(k, UlogField::Rates(i), base) as f32)
            .collect();
        w.data_f32(g, t, &f);
        w.data_f32(s, t, &[pick(k, UlogField::Airspeed, 20.0 + base) as f32]);
        let mut f: Vec<f32> = (0..4)
            .map(|i| pick(k, UlogField::Control(i), 0.5 * base) as f32)
            .collect();
        f.extend_from_slice(&[0.0; 4]);
        w.data_f32(c, t, &f);
    }
    (w.bytes, value)
}

// ---------------------------------------------------------------------------------------------
// The properties

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 96,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn the_projects_csv_refuses_values_beyond_the_ranges(
        col in 0..64usize, row in 0..ROWS, upper: bool, excess in excess(),
    ) {
        csv_property("project CSV", &wireflight_columns(), None, col, row, upper, excess)?;
    }

    #[test]
    fn jsbsim_csv_refuses_values_beyond_the_ranges(
        col in 0..64usize, row in 0..ROWS, upper: bool, excess in excess(),
    ) {
        csv_property("JSBSim CSV", &jsbsim_columns(), None, col, row, upper, excess)?;
    }

    #[test]
    fn column_maps_refuse_values_beyond_the_ranges(
        geodetic: bool, col in 0..64usize, row in 0..ROWS, upper: bool, excess in excess(),
    ) {
        let (map, cols) = mapped_columns(geodetic);
        csv_property("column map", &cols, Some(map), col, row, upper, excess)?;
    }

    #[test]
    fn ulog_never_lets_values_beyond_the_ranges_into_the_data(
        field in ulog_field(), row in 0..20usize, upper: bool, excess in excess(),
    ) {
        let (bytes, value) = hostile_ulog(field, row, upper, excess);
        let dir = tempfile::tempdir().unwrap();
        match load_text(dir.path(), "f.ulg", &bytes, &LoadOptions::default()) {
            Err(e) => prop_assert!(e.contains("f.ulg"), "{field:?} = {value:e}: {e}"),
            Ok(d) => {
                if let Err(e) = within_ranges(&d) {
                    prop_assert!(false, "ULog {field:?} = {value:e} accepted: {e}");
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 48,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn the_csv_readers_accept_values_inside_the_ranges(
        reader in 0..4usize, col in 0..64usize, row in 0..ROWS, u in 0.001..0.999f64,
    ) {
        match reader {
            0 => csv_inside(&wireflight_columns(), None, col, row, u)?,
            1 => csv_inside(&jsbsim_columns(), None, col, row, u)?,
            _ => {
                let (map, cols) = mapped_columns(reader == 3);
                csv_inside(&cols, Some(map), col, row, u)?;
            }
        }
    }
}

/// The ULog property's logs are read when the value is inside its range (so the property
/// tests the value, not a log the reader refuses anyway). Not the global position's: a
/// longitude half-way up its range is a jump whose derived velocity is refused.
#[test]
fn the_hostile_ulogs_load_with_values_inside_the_ranges() {
    let dir = tempfile::tempdir().unwrap();
    for field in [
        UlogField::Local(0),
        UlogField::Local(4),
        UlogField::Rates(1),
        UlogField::Airspeed,
        UlogField::Control(1),
        UlogField::Control(3),
    ] {
        // Half-way back from the upper bound: inside.
        let (bytes, value) = hostile_ulog(field, 5, true, -0.5);
        let d = load_text(dir.path(), "f.ulg", &bytes, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{field:?} = {value}: {e}"));
        within_ranges(&d).unwrap();
        assert!(d.controls.is_some() && d.len() > 10, "{field:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// The command line

/// The examples of the issue, through the binary: mapped cells of 1e300, times of 1e12 s and
/// longitudes of 1e6° are refused as the project's CSV refuses them.
#[test]
fn column_maps_refuse_what_the_projects_csv_refuses() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases = [
        (
            "t,x,y,z\n0,0,0,0\n1,1e300,0,0\n",
            "time=t,north=x,east=y,down=z",
            "`x`",
            "±1e8 m",
        ),
        (
            "t,x,y,z\n0,0,0,0\n1e18,1,0,0\n",
            "time=t:us,north=x,east=y,down=z",
            "`t`",
            "±1e9 s",
        ),
        (
            "t,la,lo,h\n0,10,1e6,0\n1,10,7,0\n",
            "time=t,lat=la:deg,lon=lo:deg,alt=h",
            "`lo`",
            "-180°..360°",
        ),
    ];
    for (text, map, column, range) in cases {
        std::fs::write(d.join("m.csv"), text).unwrap();
        let o = run(
            &[
                "import",
                "--flight",
                "m.csv",
                "--columns",
                map,
                "--out",
                "x.csv",
            ],
            d,
        );
        assert_refused(&o, &["m.csv", "line ", column, range]);
        assert!(!d.join("x.csv").exists());
    }
}

#[test]
fn surface_max_is_within_the_surfaces_range() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = crate::support::data_file("px4-sitl-hop.ulg");
    let log = log.to_str().unwrap();
    for v in ["1000", "90.5", "0", "-5"] {
        let o = run(
            &[
                "import",
                "--flight",
                log,
                "--surface-max",
                v,
                "--out",
                "x.csv",
            ],
            d,
        );
        assert_refused(&o, &["--surface-max"]);
    }
    let o = run(
        &[
            "import",
            "--flight",
            log,
            "--surface-max",
            "1000",
            "--out",
            "x.csv",
        ],
        d,
    );
    assert_refused(&o, &["±90°"]);
    assert_ok(&run(
        &[
            "import",
            "--flight",
            log,
            "--surface-max",
            "90",
            "--out",
            "x.csv",
        ],
        d,
    ));
}

#[test]
fn resample_is_refused_for_a_csv_not_ignored() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    flight(d, "a.csv", &[]);
    let o = run(
        &[
            "import",
            "--flight",
            "a.csv",
            "--resample",
            "10",
            "--out",
            "x.csv",
        ],
        d,
    );
    assert_refused(&o, &["a.csv", "--resample", "PX4 ULog"]);
    std::fs::write(d.join("m.csv"), "t,x,y,z\n0,0,0,0\n1,1,0,0\n").unwrap();
    let o = run(
        &[
            "import",
            "--flight",
            "m.csv",
            "--columns",
            "time=t,north=x,east=y,down=z",
            "--resample",
            "10",
            "--out",
            "x.csv",
        ],
        d,
    );
    assert_refused(&o, &["m.csv", "--resample"]);
    assert!(!d.join("x.csv").exists());
}

#[test]
fn cr_line_endings_are_line_ends() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = flight(d, "a.csv", &[]);
    let text = std::fs::read_to_string(&a).unwrap();
    std::fs::write(d.join("cr.csv"), text.replace('\n', "\r")).unwrap();
    let o = run(&["import", "--flight", "cr.csv", "--out", "x.csv"], d);
    assert_ok(&o);
    assert_ok(&run(&["import", "--flight", "a.csv", "--out", "y.csv"], d));
    assert_eq!(
        std::fs::read_to_string(d.join("x.csv")).unwrap(),
        std::fs::read_to_string(d.join("y.csv")).unwrap(),
    );
    // An error in a CR file names the line as an editor shows it.
    let bad = text.replacen("\n0.02,", "\nx,", 1);
    let line = bad.lines().position(|l| l.starts_with("x,")).unwrap() + 1;
    std::fs::write(d.join("bad.csv"), bad.replace('\n', "\r")).unwrap();
    let o = run(&["import", "--flight", "bad.csv", "--out", "b.csv"], d);
    assert_refused(
        &o,
        &[
            "bad.csv",
            &format!("line {line}"),
            "time_s",
            "not a number: `x`",
        ],
    );
    // Through a column map too.
    std::fs::write(d.join("m.csv"), "t,x,y,z\r0,0,0,0\r1,1,0,0\r2,2,0,0\r").unwrap();
    assert_ok(&run(
        &[
            "import",
            "--flight",
            "m.csv",
            "--columns",
            "time=t,north=x,east=y,down=z",
            "--out",
            "z.csv",
        ],
        d,
    ));
}

/// A simulated flight ends where it reaches the ground (the origin's altitude), with a note,
/// instead of flying on below it: none of its samples but the last is under the ground.
#[test]
fn a_simulated_flight_ends_on_the_ground() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for args in [
        ["--height", "1", "--rate", "50"],
        ["--height", "200", "--rate", "0.5"],
    ] {
        let mut line = vec![
            "simulate",
            "--manoeuvre",
            "flight-test",
            "--duration",
            "600",
        ];
        line.extend(args);
        line.extend(["--out", "low.csv"]);
        let o = run(&line, d);
        assert_ok(&o);
        assert!(
            crate::support::cli::stderr(&o)
                .contains("reached the ground (the origin's altitude, 0 m)"),
            "{args:?}: {}",
            crate::support::cli::stderr(&o)
        );
        let f = wireflight::data::read(&d.join("low.csv")).unwrap();
        let n = f.len();
        assert!(f.duration() < 600.0, "{args:?}");
        assert!(f.pos_ned[..n - 1].iter().all(|p| p.z <= 0.0), "{args:?}");
        assert!(f.pos_ned[n - 1].z > 0.0, "{args:?}");
    }
}
