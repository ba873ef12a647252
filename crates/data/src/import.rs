//! Flight data from any supported file, through one function: [`load`], which asks the
//! [`READERS`] in order and lets the first that claims the file read it:
//!
//! * a PX4 ULog (`.ulg`, or any file that starts with the ULog magic) → [`super::px4`];
//! * any CSV with a column map ([`LoadOptions::columns`]) → [`super::mapped`];
//! * otherwise the project's CSV or JSBSim's CSV output → [`super::read()`].
//!
//! Each format's [`FlightReader`] is a module here (`csv.rs`, `mapped.rs`, `ulog.rs`); a new
//! format is such a module and a line in [`READERS`].
//!
//! The ULog and column-mapped readers also say what they found: an [`ImportReport`] listing,
//! per channel, where it came from, how many samples and at what rate, and what was done to it
//! (resampled, held, dropped), with notes on anything doubtful in the file.

use std::path::{Path, PathBuf};

use super::mapped::{ColumnMap, MappedError};
use super::px4::UlogOptions;
use super::report::ImportReport;
use super::ulog::UlogError;
use super::{DataError, DataErrorKind, FlightData};

mod csv;
mod mapped;
mod ulog;

use self::csv::CsvReader;
use self::mapped::MappedReader;
use self::ulog::UlogReader;

/// A flight-data format: which files are its, and how to read them.
pub trait FlightReader: Sync {
    /// The format's name, as reports give it (`PX4 ULog`).
    fn name(&self) -> &'static str;

    /// Whether this reader reads the file at `path`, whose first bytes are `head` (at most
    /// [`HEAD_BYTES`]; none when the file cannot be opened), with these options.
    fn claims(&self, path: &Path, head: &[u8], options: &LoadOptions) -> bool;

    /// Reads the file, refusing options that are not this format's.
    ///
    /// # Errors
    /// The format's error, naming the file and the line, byte, column, topic or field.
    fn read(&self, path: &Path, options: &LoadOptions) -> Result<Loaded, ImportError>;
}

/// The formats, in the order [`load`] asks them; the last, the project's CSV, claims every
/// file.
pub static READERS: &[&dyn FlightReader] = &[&UlogReader, &MappedReader, &CsvReader];

/// How many of a file's first bytes [`FlightReader::claims`] is shown.
pub const HEAD_BYTES: usize = 16;

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

/// Reads flight data from `path` with the first of the [`READERS`] that claims it (see the
/// module docs).
///
/// # Errors
/// The reader's error, which names the file and the line, byte, column, topic or field.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded, ImportError> {
    let head = head(path);
    let reader = READERS
        .iter()
        .find(|r| r.claims(path, &head, options))
        .copied()
        .unwrap_or(&CsvReader);
    reader.read(path, options)
}

/// The file's first [`HEAD_BYTES`] (fewer for a shorter file; none when it cannot be read).
fn head(path: &Path) -> Vec<u8> {
    use std::io::Read;
    let mut head = Vec::with_capacity(HEAD_BYTES);
    match wireflight_fsio::open_regular(path)
        .and_then(|f| f.take(HEAD_BYTES as u64).read_to_end(&mut head))
    {
        Ok(_) => head,
        Err(_) => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_reader_that_claims_a_file_reads_it() {
        let chosen = |path: &str, head: &[u8], options: &LoadOptions| {
            READERS
                .iter()
                .find(|r| r.claims(Path::new(path), head, options))
                .map(|r| r.name())
        };
        let plain = LoadOptions::default();
        let mapped = LoadOptions {
            columns: Some(ColumnMap::default()),
            ..LoadOptions::default()
        };
        assert_eq!(chosen("f.ulg", b"", &plain), Some("PX4 ULog"));
        assert_eq!(chosen("f.ULG", b"time", &mapped), Some("PX4 ULog"));
        assert_eq!(
            chosen("f.csv", &crate::ulog::MAGIC, &plain),
            Some("PX4 ULog")
        );
        assert_eq!(
            chosen("f.csv", b"time", &mapped),
            Some("CSV with a column map")
        );
        assert_eq!(chosen("f.csv", b"time", &plain), Some("wireflight CSV"));
        assert_eq!(chosen("f", b"", &plain), Some("wireflight CSV"));
    }
}
