//! One page's WebSocket: its requests in, its frames and replies out.
//!
//! A single task owns the socket and does all the writing, so messages leave in the
//! order it decides: a render request bumps the generation, is acknowledged, and
//! from then on frames of older generations are dropped (the render thread may
//! still finish one). Ray trees are traced on a blocking thread, one at a time per
//! session; a second request meanwhile is answered "busy".

use std::sync::Arc;
use std::time::Instant;

use axum::body::Bytes;
use axum::extract::ws::{Message, WebSocket};
use tokio::sync::{broadcast, watch};

use super::camera::{camera_block, first_options, options_of, prepare_options, view_of};
use super::protocol::{
    encode_binary, parse_client_message, CameraMsg, ClientMessage, LimitsMsg, OptionsMsg, ServerMessage,
    MAX_REFERENCE_BYTES,
};
use super::reference::Reference;
use super::scene::{Loaded, SceneEvent};
use super::server::App;
use super::worker::{Frame, Job, Outlets, ShownPicture, Worker};
use nffrt::geometry::SourceKind;
use nffrt::image::{encode_png_rgb8, SOFTWARE_TEXT};
use nffrt::options::{display_encoding, Sampling};
use nffrt::render::debug::{kind_name, trace_pixel};
use nffrt::scene::{AngleSpan, Dialect};

/// The largest ray-tree reply, in bytes of JSON.
const MAX_TREE_BYTES: usize = 8 << 20;

/// What the page last asked for.
#[derive(Clone, Copy)]
struct Request {
    camera: CameraMsg,
    options: OptionsMsg,
    frame: Option<u32>,
}

/// A session's state, owned by its task.
struct Session {
    app: Arc<App>,
    loaded: Arc<Loaded>,
    worker: Worker,
    gen: u64,
    request: Option<Request>,
    /// A ray tree being traced.
    tracing: Option<tokio::task::JoinHandle<ServerMessage>>,
    /// The reference picture, if one is loaded.
    reference: Option<Arc<Reference>>,
}

/// Serves one WebSocket until it closes.
pub async fn run(mut socket: WebSocket, app: Arc<App>) {
    let (frames_tx, mut frames) = watch::channel::<Option<Arc<Frame>>>(None);
    let (maps_tx, mut maps) = tokio::sync::mpsc::unbounded_channel::<Arc<Frame>>();
    let (failed_tx, mut failed) = tokio::sync::mpsc::unbounded_channel::<(u64, String)>();
    let outlets = Outlets {
        frames: frames_tx,
        maps: maps_tx,
        failed: failed_tx,
    };
    let Ok(worker) = Worker::spawn(outlets, app.turns.clone()) else {
        return;
    };
    let mut events = app.events.subscribe();
    let loaded = app.current();
    let mut s = Session {
        app,
        loaded,
        worker,
        gen: 0,
        request: None,
        tracing: None,
        reference: None,
    };
    s.reference = s.app.reference.clone();
    if send_json(&mut socket, &s.scene_message()).await.is_err() {
        return;
    }
    if let Some(r) = &s.reference {
        if send_json(&mut socket, &r.message()).await.is_err()
            || socket
                .send(Message::Binary(r.display_message().into()))
                .await
                .is_err()
        {
            return;
        }
    }
    loop {
        let out = tokio::select! {
            msg = socket.recv() => match msg {
                Some(Ok(Message::Text(text))) => s.handle(text.as_str()),
                Some(Ok(Message::Binary(bytes))) => s.reference_sent(&bytes),
                Some(Ok(Message::Ping(_) | Message::Pong(_))) => vec![],
                Some(Ok(Message::Close(_))) | Some(Err(_)) | None => break,
            },
            map = maps.recv() => match map {
                // Maps of older generations are dropped, as frames are.
                Some(m) if m.gen >= s.gen => vec![Reply::Binary(m.bytes.clone())],
                Some(_) => vec![],
                None => break,
            },
            failure = failed.recv() => match failure {
                // As frames: a failure of an older generation is no longer news.
                Some((gen, message)) if gen >= s.gen => vec![error(message)],
                Some(_) => vec![],
                None => break,
            },
            changed = frames.changed() => {
                if changed.is_err() {
                    break;
                }
                // Frames of older generations are dropped: the page asked for newer.
                let frame = frames.borrow_and_update().clone().filter(|f| f.gen >= s.gen);
                match frame {
                    Some(f) => vec![Reply::Binary(f.bytes.clone())],
                    None => vec![],
                }
            }
            event = events.recv() => match event {
                Ok(SceneEvent::Loaded(loaded)) => s.reloaded(loaded),
                Ok(SceneEvent::Failed { message, at }) => vec![ServerMessage::LoadError {
                    message,
                    line: at.map(|a| a.0),
                    column: at.map(|a| a.1),
                }
                .into()],
                Err(broadcast::error::RecvError::Lagged(_)) => {
                    let loaded = s.app.current();
                    s.reloaded(loaded)
                }
                Err(broadcast::error::RecvError::Closed) => break,
            },
            traced = async {
                match s.tracing.as_mut() {
                    Some(task) => task.await,
                    None => std::future::pending().await,
                }
            } => {
                s.tracing = None;
                vec![traced.map_or_else(|_| error("tracing the pixel failed"), Reply::from)]
            }
        };
        for msg in out {
            let sent = match msg {
                Reply::Json(m) => send_json(&mut socket, &m).await,
                Reply::Binary(b) => socket.send(Message::Binary(b)).await,
            };
            if sent.is_err() {
                return;
            }
        }
    }
}

