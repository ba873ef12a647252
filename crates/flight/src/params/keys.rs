//! Every number of a fixed-wing parameter set by its key (`c_m_alpha`, `mass_kg`, …): what it
//! is, its unit, the range it may take, and the force or moment term it scales — so that a
//! coefficient, the mass or an inertia can be set, fitted and named like an effect's
//! parameter (`--add aircraft:c_m_alpha`), and so that a misfit can be described by the terms
//! that would reduce it.

use super::FixedWingParams;

/// One number of a parameter set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AircraftKey {
    /// The TOML table it lives in (`mass`, `geometry`, `longitudinal`, `lateral`,
    /// `propulsion`).
    pub table: &'static str,
    /// The key, as in the TOML file.
    pub name: &'static str,
    /// Unit ("-" for a dimensionless coefficient, per radian where it multiplies an angle).
    pub unit: &'static str,
    /// The term it scales, in words (for diagnoses: "a rolling moment ∝ p").
    pub term: &'static str,
    /// Valid values, inclusive.
    pub range: (f64, f64),
}

/// Bounds of a coefficient: generous, but finite, so a fit cannot run away.
const COEF: (f64, f64) = (-1e3, 1e3);
/// Bounds of a positive physical size.
const POSITIVE: (f64, f64) = (1e-9, 1e9);

macro_rules! keys {
    ($( $table:ident . $field:ident : $unit:literal, $term:literal, $range:expr; )*) => {
        /// Every key of a fixed-wing parameter set, in file order.
        pub static KEYS: &[AircraftKey] = &[$(
            AircraftKey {
                table: stringify!($table),
                name: stringify!($field),
                unit: $unit,
                term: $term,
                range: $range,
            },
        )*];

        /// The value of a key.
        pub fn get(p: &FixedWingParams, name: &str) -> Option<f64> {
            match name {
                $( stringify!($field) => Some(p.$table.$field), )*
                _ => None,
            }
        }

        fn slot<'a>(p: &'a mut FixedWingParams, name: &str) -> Option<&'a mut f64> {
            match name {
                $( stringify!($field) => Some(&mut p.$table.$field), )*
                _ => None,
            }
        }
    };
}

