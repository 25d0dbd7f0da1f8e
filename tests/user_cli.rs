//! The command line as a user sees it: output formats and their round trips, PNG on
//! standard output, the progress bar's absence off a terminal, `--pixel` and
//! `info --bvh`.

mod common;

use std::path::{Path, PathBuf};

use common::nffrt;
use nffrt::image::{decode_exr, decode_pfm, decode_png, decode_ppm};

const SHOWCASE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff");
const SMALL: [&str; 4] = ["--width", "40", "--height", "30"];

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("user_cli", name)
}

fn render_to(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["render", SHOWCASE, "-o", out.to_str().unwrap()];
    args.extend_from_slice(&SMALL);
    args.extend_from_slice(extra);
    let o = nffrt(&args, b"");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

#[test]
fn every_format_round_trips_to_the_same_pixels() {
    let dir = scratch("formats");
    for ext in ["png", "ppm", "pfm", "exr"] {
        render_to(&dir.join(format!("a.{ext}")), &["-q"]);
    }
    let png = decode_png(&std::fs::read(dir.join("a.png")).unwrap()[..]).unwrap();
    let (w, h, ppm) = decode_ppm(&std::fs::read(dir.join("a.ppm")).unwrap()).unwrap();
    let pfm = decode_pfm(&std::fs::read(dir.join("a.pfm")).unwrap()).unwrap();
    // OpenEXR holds the PFM's linear floats exactly (32-bit channels, not 16).
    let exr = decode_exr(&std::fs::read(dir.join("a.exr")).unwrap()).unwrap();
    assert_eq!(exr, pfm);
    assert_eq!((png.width, png.height), (40, 30));
    assert_eq!((w, h), (40, 30));
    assert_eq!((pfm.width, pfm.height), (40, 30));
    assert_eq!(png.rgb, ppm);
    // The 8-bit files are the linear floats clamped, scaled by 255 and rounded.
    assert_eq!(pfm.to_rgb8(), png.rgb);
    // Not a blank image: the scene's background (0.1, 0.15, 0.3) maps to (26, 38, 77).
    assert!(png.rgb.chunks(3).any(|p| p == [26, 38, 77]));
    assert!(png.rgb.chunks(3).filter(|p| *p != [26, 38, 77]).count() > 300);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn dash_writes_png_to_standard_output() {
    let dir = scratch("stdout");
    let file = dir.join("a.png");
    render_to(&file, &["-q"]);
    let mut args = vec!["render", SHOWCASE, "-o", "-", "-q"];
    args.extend_from_slice(&SMALL);
    let o = nffrt(&args, b"");
    assert!(o.status.success());
    assert!(o.stderr.is_empty());
    assert_eq!(o.stdout, std::fs::read(&file).unwrap());
    // Without -q the summary goes to standard error, never into the image.
    let args: Vec<&str> = args.into_iter().filter(|a| *a != "-q").collect();
    let o = nffrt(&args, b"");
    assert_eq!(o.stdout, std::fs::read(&file).unwrap());
    assert!(String::from_utf8_lossy(&o.stderr).contains("rendered standard output"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn no_progress_bar_when_stderr_is_not_a_terminal() {
    let dir = scratch("progress");
    // Many samples per pixel make the render last long enough for a bar to be drawn.
    let out = dir.join("a.png");
    let o = render_to(&out, &["--spp", "16"]);
    let err = String::from_utf8(o.stderr).unwrap();
    assert!(!err.contains('\x1b') && !err.contains('\r'), "{err:?}");
    assert!(!err.contains("ETA") && !err.contains('%'), "{err:?}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{err:?}");
    let summary = lines[0];
    assert!(
        summary.starts_with(&format!("rendered {} in ", out.display())),
        "{summary}"
    );
    assert!(
        summary.contains(" rays, ") && summary.contains(" Mrays/s"),
        "{summary}"
    );
    // --quiet: nothing at all on standard error.
    let o = render_to(&out, &["--spp", "16", "--quiet"]);
    assert!(o.stderr.is_empty(), "{:?}", String::from_utf8_lossy(&o.stderr));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A glass sphere (line 11) in front of a red square (line 13), the light straight
/// behind the camera: the centre pixel's eye ray enters the sphere at t = 7, leaves
/// it 2 further on, and reaches the square 1 further, where the sphere shadows it.
const GLASS: &str = "v\nfrom 0 0 10\nat 0 0 0\nup 0 1 0\nangle 30\nhither 1\nresolution 9 9\n\
b 0 0 0\nl 0 0 20\nf 1 1 1 0.5 0.1 10 0.9 1.5\ns 0 0 2 1\nf 1 0 0 1 0 1 0 1\n\
p 4 -5 -5 0 5 -5 0 5 5 0 -5 5 0\n";

#[test]
fn pixel_prints_the_ray_tree() {
    let o = nffrt(&["render", "-", "--pixel", "4,4"], GLASS.as_bytes());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8(o.stdout).unwrap();
    let want = [
        "pixel (4, 4) of 9x9, sampling centres, max depth 5",
        "hit sphere (s) at line 11, t = 7.0000, entering",
        "material #0: colour (1.0000, 1.0000, 1.0000) Kd 0.5 Ks 0.1 shine 10 T 0.9 ior 1.5",
        // One light of intensity 1/2: 0.5 * (Kd * C * 1 + Ks * 1) = 0.3.
        "light 1 at (0.0000, 0.0000, 20.0000): adds (0.3000, 0.3000, 0.3000)",
        "refraction, weight 0.9:",
        // Leaving the sphere at its back pole (z = 1), normal facing the ray.
        "leaving\n        point (0.0000, 0.0000, 1.0000)  normal (0.0000, 0.0000, 1.0000)",
        "hit polygon (p) at line 13, t = 1.0000, entering",
        "light 1 at (0.0000, 0.0000, 20.0000): shadowed",
        "reflection, weight 0.1:",
        "miss: background (0.0000, 0.0000, 0.0000)",
    ];
    for w in want {
        assert!(out.contains(w), "missing {w:?} in\n{out}");
    }
    // The reported 8-bit value is the rendered pixel's.
    let dir = scratch("pixel");
    let png = dir.join("g.png");
    let r = nffrt(
        &["render", "-", "-q", "-o", png.to_str().unwrap()],
        GLASS.as_bytes(),
    );
    assert!(r.status.success());
    let img = decode_png(&std::fs::read(&png).unwrap()[..]).unwrap();
    let k = (4 * 9 + 4) * 3;
    let px = &img.rgb[k..k + 3];
    assert!(
        out.contains(&format!("-> 8-bit ({}, {}, {})", px[0], px[1], px[2])),
        "{out}"
    );
    // No image is written and bad pixels are usage errors.
    assert!(!Path::new("stdin.png").exists());
    for bad in ["9,0", "0,9", "1", "a,b"] {
        let o = nffrt(&["render", "-", "--pixel", bad], GLASS.as_bytes());
        assert_eq!(o.status.code(), Some(2), "{bad}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn spd_and_spp_do_not_mix() {
    let o = nffrt(&["render", SHOWCASE, "--spd", "--spp", "4", "-o", "x.png"], b"");
    assert_eq!(o.status.code(), Some(2));
    assert!(!Path::new("x.png").exists());
    assert_eq!(
        nffrt(&["render", SHOWCASE, "--spp", "0"], b"").status.code(),
        Some(2)
    );
}

#[test]
fn info_bvh_reports_the_tree() {
    let o = nffrt(&["info", "--json", "--bvh", SHOWCASE], b"");
    assert!(o.status.success());
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let b = &j["bvh"];
    let n = |k: &str| b[k].as_u64().unwrap_or_else(|| panic!("{k} in {b}"));
    // The showcase: 2 spheres, a box and 2 cones are bounded (polygons may be split
    // into triangles), the ground plane is not.
    assert_eq!(n("unbounded"), 1);
    assert!(n("primitives") >= 5);
    // The 8-wide tree the queries traverse, the only one kept: every node but the root
    // fills one lane of its parent, every entry is in one leaf, and a scene this small
    // fits in the root alone, which every ray entering it visits (the SAH cost adds the
    // expected primitive tests to that one visit).
    assert!(n("depth") >= 1 && n("min_leaf") >= 1 && n("max_leaf") >= n("min_leaf"));
    let f = |k: &str| b[k].as_f64().unwrap_or_else(|| panic!("{k} in {b}"));
    assert_eq!(
        (f("mean_lanes") * n("nodes") as f64).round() as u64,
        n("nodes") - 1 + n("leaves")
    );
    assert_eq!(
        (f("mean_leaf") * n("leaves") as f64).round() as u64,
        n("references")
    );
    assert_eq!((n("nodes"), n("depth")), (1, 1));
    assert_eq!(f("expected_visits"), 1.0);
    assert!(f("sah_cost") > 1.0);
    // The tree's box lies inside the scene's bounds (the plane excluded).
    let lo = b["bounds_min"].as_array().unwrap();
    assert!(lo[2].as_f64().unwrap() >= j["bounds_min"][2].as_f64().unwrap() - 1e-6);
    let human = nffrt(&["info", "--bvh", SHOWCASE], b"");
    let text = String::from_utf8(human.stdout).unwrap();
    for key in [
        "bvh",
        "nodes",
        "8-wide",
        "depth",
        "leaf size",
        "SAH cost",
        "node visits per ray",
    ] {
        assert!(text.contains(key), "{key} in {text}");
    }
    // Without --bvh, no tree is built or shown.
    let plain = nffrt(&["info", "--json", SHOWCASE], b"");
    let j: serde_json::Value = serde_json::from_slice(&plain.stdout).unwrap();
    assert!(j.get("bvh").is_none());
}

/// `nffrt bench --rays`: the summary line has every key BENCHMARKS.md reads, and the
/// closest-hit count of the file's rays is the hand-counted one. One sphere of radius
/// 1 at the origin; of ten rays from z = -5 towards +z, those starting within the
/// radius of the axis hit it (x = 0, ±0.5, ±0.9: five), the others (x = ±1.5, ±3,
/// and 2 in y) miss it; one packet holds eight of them, a second the last two.
#[test]
fn bench_reports_every_key_and_the_hand_counted_hits() {
    let dir = scratch("bench_rays");
    let scene = dir.join("sphere.nff");
    std::fs::write(
        &scene,
        "v\nfrom 0 0 -5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.01\nresolution 16 16\n\
         l 0 0 -10\nf 1 1 1 1 0 0 0 1\ns 0 0 0 1\n",
    )
    .unwrap();
    let xs = [0.0f32, 0.5, -0.5, 0.9, -0.9, 1.5, -1.5, 3.0, -3.0, 0.0];
    let mut bytes = Vec::new();
    for (i, &x) in xs.iter().enumerate() {
        let y = if i == 9 { 2.0 } else { 0.0 };
        for v in [x, y, -5.0, 0.0, 0.0, 1.0] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    let rays = dir.join("rays.f32");
    std::fs::write(&rays, bytes).unwrap();
    let out = nffrt(
        &[
            "bench",
            scene.to_str().unwrap(),
            "--rays",
            rays.to_str().unwrap(),
            "--repeat",
            "1",
        ],
        b"",
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8(out.stdout).unwrap();
    let summary = stdout.lines().last().unwrap();
    let value = |key: &str| {
        summary
            .split(' ')
            .find_map(|kv| kv.strip_prefix(&format!("{key}=")))
            .unwrap_or_else(|| panic!("no {key} in {summary}"))
    };
    for key in [
        "build_ms",
        "build_best_ms",
        "bvh_best_ms",
        "sah_cost",
        "primary_mrays",
        "primary_occl_mrays",
        "primary_packet_mrays",
        "random_mrays",
        "random_occl_mrays",
        "rays_mrays",
        "rays_occl_mrays",
        "rays_packet_mrays",
    ] {
        assert!(value(key).parse::<f64>().unwrap() > 0.0, "{key} in {summary}");
    }
    // `Bvh::new` alone is a part of every whole build.
    let ms = |key: &str| value(key).parse::<f64>().unwrap();
    assert!(ms("bvh_best_ms") <= ms("build_best_ms"), "{summary}");
    assert_eq!(value("rays_hits"), "5");
    assert!(stdout.contains("packets of 8 consecutive rays"), "{stdout}");
}

/// Issue 30, item F: `--srgb` writes sRGB-encoded PNG and PPM; the float formats
/// refuse it; linear stays the default.
#[test]
fn srgb_encodes_the_8_bit_formats_only() {
    let dir = scratch("srgb");
    for ext in ["png", "ppm"] {
        render_to(&dir.join(format!("s.{ext}")), &["-q", "--srgb"]);
    }
    let png = decode_png(&std::fs::read(dir.join("s.png")).unwrap()[..]).unwrap();
    let (_, _, ppm) = decode_ppm(&std::fs::read(dir.join("s.ppm")).unwrap()).unwrap();
    assert_eq!(png.rgb, ppm);
    // The background (0.1, 0.15, 0.3) through the sRGB curve, by hand: 1.055 *
    // 0.1^(1/2.4) - 0.055 = 0.3492 -> 89; 0.15 -> 108; 0.3 -> 149 (linear: 26, 38, 77).
    assert!(png.rgb.chunks(3).any(|p| p == [89, 108, 149]));
    assert!(!png.rgb.chunks(3).any(|p| p == [26, 38, 77]));
    for ext in ["pfm", "exr"] {
        let out = dir.join(format!("s.{ext}"));
        let o = nffrt(&["render", SHOWCASE, "--srgb", "-o", out.to_str().unwrap()], b"");
        assert_eq!(o.status.code(), Some(2));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("--encoding srgb: ")
                && err.contains("holds linear floats; encodings are for 8-bit .png and .ppm"),
            "{err}"
        );
        assert!(!out.exists());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
