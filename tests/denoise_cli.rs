//! `nffrt render --denoise`, `--aov` and `--encoding` from the command line: a
//! missing library is a clear error that writes nothing; the denoised Cornell box
//! is closer to a converged render than the noisy one, and the same on any thread
//! count; AOVs hold hand-computed values, as EXR layers or beside the picture; the
//! 8-bit encodings are the curves computed here from the PFM's values; tiles of
//! different encodings do not merge.
//!
//! The checks that need Open Image Denoise skip, saying so, when it is not
//! installed (`pip install pyoidn`, or `NFFRT_OIDN`); `.ci/run` installs it and sets
//! `NFFRT_REQUIRE_OIDN=1`, which makes such a skip a failure.

mod common;

use common::{denoiser_installed, nffrt, nffrt_env, scratch_dir};
use nffrt::image::{decode_exr_channels, decode_pfm, decode_png};

/// A red sphere of radius 1 at the origin seen from z = 5 on a blue background:
/// the centre pixel meets it at distance 4 with normal +z.
const SPHERE: &str = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 30 hither 1 resolution 9 9\n\
                      b 0 0 0.5\nl 0 0 10\nf 0.8 0.1 0.1 0.5 0.3 10 0 1\ns 0 0 0 1\n";

/// The Cornell box (path-traced, P3F).
const CORNELL: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/cornell.p3f");

fn ok(out: &std::process::Output) {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

fn pfm(path: &std::path::Path) -> Vec<f32> {
    let image = decode_pfm(&std::fs::read(path).unwrap()).unwrap();
    image.pixels.iter().flat_map(|p| p.to_array()).collect()
}

fn rmse(a: &[f32], b: &[f32]) -> f64 {
    let sum: f64 = a.iter().zip(b).map(|(x, y)| ((x - y) as f64).powi(2)).sum();
    (sum / a.len() as f64).sqrt()
}

#[test]
fn a_missing_library_is_an_error_that_says_how_to_get_it_and_writes_nothing() {
    let dir = scratch_dir("denoise_cli", "missing");
    let out = dir.join("c.png");
    let run = nffrt_env(
        &[
            "render",
            CORNELL,
            "--width",
            "8",
            "--denoise",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ],
        &[("NFFRT_OIDN", "/nowhere/libOpenImageDenoise.so.2")],
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(4), "{stderr}");
    assert!(
        stderr.contains("/nowhere/libOpenImageDenoise.so.2 (from NFFRT_OIDN)")
            && stderr.contains("pip install pyoidn"),
        "{stderr}"
    );
    assert!(!out.exists(), "nothing written");
}

#[test]
fn denoising_has_nothing_to_do_on_centre_rays_or_tiles() {
    let dir = scratch_dir("denoise_cli", "refused");
    let scene = dir.join("sphere.nff");
    std::fs::write(&scene, SPHERE).unwrap();
    for (args, says) in [
        (vec!["--denoise"], "no noise to remove"),
        (
            vec!["--spp", "4", "--denoise", "--region", "0,0,4,4"],
            "not on --region tiles",
        ),
        (
            vec!["--spp", "4", "--aov", "depth", "-o", "-"],
            "beside the picture's file",
        ),
        (
            vec!["--encoding", "gamma2.2", "-o", "x.pfm"],
            "holds linear floats",
        ),
        (vec!["--srgb", "--encoding", "linear"], "cannot be used with"),
    ] {
        let mut all = vec!["render", scene.to_str().unwrap()];
        all.extend(args.iter().copied());
        let run = nffrt(&all, b"");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
}

#[test]
fn the_denoised_room_is_closer_to_the_converged_one_and_the_same_on_any_thread_count() {
    if !denoiser_installed() {
        return;
    }
    let dir = scratch_dir("denoise_cli", "room");
    let run = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let out_s = out.to_str().unwrap().to_string();
        let mut args = vec![
            "render", CORNELL, "--width", "64", "--height", "64", "-q", "-o", &out_s,
        ];
        args.extend(extra);
        ok(&nffrt(&args, b""));
        std::fs::read(&out).unwrap()
    };
    let as_shown = |png: Vec<u8>| -> Vec<f32> {
        let rgb = decode_png(&png[..]).unwrap().rgb;
        rgb.into_iter().map(|b| b as f32 / 255.0).collect()
    };
    // The pictures as shown (8-bit, gamma 2.2): in linear floats the lamp's edge,
    // seen directly by camera rays and left as it is, dominates the error.
    let reference = as_shown(run("ref.png", &["--spp", "1024"]));
    let noisy = as_shown(run("noisy.png", &["--spp", "16"]));
    let denoised = run("denoised.pfm", &["--spp", "16", "--denoise", "--threads", "1"]);
    let again = run("again.pfm", &["--spp", "16", "--denoise", "--threads", "2"]);
    assert_eq!(denoised, again, "the same picture on 1 and 2 threads");
    let denoised = as_shown(run("denoised.png", &["--spp", "16", "--denoise"]));
    let (n, d) = (rmse(&noisy, &reference), rmse(&denoised, &reference));
    assert!(d < 0.5 * n, "denoised RMSE {d} against noisy {n}");
    let fast = as_shown(run("fast.png", &["--spp", "16", "--denoise=fast"]));
    assert!(rmse(&fast, &reference) < 0.5 * n, "the fast network too");
}

#[test]
fn aovs_hold_the_first_hits_as_exr_layers_or_beside_the_picture() {
    let dir = scratch_dir("denoise_cli", "aov");
    let scene = dir.join("sphere.nff");
    std::fs::write(&scene, SPHERE).unwrap();
    let with_aovs = |aovs: &str, out: &std::path::Path| {
        let (scene, out) = (scene.to_str().unwrap(), out.to_str().unwrap());
        ok(&nffrt(&["render", scene, "--aov", aovs, "-q", "-o", out], b""));
    };
    let exr = dir.join("s.exr");
    with_aovs("depth,albedo,normal", &exr);
    let channels = decode_exr_channels(&std::fs::read(&exr).unwrap()).unwrap();
    let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["B", "G", "R", "albedo.B", "albedo.G", "albedo.R", "depth.Z", "normal.X", "normal.Y", "normal.Z"]
    );
    let at = |name: &str, i: usize| channels.iter().find(|(n, _)| n == name).unwrap().1[i];
    let centre = 4 * 9 + 4;
    // Kd C + Ks = 0.5 (0.8, 0.1, 0.1) + 0.3; distance 5 - 1; normal +z.
    for (name, want) in [
        ("albedo.R", 0.7),
        ("albedo.G", 0.35),
        ("depth.Z", 4.0),
        ("normal.X", 0.0),
        ("normal.Z", 1.0),
    ] {
        assert!(
            (at(name, centre) - want).abs() < 1e-5,
            "{name}: {}",
            at(name, centre)
        );
    }
    assert_eq!(at("depth.Z", 0), f32::INFINITY, "the corner sees the background");
    assert_eq!(at("albedo.B", 0), 0.5, "the background's colour");

    with_aovs("normal,depth", &dir.join("s.png"));
    let normal = decode_png(&std::fs::read(dir.join("s.normal.png")).unwrap()[..]).unwrap();
    let depth = decode_png(&std::fs::read(dir.join("s.depth.png")).unwrap()[..]).unwrap();
    assert_eq!(
        &normal.rgb[3 * centre..3 * centre + 3],
        &[128, 128, 255],
        "(0, 0, 1) mapped to [0, 1]"
    );
    assert_eq!(&depth.rgb[..3], &[255, 255, 255], "nothing hit: white");
    assert!(
        depth.rgb[3 * centre] < 255,
        "the sphere is nearer than the farthest hit"
    );
    assert!(!dir.join("s.albedo.png").exists(), "only what was asked for");
}