keys! {
    mass.mass_kg: "kg", "the mass: every force but gravity, inversely", POSITIVE;
    mass.jx: "kg·m²", "the roll inertia: every rolling moment, inversely", POSITIVE;
    mass.jy: "kg·m²", "the pitch inertia: every pitching moment, inversely", POSITIVE;
    mass.jz: "kg·m²", "the yaw inertia: every yawing moment, inversely", POSITIVE;
    mass.jxz: "kg·m²", "the roll–yaw product of inertia: roll and yaw coupling", (-1e9, 1e9);
    geometry.s_wing: "m²", "the wing area: every aerodynamic force and moment", POSITIVE;
    geometry.b: "m", "the span: rolling and yawing moments, and their rate terms", POSITIVE;
    geometry.c: "m", "the chord: the pitching moment and the pitch-rate terms", POSITIVE;
    geometry.e: "-", "the Oswald efficiency: induced drag, inversely", POSITIVE;
    geometry.rho: "kg/m³", "the air density: every aerodynamic force and the thrust", POSITIVE;
    longitudinal.c_l_0: "-", "a constant lift", COEF;
    longitudinal.c_l_alpha: "1/rad", "a lift ∝ α", COEF;
    longitudinal.c_l_q: "1/rad", "a lift ∝ q", COEF;
    longitudinal.c_l_delta_e: "1/rad", "a lift ∝ δe", COEF;
    longitudinal.c_d_p: "-", "a constant (parasitic) drag", COEF;
    longitudinal.c_d_q: "1/rad", "a drag ∝ q", COEF;
    longitudinal.c_d_delta_e: "1/rad", "a drag ∝ δe", COEF;
    longitudinal.c_m_0: "-", "a constant pitching moment", COEF;
    longitudinal.c_m_alpha: "1/rad", "a pitching moment ∝ α (pitch stiffness)", COEF;
    longitudinal.c_m_q: "1/rad", "a pitching moment ∝ q (pitch damping)", COEF;
    longitudinal.c_m_delta_e: "1/rad", "a pitching moment ∝ δe (elevator power)", COEF;
    longitudinal.m_blend: "-", "the sharpness of the stall", POSITIVE;
    longitudinal.alpha0: "rad", "the stall angle", POSITIVE;
    lateral.c_y_0: "-", "a constant side force", COEF;
    lateral.c_y_beta: "1/rad", "a side force ∝ β", COEF;
    lateral.c_y_p: "1/rad", "a side force ∝ p", COEF;
    lateral.c_y_r: "1/rad", "a side force ∝ r", COEF;
    lateral.c_y_delta_a: "1/rad", "a side force ∝ δa", COEF;
    lateral.c_y_delta_r: "1/rad", "a side force ∝ δr", COEF;
    lateral.c_ell_0: "-", "a constant rolling moment", COEF;
    lateral.c_ell_beta: "1/rad", "a rolling moment ∝ β (dihedral effect)", COEF;
    lateral.c_ell_p: "1/rad", "a rolling moment ∝ p (roll damping)", COEF;
    lateral.c_ell_r: "1/rad", "a rolling moment ∝ r", COEF;
    lateral.c_ell_delta_a: "1/rad", "a rolling moment ∝ δa (aileron power)", COEF;
    lateral.c_ell_delta_r: "1/rad", "a rolling moment ∝ δr", COEF;
    lateral.c_n_0: "-", "a constant yawing moment", COEF;
    lateral.c_n_beta: "1/rad", "a yawing moment ∝ β (weathercock stability)", COEF;
    lateral.c_n_p: "1/rad", "a yawing moment ∝ p", COEF;
    lateral.c_n_r: "1/rad", "a yawing moment ∝ r (yaw damping)", COEF;
    lateral.c_n_delta_a: "1/rad", "a yawing moment ∝ δa (adverse yaw)", COEF;
    lateral.c_n_delta_r: "1/rad", "a yawing moment ∝ δr (rudder power)", COEF;
    propulsion.s_prop: "m²", "the propeller disc area: the thrust", POSITIVE;
    propulsion.c_prop: "-", "the propeller coefficient: the thrust", POSITIVE;
    propulsion.k_motor: "m/s", "the motor constant: the thrust ∝ throttle²", POSITIVE;
}

/// The key of that name.
pub fn find(name: &str) -> Option<&'static AircraftKey> {
    KEYS.iter().find(|k| k.name == name)
}

/// `: did you mean `KEY`?` for the key nearest to a mistyped one, or nothing.
pub fn did_you_mean(given: &str) -> String {
    super::suggest::hint(given, KEYS.iter().map(|k| k.name))
}

/// The keys matching a pattern: a name, or a prefix ending in `*` (`c_m_*`).
pub fn matching(pattern: &str) -> Vec<&'static AircraftKey> {
    match pattern.strip_suffix('*') {
        Some(prefix) => KEYS.iter().filter(|k| k.name.starts_with(prefix)).collect(),
        None => find(pattern).into_iter().collect(),
    }
}

/// A number of a parameter set that cannot be set ([`set`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum AircraftKeyError {
    /// Not a key of [`KEYS`].
    #[error(
        "unknown aircraft parameter `{0}`{hint} (`wireflight keys` lists the keys of a \
         parameter set: c_m_alpha, c_ell_p, mass_kg, jx, …)",
        hint = did_you_mean(.0)
    )]
    Unknown(String),
    /// A value outside the key's range, or not finite.
    #[error("aircraft parameter `{name}` = {value} is outside its range [{lo}, {hi}] {unit}")]
    OutOfRange {
        /// The key.
        name: &'static str,
        /// The value refused.
        value: f64,
        /// The least valid value.
        lo: f64,
        /// The greatest valid value.
        hi: f64,
        /// The key's unit.
        unit: &'static str,
    },
    /// A value that would make the inertia tensor singular or not positive definite.
    #[error(
        "aircraft parameter `{name}` = {value} makes the inertia tensor singular \
         (Jx·Jz ≤ Jxz²)"
    )]
    SingularInertia {
        /// The key.
        name: &'static str,
        /// The value refused.
        value: f64,
    },
}