/// A message to send.
enum Reply {
    /// (Boxed: a scene message is large, a binary one a pointer.)
    Json(Box<ServerMessage>),
    Binary(Bytes),
}

impl From<ServerMessage> for Reply {
    fn from(m: ServerMessage) -> Reply {
        Reply::Json(Box::new(m))
    }
}

fn error(message: impl Into<String>) -> Reply {
    Reply::Json(Box::new(ServerMessage::Error {
        message: message.into(),
    }))
}

async fn send_json(socket: &mut WebSocket, msg: &ServerMessage) -> Result<(), axum::Error> {
    let text = serde_json::to_string(msg).expect("messages serialize");
    socket.send(Message::Text(text.into())).await
}

impl Session {
    /// Answers one text message from the page.
    fn handle(&mut self, text: &str) -> Vec<Reply> {
        match parse_client_message(text) {
            Err(e) => vec![error(e)],
            Ok(ClientMessage::Render {
                camera,
                options,
                frame,
            }) => {
                if let Some(Err(e)) = frame.map(|n| self.loaded.check_frame(n)) {
                    return vec![error(e)];
                }
                self.request = Some(Request {
                    camera,
                    options,
                    frame,
                });
                vec![self.start("request").into()]
            }
            Ok(ClientMessage::Pixel { x, y }) => self.pixel(x, y),
            Ok(ClientMessage::Png) => vec![self.png()],
        }
    }

    /// Starts a generation for the current request; its acknowledgement.
    fn start(&mut self, reason: &'static str) -> ServerMessage {
        let Some(r) = self.request else {
            return ServerMessage::Error {
                message: "nothing to render".into(),
            };
        };
        self.gen += 1;
        let view = view_of(self.loaded.scene.view(), &r.camera, &r.options);
        let (opts, encoding) = match options_of(&r.options, self.loaded.scene.info()) {
            Ok(resolved) => resolved,
            Err(message) => return ServerMessage::Error { message },
        };
        // A picture of one ray through each pixel centre has no noise to remove.
        let noisy = !matches!(opts.sampling, Sampling::PixelCenters | Sampling::SpdCorners);
        self.worker.submit(Job {
            gen: self.gen,
            loaded: self.loaded.clone(),
            frame: r.frame,
            prepare: prepare_options(&r.options),
            view,
            opts,
            encoding,
            denoiser: self.app.denoiser.clone().filter(|_| r.options.denoise && noisy),
            reference: self.reference.clone(),
            start: Instant::now(),
        });
        ServerMessage::View {
            gen: self.gen,
            reason,
            camera: r.camera,
            options: r.options,
            frame: r.frame,
            camera_block: camera_block(&view, self.loaded.scene.info().dialect),
        }
    }

