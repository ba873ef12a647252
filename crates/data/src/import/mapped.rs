//! CSV in any column names, read by [`crate::mapped`]: the files given a column map
//! ([`LoadOptions::columns`]).

use std::path::Path;

use super::csv::CsvReader;
use super::{FlightReader, ImportError, LoadOptions, Loaded};
use crate::mapped;

/// The column-mapped CSV reader.
pub(super) struct MappedReader;

impl FlightReader for MappedReader {
    fn name(&self) -> &'static str {
        mapped::FORMAT
    }

    fn claims(&self, _: &Path, _: &[u8], options: &LoadOptions) -> bool {
        options.columns.is_some()
    }

    /// Refuses a resampling rate ([`ImportError::ResampleOnCsv`]); without a map, reads the
    /// project's CSV.
    fn read(&self, path: &Path, options: &LoadOptions) -> Result<Loaded, ImportError> {
        let Some(map) = &options.columns else {
            return CsvReader.read(path, options);
        };
        if options.ulog.rate_hz.is_some() {
            return Err(ImportError::ResampleOnCsv {
                path: path.to_path_buf(),
            });
        }
        let (data, report) = mapped::read(path, map)?;
        Ok(Loaded {
            data,
            report: Some(report),
        })
    }
}
