//! How numbers are written for people, in every table, label and plot of wireflight: a fixed
//! count of decimals or four significant digits, "n/a" for what is not finite, and never
//! "-0" (a rounded −0.0004 is "0.000", not "-0.000"). And how text from input is quoted in a
//! message: an excerpt, never a whole 100 MB line.

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

/// Most characters of input a message quotes ([`excerpt`]).
pub const EXCERPT_CHARS: usize = 120;

/// `text` as a message quotes it: whole when short, else its first [`EXCERPT_CHARS`]
/// characters and how many more there were.
pub fn excerpt(text: &str) -> String {
    let mut chars = text.chars();
    let head: String = chars.by_ref().take(EXCERPT_CHARS).collect();
    match chars.count() {
        0 => head,
        more => format!("{head}… ({more} more characters)"),
    }
}

/// A TOML reader's error on `text` in one bounded line: `line L, column C: WHAT` and an
/// excerpt of the text from where it is (the reader's own message repeats the whole line and
/// a caret line as long: hundreds of megabytes for one long line).
pub fn toml_problem(text: &str, e: &toml::de::Error) -> String {
    let what = e.message().trim_end();
    let Some(span) = e.span() else {
        return excerpt(what);
    };
    let at = span.start.min(text.len());
    let at = (0..=at)
        .rev()
        .find(|&i| text.is_char_boundary(i))
        .unwrap_or(0);
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    // The line around the place: up to 40 characters before it, an excerpt after.
    let before_here: Vec<char> = before[line_start..].chars().collect();
    let lead = before_here.len().saturating_sub(40);
    let shown_before: String = before_here[lead..].iter().collect();
    let after = text[at..].lines().next().unwrap_or("");
    let ellipsis = if lead > 0 { "…" } else { "" };
    format!(
        "line {line}, column {column}: {} (near `{ellipsis}{shown_before}{}`)",
        excerpt(what),
        excerpt(after)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_toml_line_is_quoted_short() {
        // An error early in a long line: the excerpt after it is cut.
        let text = format!("a = 1\nb = = \"{}\"\n", "x".repeat(300_000));
        let e = text.parse::<toml::Table>().unwrap_err();
        let m = toml_problem(&text, &e);
        assert!(m.starts_with("line 2, column 5: "), "{m}");
        assert!(m.len() < 600 && m.contains("more characters"), "{m:.300}");
        // At the end of a long line: the 40 characters before it.
        let text = format!("b = \"{}\n", "y".repeat(300_000));
        let e = text.parse::<toml::Table>().unwrap_err();
        let m = toml_problem(&text, &e);
        assert!(
            m.len() < 600 && m.contains(&format!("…{}", "y".repeat(40))),
            "{m:.300}"
        );
        assert_eq!(excerpt("short"), "short");
    }
}
