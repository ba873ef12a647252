//! refsim's flights (trim, fly, record) and CSV writer.

use super::*;

/// Vehicle family of a flight.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VehicleKind {
    FixedWing,
    PointMass,
}

/// One output sample (true, noise-free values).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Row {
    /// Value of the `time_s` column.
    pub time_s: f64,
    /// Flight time (schedule time).
    pub t_flight: f64,
    pub pos: V3,
    pub vel_ned: V3,
    /// Body velocity (fixed wing).
    pub uvw: V3,
    /// φ, θ, ψ in rad, ψ unwrapped.
    pub euler: V3,
    pub pqr: V3,
    /// The air-relative speed (what an airspeed sensor reads), m/s.
    pub airspeed: f64,
    pub alpha: f64,
    pub beta: f64,
    /// The wind the aircraft is in (NED, m/s): the steady wind and, in turbulence, the gust.
    pub wind: V3,
    /// Commands in force from this row until the next.
    pub controls: Controls,
    /// Surface positions (= commands unless actuator lag).
    pub surfaces: V3,
    /// What an accelerometer at the centre of gravity reads (fixed wing): the specific force,
    /// the non-gravitational force over the mass in body axes (FRD), m/s², under the commands
    /// of this row.
    pub accel: V3,
}

/// A simulated flight.
#[derive(Clone, Debug, PartialEq)]
pub struct Flight {
    pub vehicle: VehicleKind,
    /// `# aircraft:` value (fixed wing).
    pub aircraft: String,
    pub origin: Origin,
    /// `# source:` value.
    pub source: String,
    pub mass_kg: Option<f64>,
    pub reference_area_m2: Option<f64>,
    pub rows: Vec<Row>,
    pub trim: Option<Trim>,
    pub stats: IntegStats,
    /// `# turbulence:` value (the gusts' truth, [`RefGusts::record`]) of a flight flown in
    /// turbulence.
    pub turbulence: Option<String>,
}

