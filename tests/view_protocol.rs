//! `nffrt view` over HTTP and WebSocket: the guard (token, Host, Origin), hostile
//! messages, progressive frames that end in `nffrt render`'s bytes, generations that
//! never go backwards, live reload and located load errors, ray trees.

mod common;
mod view_client;

use std::path::{Path, PathBuf};

use serde_json::{json, Value};
use view_client::{render_msg, Msg, Server};

fn showcase() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/showcase.nff")
}

/// A fresh folder under the target directory for this test's files.
fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("view-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The `scene` message every session starts with.
fn scene_of(client: &mut view_client::Client) -> Value {
    client.until_json("scene", |_| {})
}

/// `nffrt render SCENE --width W --height H [--spp N] -o OUT`: the PNG's bytes.
fn rendered(scene: &Path, width: u32, height: u32, spp: u32, out: &Path) -> Vec<u8> {
    let (w, h, n) = (width.to_string(), height.to_string(), spp.to_string());
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "--width",
        &w,
        "--height",
        &h,
        "-q",
        "-o",
        out.to_str().unwrap(),
    ];
    if spp > 1 {
        args.extend(["--spp", &n]);
    }
    let run = common::nffrt(&args, b"");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    std::fs::read(out).unwrap()
}

fn rgb_of_png(png: &[u8]) -> Vec<u8> {
    let d = nffrt::image::decode_png(png).unwrap();
    d.rgb
}

/// `token` with its last hex digit changed: a token of the right length that is
/// not the server's.
fn wrong_token(token: &str) -> String {
    let (head, last) = token.split_at(token.len() - 1);
    format!("{head}{}", if last == "0" { "1" } else { "0" })
}

#[test]
fn a_wrong_token_differs_from_the_right_one_whatever_its_last_digit() {
    for token in [
        "5df45e76e761c34e77183311b027e180",
        "5df45e76e761c34e77183311b027e18f",
    ] {
        let wrong = wrong_token(token);
        assert_eq!(wrong.len(), token.len());
        assert_ne!(wrong, token);
    }
}

#[test]
fn requests_without_the_token_or_from_elsewhere_are_refused() {
    let server = Server::start(&showcase(), &[]);
    let t = &server.token;
    let (status, page) = server.get(&format!("/?token={t}"), &[]);
    assert_eq!(status, 200);
    let page = String::from_utf8(page).unwrap();
    assert!(
        page.contains(&format!("app.js?token={t}")),
        "the page loads its script with the token"
    );
    assert_eq!(server.get(&format!("/app.js?token={t}"), &[]).0, 200);
    assert_eq!(server.get(&format!("/app.css?token={t}"), &[]).0, 200);
    // No token, a wrong one, one of another length: 403 everywhere. The wrong one
    // differs in its last digit (replacing it by a fixed digit gave the token itself
    // whenever the token ended in that digit: one run in 16 failed).
    let wrong = wrong_token(t);
    for path in [
        "/".to_string(),
        "/app.js".into(),
        format!("/?token={wrong}"),
        format!("/?token={t}0"),
        "/ws".into(),
    ] {
        assert_eq!(server.get(&path, &[]).0, 403, "{path}");
    }
    // Only the embedded assets exist: paths never reach the file system.
    for path in [
        "/Cargo.toml",
        "/../Cargo.toml",
        "/examples/showcase.nff",
        "/%2e%2e/Cargo.toml",
        "/app.js/../../Cargo.toml",
    ] {
        assert_eq!(server.get(&format!("{path}?token={t}"), &[]).0, 404, "{path}");
    }
    // A name that could be rebound to this address (DNS rebinding), a wrong port.
    for host in [
        "evil.example:".to_string() + &server.port.to_string(),
        "127.0.0.1:1".into(),
    ] {
        assert_eq!(
            server.get(&format!("/?token={t}"), &[("Host", &host)]).0,
            403,
            "{host}"
        );
    }
    // Another site's page.
    let (status, _) = server.get(&format!("/?token={t}"), &[("Origin", "http://evil.example")]);
    assert_eq!(status, 403);
    // The WebSocket: no token, a wrong token, a foreign origin.
    let origin = format!("http://{}", server.host());
    for (path, origin) in [
        ("/ws".to_string(), Some(origin.as_str())),
        (format!("/ws?token={wrong}"), Some(origin.as_str())),
        (format!("/ws?token={t}"), Some("http://evil.example")),
        (format!("/ws?token={t}"), Some("null")),
    ] {
        match server.connect_with(&path, origin) {
            Err(tungstenite::Error::Http(r)) => assert_eq!(r.status(), 403, "{path} {origin:?}"),
            other => panic!("{path} {origin:?}: {:?}", other.map(|_| "opened")),
        }
    }
    let mut ok = server.connect();
    assert_eq!(scene_of(&mut ok)["name"], showcase().display().to_string());
}

