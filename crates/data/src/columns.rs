//! The column tables of flight-data CSV: the wireflight column names with their units, the
//! JSBSim output columns understood ([`JSBSIM_COLUMNS`]), which dialect a header is written
//! in, and how a missing column is named in errors.
//!
//! These tables are the vocabulary of the format, kept apart from the reader's control flow
//! ([`super::read`]) so that adding or renaming a column is an edit to this file alone.

use std::f64::consts::PI;

use super::{METRES_PER_FOOT, MPS_PER_KNOT};

/// The JSBSim output column names understood, with the quantity each gives. Property names may
/// be written with or without the `/fdm/jsbsim/` prefix; where several give one quantity, the
/// earlier in this list wins. The last entries are captions of JSBSim's built-in output groups.
pub const JSBSIM_COLUMNS: &[(&str, &str)] = &[
    ("Time", "time, s"),
    ("/fdm/jsbsim/simulation/sim-time-sec", "time, s"),
    ("/fdm/jsbsim/position/lat-geod-rad", "latitude, rad"),
    ("/fdm/jsbsim/position/lat-geod-deg", "latitude, deg"),
    (
        "/fdm/jsbsim/position/lat-gc-rad",
        "latitude (geocentric), rad",
    ),
    (
        "/fdm/jsbsim/position/lat-gc-deg",
        "latitude (geocentric), deg",
    ),
    ("/fdm/jsbsim/position/long-gc-rad", "longitude, rad"),
    ("/fdm/jsbsim/position/long-gc-deg", "longitude, deg"),
    (
        "/fdm/jsbsim/position/h-sl-meters",
        "height above sea level, m",
    ),
    ("/fdm/jsbsim/position/h-sl-ft", "height above sea level, ft"),
    ("/fdm/jsbsim/attitude/phi-rad", "roll, rad"),
    ("/fdm/jsbsim/attitude/phi-deg", "roll, deg"),
    ("/fdm/jsbsim/attitude/roll-rad", "roll, rad"),
    ("/fdm/jsbsim/attitude/theta-rad", "pitch, rad"),
    ("/fdm/jsbsim/attitude/theta-deg", "pitch, deg"),
    ("/fdm/jsbsim/attitude/pitch-rad", "pitch, rad"),
    ("/fdm/jsbsim/attitude/psi-rad", "yaw, rad"),
    ("/fdm/jsbsim/attitude/psi-deg", "yaw, deg"),
    ("/fdm/jsbsim/attitude/heading-true-rad", "yaw, rad"),
    ("/fdm/jsbsim/velocities/p-rad_sec", "roll rate p, rad/s"),
    ("/fdm/jsbsim/velocities/q-rad_sec", "pitch rate q, rad/s"),
    ("/fdm/jsbsim/velocities/r-rad_sec", "yaw rate r, rad/s"),
    ("/fdm/jsbsim/velocities/u-fps", "body u, ft/s"),
    ("/fdm/jsbsim/velocities/v-fps", "body v, ft/s"),
    ("/fdm/jsbsim/velocities/w-fps", "body w, ft/s"),
    ("/fdm/jsbsim/velocities/v-north-fps", "north velocity, ft/s"),
    ("/fdm/jsbsim/velocities/v-east-fps", "east velocity, ft/s"),
    ("/fdm/jsbsim/velocities/v-down-fps", "down velocity, ft/s"),
    ("/fdm/jsbsim/velocities/vt-fps", "true airspeed, ft/s"),
    ("/fdm/jsbsim/velocities/vtrue-kts", "true airspeed, kt"),
    ("Latitude Geodetic (deg)", "latitude, deg"),
    ("Latitude (deg)", "latitude (geocentric), deg"),
    ("Longitude (deg)", "longitude, deg"),
    ("Altitude ASL (ft)", "height above sea level, ft"),
    ("Phi (deg)", "roll, deg"),
    ("Theta (deg)", "pitch, deg"),
    ("Psi (deg)", "yaw, deg"),
    ("P (deg/s)", "roll rate p, deg/s"),
    ("Q (deg/s)", "pitch rate q, deg/s"),
    ("R (deg/s)", "yaw rate r, deg/s"),
    ("V_{North} (ft/s)", "north velocity, ft/s"),
    ("V_{East} (ft/s)", "east velocity, ft/s"),
    ("V_{Down} (ft/s)", "down velocity, ft/s"),
];

