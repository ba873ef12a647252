//! "Did you mean …": the nearest known name to a mistyped one, by edit distance, for the
//! messages that refuse an aircraft key (`aircraft:c_m_alfa`), an effect (`--add wnd`) or an
//! effect's parameter (`wind:nort_mps=3`). Every command resolves those names through
//! [`crate::spec`], [`crate::effects`] and [`super::keys`], so every command gets the hint.

/// The edit distance between `a` and `b` (optimal string alignment: insertions, deletions,
/// substitutions and swaps of two neighbours each cost 1), case-insensitive.
pub fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.to_lowercase().chars().collect();
    let b: Vec<char> = b.to_lowercase().chars().collect();
    // Three rows: two back (for swaps), one back, this one.
    let mut prev2 = vec![0usize; b.len() + 1];
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut row = vec![0usize; b.len() + 1];
    for i in 1..=a.len() {
        row[0] = i;
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut d = (prev[j] + 1).min(row[j - 1] + 1).min(prev[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(prev2[j - 2] + 1);
            }
            row[j] = d;
        }
        std::mem::swap(&mut prev2, &mut prev);
        std::mem::swap(&mut prev, &mut row);
    }
    prev[b.len()]
}

/// The known name nearest to `given`, if it is near enough to be a slip: within about one
/// edit per three characters (at least 1, at most 3), or a name that `given` (3 characters or
/// more) begins. Ties go to the earlier name.
pub fn nearest<'a, I>(given: &str, known: I) -> Option<&'a str>
where
    I: IntoIterator<Item = &'a str>,
{
    let given = given.trim();
    if given.is_empty() {
        return None;
    }
    let n = given.chars().count();
    let limit = n.div_ceil(3).clamp(1, 3);
    let lower = given.to_lowercase();
    let mut best: Option<(usize, &'a str)> = None;
    for name in known {
        if name == given {
            continue;
        }
        let d = if n >= 3 && name.to_lowercase().starts_with(&lower) {
            1
        } else {
            distance(given, name)
        };
        if d <= limit && best.is_none_or(|(b, _)| d < b) {
            best = Some((d, name));
        }
    }
    best.map(|(_, name)| name)
}

/// `: did you mean `NAME`?` for the nearest known name, or nothing: written right after the
/// mistyped name in a message.
pub fn hint<'a, I>(given: &str, known: I) -> String
where
    I: IntoIterator<Item = &'a str>,
{
    nearest(given, known)
        .map(|name| format!(": did you mean `{name}`?"))
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_counts_edits_and_swaps() {
        assert_eq!(distance("", "abc"), 3);
        assert_eq!(distance("wind", "wind"), 0);
        assert_eq!(distance("wnd", "wind"), 1);
        assert_eq!(distance("wnid", "wind"), 1, "a swap");
        assert_eq!(distance("c_m_alfa", "c_m_alpha"), 2);
        assert_eq!(distance("Drag", "drag"), 0);
    }

    #[test]
    fn nearest_suggests_slips_only() {
        let effects = ["wind", "drag", "density_altitude", "earth_rotation"];
        assert_eq!(nearest("wnd", effects), Some("wind"));
        assert_eq!(nearest("earth_rotaton", effects), Some("earth_rotation"));
        assert_eq!(nearest("density", effects), Some("density_altitude"));
        assert_eq!(nearest("banana", effects), None);
        assert_eq!(nearest("", effects), None);
        assert_eq!(hint("drga", effects), ": did you mean `drag`?");
        assert_eq!(hint("zzzz", effects), "");
    }
}
