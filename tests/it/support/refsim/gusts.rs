//! refsim's own gust model: Dryden turbulence as a sum of sinusoids.
//!
//! A different construction from the project's shaping filters, so the two can cross-check:
//! each gust component is Σ_k a_k·cos(ω_k·t + φ_k) over `SINUSOIDS` frequencies spaced
//! logarithmically from 10⁻³/T to 10³/T (T = L/V), with amplitudes a_k = √(2·Φ(ω_k)·Δω_k) from
//! the Dryden spectrum in time (one-sided, ∫₀^∞ Φ dω = σ²) and phases uniform in [0, 2π) from
//! refsim's own generator. Its variance is Σ a_k²/2, the spectrum's integral over the band
//! (normalised to σ² exactly), and its correlation Σ (a_k²/2)·cos(ω_k·τ), the band's
//! transform of the Dryden spectrum.
//!
//! Dryden spectra in time (frozen field at V): u: Φ(ω) = σ²·(2T/π)/(1 + (Tω)²);
//! v, w: Φ(ω) = σ²·(T/π)·(1 + 3(Tω)²)/(1 + (Tω)²)² (MIL-F-8785C).
//!
//! refsim's fixed wing flies through them ([`RefGusts`] on the flight's options): the
//! intensities and scale lengths of MIL-F-8785C (computed here, not by the product), the
//! field tabulated once per flight ([`GustTable`]) and written into the flight's file as the
//! `# turbulence:` line the product's simulator writes.

use super::{Rng, V3};

/// Sinusoids per component.
pub const SINUSOIDS: usize = 400;

/// Which Dryden form a component has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrydenForm {
    /// First order (longitudinal u).
    Longitudinal,
    /// Second order (lateral v, vertical w).
    Transverse,
}

impl DrydenForm {
    /// One-sided spectrum at angular frequency `w` for σ = 1 and time scale `t_s`.
    pub fn spectrum(self, w: f64, t_s: f64) -> f64 {
        let x = (t_s * w).powi(2);
        match self {
            Self::Longitudinal => 2.0 * t_s / std::f64::consts::PI / (1.0 + x),
            Self::Transverse => t_s / std::f64::consts::PI * (1.0 + 3.0 * x) / (1.0 + x).powi(2),
        }
    }

    /// The normalised correlation at lag `tau` (σ = 1).
    pub fn correlation(self, tau: f64, t_s: f64) -> f64 {
        let r = tau.abs() / t_s;
        match self {
            Self::Longitudinal => (-r).exp(),
            Self::Transverse => (1.0 - r / 2.0) * (-r).exp(),
        }
    }
}

/// One gust component as a sum of sinusoids.
#[derive(Clone, Debug)]
pub struct SinusoidGust {
    /// (ω, amplitude, phase).
    pub terms: Vec<(f64, f64, f64)>,
}

impl SinusoidGust {
    /// A component of standard deviation `sigma`, time scale `t_s` = L/V, Dryden `form`,
    /// phases from `rng`.
    pub fn new(form: DrydenForm, sigma: f64, t_s: f64, rng: &mut Rng) -> Self {
        let (lo, hi) = ((1e-3 / t_s).ln(), (1e3 / t_s).ln());
        let step = (hi - lo) / SINUSOIDS as f64;
        let mut terms: Vec<(f64, f64, f64)> = (0..SINUSOIDS)
            .map(|k| {
                // Midpoint in log frequency; Δω of the band.
                let w = (lo + (k as f64 + 0.5) * step).exp();
                let dw = (lo + (k as f64 + 1.0) * step).exp() - (lo + k as f64 * step).exp();
                let a = (2.0 * form.spectrum(w, t_s) * dw).sqrt();
                (w, a, 2.0 * std::f64::consts::PI * rng.uniform())
            })
            .collect();
        let var: f64 = terms.iter().map(|t| t.1 * t.1 / 2.0).sum();
        let scale = sigma / var.sqrt();
        for t in &mut terms {
            t.1 *= scale;
        }
        Self { terms }
    }

