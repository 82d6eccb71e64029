//! "Did you mean …?" suggestions from the edit distance between names.

/// The edit distance between `a` and `b` counting insertions, deletions, substitutions and
/// transpositions of neighbours (optimal string alignment), or `None` when it exceeds `limit`.
pub(crate) fn edit_distance(a: &str, b: &str, limit: usize) -> Option<usize> {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    if a.len().abs_diff(b.len()) > limit {
        return None;
    }
    let width = b.len() + 1;
    // Three rolling rows: two back (for transpositions), one back, current.
    let mut before: Vec<usize> = vec![0; width];
    let mut previous: Vec<usize> = (0..width).collect();
    let mut current = vec![0; width];
    for i in 1..=a.len() {
        current[0] = i;
        let mut row_min = current[0];
        for j in 1..width {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut value = (previous[j - 1] + cost)
                .min(previous[j] + 1)
                .min(current[j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                value = value.min(before[j - 2] + 1);
            }
            current[j] = value;
            row_min = row_min.min(value);
        }
        if row_min > limit {
            return None;
        }
        std::mem::swap(&mut before, &mut previous);
        std::mem::swap(&mut previous, &mut current);
    }
    let distance = previous[b.len()];
    (distance <= limit).then_some(distance)
}

/// The candidate closest to `name`, if one is close enough to be a plausible typo: at most one
/// edit for short names, about one edit per three characters for longer ones. Ties go to the
/// first candidate. A whole name is never rewritten: `i` does not suggest `f`.
pub(crate) fn closest<'c>(
    name: &str,
    candidates: impl IntoIterator<Item = &'c str>,
) -> Option<&'c str> {
    let length = name.chars().count();
    let limit = (length / 3).max(1).min(length.saturating_sub(1));
    if limit == 0 {
        return None;
    }
    let mut best: Option<(usize, &str)> = None;
    for candidate in candidates {
        if candidate == name {
            continue;
        }
        let bound = best.map_or(limit, |(d, _)| d.saturating_sub(1));
        if let Some(distance) = edit_distance(name, candidate, bound)
            && best.is_none_or(|(d, _)| distance < d)
        {
            best = Some((distance, candidate));
        }
    }
    best.map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        assert_eq!(edit_distance("kitten", "sitting", 5), Some(3));
        assert_eq!(edit_distance("kitten", "sitting", 2), None);
        assert_eq!(edit_distance("", "abc", 3), Some(3));
        assert_eq!(edit_distance("same", "same", 0), Some(0));
        assert_eq!(edit_distance("depth", "depht", 1), Some(1));
    }

    #[test]
    fn closest_picks_plausible_typos_only() {
        let names = ["cube", "cylinder", "sphere", "translate"];
        assert_eq!(closest("cub", names), Some("cube"));
        assert_eq!(closest("trnaslate", names), Some("translate"));
        assert_eq!(closest("zzz", names), None);
        assert_eq!(closest("cylindr", names), Some("cylinder"));
        assert_eq!(closest("i", ["f", "j"]), None);
    }
}
