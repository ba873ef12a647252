//! Atmospheric turbulence for simulated flights: the MIL-F-8785C Dryden gust model, seeded.
//!
//! A turbulent flight flies through a gust field that is part of the truth's air (a wind that
//! varies in time, [`GustField`]), never a modelled effect the analysis could fit. The field
//! is generated once, before the flight, as a time series at the integration step from three
//! Dryden shaping filters driven by seeded Gaussian white noise, and read by linear
//! interpolation.
//!
//! * Intensities and scales ([`DrydenIntensity::at`]): MIL-F-8785C §3.7.2 (low altitude,
//!   h < 1000 ft: σ_w = 0.1·W20, σ_u/σ_w = σ_v/σ_w = 1/(0.177 + 0.000823·h)^0.4, L_w = h,
//!   L_u = L_v = h/(0.177 + 0.000823·h)^1.2, h in ft, at least 10 ft; medium/high altitude,
//!   h ≥ 2000 ft: σ_u = σ_v = σ_w from the probability-of-exceedance curves, L = 1750 ft;
//!   linear interpolation between 1000 and 2000 ft). W20 is 15/30/45 kt for
//!   light/moderate/severe.
//! * Spectra: Φ_u(Ω) = σ_u²·(2L_u/π)/(1 + (L_u·Ω)²) and
//!   Φ_{v,w}(Ω) = σ²·(L/π)·(1 + 3(L·Ω)²)/(1 + (L·Ω)²)², so that (frozen field, time scale
//!   T = L/V at the airspeed V) the correlations are R_u(τ) = σ_u²·e^{−τ/T} and
//!   R_{v,w}(τ) = σ²·(1 − τ/(2T))·e^{−τ/T}.
//! * Discretisation: each filter is stepped with its exact discrete transition and the
//!   process noise covariance Q = P − Φ·P·Φᵀ (P the stationary covariance), and starts from a
//!   draw of P: the series is stationary from its first sample, and its variance and
//!   correlation are exact at every step size, not only for small `dt`.
//!
//! The gust axes are u north, v east, w down: the trim heads north, so u is the longitudinal
//! gust of the straight part of a flight; the low-altitude model has σ_u = σ_v and
//! L_u = L_v, so only the spectral shape of u and v differs when the aircraft turns. Rotary
//! gusts (p_g, q_g, r_g) are not modelled.

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use glam::DVec3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use super::effects::{Applies, Effect, EffectContext, EffectInfo};

/// Metres in a foot.
const FT: f64 = 0.3048;
/// Knots to m/s.
const KT: f64 = 1852.0 / 3600.0;
/// Lowest height of the low-altitude model, ft (MIL-F-8785C's curves start there).
const MIN_HEIGHT_FT: f64 = 10.0;
/// Top of the low-altitude model, ft.
const LOW_TOP_FT: f64 = 1000.0;
/// Bottom of the medium/high-altitude model, ft.
const HIGH_BOTTOM_FT: f64 = 2000.0;
/// Scale length of the medium/high-altitude model, ft.
const HIGH_LENGTH_FT: f64 = 1750.0;

/// Heights of the probability-of-exceedance table, ft (MIL-F-8785C figure 7, as tabulated in
/// MIL-HDBK-1797 and JSBSim's `FGWinds`).
const POE_HEIGHT_FT: [f64; 12] = [
    500.0, 1750.0, 3750.0, 7500.0, 15000.0, 25000.0, 35000.0, 45000.0, 55000.0, 65000.0, 75000.0,
    80000.0,
];
// The figure has seven curves, probabilities of exceedance 2·10⁻¹, 10⁻¹, 10⁻², 10⁻³, 10⁻⁴,
// 10⁻⁵ and 10⁻⁶ (JSBSim's severity index 1 to 7; its `FGWinds.h`: 3 light, 4 moderate, 6
// severe). The levels are the third, fourth and sixth.
/// σ, ft/s, at [`POE_HEIGHT_FT`], probability of exceedance 10⁻² (light).
const POE_LIGHT: [f64; 12] = [6.6, 6.9, 7.4, 6.7, 4.6, 2.7, 0.4, 0.0, 0.0, 0.0, 0.0, 0.0];
/// Likewise, 10⁻³ (moderate).
const POE_MODERATE: [f64; 12] = [8.6, 9.6, 10.6, 10.1, 8.0, 6.6, 5.0, 4.2, 2.7, 0.0, 0.0, 0.0];
/// Likewise, 10⁻⁵ (severe).
const POE_SEVERE: [f64; 12] = [
    15.6, 17.6, 23.0, 23.6, 22.1, 20.0, 16.0, 15.1, 12.1, 7.9, 6.2, 5.1,
];