    /// The gust at time `t`, m/s.
    pub fn at(&self, t: f64) -> f64 {
        self.terms
            .iter()
            .map(|(w, a, p)| a * (w * t + p).cos())
            .sum()
    }

    /// The correlation of this sum at lag `tau` (the band's, not a sample's), normalised.
    pub fn correlation(&self, tau: f64) -> f64 {
        let var: f64 = self.terms.iter().map(|t| t.1 * t.1 / 2.0).sum();
        self.terms
            .iter()
            .map(|(w, a, _)| a * a / 2.0 * (w * tau).cos())
            .sum::<f64>()
            / var
    }
}

/// Three gust components (u north, v east, w down) of given σ and time scales.
#[derive(Clone, Debug)]
pub struct DrydenGusts {
    /// u, v, w.
    pub components: [SinusoidGust; 3],
}

impl DrydenGusts {
    /// σ (m/s) and T (s) per component, phases from `seed`.
    pub fn new(sigma: [f64; 3], t_s: [f64; 3], seed: u64) -> Self {
        let mut rng = Rng::new(seed);
        let forms = [
            DrydenForm::Longitudinal,
            DrydenForm::Transverse,
            DrydenForm::Transverse,
        ];
        Self {
            components: [0, 1, 2].map(|i| SinusoidGust::new(forms[i], sigma[i], t_s[i], &mut rng)),
        }
    }

    /// The gust wind NED at `t`, m/s.
    pub fn wind_at(&self, t: f64) -> [f64; 3] {
        [0, 1, 2].map(|i| self.components[i].at(t))
    }
}

/// MIL-F-8785C turbulence levels (the probability-of-exceedance curves above 2000 ft, the
/// wind speed 20 ft above the ground below 1000 ft).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GustLevel {
    /// W20 = 15 kt; probability of exceedance 10⁻².
    Light,
    /// W20 = 30 kt; 10⁻³.
    Moderate,
    /// W20 = 45 kt; 10⁻⁵.
    Severe,
}

/// Metres per foot.
const FOOT_M: f64 = 0.3048;
/// m/s per knot.
const KNOT_MPS: f64 = 1852.0 / 3600.0;

/// Heights (ft) of the medium/high-altitude intensities below, MIL-F-8785C figure 7 as
/// tabulated in MIL-HDBK-1797.
const EXCEEDANCE_HEIGHTS_FT: [f64; 12] = [
    500.0, 1750.0, 3750.0, 7500.0, 15000.0, 25000.0, 35000.0, 45000.0, 55000.0, 65000.0, 75000.0,
    80000.0,
];

impl GustLevel {
    /// The name the `# turbulence:` record starts with.
    pub fn name(self) -> &'static str {
        match self {
            Self::Light => "light",
            Self::Moderate => "moderate",
            Self::Severe => "severe",
        }
    }

    /// W20, kt.
    fn w20_kt(self) -> f64 {
        match self {
            Self::Light => 15.0,
            Self::Moderate => 30.0,
            Self::Severe => 45.0,
        }
    }

    /// σ (ft/s) at [`EXCEEDANCE_HEIGHTS_FT`].
    fn exceedance_sigma_fps(self) -> [f64; 12] {
        match self {
            Self::Light => [6.6, 6.9, 7.4, 6.7, 4.6, 2.7, 0.4, 0.0, 0.0, 0.0, 0.0, 0.0],
            Self::Moderate => [8.6, 9.6, 10.6, 10.1, 8.0, 6.6, 5.0, 4.2, 2.7, 0.0, 0.0, 0.0],
            Self::Severe => [
                15.6, 17.6, 23.0, 23.6, 22.1, 20.0, 16.0, 15.1, 12.1, 7.9, 6.2, 5.1,
            ],
        }
    }

    /// (σ_u, σ_v, σ_w) in ft/s and (L_u, L_v, L_w) in ft at `h_ft` (≥ 10 ft).
    fn dryden_ft(self, h_ft: f64) -> ([f64; 3], [f64; 3]) {
        if h_ft <= 1000.0 {
            // Low altitude: σ_w = 0.1·W20, the horizontal ones larger near the ground.
            let k = 0.177 + 0.000823 * h_ft;
            let sigma_w = 0.1 * self.w20_kt() * KNOT_MPS / FOOT_M;
            let sigma_h = sigma_w / k.powf(0.4);
            let length_h = h_ft / k.powf(1.2);
            ([sigma_h, sigma_h, sigma_w], [length_h, length_h, h_ft])
        } else if h_ft >= 2000.0 {
            // Medium and high altitude: isotropic, 1750 ft scales.
            let table = self.exceedance_sigma_fps();
            let hs = EXCEEDANCE_HEIGHTS_FT;
            let above = hs
                .iter()
                .take_while(|&&x| x < h_ft)
                .count()
                .clamp(1, hs.len() - 1);
            let f = ((h_ft - hs[above - 1]) / (hs[above] - hs[above - 1])).min(1.0);
            let sigma = table[above - 1] + f * (table[above] - table[above - 1]);
            ([sigma; 3], [1750.0; 3])
        } else {
            // Between the two: each number linearly in height.
            let (low, high) = (self.dryden_ft(1000.0), self.dryden_ft(2000.0));
            let f = (h_ft - 1000.0) / 1000.0;
            let mix = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|i| a[i] * (1.0 - f) + b[i] * f);
            (mix(low.0, high.0), mix(low.1, high.1))
        }
    }
}

