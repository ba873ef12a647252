//! refsim's own noise: SplitMix64 seeding xoshiro256**, Box–Muller.

/// xoshiro256** seeded by SplitMix64, normals by Box–Muller.
#[derive(Clone, Debug)]
pub struct Rng {
    s: [u64; 4],
    spare: Option<f64>,
}

impl Rng {
    pub fn new(seed: u64) -> Self {
        let mut sm = seed;
        let mut next = || {
            sm = sm.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = sm;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        Rng {
            s: [next(), next(), next(), next()],
            spare: None,
        }
    }
    pub fn next_u64(&mut self) -> u64 {
        let result = self.s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = self.s[1] << 17;
        self.s[2] ^= self.s[0];
        self.s[3] ^= self.s[1];
        self.s[1] ^= self.s[2];
        self.s[0] ^= self.s[3];
        self.s[2] ^= t;
        self.s[3] = self.s[3].rotate_left(45);
        result
    }
    /// Uniform in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
    }
    /// Standard normal.
    pub fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        let u1 = self.uniform();
        let u2 = self.uniform();
        let r = (-2.0 * u1.ln()).sqrt();
        let (s, c) = (2.0 * std::f64::consts::PI * u2).sin_cos();
        self.spare = Some(r * s);
        r * c
    }
}

/// Measurement noise standard deviations per channel. Controls are never noised.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Noise {
    pub position_m: f64,
    pub attitude_deg: f64,
    pub velocity_mps: f64,
    pub rate_dps: f64,
    pub airspeed_mps: f64,
    /// Accelerometer, m/s² per axis (written only by `Flight::to_csv_with`).
    pub accel_mps2: f64,
}

impl Noise {
    pub fn none() -> Self {
        Noise::default()
    }
    pub fn new(
        position_m: f64,
        attitude_deg: f64,
        velocity_mps: f64,
        rate_dps: f64,
        airspeed_mps: f64,
    ) -> Self {
        Noise {
            position_m,
            attitude_deg,
            velocity_mps,
            rate_dps,
            airspeed_mps,
            accel_mps2: 0.0,
        }
    }
    pub fn is_none(&self) -> bool {
        *self == Noise::default()
    }
}
