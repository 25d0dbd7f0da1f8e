//! Odd but valid inputs parse, with the counts and warnings their headers promise.
//!
//! The corpus lives in `tests/data/ok/`. Each file's leading comment carries
//! `# expect: KEY=N ...` (keys of `nffrt info --json`; a primitive count or `lights` not
//! listed must be 0, other keys are checked when listed) and one `# warning: LINE:COL TEXT`
//! per warning the parser must give, in order. No other warning is allowed.

mod common;

use std::path::Path;

use common::compare::same_scene;
use common::{data_dir, field, header_values, info_json, json_of, name, nff_files, nffrt, warnings};
use nffrt::math::Vec3;
use nffrt::scene::Material;
use nffrt::Scene;

/// Counts that must be 0 unless the header says otherwise.
const ZERO_BY_DEFAULT: [&str; 13] = [
    "spheres",
    "moving_spheres",
    "emissive_materials",
    "rough_materials",
    "polygons",
    "patches",
    "cones",
    "planes",
    "boxes",
    "lights",
    "area_lights",
    "meshes",
    "mesh_triangles",
];

fn check(path: &Path) -> Result<(), String> {
    let file = name(path);
    let bytes = std::fs::read(path).map_err(|e| format!("{file}: {e}"))?;
    let expects = header_values(&bytes, "expect");
    let [expect] = expects.as_slice() else {
        return Err(format!("{file}: needs exactly one '# expect:' header line"));
    };
    let json = json_of(&info_json(path), &file);
    let mut problems = Vec::new();
    let mut listed = Vec::new();
    for pair in expect.split_whitespace() {
        let Some((key, want)) = pair.split_once('=') else {
            return Err(format!("{file}: bad expect item {pair:?}"));
        };
        let want: u64 = want
            .parse()
            .map_err(|_| format!("{file}: bad number in {pair:?}"))?;
        if json.get(key).is_none() {
            return Err(format!("{file}: info --json has no {key:?}"));
        }
        listed.push(key);
        if field(&json, key) != want {
            problems.push(format!("{key} = {}, expected {want}", field(&json, key)));
        }
    }
    for key in ZERO_BY_DEFAULT.iter().filter(|k| !listed.contains(k)) {
        if field(&json, key) != 0 {
            problems.push(format!("{key} = {}, expected 0 (not listed)", field(&json, key)));
        }
    }
    let got = warnings(&json);
    let want = header_values(&bytes, "warning");
    if got.len() != want.len() {
        problems.push(format!(
            "{} warnings, expected {}: {got:?}",
            got.len(),
            want.len()
        ));
    } else {
        for (g, w) in got.iter().zip(&want) {
            // `LINE:COL TEXT` in the header, `LINE:COL: message` from the parser.
            let (pos, text) = w.split_once(' ').unwrap_or((w, ""));
            if !(g.starts_with(&format!("{pos}: ")) && g.contains(text)) {
                problems.push(format!("warning {g:?} does not match {w:?}"));
            }
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!("{file}: {}", problems.join("; ")))
    }
}

