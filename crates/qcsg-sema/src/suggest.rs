//! "Did you mean …?" suggestions from the edit distance between names.
//!
//! A suggestion is a courtesy, so its cost is bounded whatever the input: names longer than
//! [`MAX_SUGGESTED_LEN`] get none, candidates whose length alone puts them too far are skipped
//! before any distance is computed, the distance is computed only in the band of cells that can
//! stay within the allowed number of edits (O(n·k) for a name of n characters and k edits), and
//! one check spends at most [`SEARCHES`] searches and [`WORK`] units of work on suggestions.

/// Names longer than this (in characters) get no suggestion: a typo in a name this long is
/// rare, and the cost of comparing names grows with their length times the edits allowed.
pub(crate) const MAX_SUGGESTED_LEN: usize = 64;

/// How many "did you mean" searches one check does at most (each scans the names in scope).
pub(crate) const SEARCHES: u32 = 256;

/// How much work one check spends on suggestions at most, counted in candidates looked at and
/// cells of the distance table computed (a few milliseconds' worth per million).
pub(crate) const WORK: u64 = 50_000_000;

/// The suggestion budget of one check.
#[derive(Debug)]
pub(crate) struct Suggester {
    searches_left: u32,
    work_left: u64,
}

impl Default for Suggester {
    fn default() -> Self {
        Self {
            searches_left: SEARCHES,
            work_left: WORK,
        }
    }
}

impl Suggester {
    /// Whether a suggestion for `name` may be searched for: the budget is not spent and the name
    /// is short enough. Callers check this before gathering candidates, which costs too.
    pub(crate) fn wants(&self, name: &str) -> bool {
        self.searches_left > 0 && self.work_left > 0 && suggested_chars(name).is_some()
    }

    /// The candidate closest to `name`, if one is close enough to be a plausible typo: at most
    /// one edit for short names, about one edit per three characters for longer ones. Ties go
    /// to the candidate first in byte order, so the answer does not depend on the candidates'
    /// order. A whole name is never rewritten: `i` does not suggest `f`.
    pub(crate) fn closest<'c>(
        &mut self,
        name: &str,
        candidates: impl IntoIterator<Item = &'c str>,
    ) -> Option<&'c str> {
        if !self.wants(name) {
            return None;
        }
        self.searches_left -= 1;
        let chars = suggested_chars(name)?;
        let length = chars.len();
        let limit = (length / 3).max(1).min(length.saturating_sub(1));
        if limit == 0 {
            return None;
        }
        let mut best: Option<(usize, &str)> = None;
        let mut candidate_chars = Vec::new();
        for candidate in candidates {
            if self.work_left == 0 {
                break;
            }
            self.work_left -= 1;
            if candidate == name {
                continue;
            }
            // A tie may still win on its name, so the bound keeps the best distance itself.
            let bound = best.map_or(limit, |(d, _)| d);
            if !within_length(candidate, length, bound) {
                continue;
            }
            candidate_chars.clear();
            candidate_chars.extend(candidate.chars());
            let Some(distance) =
                edit_distance(&chars, &candidate_chars, bound, &mut self.work_left)
            else {
                continue;
            };
            if best.is_none_or(|(d, c)| (distance, candidate) < (d, c)) {
                best = Some((distance, candidate));
            }
        }
        best.map(|(_, c)| c)
    }
}

/// The characters of `name`, when it is short enough to get suggestions; without counting more
/// than [`MAX_SUGGESTED_LEN`] of them.
fn suggested_chars(name: &str) -> Option<Vec<char>> {
    // A character takes at most 4 bytes: a longer name has more characters than allowed.
    if name.len() > 4 * MAX_SUGGESTED_LEN {
        return None;
    }
    let chars: Vec<char> = name.chars().collect();
    (chars.len() <= MAX_SUGGESTED_LEN).then_some(chars)
}

/// Whether `candidate` has between `length − limit` and `length + limit` characters, found
/// without counting more than `length + limit + 1` of them.
fn within_length(candidate: &str, length: usize, limit: usize) -> bool {
    // Characters are 1 to 4 bytes: the byte length alone settles most candidates.
    let bytes = candidate.len();
    if bytes + limit < length || bytes > 4 * (length + limit) {
        return false;
    }
    let counted = candidate.chars().take(length + limit + 1).count();
    counted.abs_diff(length) <= limit
}

