//! The HTTP side: a fixed set of routes to embedded assets and the WebSocket, each
//! behind the checks of `security.rs`, on a listener that holds a bounded number of
//! connections.
//!
//! No request path reaches the file system: the routes are string constants mapped
//! to text compiled into the binary, and everything else is 404.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use axum::body::Body;
use axum::extract::ws::WebSocketUpgrade;
use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{broadcast, OwnedSemaphorePermit, Semaphore};

use super::scene::{Current, Loaded, SceneEvent};
use super::{assets, security, session};

/// The most WebSocket sessions at once (each has a render thread and a picture):
/// a classroom's pages on one server.
pub const MAX_SESSIONS: usize = 32;
/// The most TCP connections at once; further ones wait in the system's backlog.
pub const MAX_CONNECTIONS: usize = 64;
/// The largest WebSocket message read at all: a reference picture's upload
/// (`protocol::MAX_REFERENCE_BYTES`) and its header; past it the connection is
/// closed. (Text messages past `protocol::MAX_MESSAGE_BYTES` but within this get an
/// error reply.)
pub const MAX_WS_MESSAGE: usize = super::protocol::MAX_REFERENCE_BYTES + 8192;

/// What every request and session shares.
pub struct App {
    /// The access token.
    pub token: String,
    /// The port the server listens on (the `Host` header must carry it).
    pub port: u16,
    /// The scene file as named on the command line.
    pub name: String,
    /// `--spp`, replacing the file's and the default target.
    pub spp: Option<u32>,
    /// `--integrator`, replacing the file's.
    pub integrator: Option<nffrt::scene::IntegratorKind>,
    /// `--accel`: the structure the page starts with (default: the file's).
    pub accel: Option<nffrt::scene::Accel>,
    /// The latest good scene.
    pub scene: Current,
    /// Reloads and load errors.
    pub events: broadcast::Sender<SceneEvent>,
    /// Open sessions.
    pub sessions: AtomicUsize,
    /// The sessions' renders, waiting for their turns.
    pub turns: Arc<super::turns::Turns>,
    /// Open Image Denoise, if it is installed.
    pub denoiser: Option<Arc<nffrt::denoise::Denoiser>>,
    /// Why there is no denoiser and how to get one.
    pub denoiser_help: Option<String>,
    /// `--reference`: the picture every session starts with.
    pub reference: Option<Arc<super::reference::Reference>>,
}

impl App {
    /// The latest good scene.
    pub fn current(&self) -> Arc<Loaded> {
        match self.scene.read() {
            Ok(c) => c.clone(),
            Err(poisoned) => poisoned.into_inner().clone(),
        }
    }
}

/// The routes, behind the guard.
pub fn router(app: Arc<App>) -> Router {
    Router::new()
        .route("/", get(index))
        .route(
            "/app.js",
            get(|| async { asset(assets::APP_JS, "text/javascript; charset=utf-8") }),
        )
        .route(
            "/compare.js",
            get(|| async { asset(assets::COMPARE_JS, "text/javascript; charset=utf-8") }),
        )
        .route(
            "/app.css",
            get(|| async { asset(assets::APP_CSS, "text/css; charset=utf-8") }),
        )
        .route("/ws", get(websocket))
        .fallback(|| async { (StatusCode::NOT_FOUND, "not found") })
        .layer(middleware::from_fn_with_state(app.clone(), guard))
        .with_state(app)
}

/// Refuses requests without the token, from a foreign host name or from another
/// site's page (403), and marks every response as private and unframeable.
async fn guard(State(app): State<Arc<App>>, req: Request, next: Next) -> Response {
    fn text(h: &HeaderMap, name: header::HeaderName) -> Option<&str> {
        h.get(name).and_then(|v| v.to_str().ok())
    }
    let headers = req.headers();
    let refused = security::refusal(
        text(headers, header::HOST),
        text(headers, header::ORIGIN),
        req.uri().query(),
        &app.token,
        app.port,
    );
    let mut response = match refused {
        Some(why) => (StatusCode::FORBIDDEN, why).into_response(),
        None => next.run(req).await,
    };
    let h = response.headers_mut();
    for (name, value) in [
        (header::CACHE_CONTROL, "no-store"),
        (header::X_CONTENT_TYPE_OPTIONS, "nosniff"),
        (header::REFERRER_POLICY, "no-referrer"),
        (header::X_FRAME_OPTIONS, "DENY"),
    ] {
        h.insert(name, HeaderValue::from_static(value));
    }
    response
}