    /// A new scene: tell the page, and render it again with the page's camera, or
    /// with the file's if the edit moved it.
    fn reloaded(&mut self, loaded: Arc<Loaded>) -> Vec<Reply> {
        let (old, new) = (*self.loaded.scene.view(), *loaded.scene.view());
        self.loaded = loaded;
        if let Some(r) = self.request.as_mut() {
            // A frame the new scene does not have: its last, or none if it is not AFF.
            let frames = self.loaded.aff.as_ref().map(|a| a.frames());
            r.frame = r.frame.and_then(|n| frames.map(|f| n.min(f - 1)));
            if (old.from, old.at, old.up, old.angle) != (new.from, new.at, new.up, new.angle) {
                r.camera = CameraMsg::of(&new);
            }
            if (old.width, old.height) != (new.width, new.height) {
                (r.options.width, r.options.height) = (new.width, new.height);
            }
        }
        let mut out = vec![self.scene_message().into()];
        if self.request.is_some() {
            out.push(self.start("reload").into());
        }
        out
    }

    /// The scene as the page first sees it.
    fn scene_message(&self) -> ServerMessage {
        let l = &self.loaded;
        let info = l.scene.info();
        let view = &info.view;
        ServerMessage::Scene {
            name: self.app.name.clone(),
            dialect: info.dialect.name(),
            version: l.version,
            counts: l.counts.clone(),
            warnings: l.warnings.clone(),
            camera: CameraMsg::of(view),
            options: first_options(info, self.app.spp, self.app.integrator, self.app.accel),
            has_lens: view.aperture > 0.0,
            has_area_lights: info.area_lights() > 0,
            has_roughness: info.has_rough_materials(),
            has_motion: info.has_moving_spheres(),
            animation: l.animation(),
            load_s: l.load_s,
            limits: LimitsMsg::NFFRT,
            denoiser: self
                .app
                .denoiser
                .as_ref()
                .map(|d| format!("Open Image Denoise {}", d.version())),
            denoiser_help: self.app.denoiser_help.clone(),
        }
    }

    /// A reference picture the page sent: a binary message of a 4-byte length, a
    /// JSON header `{"kind":"reference","name":NAME}` and the file's bytes. It
    /// replaces the last one, and the current request is rendered again to be
    /// measured against it.
    fn reference_sent(&mut self, bytes: &[u8]) -> Vec<Reply> {
        if bytes.len() > MAX_REFERENCE_BYTES {
            return vec![error(format!(
                "reference too large: {} bytes (at most {MAX_REFERENCE_BYTES})",
                bytes.len()
            ))];
        }
        let (name, file) = match reference_upload(bytes) {
            Ok(parts) => parts,
            Err(e) => return vec![error(e)],
        };
        let encoding = self.request.map_or_else(
            || {
                display_encoding(
                    self.loaded.scene.info().integrator.unwrap_or_default(),
                    self.loaded.scene.info().dialect.is_p3f(),
                )
            },
            |r| {
                options_of(&r.options, self.loaded.scene.info())
                    .map_or(nffrt::image::Encoding::Linear, |o| o.1)
            },
        );
        let reference = match Reference::decode(&name, file, encoding) {
            Ok(r) => Arc::new(r),
            Err(e) => return vec![error(e)],
        };
        let mut out = vec![
            reference.message().into(),
            Reply::Binary(reference.display_message().into()),
        ];
        self.reference = Some(reference);
        if self.request.is_some() {
            out.push(self.start("reference").into());
        }
        out
    }