/// The edit distance between `a` and `b` counting insertions, deletions, substitutions and
/// transpositions of neighbours (optimal string alignment), or `None` when it exceeds `limit`.
///
/// Only the cells within `limit` of the diagonal are computed: an alignment that leaves that
/// band has more than `limit` edits, so the cells outside it count as "too far". `work` is
/// charged one unit per cell computed (and the search gives up, `None`, when it runs out).
fn edit_distance(a: &[char], b: &[char], limit: usize, work: &mut u64) -> Option<usize> {
    if a.len().abs_diff(b.len()) > limit {
        return None;
    }
    // Any value above the limit means "too far"; this one also stands for the cells outside
    // the band.
    let far = limit + 1;
    let width = b.len() + 1;
    // Three rolling rows: two back (for transpositions), one back, current.
    let mut before: Vec<usize> = vec![far; width];
    let mut previous: Vec<usize> = (0..width).map(|j| j.min(far)).collect();
    let mut current = vec![far; width];
    for i in 1..=a.len() {
        let low = i.saturating_sub(limit).max(1);
        let high = (i + limit).min(b.len());
        let cells = (high + 1).saturating_sub(low) as u64;
        if *work < cells {
            *work = 0;
            return None;
        }
        *work -= cells;
        current[0] = i.min(far);
        // The cell left of the band is outside it: what an older row left there must not count.
        current[low - 1] = if low == 1 { current[0] } else { far };
        let mut row_min = current[low - 1];
        for j in low..=high {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut value = (previous[j - 1] + cost)
                .min(previous[j] + 1)
                .min(current[j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                value = value.min(before[j - 2] + 1);
            }
            current[j] = value.min(far);
            row_min = row_min.min(current[j]);
        }
        // So is the cell right of the band, which the next row reads as `previous[j]`.
        if high < b.len() {
            current[high + 1] = far;
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

#[cfg(test)]
mod tests {
    use super::*;

    fn distance(a: &str, b: &str, limit: usize) -> Option<usize> {
        let a: Vec<char> = a.chars().collect();
        let b: Vec<char> = b.chars().collect();
        let mut work = u64::MAX;
        edit_distance(&a, &b, limit, &mut work)
    }

    fn closest<'c>(name: &str, candidates: impl IntoIterator<Item = &'c str>) -> Option<&'c str> {
        Suggester::default().closest(name, candidates)
    }

    /// The full table, for comparison with the banded one.
    fn unbanded(a: &str, b: &str) -> usize {
        let a: Vec<char> = a.chars().collect();
        let b: Vec<char> = b.chars().collect();
        let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
        for (i, row) in d.iter_mut().enumerate() {
            row[0] = i;
        }
        for (j, cell) in d[0].iter_mut().enumerate() {
            *cell = j;
        }
        for i in 1..=a.len() {
            for j in 1..=b.len() {
                let cost = usize::from(a[i - 1] != b[j - 1]);
                let mut v = (d[i - 1][j - 1] + cost)
                    .min(d[i - 1][j] + 1)
                    .min(d[i][j - 1] + 1);
                if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                    v = v.min(d[i - 2][j - 2] + 1);
                }
                d[i][j] = v;
            }
        }
        d[a.len()][b.len()]
    }

    #[test]
    fn distances() {
        assert_eq!(distance("kitten", "sitting", 5), Some(3));
        assert_eq!(distance("kitten", "sitting", 2), None);
        assert_eq!(distance("", "abc", 3), Some(3));
        assert_eq!(distance("same", "same", 0), Some(0));
        assert_eq!(distance("depth", "depht", 1), Some(1));
    }

    #[test]
    fn the_band_gives_the_full_tables_distance_within_the_limit() {
        let words = [
            "",
            "a",
            "ab",
            "ba",
            "abc",
            "acb",
            "bca",
            "cube",
            "cuboid",
            "cylinder",
            "cylindre",
            "sphere",
            "spehre",
            "translate",
            "trnaslate",
            "transalte",
            "x_aaaa",
            "x_aaaab",
            "aaaaaaaaaa",
            "abababab",
            "babababa",
            "é",
            "éa",
            "aé",
        ];
        for a in words {
            for b in words {
                let full = unbanded(a, b);
                for limit in 0..8 {
                    let want = (full <= limit).then_some(full);
                    assert_eq!(distance(a, b, limit), want, "{a:?} {b:?} limit {limit}");
                }
            }
        }
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

    #[test]
    fn ties_go_to_the_first_name_in_byte_order_whatever_the_order_given() {
        assert_eq!(closest("ab", ["ac", "aa"]), Some("aa"));
        assert_eq!(closest("ab", ["aa", "ac"]), Some("aa"));
        assert_eq!(closest("width", ["widht", "wdth", "widt"]), Some("wdth"));
    }

    #[test]
    fn long_names_get_no_suggestion_and_cost_nothing() {
        let long = "a".repeat(MAX_SUGGESTED_LEN + 1);
        let near = format!("{long}b");
        let mut suggester = Suggester::default();
        assert!(!suggester.wants(&long));
        assert_eq!(suggester.closest(&long, [near.as_str()]), None);
        assert_eq!(suggester.work_left, WORK);
        let short = "a".repeat(MAX_SUGGESTED_LEN);
        let near = format!("{short}b");
        assert_eq!(
            suggester.closest(&short, [near.as_str()]),
            Some(near.as_str())
        );
    }

    #[test]
    fn candidates_of_another_length_are_skipped_without_computing_a_distance() {
        let mut suggester = Suggester::default();
        let far = "b".repeat(10_000);
        assert_eq!(suggester.closest("abcdef", [far.as_str(), "x"]), None);
        // One unit per candidate looked at, and no cell of a distance table.
        assert_eq!(suggester.work_left, WORK - 2);
    }

    #[test]
    fn the_budget_ends_the_searches() {
        let mut suggester = Suggester::default();
        for _ in 0..SEARCHES {
            assert_eq!(suggester.closest("cub", ["cube"]), Some("cube"));
        }
        assert!(!suggester.wants("cub"));
        assert_eq!(suggester.closest("cub", ["cube"]), None);
        let mut suggester = Suggester {
            searches_left: SEARCHES,
            work_left: 5,
        };
        assert_eq!(suggester.closest("translat", ["translate"]), None);
        assert_eq!(suggester.work_left, 0);
    }
}
