//! refsim's point mass.

use super::*;

/// Point-mass derivative: state [n, e, d, vn, ve, vd].
pub fn point_mass_derivative(env: &Env, drag: Option<f64>, y: &[f64; 6]) -> [f64; 6] {
    let pos = [y[0], y[1], y[2]];
    let v = [y[3], y[4], y[5]];
    let g = env.g(y[2]);
    let mut a = [0.0, 0.0, g];
    if let Some(k) = drag {
        let vr = v_sub(v, env.wind);
        let scale = if env.density_altitude {
            env.rho(y[2]) / RHO_SL
        } else {
            1.0
        };
        a = v_add(a, v_scale(vr, -k * scale * v_norm(vr)));
    }
    a = v_add(a, env.extra_accel_ned(pos, v, g));
    [v[0], v[1], v[2], a[0], a[1], a[2]]
}

/// Options of a ballistic (point-mass) flight.
#[derive(Clone, Debug, PartialEq)]
pub struct BallisticOptions {
    pub speed_mps: f64,
    /// Launch elevation above the horizon, deg.
    pub elevation_deg: f64,
    /// Launch azimuth from north toward east, deg.
    pub azimuth_deg: f64,
    pub start_height_m: f64,
    /// Effects; `drag` holds k.
    pub effects: Effects,
    pub origin: Origin,
    pub integrator: Integrator,
    pub rate_hz: f64,
    pub duration_s: f64,
    pub time_offset_s: f64,
    pub noise: Noise,
    pub seed: u64,
    pub mass_kg: Option<f64>,
    pub reference_area_m2: Option<f64>,
    /// Stop after the first sample with down > 0 (below the ground plane).
    pub stop_at_ground: bool,
    pub source: Option<String>,
}

impl BallisticOptions {
    /// Launch preset: speed, elevation, azimuth; from the origin (height 0), 50 Hz, 10 s, RK4 1 ms.
    pub fn launch(speed_mps: f64, elevation_deg: f64, azimuth_deg: f64) -> Self {
        BallisticOptions {
            speed_mps,
            elevation_deg,
            azimuth_deg,
            start_height_m: 0.0,
            effects: Effects::none(),
            origin: Origin::default(),
            integrator: Integrator::rk4_1ms(),
            rate_hz: 50.0,
            duration_s: 10.0,
            time_offset_s: 0.0,
            noise: Noise::none(),
            seed: 1,
            mass_kg: None,
            reference_area_m2: None,
            stop_at_ground: false,
            source: None,
        }
    }

    /// Initial NED velocity.
    pub fn initial_velocity(&self) -> V3 {
        let (se, ce) = (self.elevation_deg * DEG).sin_cos();
        let (sa, ca) = (self.azimuth_deg * DEG).sin_cos();
        [
            self.speed_mps * ce * ca,
            self.speed_mps * ce * sa,
            -self.speed_mps * se,
        ]
    }
}

/// Fly a point-mass flight.
pub fn fly_ballistic(opts: &BallisticOptions) -> Result<Flight, String> {
    if !valid_pos(opts.rate_hz) || !valid_nonneg(opts.duration_s) {
        return Err("rate must be > 0 and duration >= 0".into());
    }
    let env = Env::new(&opts.effects, &opts.origin, RHO_SL);
    let v0 = opts.initial_velocity();
    let mut y = [0.0, 0.0, -opts.start_height_m, v0[0], v0[1], v0[2]];
    let n = (opts.duration_s * opts.rate_hz).round() as usize;
    let mut stepper = Stepper::new(opts.integrator);
    let mut rows = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let t = i as f64 / opts.rate_hz;
        rows.push(Row {
            time_s: opts.time_offset_s + t,
            t_flight: t,
            pos: [y[0], y[1], y[2]],
            vel_ned: [y[3], y[4], y[5]],
            airspeed: v_norm(v_sub([y[3], y[4], y[5]], env.wind)),
            wind: env.wind,
            ..Row::default()
        });
        if opts.stop_at_ground && y[2] > 0.0 {
            break;
        }
        if i < n {
            let span = (i + 1) as f64 / opts.rate_hz - t;
            stepper.advance(&mut y, span, |s| {
                point_mass_derivative(&env, opts.effects.drag, s)
            });
        }
    }
    let source = opts.source.clone().unwrap_or_else(|| {
        format!(
            "refsim (independent reference simulator; {}; ballistic launch {} m/s, elevation {} deg, azimuth {} deg)",
            opts.integrator.describe(),
            opts.speed_mps,
            opts.elevation_deg,
            opts.azimuth_deg
        )
    });
    Ok(Flight {
        vehicle: VehicleKind::PointMass,
        aircraft: String::new(),
        origin: opts.origin,
        source,
        mass_kg: opts.mass_kg,
        reference_area_m2: opts.reference_area_m2,
        rows,
        trim: None,
        stats: stepper.stats,
        turbulence: None,
    })
}

/// Fly a ballistic flight and write CSV with `opts.noise` / `opts.seed`.
pub fn ballistic_csv(opts: &BallisticOptions) -> Result<String, String> {
    Ok(fly_ballistic(opts)?.to_csv(&opts.noise, opts.seed))
}
