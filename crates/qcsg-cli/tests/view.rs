//! The HTTP contract of `qcsg view` (docs/view.md), against the real binary: `/frame.png` is
//! `qcsg render`'s PNG for the same arguments, `/pick` finds the call of every primitive of a
//! gallery scene, saves are followed, and what is wrong or hostile gets a 4xx answer.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use qcsg_lsp::preview::{Preview, ViewRequest};
use qcsg_render::{ImageSize, PixelId, Projection, View};
use qcsg_testkit::cli::Invocation;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A running `qcsg view`, stopped when dropped. It is spawned here rather than by the tests'
/// runner ([`Invocation`]), which waits for its binary to end and reads its output whole: a
/// server is talked to while it runs, from the port on the first line it prints.
struct Server {
    child: Child,
    port: u16,
}

impl Server {
    fn start(file: &Path, extra: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_qcsg"))
            .arg("view")
            .arg(file)
            .args(["--no-open", "--port", "0", "--threads", "2"])
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("qcsg view starts");
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("stdout"))
            .read_line(&mut line)
            .expect("the URL line");
        let port = line
            .split("http://127.0.0.1:")
            .nth(1)
            .and_then(|rest| rest.split('/').next())
            .and_then(|port| port.parse().ok())
            .unwrap_or_else(|| panic!("no URL in {line:?}"));
        Server { child, port }
    }

    fn get(&self, path: &str) -> Answer {
        self.get_with_host(path, &format!("127.0.0.1:{}", self.port))
    }

    fn get_with_host(&self, path: &str, host: &str) -> Answer {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).expect("connects");
        stream
            .set_read_timeout(Some(Duration::from_secs(60)))
            .expect("timeout");
        write!(
            stream,
            "GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
        )
        .expect("request sent");
        let mut raw = Vec::new();
        stream.read_to_end(&mut raw).expect("answer read");
        Answer::parse(&raw)
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

struct Answer {
    status: u16,
    headers: BTreeMap<String, String>,
    body: Vec<u8>,
}

impl Answer {
    fn parse(raw: &[u8]) -> Answer {
        let end = raw
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .expect("a header block");
        let head = String::from_utf8_lossy(&raw[..end]);
        let mut lines = head.lines();
        let status = lines
            .next()
            .expect("status line")
            .split(' ')
            .nth(1)
            .expect("code");
        let headers: BTreeMap<String, String> = lines
            .filter_map(|l| l.split_once(':'))
            .map(|(k, v)| (k.trim().to_ascii_lowercase(), v.trim().to_owned()))
            .collect();
        let mut body = raw[end + 4..].to_vec();
        if headers.get("transfer-encoding").map(String::as_str) == Some("chunked") {
            body = dechunk(&body);
        }
        Answer {
            status: status.parse().expect("numeric status"),
            headers,
            body,
        }
    }

    fn json(&self) -> serde_json::Value {
        serde_json::from_slice(&self.body)
            .unwrap_or_else(|_| panic!("JSON: {}", String::from_utf8_lossy(&self.body)))
    }
}

fn dechunk(mut body: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let line_end = body
            .windows(2)
            .position(|w| w == b"\r\n")
            .expect("chunk size");
        let size =
            usize::from_str_radix(std::str::from_utf8(&body[..line_end]).unwrap().trim(), 16)
                .expect("hex size");
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&body[line_end + 2..line_end + 2 + size]);
        body = &body[line_end + 4 + size..];
    }
}

fn render_cli(file: &Path, args: &[&str]) -> Vec<u8> {
    render_with(file, &[&["--renderer", "raytrace"], args].concat())
}

/// A run of the built `qcsg` that ends by itself (a server is a [`Server`]).
fn qcsg() -> Invocation {
    Invocation::new(env!("CARGO_BIN_EXE_qcsg"))
}

/// `qcsg render FILE -o - ARGS`'s PNG.
fn render_with(file: &Path, args: &[&str]) -> Vec<u8> {
    let run = qcsg()
        .arg("render")
        .arg(file)
        .args(["-o", "-", "--quiet"])
        .args(args)
        .run();
    assert!(
        run.status == 0,
        "qcsg render {args:?} failed: {}",
        run.stderr
    );
    run.stdout
}