/// Quantities a column can give (the variants index per-quantity arrays of length
/// [`N_QUANTITIES`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Quantity {
    Time,
    North,
    East,
    Down,
    Roll,
    Pitch,
    Yaw,
    Vn,
    Ve,
    Vd,
    U,
    V,
    W,
    P,
    Q,
    R,
    Airspeed,
    Throttle,
    Elevator,
    Aileron,
    Rudder,
    Lat,
    Lon,
    Alt,
    Ax,
    Ay,
    Az,
}

impl Quantity {
    /// The values a cell of this quantity may hold, in SI units (after the column's scale),
    /// and the range as the error message states it. Beyond these the numbers are not a
    /// flight (and would overflow the analysis: squares of 1e200 are infinite).
    ///
    /// This table is the one source of the ranges: every reader (the project's and JSBSim's
    /// CSV in `read.rs`, column maps in `mapped/reader.rs`, PX4 ULog in `px4`) checks the
    /// values it takes against it where they enter, and `docs/flight-data.md` states it.
    pub(super) fn range(self) -> (f64, f64, &'static str) {
        use std::f64::consts::{FRAC_PI_2, PI, TAU};
        use Quantity as Q;
        match self {
            Q::Time => (-1e9, 1e9, "±1e9 s"),
            Q::North | Q::East | Q::Down => (-1e8, 1e8, "±1e8 m"),
            Q::Roll | Q::Pitch | Q::Yaw => (-1e6, 1e6, "±1e6 rad (unwrapped angles)"),
            Q::Vn | Q::Ve | Q::Vd | Q::U | Q::V | Q::W | Q::Airspeed => (-1e5, 1e5, "±1e5 m/s"),
            Q::P | Q::Q | Q::R => (-1e4, 1e4, "±1e4 rad/s"),
            Q::Throttle => (0.0, 1.0, "0..1"),
            Q::Elevator | Q::Aileron | Q::Rudder => (-FRAC_PI_2, FRAC_PI_2, "±90°"),
            Q::Lat => (-FRAC_PI_2, FRAC_PI_2, "±90°"),
            Q::Lon => (-PI, TAU, "-180°..360°"),
            Q::Alt => (-1e5, 1e8, "-1e5..1e8 m"),
            Q::Ax | Q::Ay | Q::Az => (
                -super::MAX_ACCEL_MPS2,
                super::MAX_ACCEL_MPS2,
                "±490.3 m/s² (50 g)",
            ),
        }
    }
}

impl Quantity {
    /// The quantity a column map's name (`crate::mapped::QUANTITIES`) gives, for its
    /// range: `height` is checked as `down` (the same range), `lat, lon, alt` as themselves.
    pub(super) fn of_mapped(name: &str) -> Option<Self> {
        use Quantity as Q;
        Some(match name {
            "time" => Q::Time,
            "north" => Q::North,
            "east" => Q::East,
            "down" | "height" => Q::Down,
            "lat" => Q::Lat,
            "lon" => Q::Lon,
            "alt" => Q::Alt,
            "roll" => Q::Roll,
            "pitch" => Q::Pitch,
            "yaw" => Q::Yaw,
            "vn" => Q::Vn,
            "ve" => Q::Ve,
            "vd" => Q::Vd,
            "u" => Q::U,
            "v" => Q::V,
            "w" => Q::W,
            "p" => Q::P,
            "q" => Q::Q,
            "r" => Q::R,
            "airspeed" => Q::Airspeed,
            "throttle" => Q::Throttle,
            "elevator" => Q::Elevator,
            "aileron" => Q::Aileron,
            "rudder" => Q::Rudder,
            "ax" => Q::Ax,
            "ay" => Q::Ay,
            "az" => Q::Az,
            _ => return None,
        })
    }

