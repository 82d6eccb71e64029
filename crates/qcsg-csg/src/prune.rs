//! Pruning: removing what a DNF does not need without changing the solid it describes.
//!
//! Construction already prunes as it goes (see [`crate::dnf`]); [`finish`] then runs the passes
//! below over the finished DNF, in order, counting terms, literal occurrences and quadrics
//! before and after each:
//!
//! 1. `empty_bounds`: terms whose box (re-tightened by their literals' own boxes) is empty;
//! 2. `literal_bounds`: a literal provably false over its term's box removes the term; a literal
//!    provably true over the box that the *other* literals (and the region) already imply is
//!    removed from the term;
//! 3. `coincident_pairs`: terms holding two literals that meet only on a surface they share
//!    with opposite orientations (`x ≤ 0` and `−x ≤ 0`, a ball and the complement of a turned
//!    copy of it: [`crate::coincident`]), which have no volume;
//! 4. `duplicate_literals`: literals of one term equal up to a positive factor;
//! 5. `duplicate_terms`: terms with the same literal set (their boxes are intersected);
//! 6. `subsumed_terms`: terms whose literal set contains another term's (they lie inside it);
//! 7. `unused_quadrics`: quadrics no term uses, with the rest renumbered in order.
//!
//! Every rule but the renumbering can be turned off on its own through [`Pruning`] (in
//! [`crate::DnfOptions::pruning`]), to measure what it saves; the DNF means the same solid
//! with any of them off, only larger.

use std::collections::HashMap;

use rayon::prelude::*;

use crate::bounds::Aabb;
use crate::dnf::{DUPLICATE_TOLERANCE, Dnf, Term, shape_key};
use crate::quadric_box::{BoxClass, classify};
use crate::stats::{ConstructionStats, DnfStats, PassStats};

/// Which pruning rules run, one switch per rule: the construction-time rules of
/// [`crate::dnf`] and the final passes of [`finish`]. The default runs all of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pruning {
    /// Construction: terms whose box misses an operand's box skip it (region of interest: a
    /// union member or intersected operand away from the term drops it, a subtracted one
    /// leaves it untouched).
    pub operand_bounds: bool,
    /// Construction: terms whose box became empty are dropped.
    pub empty_bounds: bool,
    /// Construction: terms with a literal provably false over their box are dropped.
    pub outside_literal: bool,
    /// Construction: literals provably true over their term's box are not added.
    pub inside_literal: bool,
    /// Construction: quadrics equal up to a positive factor (same colour and highlight) share
    /// one literal.
    pub merged_literals: bool,
    /// Construction: exact duplicate terms of a union are merged.
    pub duplicate_terms: bool,
    /// Construction: terms of a union that contain another term's literals are dropped.
    pub subsumed_terms: bool,
    /// Construction: a part made of planes only whose expansion outgrows a budget near-linear
    /// in its planes is cut into convex cells instead ([`crate::dnf`]'s `plane_cells`); and a
    /// subtracted part that records its complement as cells ([`crate::Dag::set_complement`],
    /// e.g. text) expands those instead of the product of its own cells' complements.
    pub plane_cells: bool,
    /// Final pass `empty_bounds`.
    pub final_empty_bounds: bool,
    /// Final pass `literal_bounds`.
    pub final_literal_bounds: bool,
    /// Final pass `coincident_pairs`.
    pub final_coincident_pairs: bool,
    /// Final pass `duplicate_literals`.
    pub final_duplicate_literals: bool,
    /// Final pass `duplicate_terms`.
    pub final_duplicate_terms: bool,
    /// Final pass `subsumed_terms`.
    pub final_subsumed_terms: bool,
}

impl Default for Pruning {
    fn default() -> Self {
        Self::all()
    }
}

impl Pruning {
    /// The names of the rules, in the order of [`Pruning::set`]: construction rules first,
    /// then the final passes (prefixed `final_`).
    pub const RULES: [&'static str; 14] = [
        "operand_bounds",
        "empty_bounds",
        "outside_literal",
        "inside_literal",
        "merged_literals",
        "duplicate_terms",
        "subsumed_terms",
        "plane_cells",
        "final_empty_bounds",
        "final_literal_bounds",
        "final_coincident_pairs",
        "final_duplicate_literals",
        "final_duplicate_terms",
        "final_subsumed_terms",
    ];

    /// Every rule on (the default).
    pub fn all() -> Self {
        Self {
            operand_bounds: true,
            empty_bounds: true,
            outside_literal: true,
            inside_literal: true,
            merged_literals: true,
            duplicate_terms: true,
            subsumed_terms: true,
            plane_cells: true,
            final_empty_bounds: true,
            final_literal_bounds: true,
            final_coincident_pairs: true,
            final_duplicate_literals: true,
            final_duplicate_terms: true,
            final_subsumed_terms: true,
        }
    }

