//! The progress a sampling run reports (`sample_with_progress`), on one thread and on two: the
//! number of basic regions, each region done once, then the number of rectangles the first pass
//! left unproven, each of those refined once. The command line's progress bar counts them; the
//! benchmark times the two passes by them.

mod common;

use std::sync::Mutex;

use common::{diagonal, three_spheres};
use qcsg_sample::{Progress, sample_with_progress, threads::pool_builder};

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

        let Some((&Progress::Regions(regions), rest)) = events.split_first() else {
            panic!("{threads} threads: the regions are not announced first: {events:?}");
        };
        assert_eq!(regions, sampling.stats.basic_regions, "{threads} threads");
        let Some(refining) = rest.iter().position(|e| matches!(e, Progress::Refining(_))) else {
            panic!("{threads} threads: no second pass announced");
        };
        let (first_pass, second_pass) = rest.split_at(refining);
        assert!(first_pass.iter().all(|e| *e == Progress::RegionDone));
        assert_eq!(first_pass.len() as u64, regions, "{threads} threads");

        let Progress::Refining(rectangles) = second_pass[0] else {
            unreachable!("found by its variant");
        };
        // Where the balls cut each other the first pass leaves rectangles unproven.
        assert!(rectangles > 0, "{threads} threads");
        let refined = &second_pass[1..];
        assert!(refined.iter().all(|e| *e == Progress::RectangleRefined));
        assert_eq!(refined.len() as u64, rectangles, "{threads} threads");
    }
}