    /// True when `v` (SI, after the column's scale and offset) is within [`Self::range`].
    pub(super) fn admits(self, v: f64) -> bool {
        let (lo, hi, _) = self.range();
        (lo..=hi).contains(&v)
    }
}

/// Number of [`Quantity`] variants.
pub(super) const N_QUANTITIES: usize = 27;
const _: () = assert!(Quantity::Az as usize + 1 == N_QUANTITIES);

/// Every [`Quantity`], indexed by its value.
pub(super) const QUANTITIES: [Quantity; N_QUANTITIES] = {
    use Quantity as Q;
    [
        Q::Time,
        Q::North,
        Q::East,
        Q::Down,
        Q::Roll,
        Q::Pitch,
        Q::Yaw,
        Q::Vn,
        Q::Ve,
        Q::Vd,
        Q::U,
        Q::V,
        Q::W,
        Q::P,
        Q::Q,
        Q::R,
        Q::Airspeed,
        Q::Throttle,
        Q::Elevator,
        Q::Aileron,
        Q::Rudder,
        Q::Lat,
        Q::Lon,
        Q::Alt,
        Q::Ax,
        Q::Ay,
        Q::Az,
    ]
};
const _: () = {
    let mut k = 0;
    while k < N_QUANTITIES {
        assert!(QUANTITIES[k] as usize == k);
        k += 1;
    }
};

/// The attitude columns (a set).
pub(super) const ATTITUDE: [Quantity; 3] = [Quantity::Roll, Quantity::Pitch, Quantity::Yaw];
/// The control columns (a set).
pub(super) const CONTROLS: [Quantity; 4] = [
    Quantity::Throttle,
    Quantity::Elevator,
    Quantity::Aileron,
    Quantity::Rudder,
];
/// The accelerometer columns (a set).
pub(super) const ACCELEROMETER: [Quantity; 3] = [Quantity::Ax, Quantity::Ay, Quantity::Az];
/// Columns that come as a set, by name: a file has all of a set or none of it.
pub(super) const GROUPS: [(&str, &[Quantity]); 6] = [
    ("attitude", &ATTITUDE),
    ("NED velocity", &[Quantity::Vn, Quantity::Ve, Quantity::Vd]),
    ("body velocity", &[Quantity::U, Quantity::V, Quantity::W]),
    ("body rates", &[Quantity::P, Quantity::Q, Quantity::R]),
    ("controls", &CONTROLS),
    ("accelerometer", &ACCELEROMETER),
];

/// The two kinds of file the reader accepts (see [`super`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Dialect {
    /// wireflight CSV: column names carry their units (`time_s`, `roll_deg`, …).
    Wireflight,
    /// JSBSim CSV output: `Time` and property names.
    Jsbsim,
}

impl Dialect {
    /// The dialect of a header with these column names: JSBSim when there is no `time_s` but
    /// a `Time` column or a `/fdm/jsbsim/` property, else wireflight.
    pub(super) fn detect(names: &[&str]) -> Self {
        if !names.contains(&"time_s")
            && names
                .iter()
                .any(|n| *n == "Time" || n.starts_with("/fdm/jsbsim/"))
        {
            Dialect::Jsbsim
        } else {
            Dialect::Wireflight
        }
    }
}

