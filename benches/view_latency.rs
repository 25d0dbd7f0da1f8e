//! `nffrt view` latency, measured from a WebSocket client as the page sees it:
//!
//! - camera to first frame: a camera message is sent (the previous camera's
//!   picture has arrived), and the clock stops at the first frame of the new
//!   generation (a coarse preview);
//! - orbiting: a drag is played at 60 camera messages a second for a few seconds;
//!   every frame the page would draw (its generation not older than the last drawn)
//!   counts, and so does each distinct camera drawn.
//!
//! `cargo bench --bench view_latency [-- SCENE...]`; without arguments the scenes are
//! `spd/mount.nff`, `spd/balls.nff` and `p3f/2025/dragon.p3f` from `../shared/scenes`
//! (skipped, saying so, when absent). Nothing is asserted: the numbers go to
//! BENCHMARKS.md.

#[path = "../tests/view_client/mod.rs"]
mod view_client;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde_json::Value;
use view_client::{orbit, render_msg, Client, Msg, Server};

/// Camera messages timed for the latency.
const LATENCY_SAMPLES: usize = 40;
/// How long the drag lasts.
const DRAG: Duration = Duration::from_secs(4);
/// Camera messages a second during the drag (a mouse's rate).
const DRAG_RATE: f64 = 60.0;

fn ack(client: &mut Client) -> u64 {
    client.until_json("view", |_| {})["gen"].as_u64().unwrap()
}

/// Sends `camera` and waits for its first frame: the time it took, and its stride.
fn first_frame(client: &mut Client, camera: &Value, opts: &Value) -> (Duration, u64) {
    let t0 = Instant::now();
    client.send(&with_options(camera, opts));
    let gen = ack(client);
    loop {
        if let Msg::Binary(h, _) = client.recv() {
            if h["gen"] == gen {
                return (t0.elapsed(), h["stride"].as_u64().unwrap());
            }
        }
    }
}

fn with_options(camera: &Value, opts: &Value) -> Value {
    let mut msg = render_msg(camera, 1, 1, 1);
    msg["options"] = opts.clone();
    msg
}

fn percentile(sorted: &[Duration], p: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize].as_secs_f64() * 1e3
}

fn bench(path: &Path) {
    let server = Server::start(path, &[]);
    let mut client = server.connect();
    let scene = client.until_json("scene", |_| {});
    let opts = scene["options"].clone();
    let mut camera = scene["camera"].clone();
    // Warm up: the first picture converges once.
    client.send(&with_options(&camera, &opts));
    let gen = ack(&mut client);
    client.until_complete(gen, |_| {});

    let mut latencies = Vec::new();
    let mut strides = Vec::new();
    for _ in 0..LATENCY_SAMPLES {
        camera = orbit(&camera, 3.0);
        let (t, stride) = first_frame(&mut client, &camera, &opts);
        latencies.push(t);
        strides.push(stride);
    }
    latencies.sort();

    // The drag: camera messages at a fixed rate, frames counted as the page draws them.
    let (mut drawn, mut cameras_drawn, mut sent, mut newest) = (0u64, 0u64, 0u64, 0u64);
    let (mut last_drawn_gen, mut acked) = (0u64, Vec::new());
    let period = Duration::from_secs_f64(1.0 / DRAG_RATE);
    let t0 = Instant::now();
    let mut next_send = t0;
    while t0.elapsed() < DRAG {
        let now = Instant::now();
        if now >= next_send {
            camera = orbit(&camera, 1.0);
            client.send(&with_options(&camera, &opts));
            sent += 1;
            next_send += period;
        }
        match client.try_recv(next_send.saturating_duration_since(Instant::now())) {
            Some(Msg::Json(v)) if v["type"] == "view" => acked.push(v["gen"].as_u64().unwrap()),
            Some(Msg::Binary(h, _)) => {
                let g = h["gen"].as_u64().unwrap();
                if g >= last_drawn_gen {
                    drawn += 1;
                    if g > last_drawn_gen {
                        cameras_drawn += 1;
                    }
                    last_drawn_gen = g;
                    newest = newest.max(g);
                }
            }
            Some(Msg::Closed) => panic!("closed during the drag"),
            _ => {}
        }
    }
    let secs = t0.elapsed().as_secs_f64();
    let (w, h) = (opts["width"].as_u64().unwrap(), opts["height"].as_u64().unwrap());
    strides.sort();
    println!(
        "{}: {w}x{h}, spp {}: camera -> first frame median {:.1} ms, p90 {:.1} ms, max {:.1} ms \
         (stride {}); orbiting at {DRAG_RATE} messages/s for {secs:.1} s: {:.1} frames/s drawn, \
         {:.1} cameras/s drawn ({sent} sent, {} acknowledged)",
        path.file_name().unwrap().to_string_lossy(),
        opts["spp"],
        percentile(&latencies, 0.5),
        percentile(&latencies, 0.9),
        percentile(&latencies, 1.0),
        strides[strides.len() / 2],
        drawn as f64 / secs,
        cameras_drawn as f64 / secs,
        acked.len()
    );
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let shared = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes");
    let scenes: Vec<PathBuf> = if args.is_empty() {
        ["spd/mount.nff", "spd/balls.nff", "p3f/2025/dragon.p3f"]
            .iter()
            .map(|s| shared.join(s))
            .collect()
    } else {
        args.iter().map(PathBuf::from).collect()
    };
    for scene in &scenes {
        if scene.exists() {
            bench(scene);
        } else {
            println!("note: {} is absent; skipped", scene.display());
        }
    }
}
