//! The command line under failure: every exit code, one clear line per mistake,
//! resource limits, and output files that are never partial and never clobbered,
//! even when the render fails or is interrupted by SIGINT or SIGTERM.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::Duration;

const TINY: &str = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 16 16\n\
                    l 0 0 10\nf 1 0 0 1 0 1 0 1\ns 0 0 0 1\n";

fn nffrt(args: &[&str]) -> Output {
    common::nffrt(args, b"")
}

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("cli_robust", name)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 test path")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts the exit code and that stderr is exactly one `nffrt: error:` line
/// containing `needle`; returns that line.
fn fails_with(out: &Output, code: i32, needle: &str) -> String {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(code), "stderr: {err}");
    assert_eq!(err.lines().count(), 1, "not one line: {err}");
    assert!(err.starts_with("nffrt: error: "), "{err}");
    assert!(err.contains(needle), "{err:?} lacks {needle:?}");
    err
}

/// Files in `dir` whose names mark them as nffrt's temporaries.
fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".nffrt-tmp-"))
        .collect()
}

fn write_tiny(dir: &Path) -> PathBuf {
    let scene = dir.join("tiny.nff");
    std::fs::write(&scene, TINY).unwrap();
    scene
}

// ---- exit codes ------------------------------------------------------------------------

#[test]
fn exit_0_on_success_with_a_complete_image() {
    let dir = scratch("ok");
    let scene = write_tiny(&dir);
    let png = dir.join("out.png");
    let out = nffrt(&["render", s(&scene), "-o", s(&png), "--quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let bytes = std::fs::read(&png).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"));
    assert!(temporaries(&dir).is_empty());
}

#[test]
fn exit_2_for_usage_errors_in_one_line_each() {
    let dir = scratch("usage");
    let scene = write_tiny(&dir);
    let line = fails_with(
        &nffrt(&["render", s(&scene), "--no-such-option"]),
        2,
        "--no-such-option",
    );
    assert!(line.contains("unexpected argument"), "{line}");
    fails_with(&nffrt(&["render", s(&scene), "--max-depth", "65"]), 2, "65");
    fails_with(&nffrt(&["render", s(&scene), "--width", "0"]), 2, "0");
    // A missing argument is named, not just said to be missing.
    fails_with(&nffrt(&["render"]), 2, "not provided: <SCENE>");
    fails_with(
        &nffrt(&["bench", s(&scene), "--rays-only"]),
        2,
        "not provided: --rays <FILE>",
    );
    fails_with(
        &nffrt(&[]),
        2,
        "no command given: gen, convert, info, render, merge, bench",
    );
    fails_with(
        &nffrt(&["render", s(&scene), "-o", s(&dir.join("x.gif"))]),
        2,
        "unknown image format",
    );
    assert!(!dir.join("x.gif").exists());
}

