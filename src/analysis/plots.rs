//! Plots of a comparison (placeholder until the plotting module lands).
use std::path::{Path, PathBuf};

use super::compare::Comparison;
use crate::flight::data::FlightData;

/// A flight condition sampled per window, for "error vs condition" plots.
pub struct ConditionSeries {
    /// Name.
    pub name: String,
    /// Unit.
    pub unit: String,
    /// Value per window.
    pub per_window: Vec<f64>,
}

/// Write the comparison plots into `dir`; returns the files written.
///
/// # Errors
/// Always, for now.
pub fn write_plots(
    _dir: &Path,
    _data: &FlightData,
    _before: &Comparison,
    _after: Option<(&Comparison, &str)>,
    _best: Option<&ConditionSeries>,
) -> anyhow::Result<Vec<PathBuf>> {
    anyhow::bail!("plots are not available yet")
}
