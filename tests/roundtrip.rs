//! Writing a parsed scene with `write_scene` (NFF or P3F, its own language) and parsing
//! the text again gives the same scene (up to source lines, warnings, material
//! numbering and the P3F dialect; see `common::compare`).

mod common;

use std::path::Path;

use common::compare::same_scene;
use common::{data_dir, name, nff_files, shared_scenes};
use nffrt::nff::{parse_format, write_scene, Format};

/// Parses `path`, writes it, parses the output; describes the first difference.
fn round_trip(path: &Path) -> Result<(), String> {
    let file = name(path);
    let bytes = std::fs::read(path).map_err(|e| format!("{file}: {e}"))?;
    let format = Format::of_path(path);
    let first = parse_format(&bytes, format, &Default::default()).map_err(|e| format!("{file}: {e}"))?;
    let mut text = Vec::new();
    write_scene(&first, &mut text).map_err(|e| format!("{file}: writing: {e}"))?;
    let second = parse_format(&text, format, &Default::default())
        .map_err(|e| format!("{file}: written text does not parse: {e}"))?;
    // The writer spells out the camera and a material before each object, and skipped
    // geometry is gone: the written text may repeat a warning (a tolerated cone, say) but
    // must not earn a new one.
    let before: Vec<&str> = first.warnings.iter().map(|w| w.message.as_str()).collect();
    if let Some(w) = second
        .warnings
        .iter()
        .find(|w| !before.contains(&w.message.as_str()))
    {
        return Err(format!("{file}: written text earns a new warning: {w}"));
    }
    same_scene(&first, &second).map_err(|d| format!("{file}: {d}"))
}

#[test]
fn shared_scenes_survive_a_write_and_reparse() {
    let Some(scenes) = shared_scenes() else {
        return;
    };
    let failures: Vec<String> = scenes.iter().filter_map(|p| round_trip(p).err()).collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn odd_but_valid_inputs_survive_a_write_and_reparse() {
    let files = nff_files(&data_dir("ok"));
    assert!(!files.is_empty());
    let failures: Vec<String> = files.iter().filter_map(|p| round_trip(p).err()).collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_comparison_sees_a_changed_value() {
    // The helper must be able to fail: nudge one coordinate, one material, one line.
    let src =
        "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40\nf 1 0 0 1 0 1 0 1\ns 0 0 0 1\np 3 0 0 0 1 0 0 0 1 0\n";
    let a = nffrt::nff::parse(src).expect("valid");
    let moved = nffrt::nff::parse(&src.replace("s 0 0 0 1", "s 0 0 0.5 1")).expect("valid");
    assert!(same_scene(&a, &moved).unwrap_err().starts_with("spheres[0]"));
    let recoloured = nffrt::nff::parse(&src.replace("f 1 0 0", "f 0 0 1")).expect("valid");
    assert!(same_scene(&a, &recoloured)
        .unwrap_err()
        .starts_with("materials[0]"));
    let vertex = nffrt::nff::parse(&src.replace("0 1 0\n", "0 2 0\n")).expect("valid");
    assert!(same_scene(&a, &vertex)
        .unwrap_err()
        .starts_with("polygon_vertices[2]"));
    // ...while source lines, warnings and table numbering do not count.
    let shifted =
        nffrt::nff::parse(&format!("# a comment\nb 0 0 0\n{}", src.replace('\n', "\n\n"))).expect("valid");
    assert_eq!(same_scene(&a, &shifted), Ok(()));
    assert_ne!(a.spheres[0].line, shifted.spheres[0].line);
}