/// Most gust samples of one field (11 hours at the 0.01 s integration step).
pub const MAX_GUST_SAMPLES: usize = 4_000_000;

/// The MIL-F-8785C turbulence levels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TurbulenceLevel {
    /// W20 = 15 kt; probability of exceedance 10⁻² above 2000 ft.
    Light,
    /// W20 = 30 kt; 10⁻³.
    Moderate,
    /// W20 = 45 kt; 10⁻⁵.
    Severe,
}

/// The level names, in order of severity.
pub const LEVELS: [&str; 3] = ["light", "moderate", "severe"];

impl TurbulenceLevel {
    /// The wind speed 20 ft above the ground, m/s.
    pub fn w20_mps(self) -> f64 {
        KT * match self {
            Self::Light => 15.0,
            Self::Moderate => 30.0,
            Self::Severe => 45.0,
        }
    }

    fn poe_table(self) -> &'static [f64; 12] {
        match self {
            Self::Light => &POE_LIGHT,
            Self::Moderate => &POE_MODERATE,
            Self::Severe => &POE_SEVERE,
        }
    }
}

impl fmt::Display for TurbulenceLevel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Light => LEVELS[0],
            Self::Moderate => LEVELS[1],
            Self::Severe => LEVELS[2],
        })
    }
}

/// A turbulence level or truth record that cannot be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TurbulenceError {
    /// Not one of [`LEVELS`].
    #[error("unknown turbulence level `{0}`: one of light, moderate, severe")]
    UnknownLevel(String),
    /// A `turbulence` metadata value without a field, or with one that is not a number.
    #[error("turbulence record `{record}`: field `{field}` is missing or not a finite number")]
    Record {
        /// The value read.
        record: String,
        /// The field.
        field: &'static str,
    },
    /// An airspeed that cannot set the frozen field's time scale.
    #[error("turbulence needs a positive finite airspeed, not {0} m/s")]
    Airspeed(f64),
    /// More gust samples than [`MAX_GUST_SAMPLES`].
    #[error("{0} gust samples is more than {MAX_GUST_SAMPLES}")]
    TooLong(f64),
}

impl FromStr for TurbulenceLevel {
    type Err = TurbulenceError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "light" => Ok(Self::Light),
            "moderate" => Ok(Self::Moderate),
            "severe" => Ok(Self::Severe),
            _ => Err(TurbulenceError::UnknownLevel(s.to_string())),
        }
    }
}

/// Turbulence to fly in: a level and the seed of its gusts (independent of the measurement
/// noise's seed, so the same gusts can be flown with other noise and the other way round).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turbulence {
    /// The level.
    pub level: TurbulenceLevel,
    /// Seed of the gusts' white noise.
    pub seed: u64,
}

/// Dryden intensities and scale lengths of the gust components (u, v, w).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrydenIntensity {
    /// σ_u, σ_v, σ_w, m/s.
    pub sigma_mps: [f64; 3],
    /// L_u, L_v, L_w, m.
    pub length_m: [f64; 3],
}

impl DrydenIntensity {
    /// MIL-F-8785C intensities and scales of `level` at `height_m` above the ground (see the
    /// module documentation); a height below 10 ft (or not finite) is taken as 10 ft.
    pub fn at(level: TurbulenceLevel, height_m: f64) -> Self {
        let h = if height_m.is_finite() {
            (height_m / FT).max(MIN_HEIGHT_FT)
        } else {
            MIN_HEIGHT_FT
        };
        if h <= LOW_TOP_FT {
            Self::low(level, h)
        } else if h >= HIGH_BOTTOM_FT {
            Self::high(level, h)
        } else {
            let (lo, hi) = (
                Self::low(level, LOW_TOP_FT),
                Self::high(level, HIGH_BOTTOM_FT),
            );
            let f = (h - LOW_TOP_FT) / (HIGH_BOTTOM_FT - LOW_TOP_FT);
            let mix = |a: [f64; 3], b: [f64; 3]| std::array::from_fn(|i| a[i] + f * (b[i] - a[i]));
            Self {
                sigma_mps: mix(lo.sigma_mps, hi.sigma_mps),
                length_m: mix(lo.length_m, hi.length_m),
            }
        }
    }

