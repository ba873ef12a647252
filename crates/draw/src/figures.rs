//! Numbers as the pictures write them. Fixed decimals, "n/a" for what is not finite and never
//! "-0" come from [`wireflight_data::format`], the one number formatter; what pictures add on
//! top is here: decimals chosen by the number's size, for labels and titles that show a value
//! of any size in a few characters. (The plots' typographic minus sign and tick labels are in
//! `wireflight-present`'s `plots::style`.)

use wireflight_data::format::fixed;

/// About three significant figures: decimals by magnitude (none from 100, one from 10, two
/// from 1, three below), "0" for zero or what rounds to it, "n/a" for what is not finite:
/// `0`, `0.042`, `3.25`, `41.7`, `1250`.
pub fn three_figures(v: f64) -> String {
    let a = v.abs();
    let decimals = if a >= 100.0 {
        0
    } else if a >= 10.0 {
        1
    } else if a >= 1.0 {
        2
    } else {
        3
    };
    let s = fixed(v, decimals);
    if s.chars().all(|c| c == '0' || c == '.') {
        "0".to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn about_three_figures() {
        assert_eq!(three_figures(0.0), "0");
        assert_eq!(three_figures(-0.0001), "0");
        assert_eq!(three_figures(0.0421), "0.042");
        assert_eq!(three_figures(-0.0421), "-0.042");
        assert_eq!(three_figures(3.254), "3.25");
        assert_eq!(three_figures(41.66), "41.7");
        assert_eq!(three_figures(1250.2), "1250");
        assert_eq!(three_figures(f64::NAN), "n/a");
    }
}
