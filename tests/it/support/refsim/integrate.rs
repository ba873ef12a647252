//! refsim's integrators: classic RK4 with a fixed step, adaptive Dormand–Prince 5(4).

/// Which integrator advances the state over each output interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Classic RK4, fixed step (the interval is split into ceil(interval/dt_s) equal steps).
    Rk4 { dt_s: f64 },
    /// Dormand–Prince 5(4), adaptive, error per component atol + rtol·|y| (RMS norm).
    DormandPrince { rtol: f64, atol: f64 },
}

impl Integrator {
    /// RK4 with a 1 ms step (the default).
    pub fn rk4_1ms() -> Self {
        Integrator::Rk4 { dt_s: 1e-3 }
    }
    /// Dormand–Prince with atol = rtol·1e-2.
    pub fn dopri(rtol: f64) -> Self {
        Integrator::DormandPrince {
            rtol,
            atol: rtol * 1e-2,
        }
    }
    pub fn describe(&self) -> String {
        match self {
            Integrator::Rk4 { dt_s } => format!("RK4 dt {} ms", dt_s * 1e3),
            Integrator::DormandPrince { rtol, atol } => {
                format!("Dormand-Prince 5(4) rtol {rtol:e} atol {atol:e}")
            }
        }
    }
}

/// Counters of one run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IntegStats {
    pub evals: u64,
    pub steps: u64,
    pub rejected: u64,
}

/// Advances a state over given spans, remembering the adaptive step between calls.
#[derive(Clone, Debug)]
pub struct Stepper {
    pub integrator: Integrator,
    pub h_next: f64,
    pub stats: IntegStats,
}

fn axpy<const N: usize>(y: &[f64; N], h: f64, terms: &[(f64, &[f64; N])]) -> [f64; N] {
    let mut out = *y;
    for (i, o) in out.iter_mut().enumerate() {
        let mut s = 0.0;
        for (c, k) in terms {
            s += c * k[i];
        }
        *o += h * s;
    }
    out
}

impl Stepper {
    pub fn new(integrator: Integrator) -> Self {
        Stepper {
            integrator,
            h_next: 1e-3,
            stats: IntegStats::default(),
        }
    }

    /// Integrate the autonomous system ẏ = f(y) from 0 to `span`.
    pub fn advance<const N: usize, F: Fn(&[f64; N]) -> [f64; N]>(
        &mut self,
        y: &mut [f64; N],
        span: f64,
        f: F,
    ) {
        self.advance_in_time(y, span, |_, y| f(y));
    }

    /// Integrate ẏ = f(s, y) from s = 0 to `span` (s the time since the span began: a wind
    /// that varies in time is read at every stage's own time).
    pub fn advance_in_time<const N: usize, F: Fn(f64, &[f64; N]) -> [f64; N]>(
        &mut self,
        y: &mut [f64; N],
        span: f64,
        f: F,
    ) {
        if span <= 0.0 {
            return;
        }
        match self.integrator {
            Integrator::Rk4 { dt_s } => {
                let n = ((span / dt_s) - 1e-9).ceil().max(1.0) as usize;
                let h = span / n as f64;
                for k in 0..n {
                    let (s0, s1) = (k as f64 * h, (k + 1) as f64 * h);
                    let mid = 0.5 * (s0 + s1);
                    let k1 = f(s0, y);
                    let k2 = f(mid, &axpy(y, 0.5 * h, &[(1.0, &k1)]));
                    let k3 = f(mid, &axpy(y, 0.5 * h, &[(1.0, &k2)]));
                    let k4 = f(s1, &axpy(y, h, &[(1.0, &k3)]));
                    *y = axpy(
                        y,
                        h / 6.0,
                        &[(1.0, &k1), (2.0, &k2), (2.0, &k3), (1.0, &k4)],
                    );
                    self.stats.evals += 4;
                    self.stats.steps += 1;
                }
            }
            Integrator::DormandPrince { rtol, atol } => self.dopri(y, span, &f, rtol, atol),
        }
    }

