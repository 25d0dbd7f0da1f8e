//! `nffrt view` on an animated (AFF) scene: the scene message gives its frames,
//! a render request names a frame and its converged picture is `nffrt render
//! --frame N`'s, a frame the scene does not have is refused and the session goes
//! on, and the pixel inspector traces the frame shown.

mod common;
mod view_client;

use std::path::{Path, PathBuf};

use serde_json::{json, Value};
use view_client::{render_msg, Server};

/// A white ball (ambient only) on black, keyed to move from x = 0 (time 0) to
/// x = 2 (time 1) over 4 frames of 0.25, as tests/aff_frames.rs's.
const BALL: &str = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 28.072486935852957 hither 1 resolution 101 101\n\
    b 0 0 0\nam 1 1 1\nfm 1 1 1  0 0 0  0 0 0  1 0 1\na 0 1 4\n\
    x ball { s 0 0 0 0.4 }\n\
    k ball { transl 4  -1 0 0 0 0 0 0   0 0 0 0 0 0 0   1 2 0 0 0 0 0   2 2 0 0 0 0 0 }\n";

fn ball() -> (PathBuf, PathBuf) {
    let dir = common::scratch_dir("view_frames", "ball");
    let path = dir.join("ball.aff");
    std::fs::write(&path, BALL).unwrap();
    (dir, path)
}

/// `nffrt render SCENE --frame N --width W --height H --spp S -q -o OUT`: the RGB.
fn rendered_frame(scene: &Path, frame: u32, size: u32, spp: u32, out: &Path) -> Vec<u8> {
    let (n, s, p) = (frame.to_string(), size.to_string(), spp.to_string());
    let args = [
        "render",
        scene.to_str().unwrap(),
        "--frame",
        &n,
        "--width",
        &s,
        "--height",
        &s,
        "--spp",
        &p,
        "-q",
        "-o",
        out.to_str().unwrap(),
    ];
    let run = common::nffrt(&args, b"");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    nffrt::image::decode_png(&*std::fs::read(out).unwrap())
        .unwrap()
        .rgb
}

/// A render request for `frame`.
fn frame_msg(camera: &Value, size: u32, spp: u32, frame: u32) -> Value {
    let mut msg = render_msg(camera, size, size, spp);
    msg["frame"] = json!(frame);
    msg
}

/// The first pixel (in reading order) of the brightest red.
fn brightest(rgb: &[u8], size: u32) -> (u32, u32) {
    let i = (0..rgb.len() / 3).max_by_key(|&i| rgb[3 * i]).unwrap() as u32;
    (i % size, i / size)
}