#[test]
fn every_odd_but_valid_input_parses_with_its_expected_counts_and_warnings() {
    let files = nff_files(&data_dir("ok"));
    assert!(files.len() >= 20, "the ok corpus shrank to {} files", files.len());
    let failures: Vec<String> = files.iter().filter_map(|p| check(p).err()).collect();
    assert!(
        failures.is_empty(),
        "{} of {} valid inputs misparsed:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
}

/// Parses a file of the ok corpus with the library.
fn parse_ok(file: &str) -> Scene {
    let bytes = std::fs::read(data_dir("ok").join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    nffrt::nff::parse_bytes(&bytes).unwrap_or_else(|e| panic!("{file}: {e}"))
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

#[test]
fn number_spellings_give_the_values_they_spell() {
    let s = parse_ok("number_forms.nff");
    assert_eq!(
        (s.view.from, s.view.up, s.view.angle, s.view.hither),
        (v(0.0, 0.0, 5.0), v(0.0, 1.0, 0.0), 40.0, 0.01)
    );
    assert_eq!(s.lights[0].position, v(-0.5, 1.5, 10.0));
    assert_eq!(s.materials[0].color, v(1.0, 0.5, 0.25));
    assert_eq!(
        (s.spheres[0].center, s.spheres[0].radius),
        (v(0.5, -0.5, 1e-3), 0.25)
    );
    assert_eq!(
        (s.spheres[1].center, s.spheres[1].radius),
        (v(0.0, 0.0, 1e-30), 2.5)
    );
    assert_eq!(s.polygons[0].count, 3);
}

#[test]
fn comments_hide_what_they_cover_and_end_glued_tokens() {
    let s = parse_ok("comments_everywhere.nff");
    assert_eq!(s.view.at, Vec3::ZERO, "the commented-out 'at 9 9 9' was read");
    assert_eq!(s.lights[0].position, v(1.0, 2.0, 3.0));
    assert_eq!(s.spheres[1].center, v(1.0, 0.0, 0.0));
    assert_eq!(s.spheres.iter().map(|x| x.line).collect::<Vec<_>>(), vec![13, 15]);
    let polygon = s.polygon_points(&s.polygons[0]).to_vec();
    assert_eq!(polygon, vec![Vec3::ZERO, v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)]);
}

#[test]
fn objects_before_any_f_use_the_default_material_with_one_warning() {
    let s = parse_ok("objects_before_f.nff");
    let used: Vec<Material> = s
        .spheres
        .iter()
        .map(|x| s.materials[x.material as usize])
        .collect();
    assert_eq!(used[0], Material::DEFAULT);
    assert_eq!(used[1], Material::DEFAULT);
    assert_eq!(used[2].color, v(1.0, 0.0, 0.0));
    // The human report prints the warning with the file and line of the first such object.
    let path = data_dir("ok").join("objects_before_f.nff");
    let out = nffrt(&["info", path.to_str().expect("UTF-8 path")], b"");
    assert_eq!(out.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let want = format!(
        "{}:7:1: warning: object before any 'f': using the default material",
        path.display()
    );
    assert!(stderr.contains(&want), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
}

#[test]
fn zero_radius_sphere_and_collinear_polygon_are_skipped_with_their_line() {
    let path = data_dir("ok").join("degenerate_skipped.nff");
    let out = nffrt(&["info", path.to_str().expect("UTF-8 path")], b"");
    assert_eq!(out.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&out.stderr);
    for want in [
        format!("{}:12:1: warning: sphere of radius 0 skipped", path.display()),
        format!(
            "{}:13:1: warning: polygon with no area (collinear or coincident vertices) skipped",
            path.display()
        ),
    ] {
        assert!(stderr.contains(&want), "missing {want:?} in {stderr}");
    }
    assert!(!stderr.contains("panicked"));
    // Nothing of the skipped geometry is left behind in the shared vertex lists.
    let s = parse_ok("degenerate_skipped.nff");
    assert_eq!(
        (
            s.polygon_vertices.len(),
            s.patch_vertices.len(),
            s.patch_normals.len()
        ),
        (3, 3, 3)
    );
    assert_eq!(s.spheres[0].radius, 1.0);
    assert_eq!(s.spheres[0].line, 19);
}

#[test]
fn lights_take_a_colour_only_when_one_follows() {
    let s = parse_ok("light_colour.nff");
    let colours: Vec<Option<Vec3>> = s.lights.iter().map(|l| l.color).collect();
    let half = Some(Vec3::splat(0.5));
    assert_eq!(colours, vec![None, half, None, Some(v(1.0, 0.0, 0.0)), half]);
    assert_eq!(s.lights[3].position, v(7.0, 8.0, 9.0));
}

#[test]
fn view_sub_keywords_may_come_in_any_order() {
    let s = parse_ok("view_reordered.nff");
    let view = s.view;
    assert_eq!(
        (view.from, view.at, view.up),
        (v(0.0, 0.0, 5.0), Vec3::ZERO, v(0.0, 1.0, 0.0))
    );
    assert_eq!((view.angle, view.width, view.height), (60.0, 100, 50));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn cones_read_the_same_whatever_their_line_breaks() {
    let s = parse_ok("cone_layouts.nff");
    let c = &s.cones;
    assert_eq!(
        (c[0].base, c[0].base_radius, c[0].apex, c[0].apex_radius),
        (Vec3::ZERO, 1.0, v(0.0, 1.0, 0.0), 0.5)
    );
    assert_eq!(
        (c[2].base, c[2].base_radius, c[2].apex, c[2].apex_radius),
        (v(2.0, 0.0, 0.0), 1.0, v(2.0, 1.0, 0.0), 1.0)
    );
    assert_eq!(c.iter().map(|x| x.line).collect::<Vec<_>>(), vec![5, 8, 9]);
}

#[test]
fn line_breaks_crlf_and_tabs_carry_no_meaning() {
    // The same scene laid out one token a line, and all on one line, in every whitespace.
    let spread = parse_ok("one_token_per_line.nff");
    let text = std::fs::read_to_string(data_dir("ok").join("one_token_per_line.nff")).expect("corpus file");
    let tokens: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .flat_map(str::split_whitespace)
        .collect();
    for sep in [" ", "\t", "\r\n", " \x0b\x0c "] {
        let flat = nffrt::nff::parse(&tokens.join(sep)).expect("valid");
        if let Err(d) = same_scene(&spread, &flat) {
            panic!("separator {sep:?}: {d}");
        }
    }
    // CRLF throughout gives what LF gives, lines included.
    let crlf = std::fs::read(data_dir("ok").join("crlf.nff")).expect("corpus file");
    let lf: Vec<u8> = crlf.iter().copied().filter(|&b| b != b'\r').collect();
    assert_ne!(crlf, lf);
    assert_eq!(
        nffrt::nff::parse_bytes(&crlf).expect("valid"),
        nffrt::nff::parse_bytes(&lf).expect("valid")
    );
}

#[test]
fn a_144_vertex_concave_polygon_keeps_every_vertex() {
    let s = parse_ok("gear_144.nff");
    assert_eq!(s.polygons[0].count, 144);
    let pts = s.polygon_points(&s.polygons[0]);
    assert_eq!(pts.len(), 144);
    assert_eq!(pts[0], v(0.8, 0.0, 0.0));
    assert_eq!(pts[143].z, 0.0);
}

#[test]
fn boxes_with_swapped_limits_are_put_in_order() {
    let s = parse_ok("plane_and_box.nff");
    assert_eq!(
        (s.boxes[0].min, s.boxes[0].max),
        (v(-1.0, -2.0, -3.0), v(1.0, 2.0, 3.0))
    );
    assert_eq!(
        (s.boxes[1].min, s.boxes[1].max),
        (v(-1.0, 0.0, 0.0), v(1.0, 1.0, 1.0))
    );
    assert_eq!(
        s.planes[0].points,
        [Vec3::ZERO, v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)]
    );
}

#[test]
fn identical_consecutive_materials_share_a_table_entry() {
    let s = parse_ok("material_merge.nff");
    let indices: Vec<u32> = s.spheres.iter().map(|x| x.material).collect();
    assert_eq!(indices, vec![0, 0, 1, 2]);
    assert_eq!(s.materials[0], s.materials[2]);
}

#[test]
fn tiny_and_huge_geometry_is_not_mistaken_for_degenerate() {
    let s = parse_ok("extreme_scales.nff");
    assert_eq!((s.spheres.len(), s.polygons.len()), (2, 2));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn empty_and_blank_inputs_are_errors_not_black_pictures() {
    // (line, column) of the end of each input, where the error points.
    for (src, end) in [
        (&b""[..], (1, 1)),
        (b"\n", (2, 1)),
        (b"   \r\n\t\n", (3, 1)),
        (b"#", (1, 2)),
    ] {
        for command in ["info", "render"] {
            let out = nffrt(
                &[command, "-", "-o", "-"][..if command == "info" { 2 } else { 4 }],
                src,
            );
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(3), "{command} {src:?}: {stderr}");
            let want = format!("nffrt: error: <stdin>:{}:{}: empty scene", end.0, end.1);
            assert!(stderr.starts_with(&want), "{command} {src:?}: {stderr}");
            assert!(out.stdout.is_empty(), "{command} {src:?}: no image");
        }
    }
}