    /// The low-altitude model at `h_ft` (10 ≤ h ≤ 1000).
    fn low(level: TurbulenceLevel, h_ft: f64) -> Self {
        let base = 0.177 + 0.000823 * h_ft;
        let sigma_w = 0.1 * level.w20_mps();
        let sigma_uv = sigma_w / base.powf(0.4);
        let l_uv = h_ft / base.powf(1.2) * FT;
        Self {
            sigma_mps: [sigma_uv, sigma_uv, sigma_w],
            length_m: [l_uv, l_uv, h_ft * FT],
        }
    }

    /// The medium/high-altitude model at `h_ft` (≥ 2000): isotropic, L = 1750 ft.
    fn high(level: TurbulenceLevel, h_ft: f64) -> Self {
        let table = level.poe_table();
        let last = POE_HEIGHT_FT.len() - 1;
        let sigma_fps = match POE_HEIGHT_FT.iter().position(|&x| x >= h_ft) {
            None => table[last],
            Some(0) => table[0],
            Some(i) => {
                let f = (h_ft - POE_HEIGHT_FT[i - 1]) / (POE_HEIGHT_FT[i] - POE_HEIGHT_FT[i - 1]);
                table[i - 1] + f * (table[i] - table[i - 1])
            }
        };
        let sigma = sigma_fps * FT;
        Self {
            sigma_mps: [sigma; 3],
            length_m: [HIGH_LENGTH_FT * FT; 3],
        }
    }
}

/// What a turbulent flight flew: recorded in its file as the `turbulence` metadata
/// ([`GustTruth::to_record`], read back with [`GustTruth::parse`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GustTruth {
    /// The level and seed.
    pub turbulence: Turbulence,
    /// Intensities and scales.
    pub intensity: DrydenIntensity,
    /// The airspeed that sets the time scales T = L/V, m/s.
    pub airspeed_mps: f64,
}

/// Key of the truth in a flight file's metadata.
pub const TRUTH_KEY: &str = "turbulence";

impl GustTruth {
    /// The truth of `turbulence` at `height_m` above the ground and `airspeed_mps`.
    pub fn new(turbulence: Turbulence, height_m: f64, airspeed_mps: f64) -> Self {
        Self {
            turbulence,
            intensity: DrydenIntensity::at(turbulence.level, height_m),
            airspeed_mps,
        }
    }

    /// The time scales T_u, T_v, T_w = L/V, s.
    pub fn time_scales_s(&self) -> [f64; 3] {
        self.intensity.length_m.map(|l| l / self.airspeed_mps)
    }

    /// The metadata value: `LEVEL sigma_u=… sigma_v=… sigma_w=… L_u=… L_v=… L_w=… V=…
    /// seed=N` (m/s, m; gust axes u north, v east, w down).
    pub fn to_record(&self) -> String {
        let [su, sv, sw] = self.intensity.sigma_mps;
        let [lu, lv, lw] = self.intensity.length_m;
        format!(
            "{} sigma_u={su:.4} sigma_v={sv:.4} sigma_w={sw:.4} L_u={lu:.2} L_v={lv:.2} \
             L_w={lw:.2} V={:.3} seed={}",
            self.turbulence.level, self.airspeed_mps, self.turbulence.seed
        )
    }

