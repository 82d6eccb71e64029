//! `qcsg view FILE`: a live preview in the browser. A local web server shows the rendered solid,
//! rebuilt whenever the file or anything it includes or uses is saved; the page turns, pans and
//! zooms it, lists the diagnostics and says which call made the part under the mouse.
//!
//! - [`scene`]: compiling the program (through `qcsg-driver`) into the preview's scene, keeping
//!   the last good one while the text has errors;
//! - [`watch`]: which files to watch, and watching them;
//! - [`query`]: the query strings, checked;
//! - [`http`]: the routes (the contract is in `docs/view.md`), the `Host` check and the
//!   embedded page (`assets/`).
//!
//! The server binds 127.0.0.1 unless told otherwise and answers only requests addressed to it by
//! name (`Host`). Frames are rendered as `qcsg render` renders them with the same `--renderer`
//! and `--device`: by default the exact CPU ray tracer, or splats where a hardware GPU is found
//! (a software adapter such as lavapipe does not count, as for `qcsg render`). Picks always
//! come from the ray tracer.

mod http;
mod query;
mod scene;
mod watch;

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::{Arc, RwLock};
use std::time::Duration;

use clap::Args;
use qcsg_render::ImageSize;
use tokio::sync::{broadcast, mpsc};

use crate::compile::LimitArgs;
use crate::render::{Choice, Device, Renderer, choose};
use crate::{CommonArgs, EXIT_OK, EXIT_USAGE, program};

/// How long a rebuild waits for the end of a save after a change that did not end one (a file
/// truncated, created or written and still open); a save's end starts the rebuild at once.
const SAVE_WAIT: Duration = Duration::from_millis(100);

/// Arguments of `qcsg view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// The program (`.qcsg` or `.scad`) to show.
    #[arg(value_name = "FILE")]
    file: String,

    /// The port to listen on (0: any free port; the URL is printed).
    #[arg(long, value_name = "N", default_value_t = 0)]
    port: u16,

    /// The address to listen on. Anything but a loopback address exposes the preview (and the
    /// program's text, through its diagnostics) to the network.
    #[arg(long, value_name = "ADDR", default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    bind: IpAddr,

    /// Do not open the page in a browser.
    #[arg(long)]
    no_open: bool,

    /// The largest frame the server renders, in pixels.
    #[arg(long, value_name = "W,H", default_value = "4096,4096", value_parser = parse_size)]
    max_size: ImageSize,

    /// The renderer of frames, as for `qcsg render`: splats on a GPU adapter, or the exact CPU
    /// ray tracer. Unset, `--device` decides.
    #[arg(long, value_enum)]
    renderer: Option<Renderer>,

    /// Where to render frames, as for `qcsg render`: `auto` uses splats on a hardware GPU when
    /// there is one and the CPU ray tracer otherwise; `gpu` requires a hardware GPU; `cpu` the
    /// CPU (the ray tracer, or with `--renderer splat` a software adapter such as lavapipe).
    #[arg(long, value_enum, default_value_t = Device::Auto)]
    device: Device,

    #[command(flatten)]
    limits: LimitArgs,

    #[command(flatten)]
    common: CommonArgs,
}

fn parse_size(text: &str) -> Result<ImageSize, String> {
    ImageSize::parse(text).map_err(|e| e.to_string())
}

/// Runs `qcsg view` until interrupted; returns the exit status of a failed start.
pub fn run(args: ViewArgs) -> u8 {
    if args.file == "-" {
        eprintln!("error: `qcsg view` watches a file; standard input cannot be watched");
        return EXIT_USAGE;
    }
    if let Err(message) = program::read(&args.file) {
        eprintln!("error: {message}");
        return EXIT_USAGE;
    }
    let pool = match program::thread_pool(args.common.threads) {
        Ok(pool) => pool,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    };
    let frames = match choose(args.renderer, args.device) {
        Ok(Choice::RayTracer { fallback }) => {
            let why = fallback.map_or(String::new(), |why| format!(" ({why})"));
            eprintln!("qcsg view: frames by the CPU ray tracer{why}");
            http::Frames::RayTracer
        }
        Ok(Choice::Splats(renderer)) => {
            eprintln!(
                "qcsg view: frames by the splat renderer (adapter: {})",
                renderer.adapter()
            );
            http::Frames::Splats(renderer)
        }
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    };
    let runtime = match tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        // The pipeline walks trees recursively, as the language server's threads do.
        .thread_stack_size(32 * 1024 * 1024)
        .enable_all()
        .build()
    {
        Ok(runtime) => runtime,
        Err(error) => {
            eprintln!("error: cannot start the server: {error}");
            return EXIT_USAGE;
        }
    };
    runtime.block_on(serve(args, pool, frames))
}

