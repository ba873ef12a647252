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

use super::Rng;

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