/// Turbulence for refsim's fixed wing to fly through: the Dryden intensities and scale
/// lengths of the gust components (u north, v east, w down) and the seed of their phases.
/// The time scales are T = L/V at the trim airspeed V (a frozen field).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefGusts {
    /// The level the `# turbulence:` record names.
    pub level: GustLevel,
    /// σ_u, σ_v, σ_w, m/s.
    pub sigma_mps: [f64; 3],
    /// L_u, L_v, L_w, m.
    pub length_m: [f64; 3],
    /// Seed of the sinusoids' phases (independent of the measurement noise's seed).
    pub seed: u64,
}

impl RefGusts {
    /// MIL-F-8785C intensities and scales of `level` at `height_m` above the ground (taken
    /// as at least 10 ft): the low-altitude model below 1000 ft, the probability-of-exceedance
    /// table from 2000 ft, linear in height between.
    pub fn mil_8785c(level: GustLevel, height_m: f64, seed: u64) -> Self {
        let h_ft = (height_m / FOOT_M).max(10.0);
        let (sigma_fps, length_ft) = level.dryden_ft(h_ft);
        RefGusts {
            level,
            sigma_mps: sigma_fps.map(|s| s * FOOT_M),
            length_m: length_ft.map(|l| l * FOOT_M),
            seed,
        }
    }

    /// The time scales T = L/V, s.
    pub fn time_scales_s(&self, airspeed_mps: f64) -> [f64; 3] {
        self.length_m.map(|l| l / airspeed_mps)
    }

    /// The sinusoid sums of these gusts at `airspeed_mps`.
    pub fn field(&self, airspeed_mps: f64) -> DrydenGusts {
        DrydenGusts::new(self.sigma_mps, self.time_scales_s(airspeed_mps), self.seed)
    }

    /// The value of the flight file's `# turbulence:` line, in the layout the product's
    /// simulator writes: `LEVEL sigma_u=… sigma_v=… sigma_w=… L_u=… L_v=… L_w=… V=… seed=N`.
    pub fn record(&self, airspeed_mps: f64) -> String {
        let [su, sv, sw] = self.sigma_mps;
        let [lu, lv, lw] = self.length_m;
        format!(
            "{} sigma_u={su:.4} sigma_v={sv:.4} sigma_w={sw:.4} L_u={lu:.2} L_v={lv:.2} \
             L_w={lw:.2} V={airspeed_mps:.3} seed={}",
            self.level.name(),
            self.seed
        )
    }

