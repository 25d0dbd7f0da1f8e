//! Render-farm tiles: `render --region` pieces merged by `nffrt merge` are byte for
//! byte the full render, whatever the split, the sampling or the tile order; broken
//! tile sets are refused with a message that names the problem.

mod common;

use std::path::{Path, PathBuf};

use common::nffrt;

const SHOWCASE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff");
/// An odd size, so no split is even.
const SIZE: [&str; 4] = ["--width", "61", "--height", "47"];

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("tiles_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Renders the scene (whole, or one region) into `out` with the extra options.
fn render(out: &Path, region: Option<&str>, extra: &[&str]) {
    let mut args = vec!["render", SHOWCASE, "-q", "-o", s(out)];
    args.extend_from_slice(&SIZE);
    args.extend_from_slice(extra);
    if let Some(r) = region {
        args.extend_from_slice(&["--region", r]);
    }
    let o = nffrt(&args, b"");
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Renders each region as a tile, merges them (listed in reverse order) and checks
/// the result against the full render.
fn merged_equals_full(name: &str, regions: &[&str], extra: &[&str]) {
    let dir = scratch(name);
    let full = dir.join("full.png");
    render(&full, None, extra);
    let tiles: Vec<PathBuf> = regions
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let t = dir.join(format!("tile{k}.png"));
            render(&t, Some(r), extra);
            t
        })
        .collect();
    let merged = dir.join("merged.png");
    let mut args = vec!["merge", "-o", s(&merged)];
    args.extend(tiles.iter().rev().map(|t| s(t)));
    let o = nffrt(&args, b"");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (std::fs::read(&full).unwrap(), std::fs::read(&merged).unwrap());
    assert!(a == b, "{name}: merged image differs from the full render");
    // A tile alone is not the full image, so the comparison above is not vacuous.
    assert_ne!(std::fs::read(&tiles[0]).unwrap(), a);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Four uneven tiles: an off-centre cross.
const FOUR: [&str; 4] = ["0,0,17,30", "17,0,61,30", "0,30,40,47", "40,30,61,47"];
/// Seven uneven tiles: three bands cut into 2, 3 and 2 pieces of different widths.
const SEVEN: [&str; 7] = [
    "0,0,5,11",
    "5,0,61,11",
    "0,11,29,12",
    "29,11,30,12",
    "30,11,61,12",
    "0,12,60,47",
    "60,12,61,47",
];

#[test]
fn four_uneven_tiles_merge_into_the_full_render() {
    merged_equals_full("four", &FOUR, &[]);
}

#[test]
fn seven_uneven_tiles_merge_into_the_full_render() {
    merged_equals_full("seven", &SEVEN, &[]);
}

#[test]
fn supersampled_tiles_merge_into_the_full_render() {
    merged_equals_full("spp", &SEVEN, &["--spp", "4"]);
}

#[test]
fn spd_protocol_tiles_merge_into_the_full_render() {
    merged_equals_full("spd", &FOUR, &["--spd"]);
}

#[test]
fn tiles_record_their_place_and_settings() {
    let dir = scratch("meta");
    let t = dir.join("t.png");
    render(&t, Some("3,4,10,20"), &["--spp", "9", "--max-depth", "3"]);
    let png = nffrt::image::decode_png(&std::fs::read(&t).unwrap()[..]).unwrap();
    assert_eq!((png.width, png.height), (7, 16));
    assert_eq!(png.text("nffrt:region"), Some("3,4,10,20,61,47"));
    assert_eq!(
        png.text("nffrt:options"),
        Some("sampling=stratified-9 max-depth=3")
    );
    assert_eq!(png.text("Software"), Some("nffrt"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn broken_tile_sets_are_refused_with_the_reason() {
    let dir = scratch("bad");
    let t = |k: &str| dir.join(format!("{k}.png"));
    render(&t("left"), Some("0,0,30,47"), &[]);
    render(&t("right"), Some("30,0,61,47"), &[]);
    render(&t("wide"), Some("20,0,61,47"), &[]);
    render(&t("right4"), Some("30,0,61,47"), &["--spp", "4"]);
    render(&t("full"), None, &[]);
    let merge = |tiles: &[&str]| {
        let out = dir.join("out.png");
        let mut args = vec!["merge".to_string(), "-o".into(), s(&out).into()];
        args.extend(tiles.iter().map(|k| s(&t(k)).to_string()));
        let args: Vec<&str> = args.iter().map(|a| a.as_str()).collect();
        let o = nffrt(&args, b"");
        assert!(!out.exists(), "no output after a failed merge");
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (code, err) = merge(&["left", "wide"]);
    assert_eq!(code, Some(3));
    assert!(err.contains("overlap"), "{err}");
    let (code, err) = merge(&["left"]);
    assert_eq!(code, Some(3));
    assert!(
        err.contains("cover 1410 of the 2867") && err.contains("pixel (30, 0)"),
        "{err}"
    );
    let (code, err) = merge(&["left", "right4"]);
    assert_eq!(code, Some(3));
    assert!(err.contains("different settings"), "{err}");
    let (code, err) = merge(&["left", "full"]);
    assert_eq!(code, Some(3));
    assert!(err.contains("not an nffrt tile"), "{err}");
    let (code, err) = merge(&["left", "missing"]);
    assert_eq!(code, Some(4));
    assert!(err.contains("missing.png"), "{err}");
    // Tiles must be PNG, and so must the merged image.
    let o = nffrt(
        &[
            "render",
            SHOWCASE,
            "--region",
            "0,0,2,2",
            "-o",
            s(&dir.join("t.ppm")),
        ],
        b"",
    );
    assert_eq!(o.status.code(), Some(2));
    let o = nffrt(
        &[
            "merge",
            s(&t("left")),
            s(&t("right")),
            "-o",
            s(&dir.join("m.ppm")),
        ],
        b"",
    );
    assert_eq!(o.status.code(), Some(2));
    // Regions outside the image or empty are usage errors.
    let x = dir.join("x.png");
    for r in ["0,0,62,10", "5,5,5,9", "1,2,3"] {
        let mut args = vec!["render", SHOWCASE, "-o", s(&x), "--region", r];
        args.extend_from_slice(&SIZE);
        assert_eq!(nffrt(&args, b"").status.code(), Some(2), "{r}");
        assert!(!x.exists());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
