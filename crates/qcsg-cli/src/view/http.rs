//! The HTTP contract of `qcsg view` (`docs/view.md`): the page and its assets, `/frame.png`,
//! `/pick`, `/camera` and the `/events` stream, behind a check of the `Host` header so that a
//! web page elsewhere cannot reach the server through a DNS name it rebinds to 127.0.0.1.
//!
//! Frames are rendered on the server's own worker pool, away from the threads that answer
//! requests; a request never waits for a rebuild (it gets the latest good scene).

use std::convert::Infallible;
use std::sync::{Arc, PoisonError, RwLock};
use std::time::Instant;

use axum::Router;
use axum::extract::{RawQuery, Request, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::middleware::{self, Next};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use futures_util::Stream;
use qcsg_lsp::preview::{Preview, ViewRequest};
use qcsg_render::{Frame, RenderOptions};
use qcsg_splat::{SplatError, SplatRenderer};
use tokio::sync::broadcast;

use super::query::{self, Refusal, SizeLimit};
use super::scene::{Image, Snapshot};

/// The page and its assets, compiled into the binary: no other file is ever served.
const INDEX_HTML: &str = include_str!("assets/index.html");
const VIEW_JS: &str = include_str!("assets/view.js");
const VIEW_CSS: &str = include_str!("assets/view.css");

/// What the page may load: its own assets and frames, nothing from elsewhere.
const CONTENT_SECURITY_POLICY: &str = "default-src 'self'; img-src 'self' blob:; \
     connect-src 'self'; style-src 'self'; script-src 'self'; frame-ancestors 'none'";

/// The server's state, shared by every request.
pub struct Shared {
    /// The latest compiled state.
    pub snapshot: RwLock<Arc<Snapshot>>,
    /// Each rebuild's `change` event.
    pub changes: broadcast::Sender<String>,
    /// The `Host` values accepted (`127.0.0.1:PORT`, `localhost:PORT`, …).
    pub hosts: Vec<String>,
    /// The largest frame rendered.
    pub limit: SizeLimit,
    /// Where frames are rendered.
    pub pool: rayon::ThreadPool,
    /// What renders them.
    pub frames: Frames,
}

/// What renders the frames (`--renderer`, `--device`); picks always come from the ray tracer.
pub enum Frames {
    /// The exact CPU ray tracer.
    RayTracer,
    /// The splat renderer on a GPU adapter.
    Splats(Box<SplatRenderer>),
}

impl Frames {
    /// The `x-qcsg-renderer` header's value.
    fn name(&self) -> &'static str {
        match self {
            Self::RayTracer => "raytrace",
            Self::Splats(_) => "splat",
        }
    }

    /// The frame of `request`, as `qcsg render` with the same renderer draws it.
    fn render(&self, preview: &Preview, request: &ViewRequest) -> Result<Frame, Refusal> {
        match self {
            Self::RayTracer => preview.render(request).map_err(camera_refusal),
            Self::Splats(renderer) => {
                let camera = request.camera(preview.scene()).map_err(camera_refusal)?;
                renderer
                    .render(
                        preview.scene(),
                        &camera,
                        request.size,
                        &RenderOptions::default(),
                    )
                    .map_err(|error| match error {
                        SplatError::ImageTooLarge { .. } => Refusal {
                            status: StatusCode::BAD_REQUEST,
                            message: error.to_string(),
                            help: Some(
                                "ask for a smaller frame, or run `qcsg view --renderer raytrace`"
                                    .into(),
                            ),
                        },
                        _ => Refusal {
                            status: StatusCode::INTERNAL_SERVER_ERROR,
                            message: format!("the splat renderer failed: {error}"),
                            help: None,
                        },
                    })
            }
        }
    }
}

impl Shared {
    fn current(&self) -> Arc<Snapshot> {
        Arc::clone(&self.snapshot.read().unwrap_or_else(PoisonError::into_inner))
    }

    /// Installs a new state and tells the pages.
    pub fn publish(&self, snapshot: Snapshot) {
        let event = snapshot.event.clone();
        *self
            .snapshot
            .write()
            .unwrap_or_else(PoisonError::into_inner) = Arc::new(snapshot);
        // No page listening is not an error.
        let _ = self.changes.send(event);
    }
}

