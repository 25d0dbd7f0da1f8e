//! `nffrt view` under load (issue 46): twenty sessions on one server, each orbiting
//! (single cameras and drags of several at once) and changing its settings (size,
//! samples, depth, integrator, acceleration structure) for a while. Every request
//! must see a frame of its camera, or of a newer one, within a second; no valid
//! request may get an error, nor any frame an older camera after a newer one's
//! acknowledgement; every frame has its request's size; the converged pictures are
//! byte for byte `nffrt render`'s of the same view and options; the server is
//! alive at the end, printed no panic, and its peak resident memory stays under
//! [`MAX_PEAK_RSS_MIB`].
//!
//! It runs for `NFFRT_VIEW_LOAD_SECONDS` (default [`DEFAULT_SECONDS`]);
//! `NFFRT_VIEW_LOAD_SECONDS=60` is the minute of docs/view.md, "Under load". The
//! figures (frames and requests per session, latencies, memory) are printed.

mod common;
mod view_client;

use std::path::Path;
use std::time::{Duration, Instant};

use serde_json::{json, Value};
use view_client::{orbit, Server};

#[path = "view_load/session.rs"]
mod load_session;
use load_session::{Converged, Log, Settings};

/// Pages open at once.
const SESSIONS: usize = 20;
/// The longest a request may wait for a frame of its camera or a newer one.
const FRAME_WITHIN: Duration = Duration::from_secs(1);
/// How long the sessions run without `NFFRT_VIEW_LOAD_SECONDS`.
const DEFAULT_SECONDS: u64 = 10;
/// The server's peak resident memory may not pass this (it holds twenty sessions'
/// pictures of at most 120 x 90 pixels, a thread each, and one small scene).
const MAX_PEAK_RSS_MIB: u64 = 64;
/// Converged pictures compared with `nffrt render`'s, per session.
const CHECKED_PER_SESSION: usize = 4;

/// The scene: a floor, a mirror, a glass and a diffuse sphere, a cone, two lights.
/// The camera block comes first ([`scene_file`]) so that a check can swap it.
const BODY: &str = "\
b 0.1 0.15 0.3
l -6 -8 10
l 6 -6 8 0.6 0.6 0.6
f 0.85 0.8 0.7 0.9 0.1 20 0 1
p 4  -5 -5 0  5 -5 0  5 5 0  -5 5 0
f 0.9 0.9 0.95 0.2 0.8 100 0 1
s 1.6 1.2 1.2 1.2
f 1 1 1 0.05 0.1 200 0.9 1.5
s -1.5 -0.8 1 1
f 0.9 0.2 0.1 0.8 0.2 30 0 1
s 0.2 -1.5 0.6 0.6
f 0.2 0.8 0.3 0.8 0.2 30 0 1
c -2.8 2 0 0.7 -2.8 2 2 0
";

/// The file's camera, as JSON (numbers that are exact `f32`s).
fn first_camera() -> Value {
    json!({"from": [0.5, -9.0, 3.2], "at": [0.3, 0.0, 1.1], "up": [0.0, 0.0, 1.0], "angle": 40.0})
}

