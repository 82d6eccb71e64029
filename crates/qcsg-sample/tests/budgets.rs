//! Work budgets on examples where an earlier sampler spent far more: distance queries and
//! rectangles left unproven, at a radius relative to the diagonal. Each bound sits about 1.5×
//! above today's count and far below the count before the change it guards, so undoing that
//! change fails the test (the guarantee itself is checked in `scenes.rs`).

mod common;

use common::{compile_file, diagonal, workspace_root};
use qcsg_sample::sample;

/// One budget: the example, the radius as a fraction of the diagonal, the most distance
/// queries and the most unproven rectangles, and what the bound guards.
struct Budget {
    example: &'static str,
    radius: f64,
    max_queries: u64,
    max_unresolved: u64,
    guards: &'static str,
}

const BUDGETS: &[Budget] = &[
    Budget {
        example: "examples/three_spheres.qcsg",
        radius: 0.01,
        max_queries: 45_000,
        max_unresolved: 0,
        guards: "the second pass: the lens edge lies on a region border, and splitting the \
                 rectangles beside it down to the cutoff took 512,704 queries (now 29,218)",
    },
    Budget {
        example: "examples/chess_bishop.qcsg",
        radius: 0.1,
        max_queries: 150_000,
        max_unresolved: 0,
        guards: "merged abutting terms: the foot's ellipsoid touches the plane between the cone \
                 and the stem at its pole (5,252 unproven rectangles, 310,659 queries; now 0 \
                 and 96,673)",
    },
    Budget {
        example: "examples/customizer_box.qcsg",
        radius: 0.1,
        max_queries: 180_000,
        max_unresolved: 8_000,
        guards: "the second pass on 50 terms (919,814 queries, now 121,314); 5,768 rectangles \
                 stay unproven along lines where corner cylinders touch the walls",
    },
];

#[test]
fn sampling_stays_within_its_budgets() {
    let mut failures = Vec::new();
    for budget in BUDGETS {
        let dnf = compile_file(&workspace_root().join(budget.example)).expect("compiles");
        let r = budget.radius * diagonal(&dnf);
        let stats = sample(&dnf, r).expect("valid radius").stats;
        let (queries, unresolved) = (
            stats.subdivision.distance_queries,
            stats.subdivision.unresolved,
        );
        eprintln!(
            "{}: {queries} queries, {unresolved} unproven",
            budget.example
        );
        if queries > budget.max_queries || unresolved > budget.max_unresolved {
            failures.push(format!(
                "{}: {queries} queries (at most {}), {unresolved} unproven rectangles (at most \
                 {}); this guards {}",
                budget.example, budget.max_queries, budget.max_unresolved, budget.guards
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