/// Quantity and factor to SI (radians for angles) of a wireflight column.
pub(super) fn native_column(name: &str) -> Option<(Quantity, f64)> {
    let d = PI / 180.0;
    Some(match name {
        "time_s" => (Quantity::Time, 1.0),
        "north_m" => (Quantity::North, 1.0),
        "east_m" => (Quantity::East, 1.0),
        "down_m" => (Quantity::Down, 1.0),
        "roll_deg" => (Quantity::Roll, d),
        "roll_rad" => (Quantity::Roll, 1.0),
        "pitch_deg" => (Quantity::Pitch, d),
        "pitch_rad" => (Quantity::Pitch, 1.0),
        "yaw_deg" => (Quantity::Yaw, d),
        "yaw_rad" => (Quantity::Yaw, 1.0),
        "vn_mps" => (Quantity::Vn, 1.0),
        "ve_mps" => (Quantity::Ve, 1.0),
        "vd_mps" => (Quantity::Vd, 1.0),
        "u_mps" => (Quantity::U, 1.0),
        "v_mps" => (Quantity::V, 1.0),
        "w_mps" => (Quantity::W, 1.0),
        "p_dps" => (Quantity::P, d),
        "p_radps" => (Quantity::P, 1.0),
        "q_dps" => (Quantity::Q, d),
        "q_radps" => (Quantity::Q, 1.0),
        "r_dps" => (Quantity::R, d),
        "r_radps" => (Quantity::R, 1.0),
        "airspeed_mps" => (Quantity::Airspeed, 1.0),
        "throttle" => (Quantity::Throttle, 1.0),
        "elevator_deg" => (Quantity::Elevator, d),
        "elevator_rad" => (Quantity::Elevator, 1.0),
        "aileron_deg" => (Quantity::Aileron, d),
        "aileron_rad" => (Quantity::Aileron, 1.0),
        "rudder_deg" => (Quantity::Rudder, d),
        "rudder_rad" => (Quantity::Rudder, 1.0),
        "ax_mps2" => (Quantity::Ax, 1.0),
        "ay_mps2" => (Quantity::Ay, 1.0),
        "az_mps2" => (Quantity::Az, 1.0),
        _ => return None,
    })
}

/// Quantity, factor to SI and priority (lower wins) of a JSBSim column.
pub(super) fn jsbsim_column(name: &str) -> Option<(Quantity, f64, usize)> {
    let find = |key: &str| JSBSIM_COLUMNS.iter().position(|(n, _)| *n == key);
    // Property names with or without the `/fdm/jsbsim/` prefix.
    let priority = find(name).or_else(|| {
        let short = name.trim_start_matches('/');
        let short = short.strip_prefix("fdm/jsbsim/").unwrap_or(short);
        find(&format!("/fdm/jsbsim/{short}"))
    })?;
    let what = JSBSIM_COLUMNS[priority].1;
    let quantity = if what.starts_with("time") {
        Quantity::Time
    } else if what.starts_with("latitude") {
        Quantity::Lat
    } else if what.starts_with("longitude") {
        Quantity::Lon
    } else if what.starts_with("height") {
        Quantity::Alt
    } else if what.starts_with("roll,") {
        Quantity::Roll
    } else if what.starts_with("pitch,") {
        Quantity::Pitch
    } else if what.starts_with("yaw,") {
        Quantity::Yaw
    } else if what.starts_with("roll rate") {
        Quantity::P
    } else if what.starts_with("pitch rate") {
        Quantity::Q
    } else if what.starts_with("yaw rate") {
        Quantity::R
    } else if what.starts_with("body u") {
        Quantity::U
    } else if what.starts_with("body v") {
        Quantity::V
    } else if what.starts_with("body w") {
        Quantity::W
    } else if what.starts_with("north") {
        Quantity::Vn
    } else if what.starts_with("east") {
        Quantity::Ve
    } else if what.starts_with("down") {
        Quantity::Vd
    } else {
        Quantity::Airspeed
    };
    let scale = if what.ends_with("ft/s") || what.ends_with(", ft") {
        METRES_PER_FOOT
    } else if what.ends_with(", kt") {
        MPS_PER_KNOT
    } else if what.ends_with("deg") || what.ends_with("deg/s") {
        PI / 180.0
    } else {
        1.0
    };
    Some((quantity, scale, priority))
}