#[test]
fn frames_are_the_pngs_of_qcsg_render() {
    let file = workspace().join("examples/wheel.qcsg");
    // The ray tracer, as on a machine without a hardware GPU (where `auto` draws splats).
    let server = Server::start(&file, &["--renderer", "raytrace"]);
    let cases: [(&str, &[&str]); 4] = [
        ("", &[]),
        (
            "width=96&height=64&camera=top&projection=ortho",
            &[
                "--size",
                "96,64",
                "--camera",
                "top",
                "--projection",
                "ortho",
            ],
        ),
        (
            "width=80&height=60&camera=55%2C-80%2C75%2C0%2C0%2C3",
            &["--size", "80,60", "--camera", "55,-80,75,0,0,3"],
        ),
        (
            "height=50&width=70&camera=right&projection=perspective",
            &["--size", "70,50", "--camera", "right"],
        ),
    ];
    for (query, args) in cases {
        let answer = server.get(&format!("/frame.png?{query}"));
        assert_eq!(answer.status, 200, "{query}");
        assert_eq!(answer.headers["content-type"], "image/png");
        assert!(answer.headers.contains_key("x-qcsg-generation"));
        assert_eq!(answer.headers["x-qcsg-renderer"], "raytrace");
        assert!(
            answer.body == render_cli(&file, args),
            "/frame.png?{query} differs from qcsg render {args:?}"
        );
    }
}

/// For every quadric of the solid, a pixel of some view that shows it.
fn pixels_showing_each_call(file: &Path) -> Vec<(String, ViewRequest, u32, u32, [u32; 2])> {
    /// The camera's text, the frame and the pixel.
    type Seen = (String, ViewRequest, u32, u32);
    let name = file.to_string_lossy().into_owned();
    let source = qcsg_sema::read_source(file).expect("readable");
    let compilation = qcsg_driver::compile_source(
        &name,
        source,
        &qcsg_driver::Options::default(),
        &qcsg_sema::FsLoader,
        qcsg_driver::Stage::Dnf,
    );
    assert!(!compilation.has_errors());
    let preview = Preview::new(
        &compilation.analysis,
        compilation.layers.expect("layers"),
        &compilation.instantiations,
    );
    let quadrics = &preview
        .scene()
        .solid
        .as_ref()
        .expect("a solid")
        .dnf()
        .quadrics;
    let mut wanted: BTreeMap<[u32; 2], Option<Seen>> = quadrics
        .iter()
        .map(|q| ([q.source.span.start, q.source.span.end], None))
        .collect();
    let views = [
        ("iso", View::Iso),
        ("front", View::Front),
        ("top", View::Top),
        ("right", View::Right),
        ("-60,70,-50,0,0,5", View::parse("-60,70,-50,0,0,5").unwrap()),
        ("0,0,-90,0,0,0", View::parse("0,0,-90,0,0,0").unwrap()),
    ];
    for (text, view) in views {
        let request = ViewRequest {
            size: ImageSize::new(160, 120).unwrap(),
            view,
            projection: Projection::Perspective,
        };
        let frame = preview.render(&request).expect("renders");
        for y in 0..120 {
            for x in 0..160 {
                let id = frame.ids[frame.index(x, y)];
                if id == PixelId::MISS || id.quadric == PixelId::NONE {
                    continue;
                }
                let q = &quadrics[id.quadric as usize];
                let slot = wanted
                    .get_mut(&[q.source.span.start, q.source.span.end])
                    .expect("known");
                if slot.is_none() {
                    *slot = Some((text.to_owned(), request, x, y));
                }
            }
        }
    }
    wanted
        .into_iter()
        .map(|(range, found)| {
            let (text, request, x, y) =
                found.unwrap_or_else(|| panic!("the call at {range:?} is seen in no view"));
            (text, request, x, y, range)
        })
        .collect()
}

