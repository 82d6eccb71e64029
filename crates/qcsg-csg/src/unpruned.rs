//! The size of a solid's DNF multiplied out by De Morgan and distribution with no pruning at
//! all: the baseline that the DNF builder's pruning is measured against. Only counted, never
//! built, so astronomically large sizes are fine (they are `f64`).

use std::collections::HashMap;

use crate::{Dag, Edge, NodeId, NodeKind};

/// Terms and literal occurrences of a DNF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DnfSize {
    /// Terms.
    pub terms: f64,
    /// Literal occurrences over all terms.
    pub literals: f64,
}

impl DnfSize {
    const NOTHING: DnfSize = DnfSize {
        terms: 0.0,
        literals: 0.0,
    };
    const EVERYTHING: DnfSize = DnfSize {
        terms: 1.0,
        literals: 0.0,
    };

    /// The union of two DNFs: their terms side by side.
    fn or(self, other: DnfSize) -> DnfSize {
        DnfSize {
            terms: self.terms + other.terms,
            literals: self.literals + other.literals,
        }
    }

    /// The intersection of two DNFs multiplied out: every pair of terms.
    fn and(self, other: DnfSize) -> DnfSize {
        DnfSize {
            terms: self.terms * other.terms,
            literals: self.literals * other.terms + other.literals * self.terms,
        }
    }
}

/// The size of the unpruned DNF of the solid behind `root`.
pub fn unpruned_size(dag: &Dag, root: Edge) -> DnfSize {
    size_of(dag, root, false, &mut HashMap::new())
}

/// The size for the solid behind `edge`, or for its complement if `negated`; shared nodes are
/// counted once per sign.
fn size_of(
    dag: &Dag,
    edge: Edge,
    negated: bool,
    memo: &mut HashMap<(NodeId, bool), DnfSize>,
) -> DnfSize {
    if let Some(&size) = memo.get(&(edge.child, negated)) {
        return size;
    }
    let Some(node) = dag.node(edge.child) else {
        return DnfSize::NOTHING;
    };
    // `all`: the operands are intersected (else united).
    let fold = |operands: Vec<(Edge, bool)>, all: bool, memo: &mut HashMap<_, _>| {
        let empty = if all {
            DnfSize::EVERYTHING
        } else {
            DnfSize::NOTHING
        };
        operands.into_iter().fold(empty, |acc, (e, n)| {
            let size = size_of(dag, e, n, memo);
            if all { acc.and(size) } else { acc.or(size) }
        })
    };
    let size = match &node.kind {
        NodeKind::Leaf(_) => DnfSize {
            terms: 1.0,
            literals: 1.0,
        },
        NodeKind::Complement(e) => size_of(dag, *e, !negated, memo),
        NodeKind::Color(_, e) | NodeKind::Highlight(e) => size_of(dag, *e, negated, memo),
        NodeKind::Union(c) => fold(c.iter().map(|&e| (e, negated)).collect(), negated, memo),
        NodeKind::Intersection(c) => {
            fold(c.iter().map(|&e| (e, negated)).collect(), !negated, memo)
        }
        // An empty difference is empty, and its complement everything.
        NodeKind::Difference(c) if c.is_empty() => {
            if negated {
                DnfSize::EVERYTHING
            } else {
                DnfSize::NOTHING
            }
        }
        // A − B − C = A ∩ ¬B ∩ ¬C; its complement ¬A ∪ B ∪ C.
        NodeKind::Difference(c) => fold(
            c.iter()
                .enumerate()
                .map(|(i, &e)| (e, (i == 0) == negated))
                .collect(),
            !negated,
            memo,
        ),
    };
    memo.insert((edge.child, negated), size);
    size
}
