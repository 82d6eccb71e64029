//! Counters of DNF construction and pruning, reported in the DNF's `stats`.

use serde::Serialize;

/// What pruning removed while the DNF was being formed (before any term could multiply).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct ConstructionStats {
    /// Leaf visits (a shared leaf reached through N paths counts N times).
    pub leaves_visited: usize,
    /// Distinct world-space literals (a leaf under one transform, sign and colour).
    pub literals_interned: usize,
    /// Interned literals found equal (up to a positive factor) to an earlier one and merged.
    pub literals_merged: usize,
    /// Terms dropped because their box missed an operand's box (region-of-interest pruning:
    /// a union member, intersection operand or difference's left side away from the term).
    pub terms_outside_operand_bounds: usize,
    /// Term visits that skipped a subtracted operand whose box missed the term's box.
    pub operands_skipped: usize,
    /// Terms dropped because their box became empty.
    pub terms_empty_bounds: usize,
    /// Terms dropped because one literal is provably false over the whole term box.
    pub terms_outside_literal: usize,
    /// Literals not added because they hold over the whole term box.
    pub literals_inside: usize,
    /// Literals not added because the term already had them.
    pub literals_duplicate: usize,
    /// Terms dropped as exact duplicates of another.
    pub terms_duplicate: usize,
    /// Terms dropped because another term's literals are a subset of theirs.
    pub terms_subsumed: usize,
    /// Largest number of terms held at once.
    pub peak_terms: usize,
    /// Parts made of planes only that were cut into convex cells instead of multiplied out.
    pub plane_parts: usize,
    /// The cells those parts were cut into.
    pub plane_cells: usize,
}

/// The effect of one pruning pass over the finished DNF.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct PassStats {
    /// The pass's name.
    pub pass: &'static str,
    /// Terms before the pass.
    pub terms_before: usize,
    /// Terms after the pass.
    pub terms_after: usize,
    /// Literal occurrences (sum of term lengths) before the pass.
    pub literals_before: usize,
    /// Literal occurrences after the pass.
    pub literals_after: usize,
    /// Quadrics in the table before the pass.
    pub quadrics_before: usize,
    /// Quadrics in the table after the pass.
    pub quadrics_after: usize,
}

/// All counters of one DNF build.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct DnfStats {
    /// Nodes in the DAG.
    pub dag_nodes: usize,
    /// Background parts (`%`) of the DAG: drawn by the renderer, not part of this solid.
    pub background_parts: usize,
    /// Counters of the construction phase.
    pub construction: ConstructionStats,
    /// The passes over the finished DNF, in order.
    pub passes: Vec<PassStats>,
    /// Terms in the result.
    pub terms: usize,
    /// Literal occurrences in the result.
    pub literals: usize,
    /// Quadrics in the result.
    pub quadrics: usize,
}

impl std::fmt::Display for DnfStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let c = &self.construction;
        writeln!(
            f,
            "construction: {} leaf visits, {} literals ({} merged); dropped terms: {} outside operand \
             bounds, {} empty bounds, {} outside a literal, {} duplicate, {} subsumed; \
             {} operands skipped; literals not added: {} inside, {} duplicate; peak {} terms",
            c.leaves_visited,
            c.literals_interned,
            c.literals_merged,
            c.terms_outside_operand_bounds,
            c.terms_empty_bounds,
            c.terms_outside_literal,
            c.terms_duplicate,
            c.terms_subsumed,
            c.operands_skipped,
            c.literals_inside,
            c.literals_duplicate,
            c.peak_terms,
        )?;
        for p in &self.passes {
            writeln!(
                f,
                "pass {:<18} terms {:>7} -> {:<7} literals {:>8} -> {:<8} quadrics {:>6} -> {}",
                p.pass,
                p.terms_before,
                p.terms_after,
                p.literals_before,
                p.literals_after,
                p.quadrics_before,
                p.quadrics_after
            )?;
        }
        write!(
            f,
            "result: {} terms, {} literals, {} quadrics",
            self.terms, self.literals, self.quadrics
        )
    }
}
