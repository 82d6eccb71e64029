//! The measurements that put the sampling times in context: the cost of emitting a sample (a
//! lone ball sampled finely, beside paper 000's Table 1), `Q(x)` for calibration against the
//! paper's machine, how memory bandwidth scales with threads, the cost of first touching memory
//! and of waking a parked thread, and the machine's name and load.

use std::hint::black_box;
use std::time::{Duration, Instant};

use qcsg_quadric::{DMat4, DVec3, Quadric};
use qcsg_sample::{resample, sample};

use crate::{common, median};

/// The lone ball's radius in [`single_quadric`], as a fraction of its bounding-box diagonal:
/// millions of samples, so that a run's fixed costs vanish beside emitting them.
pub(crate) const BALL_FRACTION: f64 = 0.0005;

/// Paper 000, Table 1: sampling a single quadric without subdivision, ns per sample.
pub(crate) const PAPER_SINGLE_NS: f64 = 7.41;

/// Samples and median seconds of one-thread runs sampling a lone ball at [`BALL_FRACTION`] of
/// its diagonal, each into the previous run's output. Its basic regions are filled whole, so
/// this is the cost of emitting a sample (its point, the check that it lies on the quadric, its
/// normal, and the 72 bytes written), with the region borders; its clip lists are empty and
/// skipped box by box.
pub(crate) fn single_quadric() -> (u64, f64) {
    let dnf = common::compile_text("ball.qcsg", "sphere(r = 10);\n".into()).expect("a ball");
    let r = BALL_FRACTION * common::diagonal(&dnf);
    let pool = qcsg_sample::threads::pool_builder(1)
        .build()
        .expect("thread pool");
    pool.install(|| {
        let mut previous = sample(&dnf, r).expect("valid radius");
        let samples = previous.stats.samples;
        let seconds = median_seconds(Duration::from_millis(500), || {
            let earlier = std::mem::take(&mut previous);
            previous = resample(black_box(&dnf), r, earlier).expect("sample");
        });
        (samples, seconds)
    })
}

/// Median seconds of repeated runs of `f` (at least 3, more while under `budget`).
pub(crate) fn median_seconds(budget: Duration, mut f: impl FnMut()) -> f64 {
    let mut times = Vec::new();
    let started = Instant::now();
    while times.len() < 3 || (started.elapsed() < budget && times.len() < 25) {
        let t = Instant::now();
        f();
        times.push(t.elapsed().as_secs_f64());
    }
    median(times)
}

/// Nanoseconds per `Q(x)` over a batch of 1024 points near an ellipsoid (as in
/// `qcsg-quadric`'s `ops` benchmark), median of 31 rounds.
pub(crate) fn qx_nanoseconds() -> f64 {
    let q = Quadric::ellipsoid(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0))
        .and_then(|q| {
            q.transformed(
                &(DMat4::from_translation(DVec3::new(0.5, -1.0, 2.0))
                    * DMat4::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7)),
            )
        })
        .expect("ellipsoid");
    let mut rng = common::Rng::new(5);
    let points: Vec<DVec3> = (0..1024)
        .map(|_| {
            DVec3::new(
                rng.range(-4.0, 4.0),
                rng.range(-4.0, 4.0),
                rng.range(-4.0, 4.0),
            )
        })
        .collect();
    let rounds = 2000;
    let mut per_op = Vec::new();
    for _ in 0..31 {
        let t = Instant::now();
        for _ in 0..rounds {
            let mut sum = 0.0;
            for &p in black_box(&points) {
                sum += black_box(&q).value(p);
            }
            black_box(sum);
        }
        per_op.push(t.elapsed().as_secs_f64() * 1e9 / (rounds * points.len()) as f64);
    }
    per_op.sort_by(f64::total_cmp);
    per_op[per_op.len() / 2]
}

/// Bytes each thread streams through in [`memory_scaling`] and [`first_touch_microseconds`].
pub(crate) const PROBE_BYTES: usize = 64 << 20;

