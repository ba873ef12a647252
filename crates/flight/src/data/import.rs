//! Flight data from any supported file, through one function: [`load`].
//!
//! * a PX4 ULog (`.ulg`, or any file that starts with the ULog magic) → [`super::px4`];
//! * any CSV with a column map ([`LoadOptions::columns`]) → [`super::mapped`];
//! * otherwise the project's CSV or JSBSim's CSV output → [`super::read()`].
//!
//! The ULog and column-mapped readers also say what they found: an [`ImportReport`] listing,
//! per channel, where it came from, how many samples and at what rate, and what was done to it
//! (resampled, held, dropped), with notes on anything doubtful in the file.

use std::path::{Path, PathBuf};

use super::mapped::{self, ColumnMap, MappedError};
use super::px4::{self, UlogOptions};
use super::report::ImportReport;
use super::ulog::{self, UlogError};
use super::{read, DataError, DataErrorKind, FlightData};

/// A flight-data file that cannot be read, from whichever reader [`load`] chose. Every message
/// names the file and, where one is involved, the line, byte, column, topic or field.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportError {
    /// A column map given for a ULog file.
    #[error(
        "{}: a column map is for CSV files; this is a PX4 ULog file (leave out --columns)",
        path.display()
    )]
    ColumnMapOnUlog {
        /// The file.
        path: PathBuf,
    },
    /// A resampling rate given for a CSV (resampling is the ULog reader's).
    #[error(
        "{}: --resample is for PX4 ULog files; this is a CSV, whose samples are used as they \
         are (leave out --resample)",
        path.display()
    )]
    ResampleOnCsv {
        /// The file.
        path: PathBuf,
    },
    /// The project's (or JSBSim's) CSV reader's error.
    #[error(transparent)]
    Csv(DataError),
    /// A CSV without the project's column names: the CSV reader's error, with a hint at the
    /// column map.
    #[error(
        "{0}\n  (a CSV with other column names can be read with a column map: --columns, \
         see docs/flight-data.md)"
    )]
    OtherColumns(DataError),
    /// The column-mapped reader's error.
    #[error(transparent)]
    Mapped(#[from] MappedError),
    /// The ULog reader's error.
    #[error(transparent)]
    Ulog(#[from] UlogError),
}

impl From<DataError> for ImportError {
    /// [`ImportError::OtherColumns`] for a missing column, else [`ImportError::Csv`].
    fn from(e: DataError) -> Self {
        match e.kind {
            // A CSV in someone else's column names: say how to read it.
            DataErrorKind::MissingColumn { .. } => Self::OtherColumns(e),
            _ => Self::Csv(e),
        }
    }
}

/// How to read a flight-data file.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// Read the file as CSV with this column map (any column names, units and time offset).
    pub columns: Option<ColumnMap>,
    /// Settings of the ULog reader.
    pub ulog: UlogOptions,
}

/// A flight read, with the report of the readers that have one.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The flight, with missing channels derived.
    pub data: FlightData,
    /// What was found (ULog and column-mapped CSV; `None` for the project's own CSV).
    pub report: Option<ImportReport>,
}

/// Reads flight data from `path`, choosing the reader as described in the module docs.
///
/// # Errors
/// The reader's error, which names the file and the line, byte, column, topic or field.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded, ImportError> {
    let is_ulog = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ulg"))
        || starts_with_ulog_magic(path);
    if !is_ulog && options.ulog.rate_hz.is_some() {
        return Err(ImportError::ResampleOnCsv {
            path: path.to_path_buf(),
        });
    }
    if let Some(map) = &options.columns {
        if is_ulog {
            return Err(ImportError::ColumnMapOnUlog {
                path: path.to_path_buf(),
            });
        }
        let (data, report) = mapped::read(path, map)?;
        return Ok(Loaded {
            data,
            report: Some(report),
        });
    }
    if is_ulog {
        let (data, report) = px4::read(path, &options.ulog)?;
        return Ok(Loaded {
            data,
            report: Some(report),
        });
    }
    let data = read(path)?;
    Ok(Loaded { data, report: None })
}

/// True when the file can be opened and starts with the ULog magic.
fn starts_with_ulog_magic(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0u8; 7];
    wireflight_fsio::open_regular(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok_and(|()| ulog::is_ulog(&head))
}
