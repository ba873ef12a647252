//! The flight model's track from a comparison: the multiple-shooting prediction, restarted from
//! the data at each window start, as the viewer draws it beside the measured flight
//! ([`ModelTrack`], in the viewer's frame). Pure: no I/O.

use glam::Vec3;

use wireflight_analysis::compare::Comparison;
use wireflight_data::FlightData;
use wireflight_draw::scene::track::ModelTrack;
use wireflight_draw::scene::ReplayError;
use wireflight_geometry::euler::{viewer_from_ned, EulerZyx};

/// The track of a comparison of `data` made over all its windows (every sample predicted).
///
/// # Errors
/// A comparison that does not cover the flight sample by sample
/// ([`ReplayError::PartialComparison`]).
pub fn model_track(data: &FlightData, comparison: &Comparison) -> Result<ModelTrack, ReplayError> {
    let prediction = &comparison.prediction;
    let n = prediction.index.len();
    if n == 0 || n > data.len() || prediction.index.iter().enumerate().any(|(k, &i)| k != i) {
        return Err(ReplayError::PartialComparison);
    }
    let window_starts = comparison.windows.iter().map(|w| w.samples.0).collect();
    let path: Vec<Vec3> = prediction
        .pos_ned
        .iter()
        .map(|p| viewer_from_ned(*p).as_vec3())
        .collect();
    let error_m: Vec<f64> = (0..n)
        .map(|k| (prediction.pos_ned[k] - data.pos_ned[k]).length())
        .collect();
    Ok(ModelTrack {
        strip_scale_m: error_m.iter().copied().fold(0.0, f64::max),
        time: data.time[..n].to_vec(),
        path,
        attitude: prediction
            .attitude
            .iter()
            .map(|a| EulerZyx::from_aerospace(*a))
            .collect(),
        window_starts,
        error_m,
    })
}