/// The page, with the token filled in where it loads its script and style.
async fn index(State(app): State<Arc<App>>) -> Response {
    let html = assets::INDEX_HTML.replace("__TOKEN__", &app.token);
    let mut r = asset_owned(html, "text/html; charset=utf-8");
    r.headers_mut().insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(
            "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' blob: data:; \
             connect-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'",
        ),
    );
    r
}

fn asset(body: &'static str, content_type: &'static str) -> Response {
    ([(header::CONTENT_TYPE, content_type)], body).into_response()
}

fn asset_owned(body: String, content_type: &'static str) -> Response {
    ([(header::CONTENT_TYPE, content_type)], Body::from(body)).into_response()
}

/// Upgrades to a session, if fewer than [`MAX_SESSIONS`] are open.
async fn websocket(State(app): State<Arc<App>>, upgrade: WebSocketUpgrade) -> Response {
    if app.sessions.fetch_add(1, Ordering::SeqCst) >= MAX_SESSIONS {
        app.sessions.fetch_sub(1, Ordering::SeqCst);
        return (StatusCode::SERVICE_UNAVAILABLE, "too many open pages").into_response();
    }
    let slot = SessionSlot(app.clone());
    upgrade
        .max_message_size(MAX_WS_MESSAGE)
        .max_frame_size(MAX_WS_MESSAGE)
        .on_upgrade(move |socket| async move {
            session::run(socket, slot.0.clone()).await;
            drop(slot);
        })
}

/// Frees a session's place when dropped (also if the upgrade never completes).
struct SessionSlot(Arc<App>);

impl Drop for SessionSlot {
    fn drop(&mut self) {
        self.0.sessions.fetch_sub(1, Ordering::SeqCst);
    }
}

/// A TCP listener that accepts at most [`MAX_CONNECTIONS`] connections at once.
pub struct Limited {
    listener: TcpListener,
    permits: Arc<Semaphore>,
}

impl Limited {
    /// Wraps `listener`.
    pub fn new(listener: TcpListener) -> Limited {
        Limited {
            listener,
            permits: Arc::new(Semaphore::new(MAX_CONNECTIONS)),
        }
    }
}

/// A connection holding its place among the [`MAX_CONNECTIONS`].
pub struct Counted {
    stream: TcpStream,
    _permit: OwnedSemaphorePermit,
}

impl axum::serve::Listener for Limited {
    type Io = Counted;
    type Addr = std::net::SocketAddr;

    async fn accept(&mut self) -> (Counted, Self::Addr) {
        let permit = match self.permits.clone().acquire_owned().await {
            Ok(p) => p,
            Err(_) => std::future::pending().await,
        };
        loop {
            match self.listener.accept().await {
                Ok((stream, addr)) => {
                    let _ = stream.set_nodelay(true);
                    return (
                        Counted {
                            stream,
                            _permit: permit,
                        },
                        addr,
                    );
                }
                // Out of file descriptors and the like: wait a little, as axum does.
                Err(_) => tokio::time::sleep(std::time::Duration::from_millis(50)).await,
            }
        }
    }

    fn local_addr(&self) -> std::io::Result<Self::Addr> {
        self.listener.local_addr()
    }
}

impl tokio::io::AsyncRead for Counted {
    fn poll_read(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
        buf: &mut tokio::io::ReadBuf<'_>,
    ) -> std::task::Poll<std::io::Result<()>> {
        std::pin::Pin::new(&mut self.stream).poll_read(cx, buf)
    }
}

impl tokio::io::AsyncWrite for Counted {
    fn poll_write(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
        buf: &[u8],
    ) -> std::task::Poll<std::io::Result<usize>> {
        std::pin::Pin::new(&mut self.stream).poll_write(cx, buf)
    }

    fn poll_flush(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<std::io::Result<()>> {
        std::pin::Pin::new(&mut self.stream).poll_flush(cx)
    }

    fn poll_shutdown(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<std::io::Result<()>> {
        std::pin::Pin::new(&mut self.stream).poll_shutdown(cx)
    }
}