    /// Every rule off: the DNF multiplied out, with only unused quadrics renumbered away.
    pub fn none() -> Self {
        let mut p = Self::all();
        for name in Self::RULES {
            p.set(name, false);
        }
        p
    }

    /// Every rule on but `name` (see [`Pruning::RULES`]); `None` for an unknown name.
    pub fn without(name: &str) -> Option<Self> {
        let mut p = Self::all();
        p.set(name, false).then_some(p)
    }

    /// Turns the rule `name` on or off; false when there is no such rule.
    pub fn set(&mut self, name: &str, on: bool) -> bool {
        let switch = match name {
            "operand_bounds" => &mut self.operand_bounds,
            "empty_bounds" => &mut self.empty_bounds,
            "outside_literal" => &mut self.outside_literal,
            "inside_literal" => &mut self.inside_literal,
            "merged_literals" => &mut self.merged_literals,
            "duplicate_terms" => &mut self.duplicate_terms,
            "subsumed_terms" => &mut self.subsumed_terms,
            "plane_cells" => &mut self.plane_cells,
            "final_empty_bounds" => &mut self.final_empty_bounds,
            "final_literal_bounds" => &mut self.final_literal_bounds,
            "final_coincident_pairs" => &mut self.final_coincident_pairs,
            "final_duplicate_literals" => &mut self.final_duplicate_literals,
            "final_duplicate_terms" => &mut self.final_duplicate_terms,
            "final_subsumed_terms" => &mut self.final_subsumed_terms,
            _ => return false,
        };
        *switch = on;
        true
    }
}

/// Most terms on which subsumption is tried during construction (quadratic in the worst case).
pub const INCREMENTAL_SUBSUMPTION_LIMIT: usize = 20_000;

/// Most terms on which subsumption is tried in the final pass.
pub const FINAL_SUBSUMPTION_LIMIT: usize = 200_000;

/// Removes exact duplicate terms (intersecting their boxes) and, when there are at most
/// `subsumption_limit` terms, terms whose literal set contains another's. Keeps the order of
/// the survivors.
/// `duplicates` and `subsume` turn either removal off.
pub fn simplify_terms(
    terms: &mut Vec<Term>,
    duplicates: bool,
    subsume: bool,
    subsumption_limit: usize,
    stats: &mut ConstructionStats,
) {
    let (duplicates, subsumed) =
        remove_duplicates_and_subsumed(terms, duplicates, subsume, subsumption_limit);
    stats.terms_duplicate += duplicates;
    stats.terms_subsumed += subsumed;
}

/// Returns (duplicates removed, subsumed removed).
fn remove_duplicates_and_subsumed(
    terms: &mut Vec<Term>,
    dedup: bool,
    subsume: bool,
    subsumption_limit: usize,
) -> (usize, usize) {
    if terms.len() < 2 || !(dedup || subsume) {
        return (0, 0);
    }
    // Sort indices by (length, literals): duplicates become neighbours, and a term can only be
    // subsumed by one that comes before it.
    let mut order: Vec<usize> = (0..terms.len()).collect();
    order.sort_by(|&a, &b| {
        (terms[a].literals.len(), &terms[a].literals, a).cmp(&(
            terms[b].literals.len(),
            &terms[b].literals,
            b,
        ))
    });
    let mut keep = vec![true; terms.len()];
    let mut duplicates = 0;
    for pair in order.windows(2) {
        let (first, second) = (pair[0], pair[1]);
        if dedup && terms[first].literals == terms[second].literals {
            // Keep the earlier term (the sort is stable by index), with both boxes' facts.
            let (keep_index, drop_index) = if keep[first] {
                (first, second)
            } else {
                (second, first)
            };
            if keep[drop_index] {
                let merged = terms[keep_index]
                    .bounds
                    .intersection(&terms[drop_index].bounds);
                terms[keep_index].bounds = merged;
                keep[drop_index] = false;
                duplicates += 1;
            }
        }
    }
    let mut subsumed = 0;
    if subsume && terms.len() <= subsumption_limit {
        subsumed = remove_subsumed(terms, &order, &mut keep);
    }
    let mut index = 0;
    terms.retain(|_| {
        let k = keep[index];
        index += 1;
        k
    });
    (duplicates, subsumed)
}