/// Throughput of two threads streaming through memory (each its own buffer) over one thread
/// streaming through both, median of 5: 2 where memory keeps up with both cores. The sampler
/// writes every sample once and reads some again (the index, the clip lists), so where this
/// stays near 1 its sample-heavy rows cannot speed up by 2.
pub(crate) fn memory_scaling() -> f64 {
    let words = PROBE_BYTES / 8;
    let mut buffers = [vec![1u64; words], vec![1u64; words]];
    // Read and write every word, independently: bound by memory, not by arithmetic.
    let stream = |buffer: &mut [u64]| {
        for word in buffer.iter_mut() {
            *word = word.wrapping_mul(3).wrapping_add(1);
        }
        black_box(buffer);
    };
    let mut ratios = Vec::new();
    for _ in 0..5 {
        let t = Instant::now();
        buffers.iter_mut().for_each(|b| stream(b));
        let one = t.elapsed().as_secs_f64();
        let t = Instant::now();
        std::thread::scope(|scope| {
            for buffer in &mut buffers {
                scope.spawn(|| stream(buffer));
            }
        });
        ratios.push(one / t.elapsed().as_secs_f64());
    }
    ratios.sort_by(f64::total_cmp);
    ratios[ratios.len() / 2]
}

/// Microseconds to write the first byte of each 4 KiB page of freshly allocated memory (the
/// operating system maps a page at its first touch), median of 5. The sampler touches its
/// output for the first time as it emits it.
pub(crate) fn first_touch_microseconds() -> f64 {
    let pages = PROBE_BYTES / 4096;
    let mut per_page = Vec::new();
    for _ in 0..5 {
        let mut memory = black_box(vec![0u8; PROBE_BYTES]);
        let t = Instant::now();
        for page in memory.chunks_mut(4096) {
            page[0] = 1;
        }
        per_page.push(t.elapsed().as_secs_f64() * 1e6 / pages as f64);
        black_box(&memory);
    }
    per_page.sort_by(f64::total_cmp);
    per_page[per_page.len() / 2]
}

/// How long the cores of [`wake_up_microseconds`] sit idle before work is offered.
pub(crate) const IDLE_GAP: Duration = Duration::from_millis(20);

/// How long the first thread of [`wake_up_microseconds`] works while the second may take its
/// share: the most a wake-up can measure.
pub(crate) const WAKE_WORK: Duration = Duration::from_millis(5);

/// Microseconds from offering work to the second thread of a 2-thread pool until that thread
/// starts it, median of 15: for the benchmark's pool (threads kept to a core each,
/// [`qcsg_sample::threads`]) right after it last worked and after it sat idle for [`IDLE_GAP`]
/// (as the 2-thread pool does while the 1-thread runs of a row take their turn), and for a
/// plain rayon pool after the same idle time. Capped at [`WAKE_WORK`], the first thread's work
/// meanwhile, after which it takes the offered work itself.
pub(crate) fn wake_up_microseconds() -> WakeUp {
    let work = || {
        let t = Instant::now();
        while t.elapsed() < WAKE_WORK {
            std::hint::spin_loop();
        }
    };
    let latency = |pool: &rayon::ThreadPool, idle: Duration| {
        let times = (0..15)
            .map(|_| {
                std::thread::sleep(idle);
                pool.install(|| {
                    let offered = Instant::now();
                    let (_, started) = rayon::join(work, || offered.elapsed());
                    started.as_secs_f64() * 1e6
                })
            })
            .collect();
        median(times)
    };
    let kept = qcsg_sample::threads::pool_builder(2).build();
    let plain = rayon::ThreadPoolBuilder::new().num_threads(2).build();
    let (kept, plain) = (kept.expect("thread pool"), plain.expect("thread pool"));
    WakeUp {
        busy: latency(&kept, Duration::ZERO),
        idle: latency(&kept, IDLE_GAP),
        plain_idle: latency(&plain, IDLE_GAP),
    }
}

/// [`wake_up_microseconds`].
pub(crate) struct WakeUp {
    pub(crate) busy: f64,
    pub(crate) idle: f64,
    pub(crate) plain_idle: f64,
}

pub(crate) fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

pub(crate) fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|info| {
            info.lines().find_map(|l| {
                l.strip_prefix("model name")
                    .map(|m| m.trim_start_matches([' ', '\t', ':']).to_string())
            })
        })
        .unwrap_or_else(|| "unknown".into())
}

/// CPU time (user + system) of this process in seconds, from `/proc/self/stat` (clock ticks of
/// 1/100 s); `None` where unavailable.
pub(crate) fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (in parentheses): utime and stime are fields 14 and 15.
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}
