//! How numbers are written for people, in every table, label and plot of wireflight: a fixed
//! count of decimals or four significant digits, "n/a" for what is not finite, and never
//! "-0" (a rounded −0.0004 is "0.000", not "-0.000").

/// Four significant digits, in scientific notation when small (drag's k is ~1e-4) or large;
/// never "-0".
pub fn fmt_number(x: f64) -> String {
    if !x.is_finite() {
        return "n/a".into();
    }
    let s = if x != 0.0 && (x.abs() < 1e-2 || x.abs() >= 1e5) {
        format!("{x:.3e}")
    } else {
        format!("{x:.4}")
    };
    no_negative_zero(s)
}

/// A number with a fixed count of decimals, never "-0.000".
pub fn fixed(x: f64, decimals: usize) -> String {
    if !x.is_finite() {
        return "n/a".into();
    }
    no_negative_zero(format!("{x:.decimals$}"))
}

/// A signed number with a fixed count of decimals ("+0.12", "−0.40"), never "-0".
pub fn signed(x: f64, decimals: usize) -> String {
    let s = fixed(x, decimals);
    if s.starts_with('-') || s == "n/a" {
        s
    } else {
        format!("+{s}")
    }
}

fn no_negative_zero(s: String) -> String {
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.' || c == 'e') => rest.to_string(),
        _ => s,
    }
}