/// How a missing quantity is named in errors.
pub(super) fn column_label(dialect: Dialect, q: Quantity) -> &'static str {
    match dialect {
        Dialect::Wireflight => match q {
            Quantity::Time => "time_s",
            Quantity::North => "north_m",
            Quantity::East => "east_m",
            Quantity::Down => "down_m",
            Quantity::Roll => "roll_deg (or roll_rad)",
            Quantity::Pitch => "pitch_deg (or pitch_rad)",
            Quantity::Yaw => "yaw_deg (or yaw_rad)",
            Quantity::Vn => "vn_mps",
            Quantity::Ve => "ve_mps",
            Quantity::Vd => "vd_mps",
            Quantity::U => "u_mps",
            Quantity::V => "v_mps",
            Quantity::W => "w_mps",
            Quantity::P => "p_dps (or p_radps)",
            Quantity::Q => "q_dps (or q_radps)",
            Quantity::R => "r_dps (or r_radps)",
            Quantity::Airspeed => "airspeed_mps",
            Quantity::Throttle => "throttle",
            Quantity::Elevator => "elevator_deg (or elevator_rad)",
            Quantity::Aileron => "aileron_deg (or aileron_rad)",
            Quantity::Rudder => "rudder_deg (or rudder_rad)",
            Quantity::Ax => "ax_mps2",
            Quantity::Ay => "ay_mps2",
            Quantity::Az => "az_mps2",
            Quantity::Lat | Quantity::Lon | Quantity::Alt => "(geodetic position)",
        },
        Dialect::Jsbsim => match q {
            Quantity::Time => "Time",
            Quantity::Lat => {
                "/fdm/jsbsim/position/lat-geod-rad (or lat-geod-deg, lat-gc-rad, lat-gc-deg)"
            }
            Quantity::Lon => "/fdm/jsbsim/position/long-gc-rad (or long-gc-deg)",
            Quantity::Alt => "/fdm/jsbsim/position/h-sl-ft (or h-sl-meters)",
            Quantity::Roll => "/fdm/jsbsim/attitude/phi-rad (or phi-deg)",
            Quantity::Pitch => "/fdm/jsbsim/attitude/theta-rad (or theta-deg)",
            Quantity::Yaw => "/fdm/jsbsim/attitude/psi-rad (or psi-deg)",
            Quantity::Vn => "/fdm/jsbsim/velocities/v-north-fps",
            Quantity::Ve => "/fdm/jsbsim/velocities/v-east-fps",
            Quantity::Vd => "/fdm/jsbsim/velocities/v-down-fps",
            Quantity::U => "/fdm/jsbsim/velocities/u-fps",
            Quantity::V => "/fdm/jsbsim/velocities/v-fps",
            Quantity::W => "/fdm/jsbsim/velocities/w-fps",
            Quantity::P => "/fdm/jsbsim/velocities/p-rad_sec",
            Quantity::Q => "/fdm/jsbsim/velocities/q-rad_sec",
            Quantity::R => "/fdm/jsbsim/velocities/r-rad_sec",
            Quantity::Airspeed => "/fdm/jsbsim/velocities/vt-fps",
            Quantity::Throttle => "throttle (controls are not read from JSBSim output)",
            Quantity::Elevator => "elevator (controls are not read from JSBSim output)",
            Quantity::Aileron => "aileron (controls are not read from JSBSim output)",
            Quantity::Rudder => "rudder (controls are not read from JSBSim output)",
            Quantity::North | Quantity::East | Quantity::Down => "(NED position)",
            Quantity::Ax | Quantity::Ay | Quantity::Az => {
                "accelerometer (not read from JSBSim output)"
            }
        },
    }
}
