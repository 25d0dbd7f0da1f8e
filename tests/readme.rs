//! The README and the pages of `docs/` it links against the tool: every flag the
//! commands accept is documented, the figures they quote are the ones the tool
//! reports, and the quick start shows the picture a user should see first.

mod common;

use std::path::Path;

use common::nffrt;

fn readme() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap()
}

/// The README and every page of `docs/`, one text.
fn documentation() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut pages: Vec<_> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    pages.sort();
    let mut text = readme();
    for page in pages {
        text += &std::fs::read_to_string(page).unwrap();
    }
    text
}

/// The options of `nffrt SUB --help`: each line's spellings (`-o`, `--output`).
fn options(sub: &str) -> Vec<Vec<String>> {
    let out = nffrt(&[sub, "--help"], b"");
    assert!(out.status.success());
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(str::trim_start)
        .filter(|l| l.starts_with('-'))
        .map(|l| {
            l.split([' ', ','])
                .take_while(|w| w.is_empty() || w.starts_with('-'))
                .filter(|w| !w.is_empty())
                // An optional value is part of the spelling in the help: `--denoise[=<QUALITY>]`.
                .map(|w| w.split("[=").next().unwrap_or(w).to_string())
                .collect::<Vec<String>>()
        })
        .filter(|names| !names.iter().any(|n| n == "--help" || n == "--version"))
        .collect()
}

/// Every subcommand's every option appears in the README under one of its
/// spellings (followed by a space, a comma, a backtick or a bracket, so `--rays` does not
/// count for `--rays-only`).
#[test]
fn every_flag_is_in_the_readme() {
    let text = documentation();
    for sub in ["info", "render", "merge", "diff", "gen", "bench", "view"] {
        let options = options(sub);
        assert!(options.len() >= 2, "{sub}: {options:?}");
        for names in options {
            let documented = names.iter().any(|flag| {
                [' ', ',', '`', ']']
                    .iter()
                    .any(|end| text.contains(&format!("{flag}{end}")))
            });
            assert!(documented, "nffrt {sub} {names:?} is not in the README or docs/");
        }
    }
}

/// Every key `--stats-json` writes is named in the README or docs/.
#[test]
fn every_stats_key_is_in_the_readme() {
    let dir = common::scratch_dir("readme", "stats");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/showcase.nff");
    let png = dir.join("a.png");
    let args = [
        "render",
        scene,
        "--width",
        "8",
        "-q",
        "-o",
        png.to_str().unwrap(),
        "--stats-json",
        "-",
    ];
    let out = nffrt(&args, b"");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let text = documentation();
    for key in json.as_object().unwrap().keys() {
        assert!(
            text.contains(&format!("`{key}`")),
            "--stats-json key {key} is not in the README or docs/"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A number as the README writes it, with thin spaces between thousands: its first
/// run of digits and spaces.
fn leading_number(cell: &str) -> u64 {
    let digits: String = cell
        .trim()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == ' ')
        .filter(char::is_ascii_digit)
        .collect();
    digits.parse().unwrap_or_else(|_| panic!("no number in {cell:?}"))
}

/// The memory table's primitive counts are `nffrt info`'s: the file's (one per
/// polygon) and the BVH's (polygons cut into triangles). Rows of `nffrt gen` scenes
/// always run; rows of `../shared` scenes skip, saying so, without it.
#[test]
fn memory_table_counts_are_the_tools() {
    let text = documentation();
    let rows: Vec<Vec<&str>> = text
        .lines()
        .filter(|l| l.starts_with("| `p3d/") || l.starts_with("| `spd/") || l.starts_with("| `nffrt gen"))
        .map(|l| l.split('|').map(str::trim).collect())
        .collect();
    assert!(rows.len() >= 4, "memory table rows: {rows:?}");
    assert!(
        rows.iter().any(|r| r[1].starts_with("`nffrt gen")),
        "a generated row"
    );
    let mut shared_skipped = false;
    for row in rows {
        let (scene, in_file, in_bvh) = (row[1].trim_matches('`'), row[2], row[3]);
        let out = if let Some(args) = scene.strip_prefix("nffrt gen ") {
            let args: Vec<&str> = args.split(' ').collect();
            let gen = nffrt(&[&["gen"][..], &args].concat(), b"");
            nffrt(&["info", "--json", "--bvh", "-"], &gen.stdout)
        } else if shared_skipped {
            continue;
        } else {
            let Some(path) = common::skip::shared(&format!("scenes/{scene}")) else {
                shared_skipped = true;
                continue;
            };
            nffrt(&["info", "--json", "--bvh", path.to_str().unwrap()], b"")
        };
        let j = common::json_of(&out, scene);
        let file: u64 = ["spheres", "cones", "polygons", "patches", "planes", "boxes"]
            .iter()
            .map(|k| common::field(&j, k))
            .sum();
        let bvh = common::field(&j["bvh"], "primitives") + common::field(&j["bvh"], "unbounded");
        assert_eq!(leading_number(in_file), file, "{scene}: primitives in the file");
        assert_eq!(leading_number(in_bvh), bvh, "{scene}: primitives in the BVH");
    }
}

/// The quick start's first render is anti-aliased: the picture to see first.
#[test]
fn the_quick_start_renders_with_anti_aliasing() {
    let text = readme();
    let first = text
        .lines()
        .find(|l| l.contains(" render ") && l.starts_with("cargo run"))
        .expect("a render command in the quick start");
    assert!(first.contains("--spp 4"), "{first}");
}