    /// Why these gusts cannot be flown at `airspeed_mps`, if they cannot.
    pub fn check(&self, airspeed_mps: f64) -> Result<(), String> {
        let ok_sigma = self.sigma_mps.iter().all(|s| s.is_finite() && *s >= 0.0);
        let ok_length = self.length_m.iter().all(|l| l.is_finite() && *l > 0.0);
        if ok_sigma && ok_length && airspeed_mps.is_finite() && airspeed_mps > 0.0 {
            Ok(())
        } else {
            Err(format!(
                "gusts need σ >= 0, L > 0 and an airspeed > 0: {self:?} at {airspeed_mps} m/s"
            ))
        }
    }
}

/// Most samples of a [`GustTable`] (a table of eleven hours at 5 ms).
pub const MAX_GUST_TABLE: usize = 8_000_000;

/// Samples a sinusoid is rotated through between two exact evaluations of it: the rotation
/// adds a rounding error of about 1e-16 of its amplitude per sample, so a run this long stays
/// within 1e-13 of the cosine.
const ROTATIONS_PER_ANCHOR: usize = 1024;

/// A gust field tabulated once before a flight, read by linear interpolation: summing 1200
/// sinusoids at every stage of every integration step would cost more than the flight.
///
/// The step is 5 ms, or 1/200 of the shortest time scale when that is shorter: a sinusoid of
/// ω is interpolated with a relative error of at most (ω·step)²/8, and the Dryden spectra
/// put under 1 % of the variance above ω = 200/T (σ²·3/(π·T·ω) for v and w), so what the
/// interpolation loses is far below the sampling spread of any flight's gusts. At 5 ms
/// the grid points fall on the ends of RK4's 1 ms steps, so those steps integrate the
/// interpolated wind without straddling a kink.
#[derive(Clone, Debug, PartialEq)]
pub struct GustTable {
    /// Sample spacing, s.
    pub step_s: f64,
    /// The gust (NED, m/s) at k·step_s from flight time 0.
    pub samples: Vec<V3>,
}

impl GustTable {
    /// `gusts` at `airspeed_mps`, tabulated over [0, `duration_s`] (and one step beyond).
    pub fn new(gusts: &RefGusts, airspeed_mps: f64, duration_s: f64) -> Result<Self, String> {
        gusts.check(airspeed_mps)?;
        let shortest = gusts
            .time_scales_s(airspeed_mps)
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        let step_s = (shortest / 200.0).min(0.005);
        let count = (duration_s.max(0.0) / step_s).ceil() + 2.0;
        if count.is_nan() || count > MAX_GUST_TABLE as f64 {
            return Err(format!(
                "a gust table of {count} samples is more than {MAX_GUST_TABLE}"
            ));
        }
        let field = gusts.field(airspeed_mps);
        let mut samples = vec![[0.0; 3]; count as usize];
        for (axis, component) in field.components.iter().enumerate() {
            for &(w, a, phase) in &component.terms {
                // a·cos(ω·t + φ) as the real part of a phasor turned by ω·step per sample,
                // set exactly at the start of every run of samples.
                let (turn_s, turn_c) = (w * step_s).sin_cos();
                for (run, chunk) in samples.chunks_mut(ROTATIONS_PER_ANCHOR).enumerate() {
                    let t0 = (run * ROTATIONS_PER_ANCHOR) as f64 * step_s;
                    let (s0, c0) = (w * t0 + phase).sin_cos();
                    let (mut re, mut im) = (a * c0, a * s0);
                    for sample in chunk {
                        sample[axis] += re;
                        (re, im) = (re * turn_c - im * turn_s, re * turn_s + im * turn_c);
                    }
                }
            }
        }
        Ok(GustTable { step_s, samples })
    }

    /// The gust (NED, m/s) at flight time `t`: linear between samples, the first before 0,
    /// the last after the end.
    pub fn at(&self, t: f64) -> V3 {
        let last = self.samples.len() - 1;
        let x = (t / self.step_s).max(0.0);
        if x >= last as f64 {
            return self.samples[last];
        }
        let k = x.floor();
        let f = x - k;
        let (a, b) = (self.samples[k as usize], self.samples[k as usize + 1]);
        [0, 1, 2].map(|i| a[i] + f * (b[i] - a[i]))
    }
}