    /// Read a [`to_record`](Self::to_record) value back.
    ///
    /// # Errors
    /// An unknown level, or a field missing or not a finite number.
    pub fn parse(record: &str) -> Result<Self, TurbulenceError> {
        let mut words = record.split_whitespace();
        let level: TurbulenceLevel = words.next().unwrap_or("").parse()?;
        let fields: Vec<(&str, &str)> = words.filter_map(|w| w.split_once('=')).collect();
        let get = |field: &'static str| -> Result<f64, TurbulenceError> {
            fields
                .iter()
                .find(|(k, _)| *k == field)
                .and_then(|(_, v)| v.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| TurbulenceError::Record {
                    record: record.to_string(),
                    field,
                })
        };
        let seed = fields
            .iter()
            .find(|(k, _)| *k == "seed")
            .and_then(|(_, v)| v.parse::<u64>().ok())
            .ok_or_else(|| TurbulenceError::Record {
                record: record.to_string(),
                field: "seed",
            })?;
        Ok(Self {
            turbulence: Turbulence { level, seed },
            intensity: DrydenIntensity {
                sigma_mps: [get("sigma_u")?, get("sigma_v")?, get("sigma_w")?],
                length_m: [get("L_u")?, get("L_v")?, get("L_w")?],
            },
            airspeed_mps: get("V")?,
        })
    }
}

/// `n` gust samples (u, v, w, m/s) `dt` seconds apart of the Dryden field `truth`, from its
/// seed: each component's exact discrete shaping filter (module documentation), started
/// stationary.
///
/// # Errors
/// A non-positive airspeed, or more than [`MAX_GUST_SAMPLES`].
pub fn dryden_series(truth: &GustTruth, dt: f64, n: usize) -> Result<Vec<DVec3>, TurbulenceError> {
    let v = truth.airspeed_mps;
    if !(v.is_finite() && v > 0.0) {
        return Err(TurbulenceError::Airspeed(v));
    }
    if n > MAX_GUST_SAMPLES {
        return Err(TurbulenceError::TooLong(n as f64));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(truth.turbulence.seed);
    let sigma = truth.intensity.sigma_mps;
    let steps = truth
        .time_scales_s()
        .map(|t| if t > 0.0 { dt / t } else { f64::INFINITY });
    let u = FirstOrder::new(steps[0]);
    let lateral = [SecondOrder::new(steps[1]), SecondOrder::new(steps[2])];
    let mut gauss = || -> f64 { StandardNormal.sample(&mut rng) };
    let mut x_u = gauss();
    let mut x_vw = [0usize, 1].map(|i| lateral[i].stationary(gauss(), gauss()));
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        out.push(DVec3::new(
            sigma[0] * x_u,
            sigma[1] * SecondOrder::output(x_vw[0]),
            sigma[2] * SecondOrder::output(x_vw[1]),
        ));
        x_u = u.step(x_u, gauss());
        for (x, f) in x_vw.iter_mut().zip(lateral.iter()) {
            *x = f.step(*x, gauss(), gauss());
        }
    }
    Ok(out)
}

/// The unit-variance first-order Dryden filter (u) over a step of `s` time scales:
/// x ← e^{−s}·x + √(1 − e^{−2s})·n.
struct FirstOrder {
    decay: f64,
    drive: f64,
}

impl FirstOrder {
    fn new(s: f64) -> Self {
        Self {
            decay: (-s).exp(),
            drive: (-(-2.0 * s).exp_m1()).max(0.0).sqrt(),
        }
    }
    fn step(&self, x: f64, n: f64) -> f64 {
        self.decay * x + self.drive * n
    }
}

/// The unit-variance second-order Dryden filter (v, w) in time scales: white noise through
/// 1/(s + 1) into x₁, x₁ through 1/(s + 1) into x₂, output √3·x₁ + (1 − √3)·x₂, whose
/// transfer is (1 + √3·s)/(1 + s)², stationary covariance P = [[1/2, 1/4], [1/4, 1/4]]
/// (variance of the output 1) and correlation (1 − τ/2)·e^{−τ}.
struct SecondOrder {
    /// e^{−s}·[[1, 0], [s, 1]].
    phi: [[f64; 2]; 2],
    /// Cholesky factor of Q = P − Φ·P·Φᵀ (lower: l11, l21, l22).
    chol: [f64; 3],
}

impl SecondOrder {
    fn new(s: f64) -> Self {
        let e = (-s).exp();
        let e2 = e * e;
        let one_minus_e2 = -(-2.0 * s).exp_m1();
        let q11 = one_minus_e2 / 2.0;
        let q21 = one_minus_e2 / 4.0 - e2 * s / 2.0;
        let q22 = one_minus_e2 / 4.0 - e2 * (s * s / 2.0 + s / 2.0);
        let l11 = q11.max(0.0).sqrt();
        let l21 = if l11 > 0.0 { q21 / l11 } else { 0.0 };
        let l22 = (q22 - l21 * l21).max(0.0).sqrt();
        let s_phi = if s.is_finite() { s * e } else { 0.0 };
        Self {
            phi: [[e, 0.0], [s_phi, e]],
            chol: [l11, l21, l22],
        }
    }

