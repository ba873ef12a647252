//! PX4 ULog files, read by [`crate::px4`]: the files named `.ulg` or starting with the ULog
//! magic.

use std::path::Path;

use super::{FlightReader, ImportError, LoadOptions, Loaded};
use crate::{px4, ulog};

/// The PX4 ULog reader.
pub(super) struct UlogReader;

impl FlightReader for UlogReader {
    fn name(&self) -> &'static str {
        px4::FORMAT
    }

    fn claims(&self, path: &Path, head: &[u8], _: &LoadOptions) -> bool {
        path.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("ulg"))
            || ulog::is_ulog(head)
    }

    /// Refuses a column map ([`ImportError::ColumnMapOnUlog`]).
    fn read(&self, path: &Path, options: &LoadOptions) -> Result<Loaded, ImportError> {
        if options.columns.is_some() {
            return Err(ImportError::ColumnMapOnUlog {
                path: path.to_path_buf(),
            });
        }
        let (data, report) = px4::read(path, &options.ulog)?;
        Ok(Loaded {
            data,
            report: Some(report),
        })
    }
}
