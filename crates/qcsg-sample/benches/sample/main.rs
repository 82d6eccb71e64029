//! The sampler benchmark report: `cargo bench -p qcsg-sample --bench sample` samples scenes of
//! 3, 5, 21, 31 and 80 quadrics at three radii on 1 and 2 threads, times the `Q(x)`
//! micro-benchmark for calibration against paper 000's Table 1, and writes
//! `docs/sampler-benchmarks.md` laid out like the paper's Table 2 with its figures beside ours.
//! A second table samples grids of 64 to 4,096 separate parts, and plates drilled with as many
//! holes: time and memory per part. A lone ball sampled finely sets the cost of emitting a
//! sample beside the paper's Table 1 row for a single quadric, and the one-thread runs' progress
//! splits each row's time between the two passes.
//!
//! Each configuration is timed over repeated runs (at least 3, up to about half a second of
//! sampling) and the median is reported; the load average of the machine is recorded at the
//! start and the end, since it moves the absolute numbers. `QCSG_BENCH_OUT` overrides the report
//! path (`-` prints it).

mod calibration;
#[path = "../../tests/common/mod.rs"]
mod common;
mod grids;
mod report;

use calibration::{
    cpu_seconds, first_touch_microseconds, load_average, median_seconds, memory_scaling,
    qx_nanoseconds, single_quadric, wake_up_microseconds,
};
use grids::{FAMILIES, GRID_CHILD, GRIDS, GridRow, grid_memory_child, measure_grid};

use std::fmt::Write as _;
use std::hint::black_box;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use qcsg_csg::Dnf;
use qcsg_quadric::DVec3;
use qcsg_sample::{
    Progress, SampleLimits, SampleStats, Sampling, resample, resample_with_limits, sample,
};

/// The allocator `qcsg` runs with.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The paper's Table 2 rows: quadrics, then per splat size (samples, distance queries, clip
/// indices, sampling ms on one 4.8 GHz core).
type PaperRow = (usize, [PaperCell; 3]);

/// One splat size of a paper row: samples, distance queries, clip indices, sampling ms.
type PaperCell = (u64, u64, u64, f64);

const PAPER: [PaperRow; 6] = [
    (
        3,
        [
            (5454, 22372, 2, 1.51),
            (23452, 47336, 2, 3.39),
            (249014, 100398, 2, 8.51),
        ],
    ),
    (
        5,
        [
            (8112, 103296, 52, 7.63),
            (35904, 215040, 23, 16.45),
            (329856, 576048, 17, 66.87),
        ],
    ),
    (
        5,
        [
            (9465, 52578, 52, 4.38),
            (27882, 103908, 31, 8.71),
            (205075, 254592, 25, 23.47),
        ],
    ),
    (
        21,
        [
            (7134, 30802, 78, 6.26),
            (31940, 85744, 37, 18.01),
            (104972, 171958, 31, 37.91),
        ],
    ),
    (
        31,
        [
            (28432, 196298, 51, 36.63),
            (91895, 325705, 34, 62.23),
            (184533, 415847, 29, 83.36),
        ],
    ),
    (
        80,
        [
            (10176, 194024, 299, 94.47),
            (141200, 558582, 244, 292.35),
            (655727, 1182464, 236, 623.92),
        ],
    ),
];

/// The paper's `Q(x)`: 3.17 ns per evaluation on one 4.8 GHz core (Table 1).
const PAPER_QX_NS: f64 = 3.17;

/// Radii as fractions of the scene's bounding-box diagonal: large, medium, small.
const RADII: [(&str, f64); 3] = [("large", 0.01), ("medium", 0.005), ("small", 0.0015)];

/// One benchmark scene.
struct Scene {
    name: &'static str,
    what: String,
    dnf: Dnf,
}

/// The `k`-th of `n` points spread over a sphere of radius `radius` (a Fibonacci lattice).
fn fibonacci(k: usize, n: usize, radius: f64) -> DVec3 {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
    let ring = (1.0 - z * z).sqrt();
    let phi = golden * k as f64;
    radius * DVec3::new(ring * phi.cos(), ring * phi.sin(), z)
}

fn vector(p: DVec3) -> String {
    format!("[{:.6}, {:.6}, {:.6}]", p.x, p.y, p.z)
}

/// A cylinder of radius `r` from `a` to `b` (2 quadrics: the cylinder and its slab).
fn rod(a: DVec3, b: DVec3, r: f64) -> String {
    let d = b - a;
    let length = d.length();
    let theta = (d.z / length).acos().to_degrees();
    let phi = d.y.atan2(d.x).to_degrees();
    format!(
        "translate({}) rotate([0, {theta:.6}, {phi:.6}]) cylinder(h = {length:.6}, r = {r});\n",
        vector(a)
    )
}