    /// A draw of the stationary state from two standard normals (P's Cholesky factor:
    /// [[1/√2, 0], [1/(2√2), 1/(2√2)]]).
    fn stationary(&self, n1: f64, n2: f64) -> [f64; 2] {
        let r = std::f64::consts::FRAC_1_SQRT_2;
        [r * n1, r / 2.0 * (n1 + n2)]
    }

    fn step(&self, x: [f64; 2], n1: f64, n2: f64) -> [f64; 2] {
        let [l11, l21, l22] = self.chol;
        [
            self.phi[0][0] * x[0] + l11 * n1,
            self.phi[1][0] * x[0] + self.phi[1][1] * x[1] + l21 * n1 + l22 * n2,
        ]
    }

    fn output(x: [f64; 2]) -> f64 {
        let r3 = 3f64.sqrt();
        r3 * x[0] + (1.0 - r3) * x[1]
    }
}

/// The catalogue-style description of the gust field (it is not in the catalogue: a gust
/// field is flown, never fitted).
pub static INFO: EffectInfo = EffectInfo {
    name: "turbulence",
    summary: "Dryden gusts (MIL-F-8785C), a wind that varies in time; truth only",
    applies: Applies::FixedWing,
    params: &[],
    make: |_: &EffectContext| Box::new(GustField::calm()),
};

/// A gust field as a wind (NED) that varies in time: samples `dt` apart from t = 0,
/// linearly interpolated, held at the last sample after the end.
#[derive(Clone, Debug)]
pub struct GustField {
    dt: f64,
    samples: Arc<[DVec3]>,
}

impl GustField {
    /// The field of `truth` for `duration_s`, sampled every `dt` seconds.
    ///
    /// # Errors
    /// As [`dryden_series`]; a non-positive `dt` or duration counts as one sample.
    pub fn new(truth: &GustTruth, duration_s: f64, dt: f64) -> Result<Self, TurbulenceError> {
        let dt = if dt.is_finite() && dt > 0.0 { dt } else { 1.0 };
        let count = (duration_s / dt).ceil() + 2.0;
        if count.is_nan() || count > MAX_GUST_SAMPLES as f64 {
            return Err(TurbulenceError::TooLong(count));
        }
        // `count` ≤ MAX_GUST_SAMPLES here.
        let n = count.max(1.0) as usize;
        Ok(Self {
            dt,
            samples: dryden_series(truth, dt, n)?.into(),
        })
    }

    /// No gusts.
    fn calm() -> Self {
        Self {
            dt: 1.0,
            samples: Arc::new([DVec3::ZERO]),
        }
    }

    /// The gust (u north, v east, w down), m/s, at `t`.
    pub fn gust_at(&self, t: f64) -> DVec3 {
        let last = self.samples.len().saturating_sub(1);
        let x = if t.is_finite() {
            (t / self.dt).max(0.0)
        } else {
            0.0
        };
        let i = x.floor();
        if i >= last as f64 {
            return self.samples.get(last).copied().unwrap_or(DVec3::ZERO);
        }
        // 0 ≤ i < last here.
        let k = i as usize;
        self.samples[k].lerp(self.samples[k + 1], x - i)
    }
}

