//! The project's CSV and JSBSim's CSV output, read by [`crate::read()`]: every file no other
//! reader claims.

use std::path::Path;

use super::{FlightReader, ImportError, LoadOptions, Loaded};

/// The reader of the project's (and JSBSim's) CSV.
pub(super) struct CsvReader;

impl FlightReader for CsvReader {
    fn name(&self) -> &'static str {
        crate::CSV_FORMAT
    }

    fn claims(&self, _: &Path, _: &[u8], _: &LoadOptions) -> bool {
        true
    }

    /// Refuses a resampling rate ([`ImportError::ResampleOnCsv`]); a column map is not
    /// looked at (it is the column-mapped reader's).
    fn read(&self, path: &Path, options: &LoadOptions) -> Result<Loaded, ImportError> {
        if options.ulog.rate_hz.is_some() {
            return Err(ImportError::ResampleOnCsv {
                path: path.to_path_buf(),
            });
        }
        let data = crate::read(path)?;
        Ok(Loaded { data, report: None })
    }
}