#[test]
fn a_pick_on_every_primitive_finds_its_call() {
    let file = workspace().join("examples/wheel.qcsg");
    let text = std::fs::read_to_string(&file).unwrap();
    let server = Server::start(&file, &[]);
    let targets = pixels_showing_each_call(&file);
    assert!(targets.len() >= 6, "{} calls", targets.len());
    for (camera, request, x, y, range) in targets {
        let query = format!(
            "/pick?width={}&height={}&camera={camera}&x={x}&y={y}",
            request.size.width(),
            request.size.height()
        );
        let answer = server.get(&query);
        assert_eq!(answer.status, 200, "{query}");
        let picked = answer.json();
        assert_eq!(picked["layer"], "solid");
        assert_eq!(
            picked["byte_range"],
            serde_json::json!(range),
            "{query}: {picked}"
        );
        assert!(picked["file"].as_str().unwrap().ends_with("wheel.qcsg"));
        let start_line = picked["range"]["start"]["line"].as_u64().unwrap();
        assert_eq!(
            start_line,
            text[..range[0] as usize].matches('\n').count() as u64
        );
        // The rim and its bore are made inside `tube`, called at the top level.
        let call = &text[range[0] as usize..range[1] as usize];
        if call.starts_with("cylinder(h = height")
            || call.starts_with("translate([0, 0, -1]) cylinder(h = height")
        {
            let chain = picked["chain"].as_array().unwrap();
            assert_eq!(chain.len(), 1, "{picked}");
            assert_eq!(chain[0]["module"], "tube");
            let at = chain[0]["byte_range"][0].as_u64().unwrap() as usize;
            assert!(text[at..].starts_with("tube(rim_width"), "{picked}");
        } else {
            assert_eq!(picked["chain"], serde_json::json!([]), "{picked}");
        }
    }
    // The background, and a pixel of no part.
    let answer = server.get("/pick?width=100&height=100&camera=iso&x=0&y=0");
    assert_eq!(answer.status, 200);
    assert_eq!(answer.json(), serde_json::Value::Null);
}

#[test]
fn wrong_hosts_other_paths_and_malformed_values_get_4xx() {
    let file = workspace().join("examples/three_spheres.qcsg");
    let server = Server::start(&file, &["--max-size", "640,480"]);
    assert_eq!(server.get("/").status, 200);
    for host in ["evil.example:80", "127.0.0.1", "localhost:1"] {
        let port_host = host.replace(":80", &format!(":{}", server.port));
        let answer = server.get_with_host("/frame.png?width=8&height=8", &port_host);
        assert_eq!(answer.status, 403, "Host {port_host}");
    }
    assert_eq!(
        server
            .get_with_host("/", &format!("localhost:{}", server.port))
            .status,
        200
    );
    for path in [
        "/../Cargo.toml",
        "/%2e%2e/%2e%2e/Cargo.toml",
        "/examples/three_spheres.qcsg",
        "/assets/view.js",
        "/etc/passwd",
        "/view.js/..",
    ] {
        let answer = server.get(path);
        assert!(
            (400..500).contains(&answer.status),
            "{path}: {}",
            answer.status
        );
        assert!(!String::from_utf8_lossy(&answer.body).contains("three_spheres"));
    }
    for query in [
        "/frame.png?width=abc",
        "/frame.png?width=0",
        "/frame.png?width=99999999999",
        "/frame.png?width=641",
        "/frame.png?camera=1,2,3",
        "/frame.png?camera=nan,0,0,0,0,0",
        "/frame.png?camera=0,0,0,0,0,0",
        "/frame.png?projection=fisheye",
        "/frame.png?zoom=3",
        "/frame.png?width=%ZZ",
        "/pick?x=1",
        "/pick?width=10&height=10&x=10&y=3",
        "/pick?width=10&height=10&x=-1&y=3",
        "/camera?camera=up",
    ] {
        let answer = server.get(query);
        assert_eq!(answer.status, 400, "{query}");
        let message = answer.json()["error"]["message"].clone();
        assert!(message.is_string(), "{query}: {message}");
    }
    let over = server.get("/frame.png?width=641").json();
    assert!(
        over["error"]["help"]
            .as_str()
            .unwrap()
            .contains("--max-size 641,480"),
        "{over}"
    );
    // Still alive and answering.
    assert_eq!(server.get("/frame.png?width=8&height=8").status, 200);
}

/// Reads the `/events` stream until a `change` event satisfies `done`.
fn wait_for_change(
    server: &Server,
    done: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    let mut stream = TcpStream::connect(("127.0.0.1", server.port)).expect("connects");
    stream
        .set_read_timeout(Some(Duration::from_secs(30)))
        .expect("timeout");
    write!(
        stream,
        "GET /events HTTP/1.1\r\nHost: 127.0.0.1:{}\r\n\r\n",
        server.port
    )
    .expect("request");
    let mut reader = BufReader::new(stream);
    let started = Instant::now();
    let mut line = String::new();
    while started.elapsed() < Duration::from_secs(30) {
        line.clear();
        if reader.read_line(&mut line).unwrap_or(0) == 0 {
            break;
        }
        if let Some(data) = line.trim_end().strip_prefix("data: ") {
            let event: serde_json::Value = serde_json::from_str(data).expect("JSON event");
            if done(&event) {
                return event;
            }
        }
    }
    panic!("no such change event within 30 s");
}

