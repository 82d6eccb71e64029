//! The progress a sampling run reports (`sample_with_progress`), on one thread and on two: the
//! basic regions with their work, each region done once with its share, then the rectangles the
//! first pass left unproven with theirs, each refined once. The command line's progress bar
//! counts the work; the benchmark times the two passes by these events.

mod common;

use std::sync::Mutex;

use common::{diagonal, three_spheres};
use qcsg_sample::{Progress, REFINE_WORK, sample_with_progress, threads::pool_builder};

#[test]
fn each_pass_announces_its_work_and_reports_each_piece_once() {
    let dnf = three_spheres();
    let radius = 0.01 * diagonal(&dnf);
    for threads in [1, 2] {
        let pool = pool_builder(threads).build().expect("thread pool");
        let events = Mutex::new(Vec::new());
        let record = |event| events.lock().expect("events").push(event);
        let sampling = pool
            .install(|| sample_with_progress(&dnf, radius, &record))
            .expect("sampling");
        let events = events.into_inner().expect("events");

        let Some((&Progress::Regions { count, work }, rest)) = events.split_first() else {
            panic!("{threads} threads: the regions are not announced first: {events:?}");
        };
        assert_eq!(count, sampling.stats.basic_regions, "{threads} threads");
        let Some(refining) = rest
            .iter()
            .position(|e| matches!(e, Progress::Refining { .. }))
        else {
            panic!("{threads} threads: no second pass announced");
        };
        let (first_pass, second_pass) = rest.split_at(refining);
        let done: Vec<u64> = first_pass
            .iter()
            .map(|e| match e {
                Progress::RegionDone { work } => *work,
                other => panic!("{threads} threads: {other:?} in the first pass"),
            })
            .collect();
        assert_eq!(done.len() as u64, count, "{threads} threads");
        // Every region weighs something, and the shares add up to the whole.
        assert!(done.iter().all(|&w| w > 0), "{threads} threads");
        assert_eq!(done.iter().sum::<u64>(), work, "{threads} threads");

        let Progress::Refining { count, work } = second_pass[0] else {
            unreachable!("found by its variant");
        };
        // Where the balls cut each other the first pass leaves rectangles unproven.
        assert!(count > 0, "{threads} threads");
        assert_eq!(work, count * REFINE_WORK, "{threads} threads");
        let refined = &second_pass[1..];
        let each = Progress::RectangleRefined { work: REFINE_WORK };
        assert!(refined.iter().all(|e| *e == each), "{threads} threads");
        assert_eq!(refined.len() as u64, count, "{threads} threads");
    }
}