impl Effect for GustField {
    crate::effect_basics! {
        info: INFO,
        varies_in_time: true,
        varies_in_space: false,
    }
    fn wind_at(&self, _pos_ned: DVec3, t: f64) -> DVec3 {
        self.gust_at(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn truth(level: TurbulenceLevel, seed: u64) -> GustTruth {
        GustTruth::new(Turbulence { level, seed }, 200.0, 25.0)
    }

    #[test]
    fn levels_parse_and_unknown_is_refused_with_the_list() {
        assert_eq!("Moderate".parse(), Ok(TurbulenceLevel::Moderate));
        let e = "gale".parse::<TurbulenceLevel>().unwrap_err().to_string();
        assert_eq!(
            e,
            "unknown turbulence level `gale`: one of light, moderate, severe"
        );
    }

    #[test]
    fn low_altitude_intensity_follows_the_formulas() {
        // 1000 ft: σ_u = σ_w = 0.1·W20, L_u = L_w = 1000 ft.
        let d = DrydenIntensity::at(TurbulenceLevel::Moderate, 1000.0 * FT);
        let sw = 3.0 * KT;
        for s in d.sigma_mps {
            assert!((s - sw).abs() < 1e-9, "{d:?}");
        }
        for l in d.length_m {
            assert!((l - 1000.0 * FT).abs() < 1e-6, "{d:?}");
        }
        // Above 2000 ft: the table's 10⁻², 10⁻³ and 10⁻⁵ curves, and 1750 ft.
        for (level, fps) in [
            (TurbulenceLevel::Light, 7.4),
            (TurbulenceLevel::Moderate, 10.6),
            (TurbulenceLevel::Severe, 23.0),
        ] {
            let h = DrydenIntensity::at(level, 3750.0 * FT);
            assert!((h.sigma_mps[2] - fps * FT).abs() < 1e-9, "{level:?}: {h:?}");
            assert!((h.length_m[0] - 1750.0 * FT).abs() < 1e-9);
        }
    }

    #[test]
    fn record_round_trips() {
        let t = truth(TurbulenceLevel::Light, 9);
        let back = GustTruth::parse(&t.to_record()).unwrap();
        assert_eq!(back.turbulence, t.turbulence);
        assert!((back.intensity.sigma_mps[0] - t.intensity.sigma_mps[0]).abs() < 1e-4);
        assert!(GustTruth::parse("light sigma_u=1").is_err());
    }

    /// Sample σ and the correlation at one time scale, for two steps: the discretisation
    /// is exact, so both match the Dryden values whatever the step (short time scales,
    /// 50 m at 100 m/s, so that the series holds thousands of them).
    #[test]
    fn variance_and_correlation_are_right_at_any_step() {
        let t = GustTruth::new(
            Turbulence {
                level: TurbulenceLevel::Moderate,
                seed: 3,
            },
            50.0,
            100.0,
        );
        let scales = t.time_scales_s();
        for dt in [0.01, 0.5] {
            let n = 1_000_000;
            let g = dryden_series(&t, dt, n).unwrap();
            for axis in 0..3 {
                let x: Vec<f64> = g.iter().map(|v| v[axis]).collect();
                let var = x.iter().map(|a| a * a).sum::<f64>() / n as f64;
                let sigma = t.intensity.sigma_mps[axis];
                let ratio = var.sqrt() / sigma;
                // Correlation at lag ≈ T.
                let lag = (scales[axis] / dt).round().max(1.0) as usize;
                let tau = lag as f64 * dt / scales[axis];
                let r = x.iter().zip(&x[lag..]).map(|(a, b)| a * b).sum::<f64>()
                    / (n - lag) as f64
                    / var;
                let want = if axis == 0 {
                    (-tau).exp()
                } else {
                    (1.0 - tau / 2.0) * (-tau).exp()
                };
                assert!(
                    (ratio - 1.0).abs() < 0.05,
                    "dt {dt} axis {axis}: σ ratio {ratio}"
                );
                assert!(
                    (r - want).abs() < 0.05,
                    "dt {dt} axis {axis}: ρ {r} vs {want}"
                );
            }
        }
    }

    #[test]
    fn same_seed_same_gusts_other_seed_other_gusts() {
        let a = dryden_series(&truth(TurbulenceLevel::Light, 1), 0.02, 500).unwrap();
        let b = dryden_series(&truth(TurbulenceLevel::Light, 1), 0.02, 500).unwrap();
        let c = dryden_series(&truth(TurbulenceLevel::Light, 2), 0.02, 500).unwrap();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn field_interpolates_and_holds_the_end() {
        let f = GustField::new(&truth(TurbulenceLevel::Light, 1), 1.0, 0.1).unwrap();
        let mid = f.gust_at(0.05);
        assert!((mid - (f.samples[0] + f.samples[1]) / 2.0).length() < 1e-12);
        assert_eq!(f.gust_at(1e9), *f.samples.last().unwrap());
        assert_eq!(f.gust_at(f64::NAN), f.samples[0]);
    }
}
