//! Render-farm tiles: `render --region` pieces merged by `nffrt merge` are byte for
//! byte the full render, whatever the split, the sampling or the tile order; broken
//! tile sets are refused with a message that names the problem.

mod common;

use std::path::{Path, PathBuf};

use common::{nffrt, nffrt_in};

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

/// Issue 30, item F: sRGB-encoded tiles merge into the full `--srgb` render, and
/// never with linear ones.
#[test]
fn srgb_tiles_merge_alike_and_not_with_linear_ones() {
    merged_equals_full("srgb", &FOUR, &["--srgb"]);
    let dir = scratch("srgb_mixed");
    render(&dir.join("top.png"), Some("0,0,61,30"), &["--srgb"]);
    render(&dir.join("bottom.png"), Some("0,30,61,47"), &[]);
    let png = nffrt::image::decode_png(&std::fs::read(dir.join("top.png")).unwrap()[..]).unwrap();
    assert_eq!(png.text("nffrt:encoding"), Some("srgb"));
    let (code, err) = merge_in(&dir, &["bottom.png", "top.png"]);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("top.png was written with --encoding srgb and")
            && err.contains("bottom.png with --encoding linear"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
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
    let options = png.text("nffrt:options").unwrap();
    for field in ["\"width\":61", "\"height\":47", "\"max_depth\":3", "\"spp\":9"] {
        assert!(options.contains(field), "{field} in {options}");
    }
    // The fingerprint: the scene file's 64-bit FNV-1a hash, and the options' hash.
    let fingerprint = png.text("nffrt:fingerprint").unwrap();
    let scene_hash = fnv1a64(&std::fs::read(SHOWCASE).unwrap());
    assert!(
        fingerprint.starts_with(&format!("scene={scene_hash:016x} options=")),
        "{fingerprint}"
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
    assert!(
        err.contains("left.png and ")
            && err.ends_with(
                "right4.png were rendered with different settings: \
                 sampling PixelCenters against Stratified, spp none against 4\n"
            ),
        "{err}"
    );
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

/// 64-bit FNV-1a, written out here from its definition (offset basis, prime) to
/// check the library's.
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h: u64, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Merges `tiles` (in `dir`) into `dir/out.png`: the exit code and standard error.
fn merge_in(dir: &Path, tiles: &[&str]) -> (Option<i32>, String) {
    let out = dir.join("out.png");
    let tiles: Vec<String> = tiles.iter().map(|t| s(&dir.join(t)).to_string()).collect();
    let mut args = vec!["merge", "-o", s(&out)];
    args.extend(tiles.iter().map(String::as_str));
    let o = nffrt(&args, b"");
    assert!(
        o.status.success() || !out.exists(),
        "no output after a failed merge"
    );
    (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// Issue 23, item 2: tiles of two scenes with the same settings do not merge; the
/// odd tile is named.
#[test]
fn tiles_of_another_scene_are_refused_and_named() {
    let dir = scratch("scenes");
    // The showcase with another background: same settings, another picture.
    let other = dir.join("other.nff");
    let text = std::fs::read_to_string(SHOWCASE).unwrap();
    std::fs::write(&other, format!("b 1 0 1\n{text}")).unwrap();
    let render_from = |scene: &Path, region: &str, out: &str| {
        let mut args = vec!["render", s(scene), "-q", "--region", region, "-o"];
        let out = dir.join(out);
        args.push(s(&out));
        args.extend_from_slice(&SIZE);
        let o = nffrt(&args, b"");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let showcase = Path::new(SHOWCASE);
    render_from(showcase, "0,0,61,20", "top.png");
    render_from(showcase, "0,20,61,30", "middle.png");
    render_from(&other, "0,20,61,30", "middle-other.png");
    render_from(showcase, "0,30,61,47", "bottom.png");
    let (code, err) = merge_in(&dir, &["top.png", "middle-other.png", "bottom.png"]);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("middle-other.png comes from a different scene"),
        "{err}"
    );
    // Two tiles that disagree: both are named, neither can be called the odd one.
    let (code, err) = merge_in(&dir, &["top.png", "middle-other.png"]);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("top.png and") && err.contains("middle-other.png come from different scenes"),
        "{err}"
    );
    // The same tiles from one scene merge.
    let (code, err) = merge_in(&dir, &["top.png", "middle.png", "bottom.png"]);
    assert_eq!(code, Some(0), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 23, item 2: a tile whose depth differs (an option that changes pixels) is
/// refused like one of another sampling, and a tile without a fingerprint (from an
/// older nffrt) is refused with the reason.
#[test]
fn tiles_without_a_fingerprint_or_of_another_depth_are_refused() {
    let dir = scratch("fingerprint");
    render(&dir.join("left.png"), Some("0,0,30,47"), &[]);
    render(&dir.join("right.png"), Some("30,0,61,47"), &["--max-depth", "2"]);
    let (code, err) = merge_in(&dir, &["left.png", "right.png"]);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("left.png and ")
            && err.ends_with("right.png were rendered with different settings: max_depth 5 against 2\n"),
        "{err}"
    );
    // An older nffrt's tile: the region and options chunks, no fingerprint.
    render(&dir.join("right.png"), Some("30,0,61,47"), &[]);
    let png = nffrt::image::decode_png(&std::fs::read(dir.join("right.png")).unwrap()[..]).unwrap();
    let old_text: Vec<(&str, String)> = png
        .text
        .iter()
        .filter(|(k, _)| k != "nffrt:fingerprint")
        .map(|(k, v)| (k.as_str(), v.clone()))
        .collect();
    assert_eq!(old_text.len(), png.text.len() - 1, "{:?}", png.text);
    let mut old = Vec::new();
    nffrt::image::encode_png_rgb8(png.width, png.height, &png.rgb, &old_text, &mut old).unwrap();
    std::fs::write(dir.join("old.png"), old).unwrap();
    let (code, err) = merge_in(&dir, &["left.png", "old.png"]);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("old.png: the tile has no scene fingerprint"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 23, item 3: without `-o`, a tile is named after its region, and a full
/// render of the same scene in the same directory is left as it was.
#[test]
fn a_tile_never_takes_the_full_pictures_default_name() {
    let dir = scratch("default_name");
    std::fs::copy(SHOWCASE, dir.join("showcase.nff")).unwrap();
    let full = nffrt_in(
        &dir,
        &["render", "showcase.nff", "-q", "--width", "40", "--height", "30"],
    );
    assert!(full.status.success(), "{}", String::from_utf8_lossy(&full.stderr));
    let before = std::fs::read(dir.join("showcase.png")).unwrap();
    let tile = nffrt_in(
        &dir,
        &[
            "render",
            "showcase.nff",
            "--region",
            "0,0,8,8",
            "--width",
            "40",
            "--height",
            "30",
        ],
    );
    assert!(tile.status.success(), "{}", String::from_utf8_lossy(&tile.stderr));
    assert_eq!(std::fs::read(dir.join("showcase.png")).unwrap(), before);
    let png =
        nffrt::image::decode_png(&std::fs::read(dir.join("showcase.0-0-8-8.png")).unwrap()[..]).unwrap();
    assert_eq!((png.width, png.height), (8, 8));
    assert!(String::from_utf8_lossy(&tile.stderr).starts_with("rendered showcase.0-0-8-8.png "));
    std::fs::remove_dir_all(&dir).unwrap();
}