/// The scene with `camera` at `width` x `height`.
fn scene_file(camera: &Value, width: u32, height: u32) -> String {
    let v = |key: &str| -> String {
        let c = &camera[key];
        (0..3)
            .map(|i| (c[i].as_f64().unwrap() as f32).to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let angle = camera["angle"].as_f64().unwrap() as f32;
    format!(
        "v\nfrom {}\nat {}\nup {}\nangle {angle}\nhither 0.01\nresolution {width} {height}\n{BODY}",
        v("from"),
        v("at"),
        v("up")
    )
}

fn seconds() -> u64 {
    match std::env::var("NFFRT_VIEW_LOAD_SECONDS") {
        Ok(s) => s
            .parse()
            .unwrap_or_else(|_| panic!("NFFRT_VIEW_LOAD_SECONDS={s:?} is not a number of seconds")),
        Err(_) => DEFAULT_SECONDS,
    }
}

/// A line of `/proc/PID/status` in KiB (`VmHWM`, `VmRSS`).
fn status_kib(pid: u32, key: &str) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Samples the resident memory of process `pid` every 0.2 s until `end`, `secs`
/// after now: the most in the first half and in the second (a leak grows between
/// them).
fn resident_by_half(pid: u32, end: Instant, secs: u64) -> std::thread::JoinHandle<[u64; 2]> {
    let half = end - Duration::from_secs(secs) / 2;
    std::thread::spawn(move || {
        let mut most = [0, 0];
        while Instant::now() < end {
            let kib = status_kib(pid, "VmRSS").unwrap_or(0);
            let which = usize::from(Instant::now() >= half);
            most[which] = most[which].max(kib);
            std::thread::sleep(Duration::from_millis(200));
        }
        most
    })
}

#[test]
fn twenty_sessions_orbiting_and_changing_settings_are_served() {
    let secs = seconds();
    let dir = common::scratch_dir("view_load", "scene");
    let path = dir.join("scene.nff");
    std::fs::write(&path, scene_file(&first_camera(), 64, 48)).unwrap();
    let mut server = Server::start_keeping_stderr(&path, &[]);
    let pages: Vec<_> = (0..SESSIONS).map(|_| server.connect()).collect();
    let end = Instant::now() + Duration::from_secs(secs);
    let halves = resident_by_half(server.pid(), end, secs);
    let drivers: Vec<_> = pages
        .into_iter()
        .enumerate()
        .map(|(i, page)| std::thread::spawn(move || load_session::drive(page, i as u64, end)))
        .collect();
    let logs: Vec<Log> = drivers
        .into_iter()
        .map(|d| d.join().expect("a page's driver"))
        .collect();
    let alive = server.alive();
    let peak_kib = status_kib(server.pid(), "VmHWM");
    let halves = halves.join().expect("the memory watch");
    report(secs, &logs, peak_kib, halves);

    assert!(alive, "the server died under load");
    let stderr = server.stderr();
    assert!(
        !stderr.iter().any(|l| l.contains("panicked")),
        "the server panicked: {stderr:?}"
    );
    let failures: Vec<String> = logs
        .iter()
        .enumerate()
        .flat_map(|(i, l)| l.failures.iter().map(move |f| format!("session {i}: {f}")))
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // Not vacuous: every session was served, many times, at every kind of step (a
    // frame may answer several requests of a drag).
    let least = (secs / 2).max(5);
    for (i, l) in logs.iter().enumerate() {
        assert!(
            l.latencies.len() as u64 >= least && l.frames >= least,
            "session {i}: {} requests answered, {} frames (at least {least} of each)",
            l.latencies.len(),
            l.frames
        );
        assert!(l.drags > 0 && l.settings_changes > 0, "session {i}: {l:?}");
        assert!(!l.converged.is_empty(), "session {i}: no converged picture");
    }
    let slowest = logs.iter().flat_map(|l| &l.latencies).max().unwrap();
    assert!(
        *slowest <= FRAME_WITHIN,
        "a request waited {slowest:?} for its first frame"
    );
    let peak = peak_kib.expect("the server's VmHWM in /proc") / 1024;
    assert!(
        peak <= MAX_PEAK_RSS_MIB,
        "peak RSS {peak} MiB over {MAX_PEAK_RSS_MIB} MiB"
    );
    let mut checked = Vec::new();
    for (i, l) in logs.iter().enumerate() {
        for c in spread(&l.converged, CHECKED_PER_SESSION) {
            check_against_render(&dir, i, c);
            checked.push(c.settings);
        }
    }
    // Both integrators and several samples among the pictures checked.
    for integrator in ["whitted", "path"] {
        assert!(
            checked.iter().any(|s| s.integrator == integrator && s.spp > 1),
            "no {integrator} picture of several samples checked: {checked:?}"
        );
    }
}

/// Up to `n` of `items`, first and last among them.
fn spread<T>(items: &[T], n: usize) -> impl Iterator<Item = &T> {
    let step = (items.len() as f64 / n as f64).max(1.0);
    let mut picks: Vec<usize> = (0..n.min(items.len()))
        .map(|k| (k as f64 * step) as usize)
        .collect();
    if let Some(last) = picks.last_mut() {
        *last = items.len() - 1;
    }
    picks.dedup();
    picks.into_iter().map(move |k| &items[k])
}

/// `nffrt render` of a converged picture's camera and settings gives its bytes.
fn check_against_render(dir: &Path, session: usize, c: &Converged) {
    let s: &Settings = &c.settings;
    let file = dir.join(format!("s{session}-g{}.nff", c.gen));
    let png = dir.join(format!("s{session}-g{}.png", c.gen));
    std::fs::write(&file, scene_file(&c.camera, s.width, s.height)).unwrap();
    let args = s.render_args();
    let mut all = vec![
        "render",
        file.to_str().unwrap(),
        "-q",
        "-o",
        png.to_str().unwrap(),
    ];
    all.extend(args.iter().map(String::as_str));
    let run = common::nffrt(&all, b"");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let rendered = nffrt::image::decode_png(&*std::fs::read(&png).unwrap())
        .unwrap()
        .rgb;
    assert!(
        rendered == c.rgb,
        "session {session}, generation {}: the converged frame differs from `nffrt render {}`",
        c.gen,
        all[1..].join(" ")
    );
}

/// Prints the figures docs/view.md quotes.
fn report(secs: u64, logs: &[Log], peak_kib: Option<u64>, halves: [u64; 2]) {
    let mut all: Vec<Duration> = logs.iter().flat_map(|l| l.latencies.iter().copied()).collect();
    all.sort();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let frames: Vec<u64> = logs.iter().map(|l| l.frames).collect();
    let requests: Vec<usize> = logs.iter().map(|l| l.latencies.len()).collect();
    let converged: usize = logs.iter().map(|l| l.converged.len()).sum();
    if let (Some(first), Some(last)) = (all.first(), all.last()) {
        println!(
            "{SESSIONS} sessions for {secs} s: requests answered per session {}..{} ({} in all, {converged} \
             converged), frames per session {}..{}; request to frame: median {:.1} ms, p99 {:.1} ms, \
             min {:.1} ms, max {:.1} ms; server peak RSS {} KiB (VmHWM), at most {} KiB in the first \
             half and {} KiB in the second",
            requests.iter().min().unwrap(),
            requests.iter().max().unwrap(),
            all.len(),
            frames.iter().min().unwrap(),
            frames.iter().max().unwrap(),
            ms(all[all.len() / 2]),
            ms(all[(all.len() - 1) * 99 / 100]),
            ms(*first),
            ms(*last),
            peak_kib.unwrap_or(0),
            halves[0],
            halves[1],
        );
    }
}

/// The drivers' cameras stay where the orbit puts them: a check of the helper the
/// load test's pictures depend on (a quarter turn about +z moves -y to +x).
#[test]
fn an_orbit_turns_about_the_up_axis_through_the_look_at_point() {
    let camera =
        json!({"from": [0.0, -4.0, 1.0], "at": [0.0, 0.0, 1.0], "up": [0.0, 0.0, 2.0], "angle": 40.0});
    let turned = orbit(&camera, 90.0);
    let from: Vec<f64> = (0..3).map(|i| turned["from"][i].as_f64().unwrap()).collect();
    assert!(
        (from[0] - 4.0).abs() < 1e-5 && from[1].abs() < 1e-5 && (from[2] - 1.0).abs() < 1e-6,
        "{from:?}"
    );
    assert_eq!(turned["at"], camera["at"]);
}
