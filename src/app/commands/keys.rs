//! `wireflight keys`: every `aircraft:KEY` of a fixed-wing parameter set, with its unit, its
//! valid range, its meaning and its value in a set.

use crate::app::cli::KeysArgs;
use crate::flight::params::keys::KEYS;
use crate::flight::params::FixedWingParams;
use crate::numeric::format::fmt_number;

/// Run `wireflight keys`.
///
/// # Errors
/// An unknown or unreadable parameter set.
pub fn run(args: &KeysArgs) -> anyhow::Result<()> {
    let set = FixedWingParams::load(&args.aircraft)?;
    print!("{}", table(&set));
    Ok(())
}

/// A range bound for people: plain where short, in powers of ten where huge or tiny.
fn bound(x: f64) -> String {
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
}
