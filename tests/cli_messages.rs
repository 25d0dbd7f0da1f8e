//! What the command line says when it is used wrongly, and what its help says: one
//! wording for one mistake in every subcommand, negative numbers read as the bad
//! values they are, typos answered with clap's "did you mean" and the subcommand's
//! own help, limits stated in words, and scene files that are not text named as such.

mod common;

use std::path::PathBuf;
use std::process::Output;

fn nffrt(args: &[&str]) -> Output {
    common::nffrt(args, b"")
}

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("cli_messages", name)
}

const SHOWCASE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff");

/// The one error line of a run that must fail with `code`.
fn error_line(out: &Output, code: i32) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "stderr: {err}");
    assert_eq!(err.lines().count(), 1, "not one line: {err}");
    assert!(err.starts_with("nffrt: error: "), "{err}");
    assert!(out.stdout.is_empty());
    err.trim_end().to_string()
}

fn help(args: &[&str]) -> String {
    let out = nffrt(args);
    assert!(out.status.success());
    String::from_utf8(out.stdout).unwrap()
}

/// Item 6 (and issue 30, item D: the lens flags and `--light-samples`): a negative
/// number is a bad value of its flag, with the range in words.
#[test]
fn negative_numbers_are_bad_values_not_unknown_arguments() {
    let cases: [(&[&str], &str); 8] = [
        (
            &["render", SHOWCASE, "--aperture", "-3"],
            "invalid value '-3' for '--aperture <PIXELS>': must be a number, 0 or more",
        ),
        (
            &["render", SHOWCASE, "--focal", "-1"],
            "invalid value '-1' for '--focal <RATIO>': must be a number above 0",
        ),
        (
            &["render", SHOWCASE, "--light-samples", "0"],
            "invalid value '0' for '--light-samples <N>': must be a whole number from 1 to 64",
        ),
        (
            &["render", SHOWCASE, "--spp", "-1"],
            "invalid value '-1' for '--spp <N>': must be a whole number from 1 to 4096",
        ),
        (
            &["render", SHOWCASE, "--max-depth", "-3"],
            "invalid value '-3' for '--max-depth <N>': must be a whole number from 1 to 64",
        ),
        (
            &["render", SHOWCASE, "--pixel", "-1,2"],
            "invalid value '-1,2' for '--pixel <X,Y>': '-1' is not a whole number",
        ),
        (
            &["gen", "balls", "--size", "-1"],
            "invalid value '-1' for '--size <N>': must be a whole number from 1",
        ),
        (
            &["info", SHOWCASE, "--max-lights", "-1"],
            "invalid value '-1' for '--max-lights <N>': must be a whole number, 0 or more",
        ),
    ];
    for (args, want) in cases {
        let line = error_line(&nffrt(args), 2);
        assert!(line.contains(want), "{args:?}: {line}");
        assert!(!line.contains("unexpected argument"), "{line}");
    }
}

