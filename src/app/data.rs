//! The one way the commands read a flight-data file: [`load_flight`].

use std::path::Path;

use crate::app::cli::DataArgs;
use crate::data::{load, FlightData, Loaded};

/// Reads the flight at `path` as `args` say ([`crate::data::load`]: the project's CSV,
/// JSBSim's, a PX4 ULog, or any CSV through a column map). The ULog and column-map readers'
/// report of what they found goes to stderr (so `--json` on stdout stays clean), unless
/// `--quiet`.
///
/// # Errors
/// The reader's error, naming the file and where in it.
pub fn load_flight(path: &Path, args: &DataArgs) -> anyhow::Result<FlightData> {
    let Loaded { data, report } = load(path, &args.options())?;
    if let Some(r) = report.filter(|_| !crate::draw::progress::is_quiet()) {
        eprint!("{}", crate::fsio::printable(&r.to_string()));
    }
    Ok(data)
}
