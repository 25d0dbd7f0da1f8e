//! `nffrt view`: a live preview in the browser.
//!
//! A local web server (axum on a small tokio runtime) serves one page, compiled into
//! the binary, that shows the scene converging, lets the camera orbit, pan and
//! dolly, changes the settings, and shows any pixel's ray tree; the scene file is
//! watched and rendered again when it changes. The rooms: `server.rs` (routes,
//! guard, connection limit), `security.rs` (token, Host and Origin checks),
//! `session.rs` (one page's WebSocket), `worker.rs` (its render thread),
//! `turns.rs` (whose render runs next, across the sessions),
//! `protocol.rs` (the messages), `camera.rs` (views and camera blocks),
//! `scene.rs` (loading and live reload), `assets.rs` (the page), `addresses.rs` (the
//! URLs printed).

mod addresses;
mod assets;
mod camera;
mod protocol;
mod reference;
mod scene;
mod security;
mod server;
mod session;
mod turns;
mod worker;

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize};
use std::sync::{Arc, RwLock};
use std::time::Duration;

use clap::Args;
use tokio::sync::broadcast;

use super::limits::SceneLimitArgs;
use super::render::AccelArg;
use super::{interrupt, CliError};
use nffrt::denoise::Denoiser;
use nffrt::options::display_encoding;
use nffrt::scene::IntegratorKind;
use reference::Reference;
use scene::Source;
use server::App;

/// Arguments of `nffrt view`.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// Scene file (NFF or P3F); it is watched and rendered again when it changes.
    /// `-` reads the scene once from standard input (no live reload).
    pub scene: PathBuf,
    /// Port to listen on (0: any free port).
    #[arg(long, default_value_t = 0)]
    pub port: u16,
    /// Address to listen on. The default, 127.0.0.1, is reachable from this machine
    /// only; anything else lets the network in (the token still guards it).
    #[arg(long, value_name = "ADDR")]
    pub host: Option<IpAddr>,
    /// Do not open a browser.
    #[arg(long)]
    pub no_open: bool,
    /// Samples per pixel to converge to (default: what `nffrt render` takes: the
    /// file's `spp`, else 1, or 16 when an effect needs samples).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=nffrt::limits::MAX_SPP as i64))]
    pub spp: Option<u32>,
    /// The light transport the page starts with: `whitted` or `path` (default: the
    /// file's P3F `integrator`, else whitted); the page can switch it.
    #[arg(long, value_name = "NAME", value_parser = super::values::integrator())]
    pub integrator: Option<IntegratorKind>,
    /// The acceleration structure the page starts with: `bvh`, `grid` or `none`
    /// (default: the file's P3F `accel`, else bvh); the page can switch it.
    #[arg(long, value_enum, value_name = "NAME")]
    pub accel: Option<AccelArg>,
    /// A reference picture (PNG, PPM, PFM or OpenEXR) to flip against the live one;
    /// every finished pass of a picture of its size is measured against it (FLIP).
    /// The page's file picker loads one too.
    #[arg(long, value_name = "REF")]
    pub reference: Option<PathBuf>,
    /// Resource limits (see "Limits" in docs/command-line.md).
    #[command(flatten)]
    pub limits: SceneLimitArgs,
}

/// Runs `nffrt view` until Ctrl-C, then says `stopped` and succeeds.
pub fn run(args: ViewArgs) -> Result<(), CliError> {
    let from_stdin = args.scene == Path::new("-");
    let source = Arc::new(Source {
        path: args.scene.clone(),
        limits: args.limits.clone(),
    });
    let loaded = source.load(0, &AtomicBool::new(false))?;
    let reference = match &args.reference {
        Some(path) => {
            let info = loaded.scene.info();
            let integrator = args.integrator.or(info.integrator).unwrap_or_default();
            let encoding = display_encoding(integrator, info.dialect.is_p3f());
            let read = Reference::read(path, encoding).map_err(|e| match path.exists() {
                true => CliError::scene(format!("--reference {e}")),
                false => CliError::io(format!("--reference {e}")),
            })?;
            Some(Arc::new(read))
        }
        None => None,
    };
    // Open Image Denoise, if installed: the page's denoise switch.
    let (denoiser, denoiser_help) = match Denoiser::open(&[], 0) {
        Ok(d) => (Some(Arc::new(d)), None),
        Err(e) => (None, Some(e.to_string())),
    };
    let host = args.host.unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST));
    if !host.is_loopback() {
        eprintln!(
            "nffrt: warning: listening on {host}: other machines can reach this server (the token guards it)"
        );
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| CliError::io(format!("cannot start the server's runtime: {e}")))?;
    let listener = runtime
        .block_on(tokio::net::TcpListener::bind(SocketAddr::new(host, args.port)))
        .map_err(|e| {
            CliError::io(format!(
                "cannot listen on {host}:{}: {}",
                args.port,
                nffrt::io_reason(&e)
            ))
        })?;
    let port = listener
        .local_addr()
        .map_err(|e| CliError::io(format!("cannot listen: {e}")))?
        .port();
    let token = security::new_token().map_err(CliError::io)?;
    let (events, _) = broadcast::channel(16);
    let app = Arc::new(App {
        token,
        port,
        name: if from_stdin {
            "<stdin>".into()
        } else {
            args.scene.display().to_string()
        },
        spp: args.spp,
        integrator: args.integrator,
        accel: args.accel.map(Into::into),
        scene: Arc::new(RwLock::new(Arc::new(loaded))),
        events,
        sessions: AtomicUsize::new(0),
        turns: Arc::default(),
        denoiser,
        denoiser_help,
        reference,
    });
    // Standard input is read once: nothing to watch.
    let _watcher = if from_stdin {
        None
    } else {
        Some(scene::watch(source, app.scene.clone(), app.events.clone()).map_err(CliError::io)?)
    };
    // The first URL is this machine's (the loopback one for --host 0.0.0.0).
    let hosts = addresses::hosts_to_show(host);
    let url = addresses::url(hosts[0], port, &app.token);
    outln!("serving {url}");
    for other in &hosts[1..] {
        outln!(
            "from other machines: {}",
            addresses::url(*other, port, &app.token)
        );
    }
    if !args.no_open {
        open_browser(&url);
    }
    let serve = axum::serve(server::Limited::new(listener), server::router(app));
    runtime
        .block_on(async {
            tokio::select! {
                served = std::future::IntoFuture::into_future(serve) => served,
                () = async {
                    while !interrupt::interrupted() {
                        tokio::time::sleep(Duration::from_millis(100)).await;
                    }
                } => Ok(()),
            }
        })
        .map_err(|e| CliError::io(format!("the server stopped: {e}")))?;
    // Open WebSockets and render threads end with the runtime and the process.
    runtime.shutdown_timeout(Duration::from_millis(200));
    // Ctrl-C is how the server is meant to stop: a clean end, not an error (a second
    // Ctrl-C still ends the process at once, with the interrupted code).
    outln!("stopped");
    Ok(())
}

/// Opens `url` in the desktop's browser, if there is one; failing silently is fine
/// (the URL is printed).
fn open_browser(url: &str) {
    let command = if cfg!(target_os = "macos") {
        Some(("open", vec![url]))
    } else if cfg!(windows) {
        Some(("cmd", vec!["/C", "start", "", url]))
    } else if std::env::var_os("DISPLAY").is_some() || std::env::var_os("WAYLAND_DISPLAY").is_some() {
        Some(("xdg-open", vec![url]))
    } else {
        None
    };
    if let Some((program, args)) = command {
        let _ = std::process::Command::new(program)
            .args(args)
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn();
    }
}