/// The routes, behind the `Host` check.
pub fn router(shared: Arc<Shared>) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/view.js", get(script))
        .route("/view.css", get(style))
        .route("/frame.png", get(frame))
        .route("/pick", get(pick))
        .route("/camera", get(camera))
        .route("/events", get(events))
        .fallback(not_found)
        .layer(middleware::from_fn_with_state(
            Arc::clone(&shared),
            check_host,
        ))
        .with_state(shared)
}

/// Refuses a request whose `Host` is not one of the server's own names (DNS rebinding).
async fn check_host(State(shared): State<Arc<Shared>>, request: Request, next: Next) -> Response {
    let host = request
        .headers()
        .get(header::HOST)
        .and_then(|h| h.to_str().ok());
    match host {
        Some(host) if shared.hosts.iter().any(|h| h.eq_ignore_ascii_case(host)) => {
            next.run(request).await
        }
        _ => refuse(Refusal {
            status: StatusCode::FORBIDDEN,
            message: format!(
                "the Host `{}` is not this server's",
                host.unwrap_or("(none)")
            ),
            help: Some(format!("open {}", shared.hosts.join(" or "))),
        }),
    }
}

fn refuse(refusal: Refusal) -> Response {
    let body = serde_json::json!({ "error": &refusal }).to_string();
    (
        refusal.status,
        [(header::CONTENT_TYPE, "application/json")],
        body,
    )
        .into_response()
}

fn asset(content_type: &'static str, body: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, content_type),
            (header::CACHE_CONTROL, "no-cache"),
            (header::CONTENT_SECURITY_POLICY, CONTENT_SECURITY_POLICY),
        ],
        body,
    )
        .into_response()
}

async fn page() -> Response {
    asset("text/html; charset=utf-8", INDEX_HTML)
}

async fn script() -> Response {
    asset("text/javascript; charset=utf-8", VIEW_JS)
}

async fn style() -> Response {
    asset("text/css; charset=utf-8", VIEW_CSS)
}

async fn not_found() -> Response {
    refuse(Refusal {
        status: StatusCode::NOT_FOUND,
        message: "no such page".into(),
        help: Some("the server answers /, /frame.png, /pick, /camera and /events".into()),
    })
}

/// The latest good scene and its generation, or the 409 answer when there has never been one.
fn image(shared: &Shared) -> Result<(u64, Arc<Image>), Refusal> {
    shared.current().image.clone().ok_or_else(|| Refusal {
        status: StatusCode::CONFLICT,
        message: "the program has errors and no earlier version compiled".into(),
        help: Some("fix the errors listed by /events (or `qcsg check`)".into()),
    })
}

/// Runs `work` on the render pool without blocking the request threads.
async fn on_pool<T: Send + 'static>(
    shared: &Arc<Shared>,
    work: impl FnOnce() -> T + Send + 'static,
) -> Result<T, Refusal> {
    let shared = Arc::clone(shared);
    tokio::task::spawn_blocking(move || shared.pool.install(work))
        .await
        .map_err(|_| Refusal {
            status: StatusCode::INTERNAL_SERVER_ERROR,
            message: "rendering failed".into(),
            help: None,
        })
}

fn camera_refusal(error: qcsg_render::CameraError) -> Refusal {
    Refusal::bad_request(format!("bad camera: {error}"))
}

async fn frame(State(shared): State<Arc<Shared>>, RawQuery(raw): RawQuery) -> Response {
    let request = match query::view_request(raw.as_deref(), shared.limit) {
        Ok(request) => request,
        Err(refusal) => return refuse(refusal),
    };
    let (generation, image) = match image(&shared) {
        Ok(image) => image,
        Err(refusal) => return refuse(refusal),
    };
    let rendering = Arc::clone(&shared);
    let rendered = on_pool(&shared, move || {
        let started = Instant::now();
        let frame = rendering.frames.render(&image.preview, &request)?;
        let png = qcsg_render::png::encode(&frame).map_err(|error| Refusal {
            status: StatusCode::INTERNAL_SERVER_ERROR,
            message: format!("the frame cannot be encoded: {error}"),
            help: None,
        })?;
        Ok::<_, Refusal>((png, started.elapsed()))
    })
    .await;
    match rendered.and_then(|r| r) {
        Err(refusal) => refuse(refusal),
        Ok((png, took)) => {
            let mut headers = HeaderMap::new();
            headers.insert(header::CONTENT_TYPE, HeaderValue::from_static("image/png"));
            headers.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
            headers.insert("x-qcsg-generation", HeaderValue::from(generation));
            headers.insert(
                "x-qcsg-renderer",
                HeaderValue::from_static(shared.frames.name()),
            );
            let millis = format!("{:.1}", took.as_secs_f64() * 1e3);
            if let Ok(value) = HeaderValue::from_str(&millis) {
                headers.insert("x-qcsg-render-ms", value);
            }
            (headers, png).into_response()
        }
    }
}