/// The scenes: the example with three spheres, and generated programs with exactly 5, 21, 31
/// and 80 quadrics.
fn scenes() -> Vec<Scene> {
    let root = common::workspace_root();
    let mut programs: Vec<(&'static str, String, String)> = Vec::new();
    let three = std::fs::read_to_string(root.join("examples/three_spheres.qcsg"))
        .expect("examples/three_spheres.qcsg");
    programs.push((
        "three spheres",
        "`examples/three_spheres.qcsg`".into(),
        three,
    ));
    programs.push((
        "hollowed cube",
        "a cube minus a ball and a corner ball".into(),
        "difference() { cube(2, center = true); sphere(1.3); translate([1, 1, 1]) sphere(0.6); }\n"
            .into(),
    ));
    let mut dimples = String::from("difference() {\n  cube(3, center = true);\n");
    for k in 0..18 {
        let p = fibonacci(k, 18, 1.6);
        let _ = writeln!(dimples, "  translate({}) sphere(0.45);", vector(p));
    }
    dimples.push_str("}\n");
    programs.push(("dimpled cube", "a cube minus 18 balls".into(), dimples));
    let mut drilled = String::from("difference() {\n  cube(3, center = true);\n");
    for k in 0..28 {
        let p = fibonacci(k, 28, 1.7);
        let _ = writeln!(drilled, "  translate({}) sphere(0.38);", vector(p));
    }
    drilled.push_str("}\n");
    programs.push(("pitted cube", "a cube minus 28 balls".into(), drilled));
    // A dodecahedral cage: 20 balls at the vertices, 30 rods along the edges.
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut vertices = Vec::new();
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                vertices.push(DVec3::new(sx, sy, sz));
            }
        }
    }
    for a in [-1.0, 1.0] {
        for b in [-1.0, 1.0] {
            vertices.push(DVec3::new(0.0, a / phi, b * phi));
            vertices.push(DVec3::new(a / phi, b * phi, 0.0));
            vertices.push(DVec3::new(a * phi, 0.0, b / phi));
        }
    }
    let edge = 2.0 / phi;
    let mut cage = String::from("union() {\n");
    for &v in &vertices {
        let _ = writeln!(cage, "  translate({}) sphere(0.22);", vector(v));
    }
    let mut rods = 0;
    for (i, &a) in vertices.iter().enumerate() {
        for &b in &vertices[i + 1..] {
            if ((a - b).length() - edge).abs() < 1e-9 {
                cage.push_str("  ");
                cage.push_str(&rod(a, b, 0.1));
                rods += 1;
            }
        }
    }
    cage.push_str("}\n");
    assert_eq!(rods, 30, "a dodecahedron has 30 edges");
    programs.push((
        "dodecahedral cage",
        "20 balls joined by 30 rods (80 quadrics, 77 distinct: parallel rods share slabs)".into(),
        cage,
    ));
    programs
        .into_iter()
        .map(|(name, what, text)| {
            let dnf = common::compile_text(&format!("{name}.qcsg"), text)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            Scene { name, what, dnf }
        })
        .collect()
}

/// One measured configuration.
struct Row {
    stats: SampleStats,
    /// Median seconds on one thread, each run writing into the previous run's output.
    one: f64,
    /// The same on two threads.
    two: f64,
    /// The fastest of those runs on one and on two threads: the least disturbed by other work
    /// on the machine.
    fastest: (f64, f64),
    /// Median seconds on one thread, each run in memory allocated anew.
    fresh: f64,
    /// Wall and CPU seconds spent in the 2-thread runs (cores actually obtained = CPU / wall).
    two_wall: f64,
    two_cpu: Option<f64>,
    /// Median seconds of a one-thread run alone, and while a second copy runs on the other
    /// core ([`two_copies_seconds`]).
    copies: (f64, f64),
    /// Medians over the one-thread runs of the seconds of their basic regions, of their first
    /// pass, of their refinement, and of the rest ([`PassClock`]).
    passes: [f64; 4],
}

/// Where a run's passes end, from its progress: the basic regions at [`Progress::Regions`], the
/// first pass at [`Progress::Refining`], the refinement (the second pass, its sample index
/// included) at its last refined rectangle.
#[derive(Default)]
struct PassClock {
    ends: Mutex<[Option<Instant>; 3]>,
    /// Rectangles still to be refined.
    unrefined: AtomicU64,
}

