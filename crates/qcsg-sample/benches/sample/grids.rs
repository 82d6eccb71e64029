//! The many-parts table: grids of `n × n` separate parts and plates drilled with as many holes,
//! sampled on one thread, with each grid's peak memory measured in a fresh process.

use std::fmt::Write as _;
use std::hint::black_box;
use std::time::Duration;

use qcsg_sample::{SampleStats, sample};

use crate::calibration::median_seconds;
use crate::common;

/// Grid sizes of the many-parts table: `n × n` separate parts.
pub(crate) const GRIDS: [usize; 4] = [8, 16, 32, 64];

/// Sample radius of the many-parts table: a tenth of a part's width, so every part takes about
/// the same samples and the time per part shows how setup and sampling grow with the parts.
pub(crate) const GRID_RADIUS: f64 = 0.2;

/// A scene family of the many-parts table: a name and the program of `n × n` of them.
pub(crate) type Family = (&'static str, fn(usize) -> String);

/// The scene families of the many-parts table.
pub(crate) const FAMILIES: [Family; 2] = [
    ("separate parts", grid_program),
    ("holes in one plate", plate_program),
];

/// A plate drilled with `n × n` holes at a pitch of 3 (one term of `n² + 3` literals; the plate
/// of `tests/stability/perforated_plate.qcsg`).
pub(crate) fn plate_program(n: usize) -> String {
    format!(
        "difference() {{\n\
         \x20   cube([{w}, {w}, 2]);\n\
         \x20   for (i = [0 : {m}], j = [0 : {m}])\n\
         \x20       translate([i * 3 + 1.5, j * 3 + 1.5, -1]) cylinder(h = 4, r = 1);\n\
         }}\n",
        w = 3 * n,
        m = n - 1
    )
}

/// `n × n` separate parts at a pitch of 3: dented blocks and pins in turn (the grid of
/// `tests/stability/many_parts.qcsg`).
pub(crate) fn grid_program(n: usize) -> String {
    format!(
        "for (i = [0 : {m}], j = [0 : {m}]) translate([i * 3, j * 3, 0]) {{
             if ((i + j) % 2 == 0)
                 difference() {{
                     cube([2, 2, 1 + (i + j) % 3]);
                     translate([1, 1, 1 + (i + j) % 3]) sphere(r = 0.6);
                 }}
             else
                 translate([1, 1, 0]) cylinder(h = 2 + i % 2, r = 0.8);
         }}
",
        m = n - 1
    )
}

/// One grid of the many-parts table.
pub(crate) struct GridRow {
    pub(crate) family: &'static str,
    pub(crate) parts: usize,
    pub(crate) terms: usize,
    pub(crate) literals: usize,
    pub(crate) stats: SampleStats,
    /// Median seconds on one thread.
    pub(crate) seconds: f64,
    /// The peak resident set of a process that compiles and samples it once, in MiB.
    pub(crate) memory: Option<f64>,
}

/// Samples `n × n` parts of a family on one thread; the memory is measured in a fresh process
/// ([`grid_memory_child`]).
pub(crate) fn measure_grid((family, program): Family, n: usize) -> GridRow {
    let dnf = common::compile_text("grid.qcsg", program(n)).expect("grid program");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    let stats = pool.install(|| sample(&dnf, GRID_RADIUS).expect("valid radius").stats);
    let seconds = pool.install(|| {
        median_seconds(Duration::from_millis(500), || {
            black_box(sample(black_box(&dnf), GRID_RADIUS).expect("sample"));
        })
    });
    let memory = std::env::current_exe().ok().and_then(|exe| {
        let output = std::process::Command::new(exe)
            .env(GRID_CHILD, format!("{family}:{n}"))
            .output()
            .ok()?;
        String::from_utf8(output.stdout).ok()?.trim().parse().ok()
    });
    GridRow {
        family,
        parts: n * n,
        terms: dnf.terms.len(),
        literals: dnf.terms.iter().map(|t| t.literals.len()).sum(),
        stats,
        seconds,
        memory,
    }
}

/// The environment variable that makes this binary the child of [`measure_grid`]:
/// `family:n`.
pub(crate) const GRID_CHILD: &str = "QCSG_BENCH_GRID_MEMORY";

/// In the child: compiles and samples one grid on one thread and prints the process's peak
/// resident set in MiB (Linux `VmHWM`), nothing where it is unknown.
pub(crate) fn grid_memory_child(spec: &str) {
    let Some((family, n)) = spec.split_once(':') else {
        return;
    };
    let (Some(&(_, program)), Ok(n)) = (
        FAMILIES.iter().find(|(name, _)| *name == family),
        n.parse::<usize>(),
    ) else {
        return;
    };
    let dnf = common::compile_text("grid.qcsg", program(n)).expect("grid program");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    black_box(pool.install(|| sample(&dnf, GRID_RADIUS).expect("valid radius")));
    let peak = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|status| {
            let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
            line.split_whitespace().nth(1)?.parse::<f64>().ok()
        });
    if let Some(kib) = peak {
        println!("{:.1}", kib / 1024.0);
    }
}

/// The many-parts table: time and memory per part as the parts grow.
pub(crate) fn many_parts_section(out: &mut String, grids: &[GridRow]) {
    let _ = writeln!(out, "## Many parts\n");
    let _ = writeln!(
        out,
        "Grids of `n × n` parts at radius {GRID_RADIUS}, a tenth of a part's width, on one \
         thread: *separate parts* are dented blocks and pins in turn (the grid of \
         `tests/stability/many_parts.qcsg`), one term each; *holes in one plate* are holes \
         drilled in a plate (as `tests/stability/perforated_plate.qcsg`), one term of `n² + 3` \
         literals. Each part takes about the same samples, so time and memory per part stay flat \
         where the sampler's cost grows with the parts and not with their square: eq. 22 of a \
         part looks only at the parts and literals near it (\"Far terms\" and \"Far \
         literals\" in `csg_distance.rs`). The ratio column is the time per part over the \
         smallest grid's of the same kind, from this run. Memory is the peak resident set of a \
         fresh process that compiles the grid and samples it once (the program included).\n"
    );
    let _ = writeln!(
        out,
        "| scene | parts | terms | literals | samples | distance queries | unresolved | 1 thread ms | µs / part | ratio | peak resident MiB |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    let per_part = |g: &GridRow| g.seconds * 1e6 / g.parts as f64;
    for g in grids {
        let first = grids
            .iter()
            .find(|f| f.family == g.family)
            .map_or(1.0, per_part);
        let memory = g.memory.map_or("unknown".into(), |m| format!("{m:.0}"));
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {:.1} | {:.1} | {:.2}× | {memory} |",
            g.family,
            g.parts,
            g.terms,
            g.literals,
            g.stats.samples,
            g.stats.subdivision.distance_queries,
            g.stats.unresolved(),
            g.seconds * 1e3,
            per_part(g),
            per_part(g) / first,
        );
    }
    let _ = writeln!(out);
}
