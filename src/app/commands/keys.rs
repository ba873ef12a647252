//! `wireflight keys`: every `aircraft:KEY` of a fixed-wing parameter set, with its unit, its
//! valid range, its meaning and its value in a set (as a table, or JSON with `--json`).

use serde_json::{json, Value};

use crate::app::cli::KeysArgs;
use crate::data::format::fmt_number;
use crate::flight::params::keys::KEYS;
use crate::flight::params::FixedWingParams;

/// Run `wireflight keys`.
///
/// # Errors
/// An unknown or unreadable parameter set.
pub fn run(args: &KeysArgs) -> anyhow::Result<()> {
    let set = FixedWingParams::load(&args.aircraft)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&to_json(&set))?);
    } else {
        print!("{}", table(&set));
    }
    Ok(())
}

/// What `keys --json` prints for a set: its name, and every key with its table, unit, range
/// `[lo, hi]`, value in the set and meaning. A value that is not finite is `null` (JSON has no
/// NaN), as serde_json writes any non-finite number.
pub fn to_json(set: &FixedWingParams) -> Value {
    let keys: Vec<Value> = KEYS
        .iter()
        .map(|k| {
            json!({
                "key": k.name,
                "table": k.table,
                "unit": k.unit,
                "range": [k.range.0, k.range.1],
                "value": crate::flight::params::keys::get(set, k.name),
                "meaning": k.term,
            })
        })
        .collect();
    json!({ "aircraft": set.name, "keys": keys })
}

/// A range bound for people: plain where short, in powers of ten where huge or tiny.
pub(super) fn bound(x: f64) -> String {
    if x != 0.0 && (x.abs() >= 1e4 || x.abs() < 1e-3) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// The table `keys` prints for a set.
pub fn table(set: &FixedWingParams) -> String {
    let name = if set.name.is_empty() {
        "value"
    } else {
        set.name.as_str()
    };
    let value_width = name.chars().count().max(10);
    let mut out = format!(
        "aircraft:KEY: the {} numbers of a fixed-wing parameter set ({name}); \
         --add aircraft:KEY fits one, --add/--hidden aircraft:KEY=VALUE sets it, identify --free \
         KEY,PREFIX* fits many\n",
        KEYS.len()
    );
    out += &format!(
        "  {:<15} {:<7} {:<12} {:>value_width$}  meaning\n",
        "key", "unit", "range", name
    );
    let mut table = "";
    for k in KEYS {
        if k.table != table {
            table = k.table;
            out += &format!("[{table}]\n");
        }
        let value = crate::flight::params::keys::get(set, k.name).unwrap_or(f64::NAN);
        let range = format!("{}..{}", bound(k.range.0), bound(k.range.1));
        out += &format!(
            "  {:<15} {:<7} {:<12} {:>value_width$}  {}\n",
            k.name,
            k.unit,
            range,
            fmt_number(value),
            k.term
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_is_listed_once_with_unit_range_and_meaning() {
        let text = table(&FixedWingParams::aerosonde());
        for k in KEYS {
            let line = text
                .lines()
                .find(|l| l.split_whitespace().next() == Some(k.name))
                .unwrap_or_else(|| panic!("{} missing:\n{text}", k.name));
            assert!(line.contains(k.unit) && line.contains(k.term), "{line}");
        }
        assert_eq!(bound(-1e3), "-1000");
        assert_eq!(bound(1e-9), "1e-9");
        assert_eq!(bound(1e9), "1e9");
    }

    #[test]
    fn json_has_every_key_and_stays_valid_with_a_value_that_is_not_finite() {
        let mut set = FixedWingParams::aerosonde();
        set.mass.mass_kg = f64::NAN;
        set.longitudinal.c_m_alpha = f64::INFINITY;
        let text = serde_json::to_string_pretty(&to_json(&set)).unwrap();
        let v: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["aircraft"], "aerosonde");
        let keys = v["keys"].as_array().unwrap();
        assert_eq!(keys.len(), KEYS.len());
        for (k, j) in KEYS.iter().zip(keys) {
            assert_eq!(j["key"], k.name);
            assert_eq!(j["table"], k.table);
            assert_eq!(j["unit"], k.unit);
            assert_eq!(j["meaning"], k.term);
            assert_eq!(j["range"], json!([k.range.0, k.range.1]), "{}", k.name);
        }
        let value = |name: &str| keys.iter().find(|j| j["key"] == name).unwrap()["value"].clone();
        assert_eq!(value("mass_kg"), Value::Null);
        assert_eq!(value("c_m_alpha"), Value::Null);
        assert_eq!(value("c_m_q"), json!(-38.21));
    }
}