#[test]
fn frames_converge_to_nffrt_render_frame_and_bad_ones_are_refused() {
    let (dir, path) = ball();
    let server = Server::start(&path, &[]);
    let mut c = server.connect();
    let scene = c.until_json("scene", |_| {});
    let animation = &scene["animation"];
    assert_eq!(animation["frames"], 4, "{scene}");
    assert_eq!(animation["start"], 0.0);
    assert_eq!(animation["step"], 0.25);
    let camera = &scene["camera"];
    let (size, spp) = (40, 4);
    let mut pictures = vec![];
    for frame in [0, 2] {
        c.send(&frame_msg(camera, size, spp, frame));
        let view = c.until_json("view", |_| {});
        assert_eq!(view["frame"], frame);
        let (header, rgb) = c.until_complete(view["gen"].as_u64().unwrap(), |_| {});
        assert_eq!(header["samples"], spp);
        let out = dir.join(format!("frame{frame}.png"));
        assert!(
            rgb == rendered_frame(&path, frame, size, spp, &out),
            "frame {frame} differs from nffrt render --frame {frame}"
        );
        pictures.push(rgb);
    }
    assert!(pictures[0] != pictures[1], "frames 0 and 2 show the same picture");

    // Frame 4 is past the last (0 to 3): refused, and the session goes on.
    c.send(&frame_msg(camera, size, 1, 4));
    let e = c.until_json("error", |_| {});
    assert!(e["message"].as_str().unwrap().contains("0 to 3"), "{e}");

    // The pixel inspector traces the frame shown: where frame 2's ball is brightest,
    // frame 2's ray meets the sphere and frame 0's does not.
    let (x, y) = brightest(&pictures[1], size);
    let (x0, _) = brightest(&pictures[0], size);
    assert!(
        x > x0 + 2,
        "the ball moves right: column {x0} at frame 0, {x} at frame 2"
    );
    c.send(&json!({"type": "pixel", "x": x, "y": y}));
    let tree = c.until_json("ray_tree", |_| {});
    assert_eq!(tree["frame"], 2);
    assert_eq!(tree["trace"]["samples"][0][1]["hit"]["kind"], "Sphere", "{tree}");
    c.send(&frame_msg(camera, size, 1, 0));
    let gen = c.until_json("view", |_| {})["gen"].as_u64().unwrap();
    c.until_complete(gen, |_| {});
    c.send(&json!({"type": "pixel", "x": x, "y": y}));
    let tree = c.until_json("ray_tree", |_| {});
    assert_eq!(tree["frame"], 0);
    assert_ne!(tree["trace"]["samples"][0][1]["hit"]["kind"], "Sphere", "{tree}");
}

#[test]
fn a_frame_of_a_scene_that_does_not_move_is_refused() {
    let showcase = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/showcase.nff");
    let server = Server::start(&showcase, &[]);
    let mut c = server.connect();
    let scene = c.until_json("scene", |_| {});
    assert!(scene["animation"].is_null(), "{scene}");
    c.send(&frame_msg(&scene["camera"], 16, 1, 0));
    let e = c.until_json("error", |_| {});
    assert!(e["message"].as_str().unwrap().contains("not AFF"), "{e}");
    c.send(&render_msg(&scene["camera"], 16, 12, 1));
    let gen = c.until_json("view", |_| {})["gen"].as_u64().unwrap();
    c.until_complete(gen, |_| {});
}

/// A ball that grows from radius 10 at time 0 to past the range of `f32` by
/// time 1: its frame 0 renders, its frame 2 cannot be flattened.
const GROWING: &str = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 30 hither 1 resolution 20 20\n\
    b 0 0 0\nam 1 1 1\nfm 1 1 1  0 0 0  0 0 0  1 0 1\na 0 1 4\n\
    x grow { s 0 0 0 10 }\n\
    k grow { scale 4  -1 1 1 1 0 0 0   0 1 1 1 0 0 0   1 1e38 1e38 1e38 0 0 0   2 1e38 1e38 1e38 0 0 0 }\n";

#[test]
fn a_frame_that_cannot_be_flattened_is_answered_with_an_error() {
    let dir = common::scratch_dir("view_frames", "growing");
    let path = dir.join("grow.aff");
    std::fs::write(&path, GROWING).unwrap();
    // The command line refuses that frame too.
    let out = dir.join("frame2.png");
    let run = common::nffrt(
        &[
            "render",
            path.to_str().unwrap(),
            "--frame",
            "2",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ],
        b"",
    );
    assert!(!run.status.success() && !out.exists());
    let server = Server::start(&path, &[]);
    let mut c = server.connect();
    let scene = c.until_json("scene", |_| {});
    let camera = &scene["camera"];
    c.send(&frame_msg(camera, 16, 1, 2));
    c.until_json("view", |_| {});
    let e = c.until_json("error", |_| {});
    let message = e["message"].as_str().unwrap();
    assert!(
        message.contains("frame 2") && message.contains("past the range"),
        "{e}"
    );
    // The session goes on: frame 0 renders.
    c.send(&frame_msg(camera, 16, 1, 0));
    let gen = c.until_json("view", |_| {})["gen"].as_u64().unwrap();
    c.until_complete(gen, |_| {});
}