async fn serve(args: ViewArgs, pool: rayon::ThreadPool, frames: http::Frames) -> u8 {
    let listener = match tokio::net::TcpListener::bind(SocketAddr::new(args.bind, args.port)).await
    {
        Ok(listener) => listener,
        Err(error) => {
            eprintln!(
                "error: cannot listen on {}:{}: {error}",
                args.bind, args.port
            );
            return EXIT_USAGE;
        }
    };
    let address = match listener.local_addr() {
        Ok(address) => address,
        Err(error) => {
            eprintln!("error: {error}");
            return EXIT_USAGE;
        }
    };
    let options = Arc::new(args.limits.options(&args.common.defines));
    let file = args.file.clone();
    let first = {
        let (file, options) = (file.clone(), Arc::clone(&options));
        tokio::task::spawn_blocking(move || scene::rebuild(&file, &options, None)).await
    };
    let Ok(first) = first else {
        eprintln!("error: the first build failed");
        return EXIT_USAGE;
    };
    let (changed, mut change_events) = mpsc::unbounded_channel();
    let mut watch = match watch::FileWatch::new(changed) {
        Ok(watch) => watch,
        Err(error) => {
            eprintln!("error: cannot watch files: {error}");
            return EXIT_USAGE;
        }
    };
    watch.follow(&first.files);
    let port = address.port();
    let mut hosts = vec![
        format!("127.0.0.1:{port}"),
        format!("localhost:{port}"),
        format!("[::1]:{port}"),
    ];
    let own = match address.ip() {
        IpAddr::V6(ip) => format!("[{ip}]:{port}"),
        IpAddr::V4(ip) => format!("{ip}:{port}"),
    };
    if !hosts.contains(&own) && !address.ip().is_unspecified() {
        hosts.push(own);
    }
    let shared = Arc::new(http::Shared {
        snapshot: RwLock::new(Arc::new(first)),
        changes: broadcast::channel(16).0,
        hosts,
        limit: query::SizeLimit {
            width: args.max_size.width(),
            height: args.max_size.height(),
        },
        pool,
        frames,
    });

    // Rebuild after changes: once a save has ended (or after a while without its end), gather
    // the rest of its events, then compile once.
    let rebuilding = Arc::clone(&shared);
    tokio::spawn(async move {
        while let Some(mut change) = change_events.recv().await {
            let deadline = tokio::time::Instant::now() + SAVE_WAIT;
            while change != watch::Change::Saved {
                match tokio::time::timeout_at(deadline, change_events.recv()).await {
                    Ok(Some(next)) => change = next,
                    Ok(None) => return,
                    Err(_) => break,
                }
            }
            while change_events.try_recv().is_ok() {}
            let previous = Arc::clone(
                &rebuilding
                    .snapshot
                    .read()
                    .unwrap_or_else(std::sync::PoisonError::into_inner),
            );
            let (file, options) = (file.clone(), Arc::clone(&options));
            let Ok(next) = tokio::task::spawn_blocking(move || {
                scene::rebuild(&file, &options, Some(&previous))
            })
            .await
            else {
                continue;
            };
            watch.follow(&next.files);
            rebuilding.publish(next);
        }
    });

    let display_host = if address.ip().is_loopback() || address.ip().is_unspecified() {
        format!("127.0.0.1:{port}")
    } else {
        shared.hosts.last().cloned().unwrap_or_default()
    };
    let url = format!("http://{display_host}/");
    println!("qcsg view: {} at {url} (Ctrl-C stops)", args.file);
    use std::io::Write as _;
    let _ = std::io::stdout().flush();
    if !args.no_open {
        open_browser(&url);
    }
    match axum::serve(listener, http::router(shared)).await {
        Ok(()) => EXIT_OK,
        Err(error) => {
            eprintln!("error: the server stopped: {error}");
            EXIT_USAGE
        }
    }
}

/// Opens `url` in the desktop's browser; a failure only leaves the printed URL to follow.
fn open_browser(url: &str) {
    let command = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    let spawned = std::process::Command::new(command)
        .arg(url)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
    if spawned.is_err() {
        eprintln!("(could not start a browser; open the URL above)");
    }
}