impl PassClock {
    fn progress(&self, event: Progress) {
        let end = |pass: usize| lock(&self.ends)[pass] = Some(Instant::now());
        match event {
            Progress::Regions { .. } => end(0),
            Progress::Refining { count, .. } => {
                end(1);
                self.unrefined.store(count, Ordering::Relaxed);
                if count == 0 {
                    end(2);
                }
            }
            Progress::RectangleRefined { .. } => {
                if self.unrefined.fetch_sub(1, Ordering::Relaxed) == 1 {
                    end(2);
                }
            }
            Progress::RegionDone { .. } => {}
        }
    }

    /// The seconds of the basic regions, of the first pass, of the refinement and of the rest
    /// of a run that started at `start` and ended at `end`; zeros where a pass went unreported.
    fn passes(&self, start: Instant, end: Instant) -> [f64; 4] {
        let [Some(regions), Some(first), Some(refined)] = *lock(&self.ends) else {
            return [0.0; 4];
        };
        [
            regions - start,
            first - regions,
            refined - first,
            end - refined,
        ]
        .map(|d| d.as_secs_f64())
    }
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Median seconds of one-thread runs of `dnf` at `r` alone and while an independent copy of the
/// same work runs at the same time, each on a core of its own with its own memory: nothing is
/// shared but the machine (caches, memory, clock), so `2 × alone / together` is the most two
/// threads of any division of the work can gain here. `runs` of each, in three alternating
/// rounds.
fn two_copies_seconds(dnf: &Dnf, r: f64, runs: usize) -> (f64, f64) {
    let copies = |count: usize, runs: usize| {
        let start = std::sync::Barrier::new(count);
        let copy = || {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .expect("thread pool");
            pool.install(|| {
                let mut previous = sample(dnf, r).expect("valid radius");
                start.wait();
                (0..runs)
                    .map(|_| {
                        let t = Instant::now();
                        let earlier = std::mem::take(&mut previous);
                        previous = resample(black_box(dnf), r, earlier).expect("sample");
                        t.elapsed().as_secs_f64()
                    })
                    .collect::<Vec<f64>>()
            })
        };
        std::thread::scope(|scope| {
            let running: Vec<_> = (0..count).map(|_| scope.spawn(copy)).collect();
            let times = running.into_iter().flat_map(|c| c.join().expect("copy"));
            times.collect::<Vec<f64>>()
        })
    };
    let (mut alone, mut together) = (Vec::new(), Vec::new());
    for _ in 0..3 {
        alone.extend(copies(1, runs.div_ceil(3)));
        together.extend(copies(2, runs.div_ceil(3)));
    }
    (median(alone), median(together))
}

/// The median of `times`.
fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Runs of `first` and of `second` in a row that [`median_pair`] takes in turn.
const TURN: usize = 3;

/// Medians of runs of `first` and `second`, [`TURN`] of one then as many of the other (at least
/// two turns each, more while under `budget` each), so that a change in the machine's load
/// while they run touches both alike, with the total and the fastest seconds of each. Within a
/// turn the runs follow each other as repeated runs do (a thread pool that has just worked does
/// not sleep); the first run of a turn wakes its pool, a third of the runs, above the median
/// when slower.
fn median_pair(
    budget: Duration,
    mut first: impl FnMut(),
    mut second: impl FnMut(),
) -> ((f64, f64, f64), (f64, f64, f64)) {
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let started = Instant::now();
    let turn = |f: &mut dyn FnMut(), times: &mut Vec<f64>| {
        for _ in 0..TURN {
            let t = Instant::now();
            f();
            times.push(t.elapsed().as_secs_f64());
        }
    };
    while a.len() < 2 * TURN || (started.elapsed() < 2 * budget && a.len() < 24) {
        turn(&mut first, &mut a);
        turn(&mut second, &mut b);
    }
    let fastest = |times: &[f64]| times.iter().copied().fold(f64::INFINITY, f64::min);
    let (sum_a, sum_b) = (a.iter().sum(), b.iter().sum());
    let (fastest_a, fastest_b) = (fastest(&a), fastest(&b));
    ((median(a), sum_a, fastest_a), (median(b), sum_b, fastest_b))
}

fn measure(dnf: &Dnf, r: f64) -> Row {
    let pool = |threads: usize| {
        qcsg_sample::threads::pool_builder(threads)
            .build()
            .expect("thread pool")
    };
    let (one_pool, two_pool) = (pool(1), pool(2));
    let mut previous = sample(dnf, r).expect("valid radius");
    let stats = previous.stats;
    let budget = Duration::from_millis(500);
    let fresh = one_pool.install(|| {
        median_seconds(budget, || {
            black_box(sample(black_box(dnf), r).expect("sample"));
        })
    });
    // Each pool samples into its own earlier output (the other threads' buffers included).
    let mut on_two = previous.clone();
    let again = |pool: &rayon::ThreadPool, previous: &mut Sampling| {
        let earlier = std::mem::take(previous);
        *previous = pool.install(|| resample(black_box(dnf), r, earlier).expect("sample"));
    };
    // The one-thread runs also time their passes.
    let mut passes = Vec::new();
    let mut timed = |previous: &mut Sampling| {
        let clock = PassClock::default();
        let progress = |event| clock.progress(event);
        let limits = (
            SampleLimits::default(),
            &progress as &(dyn Fn(Progress) + Sync),
        );
        let earlier = std::mem::take(previous);
        let start = Instant::now();
        let run = one_pool.install(|| resample_with_limits(black_box(dnf), r, limits, earlier));
        passes.push(clock.passes(start, Instant::now()));
        *previous = run.expect("sample");
    };
    let cpu_start = cpu_seconds();
    let ((one, one_total, fastest_one), (two, two_wall, fastest_two)) = median_pair(
        budget,
        || timed(&mut previous),
        || again(&two_pool, &mut on_two),
    );
    let passes = [0, 1, 2, 3].map(|k| median(passes.iter().map(|p| p[k]).collect()));
    // One thread keeps one core busy: the rest of the CPU time is the 2-thread runs'.
    let two_cpu = cpu_start.zip(cpu_seconds()).map(|(a, b)| b - a - one_total);
    // As many runs as `median_pair` makes of each in its budget.
    let runs = ((budget.as_secs_f64() / one) as usize).clamp(3, 25);
    let copies = two_copies_seconds(dnf, r, runs);
    Row {
        stats,
        one,
        two,
        fastest: (fastest_one, fastest_two),
        fresh,
        two_wall,
        two_cpu,
        copies,
        passes,
    }
}

fn main() {
    if let Ok(spec) = std::env::var(GRID_CHILD) {
        grid_memory_child(&spec);
        return;
    }
    // `cargo bench` passes `--bench`; `cargo test --benches` runs this without it: stay quick.
    if !std::env::args().any(|a| a == "--bench") {
        eprintln!("qcsg-sample bench: run with `cargo bench -p qcsg-sample --bench sample`");
        return;
    }
    let started = Instant::now();
    let load_before = load_average();
    // `Q(x)` at the start, before each scene and at the end: its median calibrates, so that a
    // burst of other work while one of them runs does not.
    let mut qx = vec![qx_nanoseconds()];
    // First: timed after the grids, it once took half as long again (71 against 110 ms).
    let single = single_quadric();
    let machine = (
        memory_scaling(),
        first_touch_microseconds(),
        wake_up_microseconds(),
    );
    let grids: Vec<GridRow> = FAMILIES
        .iter()
        .flat_map(|&family| GRIDS.iter().map(move |&n| (family, n)))
        .map(|(family, n)| {
            let row = measure_grid(family, n);
            eprintln!(
                "{} {}: {} samples, {:.2} ms (1 thread)",
                row.parts,
                row.family,
                row.stats.samples,
                row.seconds * 1e3
            );
            row
        })
        .collect();
    let scenes = scenes();
    let mut rows = Vec::new();
    for scene in &scenes {
        qx.push(qx_nanoseconds());
        let diagonal = common::diagonal(&scene.dnf);
        for (size, fraction) in RADII {
            let row = measure(&scene.dnf, fraction * diagonal);
            eprintln!(
                "{} {size}: {} samples, {:.2} ms (1 thread), {:.2} ms (2 threads)",
                scene.name,
                row.stats.samples,
                row.one * 1e3,
                row.two * 1e3
            );
            rows.push(row);
        }
    }
    qx.push(qx_nanoseconds());
    let load_after = load_average();
    let report = report::report(
        &scenes,
        &rows,
        (&grids, single),
        &qx,
        (&load_before, &load_after),
        machine,
        started.elapsed(),
    );
    let target = std::env::var("QCSG_BENCH_OUT").unwrap_or_else(|_| {
        common::workspace_root()
            .join("docs/sampler-benchmarks.md")
            .to_string_lossy()
            .into_owned()
    });
    if target == "-" {
        print!("{report}");
    } else {
        // The measurements behind the sampler's design are written by hand below the generated
        // tables; a new run keeps them.
        let kept = std::fs::read_to_string(&target)
            .ok()
            .and_then(|old| Some(old[old.find(DESIGN_MEASUREMENTS)?..].to_owned()))
            .unwrap_or_default();
        let report = if kept.is_empty() {
            report
        } else {
            format!("{}\n\n{kept}", report.trim_end())
        };
        std::fs::write(&target, report).expect("write the report");
        eprintln!("wrote {target}");
    }
}

/// The heading of the report's hand-written part, which a new run keeps.
const DESIGN_MEASUREMENTS: &str = "## Measurements behind the design";
