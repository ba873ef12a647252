//! How a flight-data file is read (`--columns`, `--resample`, `--surface-max`), and `wireflight import`'s options.

use std::path::PathBuf;

use clap::Args;

use super::{finite_f64, positive};
use crate::data::mapped::ColumnMap;
use crate::data::px4::UlogOptions;
use crate::data::LoadOptions;

/// How a flight-data file is read (shared by every command that reads one): the project's
/// CSV and JSBSim's as they are, a PX4 ULog (`.ulg`) resampled, anything else through a
/// column map.
#[derive(Clone, Debug, Args)]
pub struct DataArgs {
    /// Read the flight file as CSV through this column map: `QUANTITY=COLUMN[:UNIT[:OFFSET]],…`
    /// (e.g. `time=t_us:us,north=x,east=y,down=z,roll=phi:deg,…`) or a .toml file.
    #[arg(long, value_name = "MAP|FILE.toml", value_parser = parse_columns)]
    pub columns: Option<ColumnMap>,
    /// PX4 ULog: keep at most this many samples a second of each topic, Hz (a faster topic is
    /// thinned to samples it has, each at its own time) [default: a round rate (50, 25, 20,
    /// 10, 5, 2, 1) not above the position's and attitude's]. Refused for a CSV, whose samples
    /// are used as they are.
    #[arg(long, value_name = "HZ", value_parser = resample_rate)]
    pub resample: Option<f64>,
    /// PX4 ULog: surface deflection of a full (±1) PX4 roll/pitch/yaw command, degrees, in
    /// (0, 90] (the surfaces' range is ±90°).
    #[arg(long, value_name = "DEG", default_value_t = 25.0, value_parser = surface_max)]
    pub surface_max: f64,
}

impl DataArgs {
    /// The reader settings these options choose.
    pub fn options(&self) -> LoadOptions {
        LoadOptions {
            columns: self.columns.clone(),
            ulog: UlogOptions {
                rate_hz: self.resample,
                surface_max_deg: self.surface_max,
            },
        }
    }
}

pub(super) fn parse_columns(s: &str) -> Result<ColumnMap, String> {
    ColumnMap::from_arg(s).map_err(|e| e.to_string())
}

/// `--surface-max`: a deflection in (0, 90] degrees, the surfaces' range (±90°, the range of
/// every reader's `elevator`, `aileron` and `rudder`).
pub(super) fn surface_max(s: &str) -> Result<f64, String> {
    let v = positive(s)?;
    if v <= 90.0 {
        Ok(v)
    } else {
        Err(format!(
            "{v}° is more than a surface can deflect: the surfaces' range is ±90°, so \
             --surface-max is at most 90"
        ))
    }
}

pub(super) fn resample_rate(s: &str) -> Result<f64, String> {
    let v = finite_f64(s)?;
    if v > 0.0 && v <= 10_000.0 {
        Ok(v)
    } else {
        Err(format!("rate {v} Hz is outside (0, 10000]"))
    }
}

const IMPORT_EXAMPLES: &str = "\
Examples:
  wireflight import --flight tests/data/px4-sitl-hop.ulg --out hop.csv
  wireflight import --flight log.ulg --resample 25 --out flight.csv --json
  wireflight import --flight logger.csv --columns 'time=t_us:us,north=x,east=y,down=z' --out f.csv

Prints what was found (channels, sources, rates, anything doubtful) and writes the flight in
the project's CSV (atomically). Every command that takes --flight reads these files the same
way; import is for looking at a log and keeping the result.";

/// `wireflight import` options.
#[derive(Debug, Args)]
#[command(after_help = IMPORT_EXAMPLES)]
pub struct ImportArgs {
    /// The log: a PX4 ULog (.ulg), or a CSV (with --columns unless it is the project's own).
    #[arg(long, value_name = "FILE")]
    pub flight: PathBuf,
    /// How to read it.
    #[command(flatten)]
    pub data: DataArgs,
    /// Write the flight data here (project CSV, atomically).
    #[arg(long, value_name = "FILE.csv")]
    pub out: Option<PathBuf>,
    /// The report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}