#[test]
fn eight_bit_pictures_take_the_encoding_of_their_integrator_or_the_one_asked_for() {
    let dir = scratch_dir("denoise_cli", "encoding");
    let nff = dir.join("sphere.nff");
    std::fs::write(&nff, SPHERE).unwrap();
    let gamma = |v: f32| (v.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8;
    let srgb = |v: f32| {
        let v = v.clamp(0.0, 1.0);
        let e = if v <= 0.0031308 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (e * 255.0).round() as u8
    };
    let linear = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    // (scene, flags, the curve from a linear value to its byte, the encoding's name)
    type Case<'a> = (&'a str, &'a [&'a str], &'a dyn Fn(f32) -> u8, &'a str);
    let cases: [Case; 5] = [
        (CORNELL, &["--spp", "4"], &gamma, "gamma2.2"),
        (
            nff.to_str().unwrap(),
            &["--integrator", "path", "--spp", "4"],
            &srgb,
            "srgb",
        ),
        (nff.to_str().unwrap(), &[], &linear, "linear"),
        (
            CORNELL,
            &["--spp", "4", "--encoding", "linear"],
            &linear,
            "linear",
        ),
        (CORNELL, &["--spp", "4", "--srgb"], &srgb, "srgb"),
    ];
    for (k, (scene, flags, curve, name)) in cases.into_iter().enumerate() {
        let (png, pfm_path, json) = (
            dir.join(format!("{k}.png")),
            dir.join(format!("{k}.pfm")),
            dir.join("s.json"),
        );
        let mut args = vec!["render", scene, "--width", "16", "--height", "16", "-q"];
        args.extend(flags);
        let mut as_png = args.clone();
        as_png.extend([
            "-o",
            png.to_str().unwrap(),
            "--stats-json",
            json.to_str().unwrap(),
        ]);
        ok(&nffrt(&as_png, b""));
        let plain: Vec<&str> = args
            .into_iter()
            .filter(|a| !["--srgb", "--encoding", "linear"].contains(a))
            .collect();
        let mut as_pfm = plain;
        as_pfm.extend(["-o", pfm_path.to_str().unwrap()]);
        ok(&nffrt(&as_pfm, b""));
        let bytes = decode_png(&std::fs::read(&png).unwrap()[..]).unwrap().rgb;
        let want: Vec<u8> = pfm(&pfm_path).into_iter().map(curve).collect();
        assert_eq!(bytes, want, "case {k} ({name})");
        let stats: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        assert_eq!(stats["encoding"], name, "case {k}");
    }
}

#[test]
fn tiles_of_different_encodings_do_not_merge() {
    let dir = scratch_dir("denoise_cli", "tiles");
    let tile = |name: &str, region: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render", CORNELL, "--width", "8", "--height", "8", "--spp", "2", "--region", region,
        ];
        args.extend(extra);
        let out_s = out.to_str().unwrap().to_string();
        args.extend(["-q", "-o", &out_s]);
        ok(&nffrt(&args, b""));
        out
    };
    let left = tile("left.png", "0,0,4,8", &[]);
    let right = tile("right.png", "4,0,8,8", &["--encoding", "linear"]);
    let merged = dir.join("full.png");
    let merge = |right: &std::path::Path| {
        let paths = [&left, right, &merged].map(|p| p.to_str().unwrap().to_string());
        nffrt(&["merge", &paths[0], &paths[1], "-o", &paths[2]], b"")
    };
    let run = merge(&right);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("--encoding gamma2.2") && stderr.contains("--encoding linear"),
        "{stderr}"
    );
    ok(&merge(&tile("right.png", "4,0,8,8", &[])));
}