/// A bad `--rays` file for `nffrt bench` is reported, with the right exit code, before
/// the scene is built or anything is printed.
#[test]
fn bench_reports_a_bad_rays_file_before_anything_else() {
    let dir = scratch("bench_rays");
    let scene = write_tiny(&dir);
    let ray = |v: [f32; 6]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let bench = |rays: &Path| nffrt(&["bench", s(&scene), "--rays", s(rays), "--repeat", "1"]);
    let cases: [(&str, Vec<u8>, &str); 4] = [
        ("empty.f32", Vec::new(), "no rays in the file"),
        (
            "short.f32",
            vec![0; 25],
            "25 bytes is not a whole number of 24-byte rays",
        ),
        (
            "nan.f32",
            ray([0.0, 0.0, f32::NAN, 0.0, 0.0, -1.0]),
            "ray 0 is not finite",
        ),
        (
            "still.f32",
            [ray([0.0, 0.0, 5.0, 0.0, 0.0, -1.0]), ray([0.0; 6])].concat(),
            "ray 1 is not finite or has no direction",
        ),
    ];
    for (name, bytes, needle) in cases {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let out = bench(&path);
        fails_with(&out, 3, needle);
        assert!(
            out.stdout.is_empty(),
            "{name}: printed {:?}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
    let out = bench(&dir.join("none.f32"));
    fails_with(&out, 4, "none.f32: cannot read rays: no such file or directory");
    assert!(out.stdout.is_empty());
    fails_with(&bench(&dir), 4, "cannot read rays: is a directory");
}

#[test]
fn exit_3_for_a_bad_scene() {
    let dir = scratch("bad_scene");
    let scene = dir.join("bad.nff");
    std::fs::write(&scene, "f 1 1 1 1 0 1 0 1\ns 0 0 zero 1\n").unwrap();
    fails_with(
        &nffrt(&["render", s(&scene), "-o", s(&dir.join("o.png"))]),
        3,
        "bad.nff:2:7:",
    );
    assert!(!dir.join("o.png").exists());
}

#[test]
fn exit_4_with_a_distinct_line_for_missing_directory_and_unreadable_scenes() {
    let dir = scratch("io");
    let missing = fails_with(&nffrt(&["render", s(&dir.join("none.nff"))]), 4, "no such file");
    let directory = fails_with(&nffrt(&["render", s(&dir)]), 4, "is a directory");
    // /proc/self/mem opens but cannot be read at offset 0: an unreadable file even for root.
    let unreadable = fails_with(&nffrt(&["info", "/proc/self/mem"]), 4, "cannot read scene");
    assert_ne!(missing, unreadable);
    assert_ne!(directory, unreadable);
    assert!(!unreadable.contains("no such file"), "{unreadable}");
}

#[test]
fn max_depth_64_is_accepted_and_65_is_not() {
    let dir = scratch("depth");
    let scene = write_tiny(&dir);
    let png = dir.join("d.png");
    let out = nffrt(&["render", s(&scene), "-o", s(&png), "--max-depth", "64", "--quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(png.exists());
}

// ---- limits ----------------------------------------------------------------------------

#[test]
fn too_many_primitives_are_refused_at_the_line_and_the_limit_can_be_raised() {
    let dir = scratch("prims");
    let scene = dir.join("three.nff");
    std::fs::write(
        &scene,
        "l 0 0 9\nf 1 1 1 1 0 1 0 1\ns 0 0 0 1\ns 3 0 0 1\ns 6 0 0 1\n",
    )
    .unwrap();
    fails_with(
        &nffrt(&["info", s(&scene), "--max-primitives", "2"]),
        3,
        "three.nff:5:1: more than 2 primitives",
    );
    let out = nffrt(&["info", s(&scene), "--max-primitives", "3"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    fails_with(
        &nffrt(&["info", s(&scene), "--max-lights", "0"]),
        3,
        "three.nff:1:1: more than 0 lights",
    );
}

#[test]
fn a_scene_file_over_the_byte_limit_is_refused_before_it_is_read() {
    let dir = scratch("bytes");
    let scene = write_tiny(&dir);
    fails_with(
        &nffrt(&["info", s(&scene), "--max-scene-bytes", "20"]),
        3,
        "larger than 20 bytes",
    );
    let out = nffrt(&["info", s(&scene), "--max-scene-bytes", &TINY.len().to_string()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

#[test]
fn standard_input_over_the_byte_limit_is_refused() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_nffrt"))
        .args(["info", "-", "--max-scene-bytes", "20"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    use std::io::Write;
    let _ = child.stdin.take().unwrap().write_all(TINY.as_bytes());
    let out = child.wait_with_output().unwrap();
    fails_with(&out, 3, "<stdin>: the scene is larger than 20 bytes");
}

#[test]
fn an_image_over_the_pixel_limit_is_refused_before_rendering() {
    let dir = scratch("pixels");
    let big = dir.join("big.nff");
    std::fs::write(&big, TINY.replace("resolution 16 16", "resolution 32768 32768")).unwrap();
    let png = dir.join("big.png");
    // From the file: a bad scene; from the command line: a usage error.
    fails_with(
        &nffrt(&["render", s(&big), "-o", s(&png)]),
        3,
        "more than the limit of 67108864",
    );
    let scene = write_tiny(&dir);
    fails_with(
        &nffrt(&[
            "render",
            s(&scene),
            "-o",
            s(&png),
            "--width",
            "9000",
            "--height",
            "9000",
        ]),
        2,
        "--max-pixels",
    );
    fails_with(
        &nffrt(&["render", s(&scene), "-o", s(&png), "--max-pixels", "255"]),
        3,
        "16x16 is 256 pixels",
    );
    let spd = nffrt(&["render", s(&scene), "-o", s(&png), "--max-pixels", "256", "--spd"]);
    fails_with(&spd, 3, "16x16 is 289 pixels");
    assert!(!png.exists());
    assert!(temporaries(&dir).is_empty());
    let out = nffrt(&[
        "render",
        s(&scene),
        "-o",
        s(&png),
        "--max-pixels",
        "256",
        "--quiet",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // Supersampling costs time, not memory: 256 pixels at 4 samples are within 256.
    let spp = nffrt(&[
        "render",
        s(&scene),
        "-o",
        s(&png),
        "--max-pixels",
        "256",
        "--spp",
        "4",
        "-q",
    ]);
    assert_eq!(spp.status.code(), Some(0), "{}", stderr(&spp));
    // A tile counts its own pixels, not the full image's (20000² is over the default).
    let tile = dir.join("tile.png");
    let region = [
        "--region", "0,0,8,8", "--width", "20000", "--height", "20000", "-q",
    ];
    let ok = nffrt(&[&["render", s(&big), "-o", s(&tile)][..], &region[..]].concat());
    assert_eq!(ok.status.code(), Some(0), "{}", stderr(&ok));
    let over = [
        &["render", s(&big), "-o", s(&tile), "--max-pixels", "63"][..],
        &region[..],
    ]
    .concat();
    fails_with(&nffrt(&over), 2, "8x8 is 64 pixels");
    // `nffrt bench` makes a ray per pixel of the file's resolution, and --random rays.
    fails_with(&nffrt(&["bench", s(&big), "--repeat", "1"]), 3, "--max-pixels");
    let random = nffrt(&["bench", s(&scene), "--random", "1000", "--max-pixels", "999"]);
    fails_with(&random, 2, "--random 1000");
}

// ---- safe output -----------------------------------------------------------------------

#[test]
fn an_unwritable_destination_is_refused_before_rendering() {
    let dir = scratch("unwritable");
    let scene = write_tiny(&dir);
    let stats = dir.join("stats.json");
    for dest in ["/nonexistent-nffrt-dir/x.png", "/proc/nffrt-test.png"] {
        let out = nffrt(&["render", s(&scene), "-o", dest, "--stats-json", s(&stats)]);
        fails_with(&out, 4, "cannot write output");
        // Nothing was rendered: no stats file, no closing summary line.
        assert!(!stats.exists(), "{dest}: stats written");
        assert!(!stderr(&out).contains("rendered"), "{dest}");
    }
    let out = nffrt(&["render", s(&scene), "-o", s(&dir)]);
    fails_with(&out, 4, "cannot write output: is a directory");
    let out = nffrt(&["render", s(&scene), "-o", s(&dir.join("sub.png/x.png"))]);
    fails_with(&out, 4, "cannot write output");
}

#[test]
fn an_existing_file_survives_a_failed_render() {
    let dir = scratch("survives");
    let png = dir.join("keep.png");
    let before = b"not an image, but the user's file".to_vec();
    std::fs::write(&png, &before).unwrap();
    // Refused after the temporary output exists: the scene asks for too many pixels.
    let big = dir.join("big.nff");
    std::fs::write(&big, TINY.replace("resolution 16 16", "resolution 20000 20000")).unwrap();
    fails_with(&nffrt(&["render", s(&big), "-o", s(&png)]), 3, "--max-pixels");
    // A bad scene, and an unwritable stats file next to a good output.
    let bad = dir.join("bad.nff");
    std::fs::write(&bad, "s 0 0 0\n").unwrap();
    fails_with(&nffrt(&["render", s(&bad), "-o", s(&png)]), 3, "bad.nff:2:1");
    let scene = write_tiny(&dir);
    let out = nffrt(&[
        "render",
        s(&scene),
        "-o",
        s(&png),
        "--stats-json",
        "/nonexistent-nffrt-dir/s.json",
    ]);
    fails_with(&out, 4, "s.json");
    assert_eq!(std::fs::read(&png).unwrap(), before);
    assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
}

/// A scene that takes several seconds on one thread: SPD balls, size 4 (7381 spheres).
fn slow_scene(dir: &Path) -> PathBuf {
    let scene = nffrt::gen::generate(nffrt::gen::SpdScene::Balls, 4).unwrap();
    let path = dir.join("balls4.nff");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    nffrt::nff::write_nff(&scene, &mut f).unwrap();
    drop(f);
    path
}

/// A render started in the background, its standard error read by a thread that
/// hands each line over as it comes.
struct Running {
    child: Child,
    lines: std::sync::mpsc::Receiver<String>,
}

/// Starts a long render into `dest` (stderr a pipe, not a terminal) with
/// `--progress`, and returns once it reports its first tenth of rows: the BVH is
/// built and the render is under way, with nine tenths to go.
fn start_render(scene: &Path, dest: &Path) -> Running {
    let mut child = Command::new(env!("CARGO_BIN_EXE_nffrt"))
        .args([
            "render",
            s(scene),
            "-o",
            s(dest),
            "--threads",
            "1",
            "--width",
            "3000",
            "--height",
            "3000",
            "--progress",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stderr = child.stderr.take().unwrap();
    let (send, lines) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        use std::io::BufRead;
        for line in std::io::BufReader::new(stderr).lines() {
            if send.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    // Generous: the machine may be busy; the line comes after about a second alone.
    let first = lines
        .recv_timeout(Duration::from_secs(300))
        .unwrap_or_else(|e| panic!("no progress line from the render ({e})"));
    assert!(first.starts_with("progress: 10% ("), "{first}");
    assert!(
        !temporaries(dest.parent().unwrap()).is_empty(),
        "no temporary output mid-render"
    );
    Running { child, lines }
}

/// Sends `signal` (INT or TERM) to the render and checks the aftermath: exit 130,
/// one line saying so (beside progress lines), no temporary left, and the
/// destination as it was before.
fn interrupt(signal: &str, existing: Option<&[u8]>) {
    let dir = scratch(&format!("sig{signal}{}", existing.is_some()));
    let scene = slow_scene(&dir);
    let dest = dir.join("out.png");
    if let Some(bytes) = existing {
        std::fs::write(&dest, bytes).unwrap();
    }
    let Running { mut child, lines } = start_render(&scene, &dest);
    let pid = child.id().to_string();
    let kill = Command::new("kill")
        .args([format!("-{signal}").as_str(), &pid])
        .status()
        .unwrap();
    assert!(kill.success());
    let status = child.wait().unwrap();
    // The reader ends with standard error: every line is in the channel.
    let errors: Vec<String> = lines.iter().filter(|l| !l.starts_with("progress: ")).collect();
    assert_eq!(status.code(), Some(130), "{errors:?}");
    assert_eq!(errors, ["nffrt: error: interrupted"]);
    match existing {
        Some(bytes) => assert_eq!(std::fs::read(&dest).unwrap(), bytes),
        None => assert!(!dest.exists(), "a partial image was left"),
    }
    assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
}

#[test]
fn sigint_mid_render_leaves_no_file() {
    interrupt("INT", None);
}

#[test]
fn sigint_mid_render_leaves_an_existing_file_untouched() {
    interrupt("INT", Some(b"the user's earlier picture"));
}

#[test]
fn sigterm_mid_render_leaves_no_file() {
    interrupt("TERM", None);
}

#[test]
fn sigterm_mid_render_leaves_an_existing_file_untouched() {
    interrupt("TERM", Some(b"the user's earlier picture"));
}