/// Issue 30, item D: a directory given as the output is called one (not an unknown
/// image format), and a P3F file read as NFF gets a hint at its first P3F keyword.
#[test]
fn a_directory_output_and_a_p3f_file_read_as_nff_are_named() {
    let dir = scratch("named");
    let outdir = dir.join("outdir");
    std::fs::create_dir(&outdir).unwrap();
    let o = outdir.to_str().unwrap();
    for args in [
        &["render", SHOWCASE, "-o", o][..],
        &["merge", SHOWCASE, "-o", o][..],
    ] {
        assert_eq!(
            error_line(&nffrt(args), 4),
            format!("nffrt: error: {o}: cannot write output: is a directory")
        );
    }
    // Its first keyword, at line 3, is `accel`.
    let p3f = std::fs::read(common::data_dir("ok").join("p3f_2025_every_keyword.p3f")).unwrap();
    let line = error_line(&common::nffrt(&["info", "-"], &p3f), 3);
    assert_eq!(
        line,
        r#"nffrt: error: <stdin>:3:1: unknown keyword "accel"; "accel" is a P3F keyword: is this a P3F file? (--format p3f)"#
    );
    let ok = common::nffrt(&["info", "-", "--format", "p3f"], &p3f);
    assert_eq!(
        ok.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 7: a typo gets clap's suggestion, and the pointer to the help that lists the
/// subcommand's flags.
#[test]
fn typos_get_a_suggestion_and_the_subcommands_help() {
    let line = error_line(&nffrt(&["render", SHOWCASE, "--sp", "4"]), 2);
    assert!(
        line.ends_with("unexpected argument '--sp' found; did you mean '--spp'? (see nffrt render --help)"),
        "{line}"
    );
    let line = error_line(&nffrt(&["rendr", SHOWCASE]), 2);
    assert!(
        line.ends_with("unrecognized subcommand 'rendr'; did you mean 'render'? (see nffrt --help)"),
        "{line}"
    );
    let line = error_line(&nffrt(&["gen", "balls", "--sise", "2"]), 2);
    assert!(
        line.contains("did you mean '--size'? (see nffrt gen --help)"),
        "{line}"
    );
}

/// Item 11: `gen` words an unwritable output like `render`, and a size of 0 is
/// answered with the range, not with the size after the largest.
#[test]
fn gen_words_its_errors_like_render() {
    let dir = scratch("gen_words");
    let missing = dir.join("missing");
    let nff = missing.join("x.nff");
    let png = missing.join("x.png");
    let gen = error_line(&nffrt(&["gen", "tetra", "-o", nff.to_str().unwrap()]), 4);
    let render = error_line(&nffrt(&["render", SHOWCASE, "-o", png.to_str().unwrap()]), 4);
    let reason = |line: &str, path: &PathBuf| {
        line.strip_prefix(&format!("nffrt: error: {}", path.display()))
            .unwrap_or_else(|| panic!("{line}"))
            .to_string()
    };
    assert_eq!(
        reason(&gen, &nff),
        ": cannot write output: no such file or directory"
    );
    assert_eq!(reason(&gen, &nff), reason(&render, &png));
    let zero = error_line(&nffrt(&["gen", "balls", "--size", "0"]), 2);
    assert!(
        zero.ends_with("invalid value '0' for '--size <N>': must be a whole number from 1 to 7 for balls"),
        "{zero}"
    );
    // Above the largest size, the reason is given.
    let eight = error_line(&nffrt(&["gen", "balls", "--size", "8"]), 2);
    assert!(
        eight.contains("invalid value '8' for '--size <N>'") && eight.contains("over the limit"),
        "{eight}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 12: help texts say limits in words, `bench` speaks of rays (of renders only
/// for `--integrator`, which times them; never of `--spd`) and cites nothing outside the repository, every number is `<N>`, and
/// `--version` works after a subcommand too.
#[test]
fn help_says_limits_in_words_and_names_values_alike() {
    let render = help(&["render", "--help"]);
    for want in ["Samples per pixel, 1 to 4096", "Maximum ray-tree depth, 1 to 64"] {
        assert!(render.contains(want), "{want:?} in\n{render}");
    }
    let bench = help(&["bench", "--help"]);
    for unwanted in ["--spd", "embree_anchor"] {
        assert!(!bench.contains(unwanted), "{unwanted:?} in\n{bench}");
    }
    // Renders only where they are timed: --integrator's whole renders.
    let (before, after) = bench.split_once("--integrator").expect("bench --integrator");
    assert!(
        !before.contains("render"),
        "\"render\" before --integrator in\n{bench}"
    );
    assert!(after.contains("whole renders"), "{bench}");
    for sub in ["render", "bench", "gen", "info", "merge"] {
        let text = help(&[sub, "--help"]);
        for odd in [
            "<WIDTH>",
            "<HEIGHT>",
            "<THREADS>",
            "<REPEAT>",
            "<RANDOM>",
            "<SEED>",
            "<SIZE>",
            "<MAX_RAY_DEPTH>",
            "<OUTPUT>",
        ] {
            assert!(!text.contains(odd), "{sub} --help names a value {odd}");
        }
    }
    let pixel = error_line(&nffrt(&["render", SHOWCASE, "--pixel", "4"]), 2);
    assert!(
        pixel.contains("expected 2 comma-separated whole numbers, found 1 number"),
        "{pixel}"
    );
    let version = nffrt(&["render", "--version"]);
    assert!(version.status.success());
    assert_eq!(
        String::from_utf8_lossy(&version.stdout),
        String::from_utf8_lossy(&nffrt(&["--version"]).stdout)
    );
}

/// Item 8: a UTF-8 byte-order mark before the first keyword is skipped; a PNG given
/// as the scene is named binary data, at its first control byte.
#[test]
fn a_byte_order_mark_is_skipped_and_binary_files_are_named() {
    let dir = scratch("bom");
    let text = std::fs::read(SHOWCASE).unwrap();
    let with_bom = dir.join("bom.nff");
    std::fs::write(&with_bom, [&b"\xEF\xBB\xBF"[..], &text].concat()).unwrap();
    let info = |path: &str| nffrt(&["info", "--json", path]);
    let plain = info(SHOWCASE);
    let bom = info(with_bom.to_str().unwrap());
    assert!(bom.status.success(), "{}", String::from_utf8_lossy(&bom.stderr));
    let counts = |o: &Output| {
        let mut j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        // (The time and the file's name differ, not what it holds.)
        j.as_object_mut().unwrap().remove("parse_s");
        j.as_object_mut().unwrap().remove("scene");
        j
    };
    assert_eq!(counts(&bom), counts(&plain));
    // A PNG's signature is 0x89 P N G \r \n 0x1a \n: the 0x1a at offset 6 is binary.
    let png = dir.join("picture.png");
    let o = nffrt(&[
        "render",
        SHOWCASE,
        "--width",
        "8",
        "-q",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let line = error_line(&info(png.to_str().unwrap()), 3);
    assert!(
        line.ends_with("picture.png:2:1: not a text scene: binary data at byte offset 6 (0x1a)"),
        "{line}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 30, item E: the help names both languages; counts take their noun in the
/// right number; f32 values print as the decimals they were given in; `info --json`
/// has the camera and the scene's name that the text shows, and bounds that hold
/// the primitives and no more.
#[test]
fn words_numbers_and_info_json_say_what_is_there() {
    let top = help(&["--help"]);
    let about = top.lines().next().unwrap();
    assert!(
        about.contains("NFF") && about.contains("P3F") && !about.contains("Whitted"),
        "{about}"
    );
    for sub in ["render", "info", "bench"] {
        let text = help(&[sub, "--help"]);
        assert!(text.contains("Scene file, NFF, P3F or AFF"), "{sub}: {text}");
    }

    // One tile, one thread, one mesh: singular nouns.
    let dir = scratch("words");
    let tile = dir.join("all.png");
    let tile = tile.to_str().unwrap();
    let small = ["--width", "8", "--height", "6", "--threads", "1"];
    let render = nffrt(
        &[
            &["render", SHOWCASE, "--region", "0,0,8,6", "-o", tile][..],
            &small[..],
        ]
        .concat(),
    );
    let summary = String::from_utf8_lossy(&render.stderr).into_owned();
    assert!(summary.ends_with(", 1 thread\n"), "{summary}");
    let full = dir.join("full.png");
    let merge = nffrt(&["merge", tile, "-o", full.to_str().unwrap()]);
    let merged = String::from_utf8_lossy(&merge.stderr).into_owned();
    assert!(merged.starts_with("merged 1 tile into "), "{merged}");
    let p3f = common::data_dir("ok").join("p3f_2025_every_keyword.p3f");
    let info = String::from_utf8(nffrt(&["info", p3f.to_str().unwrap()]).stdout).unwrap();
    assert!(
        info.contains("  meshes    1 triangle in 1 mesh (3 vertices)\n"),
        "{info}"
    );

    // --focal 1.2 is reported as 1.2, in the JSON (standard output) and the text
    // (standard error, out of the JSON's way).
    let full_png = full.to_str().unwrap();
    let stats = ["--focal", "1.2", "--stats", "--stats-json", "-", "-q"];
    let out = nffrt(&[&["render", SHOWCASE, "-o", full_png][..], &small[..], &stats[..]].concat());
    let (json, text) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(json.contains("\"focal\": 1.2,"), "{json}");
    assert!(text.contains("\nfocal              1.2\n"), "{text}");

    // info --json: the camera of the showcase's `v` block and its name.
    let out = nffrt(&["info", "--json", SHOWCASE]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["scene"], SHOWCASE);
    assert_eq!(
        j["camera"],
        serde_json::json!({"from": [0.5, -9.0, 3.2], "at": [0.3, 0.0, 1.1], "up": [0.0, 0.0, 1.0],
                           "angle": 40.0, "resolution": [640, 480], "aperture": 0.0, "focal": 1.0})
    );
    // Everything in the showcase stands on the ground plane z = 0 (spheres of radius
    // 1 and 1.2 centred at those heights, the box from 0, the cones' bases, the
    // patches' lowest vertices) and the star's top vertex is at z = 3.7.
    assert_eq!(j["bounds_min"][2], 0.0, "{}", j["bounds_min"]);
    assert_eq!(j["bounds_max"][2], 3.7, "{}", j["bounds_max"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 29, goal 6: `NFFRT_SIMD` chooses the traversal kernels (`auto`, `avx2`,
/// `portable`); `info` says which run, and a value nffrt has no kernels for is refused
/// before any work, with the choices in words.
#[test]
fn nffrt_simd_chooses_the_kernels_and_refuses_unknown_ones() {
    let info = |simd: &str| {
        let out = common::nffrt_env(&["info", "--json", SHOWCASE], &[("NFFRT_SIMD", simd)]);
        let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        j["kernels"].as_str().unwrap().to_string()
    };
    assert_eq!(info("portable"), "portable");
    let has_avx2 = cfg!(target_arch = "x86_64") && std::is_x86_feature_detected!("avx2");
    assert_eq!(info("auto"), if has_avx2 { "avx2" } else { "portable" });
    if has_avx2 {
        assert_eq!(info("avx2"), "avx2");
    }
    let out = common::nffrt_env(&["info", SHOWCASE], &[("NFFRT_SIMD", "avx512")]);
    assert_eq!(
        error_line(&out, 2),
        "nffrt: error: NFFRT_SIMD=avx512: unknown kernels; use auto, avx2 or portable \
         (nffrt's widest kernels are AVX2)"
    );
}