fn json_response(generation: u64, body: String) -> Response {
    let mut headers = HeaderMap::new();
    headers.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static("application/json"),
    );
    headers.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    headers.insert("x-qcsg-generation", HeaderValue::from(generation));
    (headers, body).into_response()
}

async fn pick(State(shared): State<Arc<Shared>>, RawQuery(raw): RawQuery) -> Response {
    let (request, x, y) = match query::pick_request(raw.as_deref(), shared.limit) {
        Ok(parsed) => parsed,
        Err(refusal) => return refuse(refusal),
    };
    let (generation, image) = match image(&shared) {
        Ok(image) => image,
        Err(refusal) => return refuse(refusal),
    };
    match on_pool(&shared, move || {
        image.preview.pick(&image.dag, &request, x, y)
    })
    .await
    {
        Err(refusal) => refuse(refusal),
        Ok(Err(error)) => refuse(camera_refusal(error)),
        Ok(Ok(picked)) => json_response(
            generation,
            serde_json::to_string(&picked).unwrap_or_else(|_| "null".into()),
        ),
    }
}

/// The eye and centre of a request's camera, so that the page can turn a named view.
async fn camera(State(shared): State<Arc<Shared>>, RawQuery(raw): RawQuery) -> Response {
    let request: ViewRequest = match query::view_request(raw.as_deref(), shared.limit) {
        Ok(request) => request,
        Err(refusal) => return refuse(refusal),
    };
    let (generation, image) = match image(&shared) {
        Ok(image) => image,
        Err(refusal) => return refuse(refusal),
    };
    let preview = &image.preview;
    match request.camera(preview.scene()) {
        Err(error) => refuse(camera_refusal(error)),
        Ok(camera) => {
            let bounds = preview.scene().bounds();
            let bounded = !bounds.is_empty() && bounds.is_bounded();
            // A named view looks at the scene's centre; an explicit one at its own centre.
            let center = match request.view {
                qcsg_render::View::Explicit { center, .. } => center.to_array(),
                _ if bounded => bounds.centre().to_array(),
                _ => [0.0; 3],
            };
            let radius = if bounded { bounds.half_diagonal() } else { 1.0 };
            let body = serde_json::json!({
                "eye": camera.eye().to_array(),
                "center": center,
                "radius": radius,
            });
            json_response(generation, body.to_string())
        }
    }
}

/// Server-sent events: the current state at once, then one `change` event per rebuild.
async fn events(
    State(shared): State<Arc<Shared>>,
) -> Sse<impl Stream<Item = Result<Event, Infallible>>> {
    let receiver = shared.changes.subscribe();
    let first = shared.current().event.clone();
    let stream = futures_util::stream::unfold(
        (Some(first), receiver),
        |(first, mut receiver)| async move {
            if let Some(first) = first {
                return Some((
                    Ok(Event::default().event("change").data(first)),
                    (None, receiver),
                ));
            }
            loop {
                match receiver.recv().await {
                    Ok(event) => {
                        return Some((
                            Ok(Event::default().event("change").data(event)),
                            (None, receiver),
                        ));
                    }
                    // A slow page skipped some rebuilds; the next event has the whole state.
                    Err(broadcast::error::RecvError::Lagged(_)) => continue,
                    Err(broadcast::error::RecvError::Closed) => return None,
                }
            }
        },
    );
    Sse::new(stream).keep_alive(KeepAlive::default())
}