    fn dopri<const N: usize, F: Fn(f64, &[f64; N]) -> [f64; N]>(
        &mut self,
        y: &mut [f64; N],
        span: f64,
        f: &F,
        rtol: f64,
        atol: f64,
    ) {
        const C2: f64 = 1.0 / 5.0;
        const C3: f64 = 3.0 / 10.0;
        const C4: f64 = 4.0 / 5.0;
        const C5: f64 = 8.0 / 9.0;
        const A21: f64 = 1.0 / 5.0;
        const A31: f64 = 3.0 / 40.0;
        const A32: f64 = 9.0 / 40.0;
        const A41: f64 = 44.0 / 45.0;
        const A42: f64 = -56.0 / 15.0;
        const A43: f64 = 32.0 / 9.0;
        const A51: f64 = 19372.0 / 6561.0;
        const A52: f64 = -25360.0 / 2187.0;
        const A53: f64 = 64448.0 / 6561.0;
        const A54: f64 = -212.0 / 729.0;
        const A61: f64 = 9017.0 / 3168.0;
        const A62: f64 = -355.0 / 33.0;
        const A63: f64 = 46732.0 / 5247.0;
        const A64: f64 = 49.0 / 176.0;
        const A65: f64 = -5103.0 / 18656.0;
        const B1: f64 = 35.0 / 384.0;
        const B3: f64 = 500.0 / 1113.0;
        const B4: f64 = 125.0 / 192.0;
        const B5: f64 = -2187.0 / 6784.0;
        const B6: f64 = 11.0 / 84.0;
        const E1: f64 = 71.0 / 57600.0;
        const E3: f64 = -71.0 / 16695.0;
        const E4: f64 = 71.0 / 1920.0;
        const E5: f64 = -17253.0 / 339200.0;
        const E6: f64 = 22.0 / 525.0;
        const E7: f64 = -1.0 / 40.0;

        let mut t = 0.0;
        let mut k1 = f(0.0, y);
        self.stats.evals += 1;
        let mut h = self.h_next.min(span);
        loop {
            let remaining = span - t;
            let last = h >= remaining * (1.0 - 1e-12);
            let hh = if last { remaining } else { h };
            let k2 = f(t + C2 * hh, &axpy(y, hh, &[(A21, &k1)]));
            let k3 = f(t + C3 * hh, &axpy(y, hh, &[(A31, &k1), (A32, &k2)]));
            let k4 = f(
                t + C4 * hh,
                &axpy(y, hh, &[(A41, &k1), (A42, &k2), (A43, &k3)]),
            );
            let k5 = f(
                t + C5 * hh,
                &axpy(y, hh, &[(A51, &k1), (A52, &k2), (A53, &k3), (A54, &k4)]),
            );
            let k6 = f(
                t + hh,
                &axpy(
                    y,
                    hh,
                    &[(A61, &k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)],
                ),
            );
            let y5 = axpy(
                y,
                hh,
                &[(B1, &k1), (B3, &k3), (B4, &k4), (B5, &k5), (B6, &k6)],
            );
            // The next step's first stage (FSAL), at its start.
            let k7 = f(t + hh, &y5);
            self.stats.evals += 6;
            let mut acc = 0.0;
            for i in 0..N {
                let e = hh
                    * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
                let sc = atol + rtol * y[i].abs().max(y5[i].abs());
                acc += (e / sc) * (e / sc);
            }
            let err = (acc / N as f64).sqrt();
            let factor = if err == 0.0 {
                5.0
            } else {
                (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            };
            if err <= 1.0 {
                *y = y5;
                k1 = k7;
                self.stats.steps += 1;
                if last {
                    self.h_next = h.max(hh * factor).min(1.0);
                    break;
                }
                t += hh;
                h = (hh * factor).min(1.0);
            } else {
                self.stats.rejected += 1;
                h = hh * factor.min(1.0);
            }
            assert!(h > 1e-14, "Dormand-Prince: step size underflow");
        }
    }
}