/// Shortest round-trip text of a number, plain decimal notation (no exponent) except for
/// magnitudes below 1e-30 or from 1e15 on, which a flight never has.
pub fn fmt_num(x: f64) -> String {
    if x == 0.0 {
        "0".to_string()
    } else if x.abs() < 1e-30 || x.abs() >= 1e15 {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

impl Flight {
    /// CSV text per flight-data.md with the given measurement noise (deterministic per seed).
    pub fn to_csv(&self, noise: &Noise, seed: u64) -> String {
        self.to_csv_with(noise, seed, false)
    }

    /// [`to_csv`](Self::to_csv), with the accelerometer columns (`ax_mps2, ay_mps2, az_mps2`,
    /// fixed wing) when `accelerometer`. Their noise (`noise.accel_mps2`) comes from a stream
    /// of its own, so the other columns are the same with and without them.
    pub fn to_csv_with(&self, noise: &Noise, seed: u64, accelerometer: bool) -> String {
        let mut rng = Rng::new(seed);
        let mut rng_acc = Rng::new(seed ^ 0xACCE_1E20_0E7E_2000);
        let mut s = String::with_capacity(self.rows.len() * 300 + 512);
        let vehicle = match self.vehicle {
            VehicleKind::FixedWing => "fixed-wing",
            VehicleKind::PointMass => "point-mass",
        };
        let _ = writeln!(s, "# vehicle: {vehicle}");
        if self.vehicle == VehicleKind::FixedWing {
            let _ = writeln!(s, "# aircraft: {}", self.aircraft);
        }
        let _ = writeln!(s, "# latitude_deg: {}", fmt_num(self.origin.latitude_deg));
        let _ = writeln!(s, "# longitude_deg: {}", fmt_num(self.origin.longitude_deg));
        let _ = writeln!(s, "# altitude_m: {}", fmt_num(self.origin.altitude_m));
        if let Some(m) = self.mass_kg {
            let _ = writeln!(s, "# mass_kg: {}", fmt_num(m));
        }
        if let Some(a) = self.reference_area_m2 {
            let _ = writeln!(s, "# reference_area_m2: {}", fmt_num(a));
        }
        let _ = writeln!(s, "# source: {}", self.source);
        if let Some(record) = &self.turbulence {
            let _ = writeln!(s, "# turbulence: {record}");
        }
        let fw = self.vehicle == VehicleKind::FixedWing;
        let acc = fw && accelerometer;
        if acc {
            s.push_str(
                "time_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,vn_mps,ve_mps,vd_mps,\
                 p_dps,q_dps,r_dps,airspeed_mps,ax_mps2,ay_mps2,az_mps2,throttle,elevator_deg,\
                 aileron_deg,rudder_deg\n",
            );
        } else if fw {
            s.push_str(
                "time_s,north_m,east_m,down_m,roll_deg,pitch_deg,yaw_deg,vn_mps,ve_mps,vd_mps,\
                 p_dps,q_dps,r_dps,airspeed_mps,throttle,elevator_deg,aileron_deg,rudder_deg\n",
            );
        } else {
            s.push_str("time_s,north_m,east_m,down_m,vn_mps,ve_mps,vd_mps\n");
        }
        let mut nz = |sd: f64| if sd > 0.0 { sd * rng.normal() } else { 0.0 };
        for r in &self.rows {
            let mut cells: Vec<f64> = Vec::with_capacity(18);
            cells.push(r.time_s);
            for k in 0..3 {
                cells.push(r.pos[k] + nz(noise.position_m));
            }
            if fw {
                let roll = wrap_deg(r.euler[0] / DEG + nz(noise.attitude_deg));
                let pitch = r.euler[1] / DEG + nz(noise.attitude_deg);
                let yaw = wrap_deg(r.euler[2] / DEG + nz(noise.attitude_deg));
                cells.extend([roll, pitch, yaw]);
            }
            for k in 0..3 {
                cells.push(r.vel_ned[k] + nz(noise.velocity_mps));
            }
            if fw {
                for k in 0..3 {
                    cells.push(r.pqr[k] / DEG + nz(noise.rate_dps));
                }
                cells.push(r.airspeed + nz(noise.airspeed_mps));
                if acc {
                    for k in 0..3 {
                        let e = if noise.accel_mps2 > 0.0 {
                            noise.accel_mps2 * rng_acc.normal()
                        } else {
                            0.0
                        };
                        cells.push(r.accel[k] + e);
                    }
                }
                let c = r.controls;
                cells.extend([
                    c.throttle,
                    c.elevator / DEG,
                    c.aileron / DEG,
                    c.rudder / DEG,
                ]);
            }
            for (i, v) in cells.iter().enumerate() {
                if i > 0 {
                    s.push(',');
                }
                s.push_str(&fmt_num(*v));
            }
            s.push('\n');
        }
        s
    }

    /// Noise-free CSV.
    pub fn to_csv_exact(&self) -> String {
        self.to_csv(&Noise::none(), 0)
    }
}

/// Options of a fixed-wing flight.
#[derive(Clone, Debug, PartialEq)]
pub struct FlightOptions {
    pub params: Params,
    pub effects: Effects,
    pub origin: Origin,
    pub integrator: Integrator,
    pub schedule: Schedule,
    pub gains: Gains,
    pub noise: Noise,
    pub seed: u64,
    /// Output (= autopilot) rate, Hz.
    pub rate_hz: f64,
    /// Recorded duration, s (rows = round(duration·rate) + 1).
    pub duration_s: f64,
    /// Start height above the NED origin (down = −height), m.
    pub start_height_m: f64,
    /// Trim airspeed, m/s.
    pub airspeed_mps: f64,
    pub heading_deg: f64,
    /// `time_s` of the first recorded row.
    pub time_offset_s: f64,
    /// Flight time at which recording starts (initial transient), s; rounded to the sample grid.
    pub record_start_s: f64,
    /// `# aircraft:` value.
    pub aircraft: String,
    /// `# source:` value; None = "refsim (<integrator>, <schedule>)".
    pub source: Option<String>,
    /// Gusts to fly through (on top of the steady wind of `effects`); None = calm air. The
    /// trim, the schedule and the noise draw are those of the calm flight.
    pub turbulence: Option<RefGusts>,
}

impl FlightOptions {
    /// Defaults: Aerosonde, baseline effects, default origin, RK4 1 ms, 50 Hz, the schedule's
    /// duration, 200 m, 25 m/s, heading 0, no offsets, no noise, seed 1.
    pub fn new(schedule: Schedule) -> Self {
        FlightOptions {
            params: Params::aerosonde(),
            effects: Effects::none(),
            origin: Origin::default(),
            integrator: Integrator::rk4_1ms(),
            duration_s: schedule.duration_s,
            schedule,
            gains: Gains::default(),
            noise: Noise::none(),
            seed: 1,
            rate_hz: 50.0,
            start_height_m: 200.0,
            airspeed_mps: 25.0,
            heading_deg: 0.0,
            time_offset_s: 0.0,
            record_start_s: 0.0,
            aircraft: "aerosonde".into(),
            source: None,
            turbulence: None,
        }
    }

    /// These options in MIL-F-8785C turbulence of `level` at the start height (set the start
    /// height first), gust phases from `gust_seed`.
    pub fn in_turbulence(mut self, level: GustLevel, gust_seed: u64) -> Self {
        self.turbulence = Some(RefGusts::mil_8785c(level, self.start_height_m, gust_seed));
        self
    }
}

pub(super) fn valid_pos(x: f64) -> bool {
    x.is_finite() && x > 0.0
}

pub(super) fn valid_nonneg(x: f64) -> bool {
    x.is_finite() && x >= 0.0
}

/// Fly a fixed-wing flight: trim, then per sample: command (ZOH) → integrate to the next sample.
/// In turbulence the gusts are tabulated first and the wind is read at every integration
/// stage's own time.
pub fn fly(opts: &FlightOptions) -> Result<Flight, String> {
    if !valid_pos(opts.rate_hz)
        || !valid_nonneg(opts.duration_s)
        || !valid_nonneg(opts.record_start_s)
    {
        return Err("rate must be > 0, duration and record start >= 0".into());
    }
    let model = FwModel::new(&opts.params, &opts.effects, &opts.origin);
    let tr = trim(
        &model,
        opts.airspeed_mps,
        opts.start_height_m,
        opts.heading_deg,
    )?;
    let rate = opts.rate_hz;
    let dt = 1.0 / rate;
    let n_pre = (opts.record_start_s * rate).round() as usize;
    let n_rec = (opts.duration_s * rate).round() as usize;
    let gusts = match &opts.turbulence {
        Some(g) => Some(GustTable::new(
            g,
            opts.airspeed_mps,
            (n_pre + n_rec) as f64 / rate,
        )?),
        None => None,
    };
    // The wind at flight time t: in calm air the steady wind itself (not plus a zero gust,
    // so a calm flight's numbers owe nothing to the gust code), in turbulence plus the gust
    // of the moment.
    let wind_at = |t: f64| match &gusts {
        Some(table) => v_add(model.env.wind, table.at(t)),
        None => model.env.wind,
    };
    let mut x = tr.state;
    let mut ap = ApState::default();
    let mut stepper = Stepper::new(opts.integrator);
    let mut rows = Vec::with_capacity(n_rec + 1);
    for i in 0..=(n_pre + n_rec) {
        let t = i as f64 / rate;
        let wind = wind_at(t);
        let cmd = command_at(
            &model,
            &opts.schedule,
            &opts.gains,
            &tr,
            &mut ap,
            t,
            &x,
            wind,
            dt,
        );
        if i >= n_pre {
            let r = rot_body_to_ned(x[ix::PHI], x[ix::THETA], x[ix::PSI]);
            let uvw = [x[ix::U], x[ix::V], x[ix::W]];
            let (va, alpha, beta) = air_data_in(&x, wind);
            let (force, _) = model.force_moment_in(&x, &cmd, wind);
            rows.push(Row {
                time_s: opts.time_offset_s + (i - n_pre) as f64 / rate,
                t_flight: t,
                pos: [x[ix::N], x[ix::E], x[ix::D]],
                vel_ned: m_vec(&r, uvw),
                uvw,
                euler: [x[ix::PHI], x[ix::THETA], x[ix::PSI]],
                pqr: [x[ix::P], x[ix::Q], x[ix::R]],
                airspeed: va,
                alpha,
                beta,
                wind,
                controls: cmd,
                surfaces: model.surfaces(&x, &cmd),
                accel: v_scale(force, 1.0 / opts.params.mass_kg),
            });
        }
        if i < n_pre + n_rec {
            let span = (i + 1) as f64 / rate - t;
            stepper.advance_in_time(&mut x, span, |s, y| {
                model.derivative_in(y, &cmd, wind_at(t + s))
            });
            if x.iter().any(|v| !v.is_finite()) {
                return Err(format!("state became non-finite at t = {t}"));
            }
        }
    }
    let source = opts.source.clone().unwrap_or_else(|| {
        format!(
            "refsim (independent reference simulator; {}; schedule {})",
            opts.integrator.describe(),
            opts.schedule.name
        )
    });
    Ok(Flight {
        vehicle: VehicleKind::FixedWing,
        aircraft: opts.aircraft.clone(),
        origin: opts.origin,
        source,
        mass_kg: None,
        reference_area_m2: None,
        rows,
        trim: Some(tr),
        stats: stepper.stats,
        turbulence: opts
            .turbulence
            .as_ref()
            .map(|g| g.record(opts.airspeed_mps)),
    })
}

/// Fly and write CSV with `opts.noise` / `opts.seed`.
pub fn flight_csv(opts: &FlightOptions) -> Result<String, String> {
    Ok(fly(opts)?.to_csv(&opts.noise, opts.seed))
}

/// [`flight_csv`] with the accelerometer columns.
pub fn flight_csv_with_accelerometer(opts: &FlightOptions) -> Result<String, String> {
    Ok(fly(opts)?.to_csv_with(&opts.noise, opts.seed, true))
}
