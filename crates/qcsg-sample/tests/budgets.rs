//! Work budgets on examples where an earlier sampler spent far more: distance queries,
//! rectangles left unproven and samples, at a radius relative to the diagonal. Each bound sits above
//! today's count and below the count without the change it guards, so undoing that change
//! fails the test (the guarantee itself is checked in `scenes.rs`).

mod common;

use common::{compile_file, compile_file_with, diagonal, workspace_root};
use qcsg_csg::DnfOptions;
use qcsg_csg::dnf::Pruning;
use qcsg_sample::sample;

/// One budget: the example, the radius as a fraction of the diagonal, the most distance
/// queries, unproven rectangles and samples, and what the bound guards.
struct Budget {
    example: &'static str,
    radius: f64,
    max_queries: u64,
    max_unresolved: u64,
    max_samples: u64,
    guards: &'static str,
}

/// No bound on the samples.
const ANY: u64 = u64::MAX;

const BUDGETS: &[Budget] = &[
    Budget {
        example: "examples/three_spheres.qcsg",
        radius: 0.01,
        max_queries: 19_400,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "the centre's disc and the corner discs' quarters: beside the lens's rim the \
                 corners of a small rectangle are near the rim, and the disc of the centre \
                 (queried already) or the discs at one end reaching past the middle prove it off \
                 the surface (without the centre's disc: 19,786 queries; without the quarters: \
                 20,110; without both: 21,968; now 19,030)",
    },
    Budget {
        example: "tests/stability/tangent_rounded_tray_tilted.qcsg",
        radius: 0.01,
        max_queries: 250_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "one side of a turned slab on a sampled wall: the terms' axis-aligned boxes span \
                 both planes of the slabs whose outsides they hold, and the side that faces the \
                 term's own half-spaces across a strip of no width is dropped (without: 407,337 \
                 queries and 17,359 rectangles unproven; now 156,818 and none)",
    },
    Budget {
        example: "crates/qcsg-splat/tests/scenes/coincident_faces.qcsg",
        radius: 0.01,
        max_queries: 60_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "one side of a slab up to the tolerance: a cut flush with three faces of a box \
                 leaves, within the box, one side of each of the cut's slabs and a layer of no \
                 thickness (while the box had to lie strictly inside: 361,882 queries and \
                 24,584 rectangles unproven; now 28,209 and none)",
    },
    Budget {
        example: "tests/stability/coincident_difference_same.qcsg",
        radius: 0.05,
        max_queries: 10_000,
        max_unresolved: 0,
        max_samples: 0,
        guards: "one side of a slab up to the tolerance: a cube minus itself has no surface, \
                 and each term is the cube against a face of no width (before: the coincident \
                 faces subdivided down to the cut-off, 1.6 million rectangles at 30 %; now 384 \
                 queries)",
    },
    Budget {
        example: "examples/quadric_primitives.qcsg",
        radius: 0.3,
        max_queries: 60_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "apex rings closer than r/2: at a radius far above the cone, a ring r/2 from its \
                 tip lies outside the part, and one a quarter as far lies on it (without: 244 \
                 rectangles unproven; now none)",
    },
    Budget {
        example: "examples/recursive_tree.qcsg",
        radius: 0.01,
        max_queries: 220_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "probing down to a speck: three branches start at the centre of their trunk's \
                 cap, which is hidden all around it by one branch or another but by none alone, \
                 so eq. 22 is zero there; what probing leaves of the rectangles around it is \
                 that point (without: 196 rectangles unproven; now none in 170,496 queries)",
    },
    Budget {
        example: "examples/machined_block.qcsg",
        radius: 0.01,
        max_queries: 250_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "probed parts: rectangles just beyond the top chamfer's edge on the side face meet \
                 the surface only along that edge, where filled cells end; probing leaves the \
                 parts along it, near enough to the cells' samples where the whole rectangle \
                 is not (without: 116 rectangles unproven; now none)",
    },
    Budget {
        example: "examples/openscad_bracket.scad",
        radius: 0.01,
        max_queries: 40_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "strips of no width: the gusset's 45° cutter has two faces meeting on the bottom \
                 plane, and the DNF term of the face that misses the gusset is only that line \
                 there (without the rule 50,494 queries and 1,024 rectangles unproven along it; \
                 now 26,946 and none)",
    },
    Budget {
        example: "examples/precision_part.qcsg",
        radius: 0.01,
        max_queries: 200_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "touching surfaces: the cup's ball and cylinder of one radius touch along its \
                 equator, outside and inside, where eq. 22 of the side alone is `z² / 2r` \
                 (without the pencil rule 1,623,947 queries and 414 rectangles unproven; with it \
                 but the inner ball's part of the wall's term still sampled, where the bore \
                 touches all of it, 1,139,687 and 303; now 106,887 and none)",
    },
    Budget {
        example: "tests/stability/tangent_internal_union.qcsg",
        radius: 0.01,
        max_queries: 10_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "touching surfaces: a ball touching the inside of another at a point lies inside \
                 it everywhere else, which the range of a plane over the ball's surface shows \
                 (without: 68,254 queries and 315 rectangles unproven; now 1,920 and none)",
    },
    Budget {
        example: "examples/three_spheres.qcsg",
        radius: 0.01,
        max_queries: 45_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "the second pass: the lens edge lies on a region border, and splitting the \
                 rectangles beside it down to the cutoff took 512,704 queries (now 21,968)",
    },
    Budget {
        example: "examples/chess_bishop.qcsg",
        radius: 0.1,
        max_queries: 50_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "sections by the sampled plane: the foot's disc and cone meet with equal radii on \
                 the plane between them, where their sections are one circle, which the cone's \
                 term then holds as the disc's term does (without: 113,621 queries and 5,791 \
                 rectangles unproven; now 33,325 and none; without merged abutting terms, where \
                 the foot's ellipsoid touches the plane between the cone and the stem, 132,273 \
                 and 10,020)",
    },
    Budget {
        example: "examples/modifiers.qcsg",
        radius: 0.01,
        max_queries: 400_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "sections by the sampled plane: the pulley's groove is two cones meeting with equal \
                 radii on the plane between them (without: 2,462,647 queries and 230,447 \
                 rectangles unproven; now 220,109 and none)",
    },
    Budget {
        example: "examples/customizer_box.qcsg",
        radius: 0.1,
        max_queries: 80_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "the tangency, section and one-sided-slab rules of eq. 22 on the rounded box's \
                 corner cylinders, which touch the walls along lines (without them 304,732 \
                 queries and 33,732 rectangles unproven; now 35,254 and none; before the second \
                 pass and the per-region terms of eq. 22, 919,814 queries)",
    },
    Budget {
        example: "tests/stability/tangent_rounded_slab.qcsg",
        radius: 0.01,
        max_queries: 40_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "planar sections: a box face ends on the CSG surface only along the line where a \
                 corner cylinder touches it, which eq. 22 with the cylinder in space cannot \
                 resolve (without tangency and sections 1,138,325 queries and 32,768 rectangles \
                 unproven; now 26,400 and none)",
    },
    Budget {
        example: "examples/openscad_bracket.scad",
        radius: 0.01,
        max_queries: 75_000,
        max_unresolved: 2_000,
        max_samples: ANY,
        guards: "half-spaces shared with the sampled term: the base, the leg and the gussets are \
                 boxes whose slabs share one side with each other's (without that rule 436,118 \
                 queries and 43,012 rectangles unproven; without it, sections and one-sided \
                 slabs 454,131 and 45,060; now 50,494 and 1,024)",
    },
    Budget {
        example: "examples/machined_block.qcsg",
        radius: 0.01,
        max_queries: 400_000,
        max_unresolved: 1_000,
        max_samples: ANY,
        guards: "planes parallel to a sampled plane: the countersinks' cones end 0.01 above the \
                 block's top, and their top planes lie wholly outside the block (without that \
                 rule 2,038,142 queries and 2,604 rectangles unproven; before this stop's rules \
                 4,925,665 and 15,981; now 182,960 and 450)",
    },
    Budget {
        example: "tests/stability/parallel_planes.qcsg",
        radius: 0.05,
        max_queries: 20_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "planar sections of planes: 16 planes meeting at 2.7e-4 rad are told apart by \
                 their lines on each other (about 9,500 queries; in space, this scene ran for \
                 minutes in a debug build)",
    },
    Budget {
        example: "tests/stability/tangent_internal_union.qcsg",
        radius: 0.01,
        max_queries: 80_000,
        max_unresolved: 400,
        max_samples: ANY,
        guards: "probing the given-up rectangles that no sample reaches: where the small ball \
                 touches the big one from inside, 1,470 stayed unproven without it (53,308 \
                 queries), now 315 (68,254 queries)",
    },
    Budget {
        example: "examples/spiral_staircase.qcsg",
        radius: 0.01,
        max_queries: 150_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "offset surfaces: the column's surface lies 0.01 inside the hole of every step \
                 around it, which eq. 22 sees holding on all of the column (without: 521,471 \
                 queries and 583 rectangles unproven; now 88,778 and none)",
    },
    Budget {
        example: "examples/quadric_primitives.qcsg",
        radius: 0.01,
        max_queries: 80_000,
        max_unresolved: 0,
        max_samples: ANY,
        guards: "the apex ring: the cone's apex is its tip, where a plane meets it, and the \
                 rectangles given up around it are settled there (without: 308 rectangles \
                 unproven); the 4 left on that plane, which meets the cone only at one point, \
                 are probed down to a speck (without: 4; now none)",
    },
    Budget {
        example: "examples/raw_quadrics.qcsg",
        radius: 0.01,
        max_queries: 100_000,
        max_unresolved: 0,
        max_samples: 8_000,
        guards: "looking back into earlier regions for a sample that covers a small rectangle: \
                 around the cone's apex the region decomposition leaves thousands of tiny \
                 regions, and each took a sample of its own (16,308 samples; now 5,218); and the \
                 apex ring, which settles the 160 rectangles given up at the apex",
    },
    Budget {
        example: "tests/stability/aspect_cylinder.qcsg",
        radius: 0.05,
        max_queries: 200_000,
        max_unresolved: 0,
        max_samples: 2_000,
        guards: "looking back into earlier regions: the rod's thin regions along its rims, seen \
                 from the planes holding its axis, took a sample each (24,584 samples; now 386)",
    },
];