/// Marks terms whose literal set contains a kept term's, visiting terms in `order` (by
/// length), and returns how many. Each kept term is filed under its rarest literal, so a term
/// only meets the candidates filed under its own literals: near-linear when terms share few
/// literals, never worse than comparing all pairs.
fn remove_subsumed(terms: &[Term], order: &[usize], keep: &mut [bool]) -> usize {
    let mut frequency: HashMap<u32, usize> = HashMap::new();
    for term in terms {
        for &l in &term.literals {
            *frequency.entry(l).or_default() += 1;
        }
    }
    let signatures: Vec<u64> = terms.iter().map(|t| signature(&t.literals)).collect();
    let mut filed: HashMap<u32, Vec<usize>> = HashMap::new();
    let mut universal = false;
    let mut subsumed = 0;
    for &index in order {
        if !keep[index] {
            continue;
        }
        let term = &terms[index];
        let covered = universal
            || term.literals.iter().any(|l| {
                filed.get(l).is_some_and(|candidates| {
                    candidates.iter().any(|&k| {
                        signatures[k] & !signatures[index] == 0
                            && is_subset(&terms[k].literals, &term.literals)
                    })
                })
            });
        if covered {
            keep[index] = false;
            subsumed += 1;
            continue;
        }
        // Ties go to the smallest id, so the filing does not depend on hash order.
        match term
            .literals
            .iter()
            .min_by_key(|&&l| (frequency.get(&l).copied().unwrap_or(0), l))
        {
            Some(&rarest) => filed.entry(rarest).or_default().push(index),
            None => universal = true,
        }
    }
    subsumed
}

/// A 64-bit Bloom signature of a literal set: `a ⊆ b` implies `sig(a) & !sig(b) == 0`.
fn signature(literals: &[u32]) -> u64 {
    literals.iter().fold(0u64, |s, &l| {
        s | 1u64 << (l.wrapping_mul(2_654_435_761) >> 26)
    })
}

/// Whether sorted `a` is a subset of sorted `b`.
fn is_subset(a: &[u32], b: &[u32]) -> bool {
    if a.len() > b.len() {
        return false;
    }
    let mut j = 0;
    for &x in a {
        while j < b.len() && b[j] < x {
            j += 1;
        }
        if j == b.len() || b[j] != x {
            return false;
        }
        j += 1;
    }
    true
}

/// Runs the final passes (when `run_passes`, each as far as `pruning` lets it) and always the
/// renumbering of unused quadrics. `own_boxes[i]` contains the solid of quadric `i`; `region`
/// is all of space without one.
pub fn finish(
    dnf: &mut Dnf,
    own_boxes: &[Aabb],
    region: Aabb,
    run_passes: bool,
    pruning: &Pruning,
    stats: &mut DnfStats,
) {
    if run_passes {
        if pruning.final_empty_bounds {
            run_pass(dnf, stats, "empty_bounds", |dnf| {
                pass_empty_bounds(dnf, own_boxes)
            });
        }
        if pruning.final_literal_bounds {
            run_pass(dnf, stats, "literal_bounds", |dnf| {
                pass_literal_bounds(dnf, own_boxes, region)
            });
        }
        if pruning.final_coincident_pairs {
            run_pass(dnf, stats, "coincident_pairs", pass_coincident_pairs);
        }
        if pruning.final_duplicate_literals {
            run_pass(dnf, stats, "duplicate_literals", pass_duplicate_literals);
        }
        if pruning.final_duplicate_terms {
            run_pass(dnf, stats, "duplicate_terms", |dnf| {
                remove_duplicates_and_subsumed(&mut dnf.terms, true, false, 0);
            });
        }
        if pruning.final_subsumed_terms {
            run_pass(dnf, stats, "subsumed_terms", |dnf| {
                remove_duplicates_and_subsumed(&mut dnf.terms, true, true, FINAL_SUBSUMPTION_LIMIT);
            });
        }
    }
    run_pass(dnf, stats, "unused_quadrics", pass_unused_quadrics);
}

fn run_pass(dnf: &mut Dnf, stats: &mut DnfStats, name: &'static str, pass: impl FnOnce(&mut Dnf)) {
    let (terms_before, literals_before, quadrics_before) =
        (dnf.terms.len(), dnf.literal_count(), dnf.quadrics.len());
    pass(dnf);
    stats.passes.push(PassStats {
        pass: name,
        terms_before,
        terms_after: dnf.terms.len(),
        literals_before,
        literals_after: dnf.literal_count(),
        quadrics_before,
        quadrics_after: dnf.quadrics.len(),
    });
}

fn pass_empty_bounds(dnf: &mut Dnf, own_boxes: &[Aabb]) {
    for term in &mut dnf.terms {
        for &id in &term.literals {
            term.bounds = term.bounds.intersection(&own_boxes[id as usize]);
        }
    }
    dnf.terms.retain(|t| !t.bounds.is_empty());
}