/// Set a key, checking its range and that the set stays physical (a positive-definite
/// inertia tensor).
///
/// # Errors
/// Unknown key, a value out of range, or a non-physical result; the set is left unchanged.
pub fn set(p: &mut FixedWingParams, name: &str, value: f64) -> Result<(), AircraftKeyError> {
    let key = find(name).ok_or_else(|| AircraftKeyError::Unknown(name.to_string()))?;
    let (lo, hi) = key.range;
    if !(value.is_finite() && value >= lo && value <= hi) {
        return Err(AircraftKeyError::OutOfRange {
            name: key.name,
            value,
            lo,
            hi,
            unit: key.unit,
        });
    }
    let mut next = p.clone();
    if let Some(slot) = slot(&mut next, name) {
        *slot = value;
    }
    if !next.mass.inertia_is_regular() {
        return Err(AircraftKeyError::SingularInertia {
            name: key.name,
            value,
        });
    }
    *p = next;
    Ok(())
}

/// The set as TOML, in the layout of `assets/aircraft/aerosonde.toml` (numbers written so
/// that they read back exactly), headed by `comment` lines.
pub fn to_toml(p: &FixedWingParams, comment: &str) -> String {
    let mut out = String::new();
    for line in comment.lines() {
        out.push_str("# ");
        out.push_str(line);
        out.push('\n');
    }
    out.push_str(&format!("name = {:?}\n", p.name));
    let mut table = "";
    for k in KEYS {
        if k.table != table {
            table = k.table;
            out.push_str(&format!("\n[{table}]\n"));
        }
        let v = get(p, k.name).unwrap_or(f64::NAN);
        // `{:?}` prints the shortest representation that reads back exactly, always with a
        // decimal point or exponent, so TOML reads it as a float.
        out.push_str(&format!("{} = {v:?}\n", k.name));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_reads_and_writes_its_own_field_and_the_toml_round_trips() {
        let p = FixedWingParams::aerosonde();
        assert_eq!(KEYS.len(), 44);
        let mut q = p.clone();
        for (i, k) in KEYS.iter().enumerate() {
            let v = get(&p, k.name).unwrap();
            let bumped = if v > 0.0 {
                v * 1.5
            } else {
                v - 0.25 - i as f64
            };
            set(&mut q, k.name, bumped).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(get(&q, k.name), Some(bumped), "{}", k.name);
        }
        // Each key moved exactly its own field: every other key changed too, once each.
        for k in KEYS {
            assert_ne!(get(&p, k.name), get(&q, k.name), "{}", k.name);
        }
        let text = to_toml(&q, "a test");
        let back = FixedWingParams::from_toml(&text, "round trip").unwrap();
        assert_eq!(back, q);
    }

    #[test]
    fn bad_values_are_refused_and_change_nothing() {
        let mut p = FixedWingParams::aerosonde();
        let before = p.clone();
        let message = |e: AircraftKeyError| e.to_string();
        assert!(message(set(&mut p, "mass_kg", -1.0).unwrap_err()).contains("range"));
        assert!(set(&mut p, "c_m_alpha", f64::NAN).is_err());
        assert!(message(set(&mut p, "jxz", 10.0).unwrap_err()).contains("singular"));
        let typo = message(set(&mut p, "c_m_alfa", 1.0).unwrap_err());
        assert!(
            typo.contains("unknown") && typo.contains("did you mean `c_m_alpha`?"),
            "{typo}"
        );
        assert_eq!(p, before);
        assert_eq!(matching("c_m_*").len(), 4);
        assert_eq!(matching("c_ell_p").len(), 1);
        assert!(matching("nope").is_empty());
    }
}