    /// Starts tracing pixel `(x, y)` with the current request.
    fn pixel(&mut self, x: u32, y: u32) -> Vec<Reply> {
        let Some(r) = self.request else {
            return vec![error("nothing rendered yet")];
        };
        if x >= r.options.width || y >= r.options.height {
            return vec![error(format!(
                "pixel ({x}, {y}) is outside the {}x{} picture",
                r.options.width, r.options.height
            ))];
        }
        if self.tracing.is_some() {
            return vec![error("busy: a ray tree is being traced")];
        }
        let (loaded, gen) = (self.loaded.clone(), self.gen);
        self.tracing = Some(tokio::task::spawn_blocking(move || {
            let scene = match loaded.prepared_frame(r.frame, &prepare_options(&r.options)) {
                Ok(scene) => scene,
                Err(message) => return ServerMessage::Error { message },
            };
            let scene = &*scene;
            let view = view_of(scene.view(), &r.camera, &r.options);
            let opts = match options_of(&r.options, scene.info()) {
                Ok((opts, _)) => opts,
                Err(message) => return ServerMessage::Error { message },
            };
            let trace = match trace_pixel(scene, &view, &opts, x, y) {
                Ok(trace) => trace,
                Err(e) => {
                    return ServerMessage::Error {
                        message: e.to_string(),
                    }
                }
            };
            let Ok(trace) = serde_json::to_value(&trace) else {
                return ServerMessage::Error {
                    message: "the ray tree could not be written".into(),
                };
            };
            if trace.to_string().len() > MAX_TREE_BYTES {
                return ServerMessage::Error {
                    message: format!(
                        "the ray tree is larger than {} MiB: lower the depth or the samples",
                        MAX_TREE_BYTES >> 20
                    ),
                };
            }
            ServerMessage::RayTree {
                gen,
                camera: r.camera,
                frame: r.frame,
                angle_spans_edges: view.angle_span == AngleSpan::ImageEdges,
                kinds: kinds(scene.info().dialect),
                trace,
            }
        }));
        vec![]
    }

    /// The current generation's full-resolution picture as a PNG file (exactly
    /// `nffrt render`'s once converged).
    fn png(&self) -> Reply {
        let picture = self.worker.shown.picture.lock().ok().and_then(|p| p.clone());
        let Some(ShownPicture {
            gen,
            image,
            complete,
            encoding,
        }) = picture.filter(|p| p.gen == self.gen)
        else {
            return error("no full-resolution picture yet");
        };
        let mut png = Vec::new();
        let text = [(SOFTWARE_TEXT.0, SOFTWARE_TEXT.1.to_string())];
        let rgb = image.to_rgb8_as(encoding);
        if encode_png_rgb8(image.width, image.height, &rgb, &text, &mut png).is_err() {
            return error("the picture could not be encoded");
        }
        let header = serde_json::json!({ "kind": "png", "gen": gen, "complete": complete });
        Reply::Binary(encode_binary(&header, &png).into())
    }
}

/// The longest file name a reference upload may give.
const MAX_NAME_BYTES: usize = 256;

/// The name and the file's bytes of a reference upload (see
/// `Session::reference_sent`).
fn reference_upload(bytes: &[u8]) -> Result<(String, &[u8]), String> {
    let bad = |why: &str| format!("bad reference upload: {why}");
    let n = bytes
        .get(..4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
        .ok_or_else(|| bad("no header"))?;
    if n > 4096 || bytes.len() < 4 + n {
        return Err(bad("the header's length is wrong"));
    }
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Header {
        kind: String,
        name: String,
    }
    let header: Header = serde_json::from_slice(&bytes[4..4 + n]).map_err(|e| bad(&e.to_string()))?;
    if header.kind != "reference" {
        return Err(bad("its kind is not \"reference\""));
    }
    let name: String = header.name.chars().filter(|c| !c.is_control()).collect();
    let name = if name.is_empty() || name.len() > MAX_NAME_BYTES {
        "the picked file".to_string()
    } else {
        name
    };
    Ok((name, &bytes[4 + n..]))
}

/// Each primitive kind's printed name in `dialect`, keyed by its JSON name.
fn kinds(dialect: Dialect) -> serde_json::Value {
    let map = SourceKind::ALL.iter().map(|&k| {
        let key = serde_json::to_value(k)
            .ok()
            .and_then(|v| v.as_str().map(String::from));
        (key.unwrap_or_default(), kind_name(k, dialect).into())
    });
    serde_json::Value::Object(map.collect())
}