#[test]
fn saves_of_the_file_and_its_includes_rebuild_and_errors_keep_the_last_image() {
    let dir = std::env::temp_dir().join(format!("qcsg-view-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let main = dir.join("main.qcsg");
    let part = dir.join("part.qcsg");
    std::fs::write(&part, "module part() sphere(2);\n").unwrap();
    std::fs::write(&main, "include <part.qcsg>\npart();\n").unwrap();
    let server = Server::start(&main, &[]);
    let first = wait_for_change(&server, |e| e["ok"] == true);
    let generation = first["generation"].as_u64().unwrap();
    let before = server.get("/frame.png?width=40&height=30").body;

    // A change in the included file.
    std::fs::write(&part, "module part() cube(3, center = true);\n").unwrap();
    let changed = wait_for_change(&server, |e| e["generation"].as_u64() > Some(generation));
    assert_eq!(changed["ok"], true);
    let after = server.get("/frame.png?width=40&height=30");
    assert_ne!(after.body, before, "the frame follows the include");
    let generation = changed["generation"].as_u64().unwrap();

    // A syntax error: diagnostics, and the last good image still served.
    std::fs::write(&main, "include <part.qcsg>\npart(;\n").unwrap();
    let broken = wait_for_change(&server, |e| e["generation"].as_u64() > Some(generation));
    assert_eq!(broken["ok"], false);
    assert_eq!(broken["image_generation"].as_u64(), Some(generation));
    let diagnostics = broken["diagnostics"].as_array().unwrap();
    assert!(
        diagnostics
            .iter()
            .any(|d| d["severity"] == "error" && d["range"]["start"]["line"] == 1)
    );
    let kept = server.get("/frame.png?width=40&height=30");
    assert_eq!(kept.status, 200);
    assert_eq!(kept.body, after.body);
    assert_eq!(kept.headers["x-qcsg-generation"], generation.to_string());
    let generation = broken["generation"].as_u64().unwrap();

    // A save by renaming a new file over the old one, as many editors save.
    let temporary = dir.join(".main.qcsg.new");
    std::fs::write(&temporary, "include <part.qcsg>\npart();\n").unwrap();
    std::fs::rename(&temporary, &main).unwrap();
    let renamed = wait_for_change(&server, |e| e["generation"].as_u64() > Some(generation));
    assert_eq!(renamed["ok"], true, "{renamed}");
    let generation = renamed["generation"].as_u64().unwrap();

    // A writer that keeps the file open: the rebuild comes without the save's end.
    let mut open = std::fs::File::create(&main).unwrap();
    open.write_all(b"sphere(1);\n").unwrap();
    open.flush().unwrap();
    // (A rename may be seen twice, so the wait is for the new solid, not the next rebuild.)
    let written = wait_for_change(&server, |e| {
        e["generation"].as_u64() > Some(generation) && e["quadrics"] == 1
    });
    assert_eq!(written["ok"], true, "{written}");
    drop(open);
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn saves_of_an_imported_mesh_rebuild() {
    let dir = std::env::temp_dir().join(format!("qcsg-view-import-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let main = dir.join("main.scad");
    let mesh = dir.join("part.off");
    let tetra = |s: u32| {
        format!(
            "OFF\n4 4 0\n0 0 0\n{s} 0 0\n0 {s} 0\n0 0 {s}\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
        )
    };
    std::fs::write(&mesh, tetra(2)).unwrap();
    std::fs::write(&main, "import(\"part.off\");\n").unwrap();
    let server = Server::start(&main, &[]);
    let first = wait_for_change(&server, |e| e["ok"] == true);
    let generation = first["generation"].as_u64().unwrap();
    std::fs::write(&mesh, tetra(3)).unwrap();
    let changed = wait_for_change(&server, |e| e["generation"].as_u64() > Some(generation));
    assert_eq!(changed["ok"], true);
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_program_that_never_compiled_answers_409_with_its_errors() {
    let dir = std::env::temp_dir().join(format!("qcsg-view-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let main = dir.join("bad.qcsg");
    std::fs::write(&main, "sphere(r = );\n").unwrap();
    let server = Server::start(&main, &[]);
    let event = wait_for_change(&server, |_| true);
    assert_eq!(event["ok"], false);
    assert_eq!(event["image_generation"], serde_json::Value::Null);
    assert_eq!(server.get("/frame.png").status, 409);
    assert_eq!(server.get("/pick?x=1&y=1").status, 409);
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The renderer `qcsg render --device auto` picks on this machine, from what it says.
fn renderer_of_render_auto(file: &Path) -> &'static str {
    let run = qcsg()
        .arg("render")
        .arg(file)
        .args(["-o", "-", "--size", "16,12"])
        .run();
    let said = run.stderr;
    if said.contains("with the splat renderer") {
        "splat"
    } else if said.contains("with the CPU ray tracer") {
        "raytrace"
    } else {
        panic!("qcsg render did not say its renderer: {said}")
    }
}

#[test]
fn the_renderer_is_chosen_as_qcsg_render_chooses_it() {
    let file = workspace().join("examples/wheel.qcsg");
    let server = Server::start(&file, &[]);
    let answer = server.get("/frame.png?width=16&height=12");
    assert_eq!(answer.status, 200);
    assert_eq!(
        answer.headers["x-qcsg-renderer"],
        renderer_of_render_auto(&file)
    );
    // A request that cannot be met stops the server at its start, as it stops `qcsg render`.
    let refused = qcsg()
        .arg("view")
        .arg(&file)
        .args(["--no-open", "--renderer", "raytrace", "--device", "gpu"])
        .run();
    assert_eq!(refused.status, 2);
    let said = refused.stderr;
    assert!(
        said.contains("the ray tracer runs on the CPU only"),
        "{said}"
    );
}

/// Of the pixels away from edges of `exact` (a one-pixel band around every pixel that differs
/// from a neighbour by more than a shading step), how many `other` shows within 2 levels per
/// channel; and how many were compared.
fn colour_agreement(exact: &image::RgbImage, other: &image::RgbImage) -> (usize, usize) {
    assert_eq!(exact.dimensions(), other.dimensions());
    let (width, height) = exact.dimensions();
    let near = |a: &image::Rgb<u8>, b: &image::Rgb<u8>, within: u8| {
        a.0.iter().zip(b.0).all(|(&x, y)| x.abs_diff(y) <= within)
    };
    let (mut agree, mut compared) = (0, 0);
    for y in 1..height - 1 {
        for x in 1..width - 1 {
            let here = exact.get_pixel(x, y);
            let edge = (y - 1..=y + 1)
                .flat_map(|v| (x - 1..=x + 1).map(move |u| (u, v)))
                .any(|(u, v)| !near(here, exact.get_pixel(u, v), 8));
            if edge {
                continue;
            }
            compared += 1;
            if near(here, other.get_pixel(x, y), 2) {
                agree += 1;
            }
        }
    }
    (agree, compared)
}

/// Splats forced (on a software adapter such as lavapipe where there is no GPU): the frames are
/// `qcsg render --renderer splat`'s, and agree with the ray tracer's away from edges.
#[test]
fn frames_by_splats_are_qcsg_render_s_and_agree_with_the_ray_tracer() {
    let file = workspace().join("examples/wheel.qcsg");
    let server = Server::start(&file, &["--renderer", "splat"]);
    let cases: [(&str, &[&str]); 2] = [
        ("width=160&height=120", &["--size", "160,120"]),
        (
            "width=160&height=120&camera=front&projection=ortho",
            &[
                "--size",
                "160,120",
                "--camera",
                "front",
                "--projection",
                "ortho",
            ],
        ),
    ];
    for (query, args) in cases {
        let answer = server.get(&format!("/frame.png?{query}"));
        assert_eq!(answer.status, 200, "{query}");
        assert_eq!(answer.headers["x-qcsg-renderer"], "splat");
        assert!(
            answer.body == render_with(&file, &[&["--renderer", "splat"], args].concat()),
            "/frame.png?{query} differs from qcsg render --renderer splat {args:?}"
        );
        let decode = |png: &[u8]| {
            image::load_from_memory_with_format(png, image::ImageFormat::Png)
                .expect("a PNG")
                .to_rgb8()
        };
        let splats = decode(&answer.body);
        let exact = decode(&render_cli(&file, args));
        let (agree, compared) = colour_agreement(&exact, &splats);
        let pixels = (exact.width() * exact.height()) as usize;
        assert!(
            compared * 2 > pixels,
            "{query}: only {compared} of {pixels} compared"
        );
        assert!(
            agree as f64 >= 0.999 * compared as f64,
            "{query}: {agree} of {compared} pixels agree"
        );
        eprintln!("{query}: {agree} of {compared} pixels agree ({pixels} in all)");
    }
}