/// `--host 0.0.0.0` listens everywhere; no browser opens `http://0.0.0.0:PORT`, so
/// the URLs printed are this machine's loopback one and its network address's
/// (when it has a route), each of which serves the page.
#[test]
fn an_unspecified_host_prints_urls_a_browser_can_open() {
    let server = Server::start(&showcase(), &["--host", "0.0.0.0"]);
    assert!(server.url.starts_with("http://127.0.0.1:"), "{}", server.url);
    let t = &server.token;
    assert_eq!(server.get(&format!("/?token={t}"), &[]).0, 200);
    for line in server.printed_after_url() {
        let url = line
            .strip_prefix("from other machines: http://")
            .unwrap_or_else(|| panic!("unexpected line {line:?}"));
        let (address, query) = url.split_once('/').unwrap();
        assert!(!address.starts_with("0.0.0.0"), "{line}");
        assert_eq!(
            server.get_via(address, &format!("/{query}"), &[]).0,
            200,
            "{line}"
        );
    }
}

#[test]
fn malformed_and_oversize_messages_get_an_error_and_the_server_lives_on() {
    let mut server = Server::start(&showcase(), &[]);
    let mut c = server.connect();
    scene_of(&mut c);
    for (bad, says) in [
        ("{", "bad message"),
        ("[]", "bad message"),
        (r#"{"type":"format_disk"}"#, "unknown variant"),
        (r#"{"type":"pixel","x":0,"y":0}"#, "nothing rendered"),
        (
            r#"{"type":"render","camera":{"from":[0,0,0],"at":[0,0,0],"up":[0,1,0],"angle":40},"options":{"width":8,"height":8,"max_depth":5,"spp":1,"lens":true,"soft_shadows":true}}"#,
            "coincide",
        ),
    ] {
        c.send_text(bad);
        let reply = c.until_json("error", |_| {});
        assert!(
            reply["message"].as_str().unwrap().contains(says),
            "{bad}: {reply}"
        );
    }
    // Past the protocol's limit but within the socket's: an error reply.
    c.send_text(&format!(r#"{{"type":"png","pad":"{}"}}"#, "x".repeat(20_000)));
    let reply = c.until_json("error", |_| {});
    assert!(
        reply["message"].as_str().unwrap().contains("too large"),
        "{reply}"
    );
    // Past the socket's limit (a reference picture's, 32 MiB): this connection is
    // closed, the server is not.
    c.send_text_to_be_refused(&"x".repeat(33 << 20));
    assert!(matches!(c.recv(), Msg::Closed));
    assert!(server.alive());
    let mut again = server.connect();
    let scene = scene_of(&mut again);
    again.send(&render_msg(&scene["camera"], 16, 12, 1));
    let gen = again.until_json("view", |_| {})["gen"].as_u64().unwrap();
    again.until_complete(gen, |_| {});
}

/// A reference picture sent as the file picker sends it: garbage and bad framing
/// get an error and change nothing; a real one is announced, shown, and every
/// finished pass of a picture of its size is measured against it, the error
/// falling as the samples grow (FLIP of the converged picture against itself: 0).
#[test]
fn a_reference_is_loaded_and_each_pass_measured_against_it() {
    let dir = scratch("reference");
    let reference = rendered(&showcase(), 32, 24, 16, &dir.join("ref.png"));
    let mut server = Server::start(&showcase(), &[]);
    let mut c = server.connect();
    let scene = scene_of(&mut c);
    for (header, payload, says) in [
        (
            json!({"kind": "reference", "name": "junk.gif"}),
            &b"GIF89a"[..],
            "not a PNG, PPM, PFM or OpenEXR",
        ),
        (
            json!({"kind": "other", "name": "x"}),
            &reference[..],
            "bad reference upload",
        ),
        (
            json!({"kind": "reference"}),
            &reference[..],
            "bad reference upload",
        ),
        (
            json!({"kind": "reference", "name": "cut.png"}),
            &reference[..40],
            "not a usable picture",
        ),
    ] {
        c.send_binary(&header, payload);
        let reply = c.until_json("error", |_| {});
        assert!(
            reply["message"].as_str().unwrap().contains(says),
            "{header}: {reply}"
        );
    }
    assert!(server.alive());
    c.send_binary(&json!({"kind": "reference", "name": "ref.png"}), &reference);
    let announced = c.until_json("reference", |_| {});
    let shown = match c.recv() {
        Msg::Binary(h, rgb) if h["kind"] == "reference" => rgb,
        other => panic!("the reference's pixels next, not {other:?}"),
    };
    assert_eq!(
        (
            &announced["name"],
            &announced["width"],
            &announced["height"],
            &announced["mode"]
        ),
        (&json!("ref.png"), &json!(32), &json!(24), &json!("ldr"))
    );
    // The same size and samples as the reference: each pass measured, down to 0.
    c.send(&render_msg(&scene["camera"], 32, 24, 16));
    let gen = c.until_json("view", |_| {})["gen"].as_u64().unwrap();
    let mut measured: Vec<(u64, f64)> = Vec::new();
    let mut converged = false;
    while !converged || measured.last().map(|m| m.0) != Some(16) {
        match c.recv() {
            Msg::Binary(h, map) if h["kind"] == "flip" && h["gen"] == gen => {
                assert_eq!(map.len(), 32 * 24 * 3, "{h}");
                measured.push((h["samples"].as_u64().unwrap(), h["mean"].as_f64().unwrap()));
            }
            Msg::Binary(h, _) if h["gen"] == gen && h["complete"] == true => converged = true,
            Msg::Closed => panic!("closed"),
            _ => {}
        }
    }
    assert_eq!(shown, rgb_of_png(&reference), "the reference as sent back");
    let samples: Vec<u64> = measured.iter().map(|m| m.0).collect();
    assert_eq!(samples, [1, 2, 4, 8, 16]);
    assert!(
        measured[0].1 > 0.01,
        "one sample is off the reference: {measured:?}"
    );
    assert!(measured[0].1 > measured[2].1, "{measured:?}");
    assert_eq!(measured[4].1, 0.0, "the converged picture is the reference");
}

/// Previews, then passes of 1, 1, 2, ... samples, and the last frame is exactly
/// `nffrt render`'s picture; "save PNG" gives exactly its file.
fn converges_to_the_render(scene_path: &Path, width: u32, height: u32, spp: u32, out: &Path) {
    let server = Server::start(scene_path, &[]);
    let mut c = server.connect();
    let scene = scene_of(&mut c);
    c.send(&render_msg(&scene["camera"], width, height, spp));
    let gen = c.until_json("view", |_| {})["gen"].as_u64().unwrap();
    let mut strides = Vec::new();
    let mut samples = Vec::new();
    let (header, rgb) = c.until_complete(gen, |m| {
        if let Msg::Binary(h, rgb) = m {
            let stride = h["stride"].as_u64().unwrap();
            let pixels = (width as u64).div_ceil(stride) * (height as u64).div_ceil(stride);
            assert_eq!(rgb.len() as u64, 3 * pixels, "payload size at stride {stride}");
            strides.push(stride);
            if stride == 1 {
                samples.push(h["samples"].as_u64().unwrap());
            }
        }
    });
    assert_eq!(header["samples"], spp);
    // Coarse frames first, finer after, never coarser again.
    assert!(strides.windows(2).all(|w| w[0] >= w[1]), "{strides:?}");
    assert!(samples.windows(2).all(|w| w[0] <= w[1]), "{samples:?}");
    let png = rendered(scene_path, width, height, spp, out);
    assert!(
        rgb == rgb_of_png(&png),
        "the converged frame differs from nffrt render's picture"
    );
    let (h, file) = saved_png(&mut c);
    assert_eq!(h["complete"], true);
    assert!(file == png, "the saved PNG differs from nffrt render's file");
    strides.dedup();
    if width * height > 8192 {
        assert!(
            strides.len() > 1 && strides[0] > 1,
            "coarse frames first: {strides:?}"
        );
    }
}

#[test]
fn progressive_frames_end_in_exactly_the_rendered_picture() {
    let dir = scratch("converge");
    converges_to_the_render(&showcase(), 160, 120, 4, &dir.join("a.png"));
    converges_to_the_render(&showcase(), 33, 17, 1, &dir.join("b.png"));
    // A lens and stratified samples: P3F's depth of field.
    if let Some(dof) = common::skip::shared("scenes/p3f/2025/dof.p3f") {
        converges_to_the_render(&dof, 96, 72, 5, &dir.join("c.png"));
    }
}

/// Issue 30, item G: the viewer names a scene's dialect as `info` and
/// `--stats-json` do (it said `p3f2019` where they said `p3f-2019`).
#[test]
fn the_dialect_has_one_name_everywhere() {
    for (file, name) in [
        ("p3f_2019_every_keyword.p3f", "p3f-2019"),
        ("p3f_2025_every_keyword.p3f", "p3f-2025"),
        ("comments_everywhere.nff", "nff"),
    ] {
        let path = common::data_dir("ok").join(file);
        let server = Server::start(&path, &[]);
        let mut c = server.connect();
        assert_eq!(scene_of(&mut c)["dialect"], name, "{file}: the viewer");
        let info = common::json_of(&common::info_json(&path), file);
        assert_eq!(info["dialect"], name, "{file}: info");
        let out = scratch("dialect").join("x.png");
        let args = [
            "render",
            path.to_str().unwrap(),
            "-q",
            "-o",
            out.to_str().unwrap(),
            "--stats-json",
            "-",
        ];
        let stats = common::json_of(&common::nffrt(&args, b""), file);
        assert_eq!(stats["dialect"], name, "{file}: --stats-json");
    }
}

#[test]
fn after_a_camera_change_no_frame_of_the_old_camera_arrives() {
    let server = Server::start(&showcase(), &[]);
    let mut c = server.connect();
    let scene = scene_of(&mut c);
    let mut camera = scene["camera"].clone();
    // A long render, so that it is still running when the camera moves.
    c.send(&render_msg(&camera, 320, 240, 256));
    let first = c.until_json("view", |_| {})["gen"].as_u64().unwrap();
    loop {
        if let Msg::Binary(h, _) = c.recv() {
            assert_eq!(h["gen"], first);
            break;
        }
    }
    for step in 1..=5 {
        camera["from"][0] = json!(0.5 + step as f64 * 0.3);
        c.send(&render_msg(&camera, 320, 240, if step == 5 { 2 } else { 256 }));
        let gen = c.until_json("view", |m| {
            if let Msg::Binary(h, _) = m {
                assert!(h["gen"].as_u64().unwrap() >= gen_before(step, first), "{h}");
            }
        })["gen"]
            .as_u64()
            .unwrap();
        assert_eq!(gen, first + step);
        // Every frame from now on belongs to this generation or a later one.
        if step == 5 {
            c.until_complete(gen, |m| {
                if let Msg::Binary(h, _) = m {
                    assert_eq!(
                        h["gen"], gen,
                        "a frame of an older camera after the new one's acknowledgement"
                    );
                }
            });
        } else {
            loop {
                if let Msg::Binary(h, _) = c.recv() {
                    assert_eq!(
                        h["gen"], gen,
                        "a frame of an older camera after the new one's acknowledgement"
                    );
                    break;
                }
            }
        }
    }
}

/// The generation acknowledged before step `step`.
fn gen_before(step: u64, first: u64) -> u64 {
    first + step - 1
}

const EDITED: &str = "v from 0 0 6 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 24 18\n\
                      b 0.1 0.1 0.1\nl 2 3 9\nf 0.9 0.2 0.2 0.8 0.1 10 0 1\n\ns 0 0 0 1.5\n";

/// A server on a copy of [`EDITED`] in a scratch folder, a session, its scene message.
fn session_on_edited(name: &str) -> (PathBuf, Server, view_client::Client, Value) {
    let file = scratch(name).join("scene.nff");
    std::fs::write(&file, EDITED).unwrap();
    let server = Server::start(&file, &[]);
    let mut c = server.connect();
    let scene = scene_of(&mut c);
    (file, server, c, scene)
}

/// Asks for the current picture as PNG: the reply's header and file.
fn saved_png(c: &mut view_client::Client) -> (Value, Vec<u8>) {
    c.send(&json!({"type": "png"}));
    loop {
        if let Msg::Binary(h, png) = c.recv() {
            if h["kind"] == "png" {
                return (h, png);
            }
        }
    }
}

#[test]
fn a_saved_file_renders_again_and_a_broken_one_keeps_the_picture() {
    let (file, _server, mut c, scene) = session_on_edited("reload");
    assert_eq!(scene["version"], 0);
    c.send(&render_msg(&scene["camera"], 24, 18, 1));
    let gen = c.until_json("view", |_| {})["gen"].as_u64().unwrap();
    let (_, red) = c.until_complete(gen, |_| {});
    // The sphere turns green: a new scene, rendered again without being asked.
    std::fs::write(&file, EDITED.replace("f 0.9 0.2 0.2", "f 0.2 0.9 0.2")).unwrap();
    let reloaded = c.until_json("scene", |_| {});
    assert_eq!(reloaded["version"], 1);
    let view = c.until_json("view", |_| {});
    assert_eq!(view["reason"], "reload");
    let gen = view["gen"].as_u64().unwrap();
    let (_, green) = c.until_complete(gen, |_| {});
    assert_ne!(red, green);
    let centre = 3 * (9 * 24 + 12);
    assert!(green[centre + 1] > green[centre], "the centre is green now");
    // A typo on line 6: a located error; the picture stays.
    std::fs::write(&file, EDITED.replace("s 0 0 0 1.5", "s 0 0 zero 1.5")).unwrap();
    let error = c.until_json("load_error", |m| {
        assert!(!matches!(m, Msg::Binary(..)), "no new frame for a broken file");
    });
    let message = error["message"].as_str().unwrap();
    assert!(
        message.starts_with(&format!("{}:6:7: ", file.display())),
        "{message}"
    );
    assert_eq!(
        (error["line"].clone(), error["column"].clone()),
        (json!(6), json!(7))
    );
    let (h, png) = saved_png(&mut c);
    assert_eq!(h["gen"], gen);
    assert!(rgb_of_png(&png) == green, "the last good picture stays");
    // Fixed again: back to rendering.
    std::fs::write(&file, EDITED).unwrap();
    assert_eq!(c.until_json("scene", |_| {})["version"], 2);
}

#[test]
fn a_pixel_gets_its_ray_tree_with_kinds_and_lines() {
    let (_file, _server, mut c, scene) = session_on_edited("tree");
    c.send(&render_msg(&scene["camera"], 24, 18, 1));
    c.until_json("view", |_| {});
    c.send(&json!({"type": "pixel", "x": 12, "y": 9}));
    let tree = c.until_json("ray_tree", |_| {});
    let hit = &tree["trace"]["samples"][0][1]["hit"];
    assert_eq!(hit["kind"], "Sphere");
    assert_eq!(hit["line"], 6);
    assert_eq!(tree["kinds"]["Sphere"], "sphere (s)");
    assert!(hit["lights"][0]["Point"]["Lit"].is_object(), "{hit}");
    c.send(&json!({"type": "pixel", "x": 24, "y": 0}));
    assert!(c.until_json("error", |_| {})["message"]
        .as_str()
        .unwrap()
        .contains("outside"));
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_the_server_with_pages_open() {
    let mut server = Server::start(&showcase(), &[]);
    let mut c = server.connect();
    let scene = scene_of(&mut c);
    c.send(&render_msg(&scene["camera"], 320, 240, 64));
    c.until_json("view", |_| {});
    // The documented way to stop it: a clean end, not an error.
    assert_eq!(server.interrupt(), (Some(0), vec!["stopped".to_string()]));
    // Frames sent before the end may still be in the socket; then it is closed.
    while !matches!(c.recv(), Msg::Closed) {}
}

/// `view -` reads the scene once from standard input, P3F with `--format p3f` as
/// `view --help` says, and a bad one is reported at its line before serving.
#[test]
fn view_serves_a_scene_from_standard_input() {
    let p3f = "bclr 0.1 0.1 0.1\nv from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 16 12\n\
               l 0 0 10\nf 1 0 0 1 1 1 1 0.5 10 0 1\ns 0 0 0 1\ns 2 0 0 1\n";
    let server = Server::start_with_input(Path::new("-"), &["--format", "p3f"], Some(p3f.as_bytes()));
    let mut c = server.connect();
    let scene = scene_of(&mut c);
    assert_eq!(
        (scene["name"].as_str(), scene["dialect"].as_str()),
        (Some("<stdin>"), Some("p3f-2019"))
    );
    assert_eq!(scene["counts"]["primitives"], 2);
    c.send(&render_msg(&scene["camera"], 16, 12, 1));
    let gen = c.until_json("view", |_| {})["gen"].as_u64().unwrap();
    c.until_complete(gen, |_| {});
    let bad = common::nffrt(&["view", "-", "--no-open"], b"s 0 0 0 1\nq\n");
    assert_eq!(bad.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("<stdin>:2:1: unknown keyword"));
    assert!(bad.stdout.is_empty(), "no URL for a scene that does not load");
}

#[test]
fn view_reports_a_bad_file_before_serving() {
    let missing = common::nffrt(&["view", "no/such/scene.nff", "--no-open"], b"");
    assert_eq!(missing.status.code(), Some(4));
    let dir = scratch("bad");
    let bad = dir.join("bad.nff");
    std::fs::write(&bad, "s 0 0 0 1\nq\n").unwrap();
    let broken = common::nffrt(&["view", bad.to_str().unwrap(), "--no-open"], b"");
    assert_eq!(broken.status.code(), Some(3));
    let stderr = String::from_utf8_lossy(&broken.stderr);
    assert!(
        stderr.contains(&format!("{}:2:1: unknown keyword", bad.display())),
        "{stderr}"
    );
    assert!(broken.stdout.is_empty(), "no URL for a scene that does not load");
}