fn pass_literal_bounds(dnf: &mut Dnf, own_boxes: &[Aabb], region: Aabb) {
    let quadrics = &dnf.quadrics;
    retain_terms(&mut dnf.terms, |term| {
        if term
            .literals
            .iter()
            .any(|&id| classify(&quadrics[id as usize].quadric, &term.bounds) == BoxClass::Outside)
        {
            return false;
        }
        // A literal may go only if the remaining literals alone keep the term inside it: test
        // it against the box they (and the region) imply, not against the term's box, which
        // may owe its extent to the literal itself. Deciding in order, with the kept literals
        // before and all literals after, keeps every decision about the current set, in
        // linear time.
        let literals = std::mem::take(&mut term.literals);
        let mut suffix = vec![Aabb::EVERYTHING; literals.len() + 1];
        for (k, &id) in literals.iter().enumerate().rev() {
            suffix[k] = suffix[k + 1].intersection(&own_boxes[id as usize]);
        }
        let mut prefix = region;
        for (k, &id) in literals.iter().enumerate() {
            let implied = prefix.intersection(&suffix[k + 1]);
            if classify(&quadrics[id as usize].quadric, &implied) != BoxClass::Inside {
                term.literals.push(id);
                prefix = prefix.intersection(&own_boxes[id as usize]);
            }
        }
        true
    });
}

/// Keeps the terms for which `keep` (which may change the term) holds, in order. Each term is
/// decided on its own, so the terms are shared out among the threads: a scene of tens of
/// thousands of cells (an imported mesh) spends a good part of its normal form here.
fn retain_terms(terms: &mut Vec<Term>, keep: impl Fn(&mut Term) -> bool + Sync + Send) {
    let kept: Vec<bool> = terms.par_iter_mut().map(&keep).collect();
    let mut decided = kept.iter();
    terms.retain(|_| *decided.next().expect("one decision per term"));
}

fn pass_coincident_pairs(dnf: &mut Dnf) {
    let surfaces = crate::dnf::surfaces_of(dnf);
    retain_terms(&mut dnf.terms, |term| {
        !crate::coincident::has_coincident_pair(&surfaces, &term.literals)
    });
}

fn pass_duplicate_literals(dnf: &mut Dnf) {
    // Equal quadrics share a shape key, so only literals with equal keys are compared.
    let keys: Vec<[u64; 9]> = dnf.quadrics.iter().map(|q| shape_key(&q.quadric)).collect();
    let quadrics = &dnf.quadrics;
    dnf.terms.par_iter_mut().for_each(|term| {
        let mut groups: HashMap<[u64; 9], Vec<u32>> = HashMap::new();
        let mut kept: Vec<u32> = Vec::with_capacity(term.literals.len());
        for &id in &term.literals {
            let q = &quadrics[id as usize].quadric;
            let group = groups.entry(keys[id as usize]).or_default();
            let duplicate = group.iter().any(|&k| {
                quadrics[k as usize]
                    .quadric
                    .approx_eq_up_to_scale(q, DUPLICATE_TOLERANCE)
            });
            if !duplicate {
                group.push(id);
                kept.push(id);
            }
        }
        term.literals = kept;
    });
}

fn pass_unused_quadrics(dnf: &mut Dnf) {
    let mut used = vec![false; dnf.quadrics.len()];
    for term in &dnf.terms {
        for &id in &term.literals {
            used[id as usize] = true;
        }
    }
    let mut renumber = vec![u32::MAX; dnf.quadrics.len()];
    let mut next = 0u32;
    for (old, &is_used) in used.iter().enumerate() {
        if is_used {
            renumber[old] = next;
            next += 1;
        }
    }
    let mut index = 0;
    dnf.quadrics.retain(|_| {
        let k = used[index];
        index += 1;
        k
    });
    for term in &mut dnf.terms {
        for id in &mut term.literals {
            *id = renumber[*id as usize];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subset_and_signature() {
        assert!(is_subset(&[1, 3], &[0, 1, 2, 3]));
        assert!(!is_subset(&[1, 4], &[0, 1, 2, 3]));
        assert!(is_subset(&[], &[5]));
        let (a, b) = (signature(&[1, 3]), signature(&[0, 1, 2, 3]));
        assert_eq!(a & !b, 0);
    }

    #[test]
    fn duplicates_and_subsumed_terms_go() {
        let term = |l: &[u32]| Term {
            literals: l.to_vec(),
            bounds: Aabb::EVERYTHING,
        };
        let mut terms = vec![term(&[1, 2, 3]), term(&[1, 2]), term(&[4]), term(&[1, 2])];
        let (d, s) = remove_duplicates_and_subsumed(&mut terms, true, true, 100);
        assert_eq!((d, s), (1, 1));
        assert_eq!(terms, vec![term(&[1, 2]), term(&[4])]);
    }
}
