//! The SPD ray-count invariants (`../shared/SPD-INVARIANTS.md`): `nffrt render --spd`
//! on each of the seven classic scenes must land within 1% of both published eye-hit
//! counts and within 10% of at least one published value for every other count, and
//! its eye hits within 0.1% of the independent camera-convention table.
//!
//! The expected numbers below are the published tables, typed in from that document.

use std::path::PathBuf;
use std::process::Command;

#[path = "common/skip.rs"]
mod skip;

/// SPD README 3.14: eye hits, reflection, refraction, shadow rays.
const SPD: [(&str, [f64; 4]); 7] = [
    ("balls", [263169.0, 175095.0, 0.0, 954368.0]),
    ("gears", [245086.0, 304643.0, 207564.0, 2246955.0]),
    ("mount", [173125.0, 354769.0, 354769.0, 412922.0]),
    ("rings", [263169.0, 315236.0, 0.0, 1085002.0]),
    ("teapot", [161120.0, 225248.0, 0.0, 407656.0]),
    ("tetra", [49788.0, 0.0, 0.0, 46112.0]),
    ("tree", [169836.0, 0.0, 0.0, 1097419.0]),
];

/// Havran and Sixta 1999: eye hits, shadow rays, shadow blocked, secondary rays.
const HAVRAN: [(&str, [f64; 4]); 7] = [
    ("balls", [263169.0, 959244.0, 285178.0, 179884.0]),
    ("gears", [245332.0, 2088012.0, 1057557.0, 494338.0]),
    ("mount", [173685.0, 361037.0, 74555.0, 710436.0]),
    ("rings", [263169.0, 1077336.0, 510719.0, 312879.0]),
    ("teapot", [161546.0, 406340.0, 34757.0, 226235.0]),
    ("tetra", [49950.0, 46262.0, 5538.0, 0.0]),
    ("tree", [169907.0, 1110323.0, 47506.0, 0.0]),
];

/// Independent ray caster, `angle` between the centres of the outer pixel rows.
const CAMERA_TABLE: [(&str, f64); 4] = [
    ("tetra", 49797.0),
    ("gears", 245090.0),
    ("mount", 173132.0),
    ("teapot", 161035.0),
];

/// Scenes with transmitting (T > 0) materials.
const SCENES_WITH_GLASS: [&str; 2] = ["gears", "mount"];

fn shared_scene(name: &str) -> Option<PathBuf> {
    skip::shared(&format!("scenes/spd/{name}.nff"))
}

struct Counts {
    eye_hits: f64,
    reflection: f64,
    refraction: f64,
    shadow: f64,
    blocked: f64,
}

fn render_spd(scene: &PathBuf, name: &str) -> Counts {
    let tag: String = name.chars().filter(char::is_ascii_alphanumeric).collect();
    let dir = std::env::temp_dir().join(format!("nffrt-spd-test-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("stats.json");
    let out = Command::new(env!("CARGO_BIN_EXE_nffrt"))
        .args(["render", "--spd", "--stats-json"])
        .arg(&json)
        .arg("-o")
        .arg(dir.join("out.png"))
        .arg(scene)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let get = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{name}: no {k} in stats"));
    assert_eq!(get("eye_rays"), 513.0 * 513.0, "{name}: eye rays");
    Counts {
        eye_hits: get("eye_hits"),
        reflection: get("reflection_rays"),
        refraction: get("refraction_rays"),
        shadow: get("shadow_rays"),
        blocked: get("shadow_blocked"),
    }
}

fn within(got: f64, want: f64, rel: f64) -> bool {
    if want == 0.0 {
        got == 0.0
    } else {
        ((got - want) / want).abs() <= rel
    }
}

fn check(name: &str) {
    let Some(scene) = shared_scene(name) else { return };
    check_counts(name, &render_spd(&scene, name));
}

/// The same invariants on the scene `nffrt gen NAME` writes (no `../shared` needed).
fn check_generated(name: &str) {
    let dir = std::env::temp_dir().join(format!("nffrt-gen-spd-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join(format!("{name}.nff"));
    let out = Command::new(env!("CARGO_BIN_EXE_nffrt"))
        .args(["gen", name, "-o"])
        .arg(&scene)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "gen {name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let counts = render_spd(&scene, &format!("generated {name}"));
    std::fs::remove_dir_all(&dir).ok();
    check_counts(name, &counts);
}

fn check_counts(name: &str, c: &Counts) {
    let spd = SPD.iter().find(|(n, _)| *n == name).unwrap().1;
    let hav = HAVRAN.iter().find(|(n, _)| *n == name).unwrap().1;
    let report = format!(
        "{name}: eye hits {}, reflection {}, refraction {}, shadow {}, blocked {}",
        c.eye_hits, c.reflection, c.refraction, c.shadow, c.blocked
    );
    eprintln!("{report}");
    assert!(
        within(c.eye_hits, spd[0], 0.01) && within(c.eye_hits, hav[0], 0.01),
        "eye hits: {report}"
    );
    assert!(
        within(c.reflection, spd[1], 0.10),
        "reflection rays vs SPD {}: {report}",
        spd[1]
    );
    assert!(
        within(c.refraction, spd[2], 0.10),
        "refraction rays vs SPD {}: {report}",
        spd[2]
    );
    assert!(
        within(c.shadow, spd[3], 0.10) || within(c.shadow, hav[1], 0.10),
        "shadow rays vs {} / {}: {report}",
        spd[3],
        hav[1]
    );
    // Only Havran publishes blocked shadow rays, and his tracer evidently lets shadow
    // rays through transparent objects in a way his paper does not specify (our
    // shadow-ray totals match the SPD's on mount and gears, his differ by 13%). The
    // blocked count is asserted for the scenes without transparent materials.
    if !SCENES_WITH_GLASS.contains(&name) {
        assert!(
            within(c.blocked, hav[2], 0.10),
            "blocked shadow rays vs Havran {}: {report}",
            hav[2]
        );
    }
    let secondary = c.reflection + c.refraction;
    assert!(
        within(secondary, hav[3], 0.10) || within(secondary, spd[1] + spd[2], 0.10),
        "secondary rays vs Havran {} / SPD {}: {report}",
        hav[3],
        spd[1] + spd[2]
    );
    if let Some((_, want)) = CAMERA_TABLE.iter().find(|(n, _)| *n == name) {
        assert!(
            within(c.eye_hits, *want, 0.001),
            "eye hits vs camera table {want}: {report}"
        );
    }
}

#[test]
fn balls() {
    check("balls");
}
#[test]
fn gears() {
    check("gears");
}
#[test]
fn mount() {
    check("mount");
}
#[test]
fn rings() {
    check("rings");
}
#[test]
fn teapot() {
    check("teapot");
}
#[test]
fn tetra() {
    check("tetra");
}
#[test]
fn tree() {
    check("tree");
}
#[test]
fn generated_balls() {
    check_generated("balls");
}
#[test]
fn generated_gears() {
    check_generated("gears");
}
#[test]
fn generated_mount() {
    check_generated("mount");
}
#[test]
fn generated_rings() {
    check_generated("rings");
}
#[test]
fn generated_teapot() {
    check_generated("teapot");
}
#[test]
fn generated_tetra() {
    check_generated("tetra");
}
#[test]
fn generated_tree() {
    check_generated("tree");
}