#[test]
fn sampling_stays_within_its_budgets() {
    let mut failures = Vec::new();
    for budget in BUDGETS {
        let path = workspace_root().join(budget.example);
        let mut dnf = compile_file(&path).expect("compiles");
        if dnf.terms.is_empty() {
            // The compiler's `coincident_pairs` pass empties a cube minus itself (each term holds
            // a slab and its complement); the sampler must still see through those terms alone.
            let options = DnfOptions {
                pruning: Pruning::without("final_coincident_pairs").expect("a rule"),
                ..DnfOptions::default()
            };
            dnf = compile_file_with(&path, &options).expect("compiles");
        }
        let r = budget.radius * diagonal(&dnf);
        let stats = sample(&dnf, r).expect("valid radius").stats;
        let (queries, unresolved) = (stats.subdivision.distance_queries, stats.unresolved());
        let samples = stats.samples;
        eprintln!(
            "{}: {queries} queries, {unresolved} unproven, {samples} samples",
            budget.example
        );
        if queries > budget.max_queries
            || unresolved > budget.max_unresolved
            || samples > budget.max_samples
        {
            failures.push(format!(
                "{}: {queries} queries (at most {}), {unresolved} unproven rectangles (at most \
                 {}), {samples} samples (at most {}); this guards {}",
                budget.example,
                budget.max_queries,
                budget.max_unresolved,
                budget.max_samples,
                budget.guards
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
