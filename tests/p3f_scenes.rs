//! The course's P3F scenes (`../shared/scenes/p3f/2019|2025`, both dialects, as
//! students receive them): `nffrt info --json` reports the counts an independent token
//! counter written here finds in each file, and every scene renders at its own
//! resolution and samples per pixel, skybox and all, without an error.

mod common;

use std::path::{Path, PathBuf};

use common::{field, info_json, json_of, nffrt, scratch_dir, tokens_without_comments};

/// The P3F scenes under `../shared/scenes/p3f/`, or `None` (after saying the test is
/// skipped) without it.
fn p3f_scenes() -> Option<Vec<PathBuf>> {
    let all = common::shared_p3f_scenes(&["2019", "2025"])?;
    assert!(all.len() >= 10, "only {} P3F scenes", all.len());
    Some(all)
}

/// What the independent counter finds in a P3F file.
#[derive(Debug, Default, PartialEq)]
struct Counts {
    spheres: u64,
    moving_spheres: u64,
    polygons: u64,
    patches: u64,
    cones: u64,
    planes: u64,
    boxes: u64,
    meshes: u64,
    mesh_triangles: u64,
    mesh_vertices: u64,
    lights: u64,
    area_lights: u64,
    width: u64,
    height: u64,
    spp: Option<u64>,
    dialect_2025: bool,
    /// An `aperture` above 0: a lens, an effect that needs samples.
    lens: bool,
}

/// Counts entities from keyword tokens alone (P3F-SPEC's tables): strip `#` comments,
/// split on whitespace, count the object keywords (`s p pp c pl npl box`; numbers
/// never spell a keyword, so operands need no skipping), read `mesh NV NT` (the mesh
/// data is all numbers), `resolution W H` and `spp N`; lights are `l`, `al` and
/// `light`, area lights `al` and `light quad`; a 2024/25 keyword (`camera light mat
/// spp accel`) marks that dialect. The course's meshes have no degenerate triangle,
/// so NT is also the triangle count the renderer keeps.
fn count_tokens(bytes: &[u8]) -> Counts {
    let text = String::from_utf8_lossy(bytes);
    let tokens = tokens_without_comments(&text);
    let whole = |i: usize| -> u64 {
        tokens[i]
            .parse()
            .unwrap_or_else(|_| panic!("token {i}: {:?}", tokens[i]))
    };
    let mut c = Counts {
        width: 512,
        height: 512,
        ..Counts::default()
    };
    for (i, tok) in tokens.iter().enumerate() {
        match *tok {
            "s" => c.spheres += 1,
            "sm" => c.moving_spheres += 1,
            "p" => c.polygons += 1,
            "pp" => c.patches += 1,
            "c" => c.cones += 1,
            "pl" | "npl" => c.planes += 1,
            "box" => c.boxes += 1,
            "mesh" => {
                c.meshes += 1;
                c.mesh_vertices += whole(i + 1);
                c.mesh_triangles += whole(i + 2);
            }
            "l" => c.lights += 1,
            "al" => {
                c.lights += 1;
                c.area_lights += 1;
            }
            "light" => {
                c.lights += 1;
                c.area_lights += u64::from(tokens[i + 1] == "quad");
            }
            "resolution" => (c.width, c.height) = (whole(i + 1), whole(i + 2)),
            "spp" => c.spp = Some(whole(i + 1)),
            "aperture" => c.lens = tokens[i + 1].parse::<f64>().is_ok_and(|a| a > 0.0),
            _ => {}
        }
        if ["camera", "light", "mat", "spp", "accel"].contains(tok) {
            c.dialect_2025 = true;
        }
    }
    c
}

/// The same fields from `nffrt info --json`.
fn reported(json: &serde_json::Value) -> Counts {
    Counts {
        spheres: field(json, "spheres"),
        moving_spheres: field(json, "moving_spheres"),
        polygons: field(json, "polygons"),
        patches: field(json, "patches"),
        cones: field(json, "cones"),
        planes: field(json, "planes"),
        boxes: field(json, "boxes"),
        meshes: field(json, "meshes"),
        mesh_triangles: field(json, "mesh_triangles"),
        mesh_vertices: field(json, "mesh_vertices"),
        lights: field(json, "lights"),
        area_lights: field(json, "area_lights"),
        width: field(json, "width"),
        height: field(json, "height"),
        spp: json.get("spp").and_then(|v| v.as_u64()),
        dialect_2025: json["dialect"] == "p3f-2025",
        lens: json["aperture"].as_f64().is_some_and(|a| a > 0.0),
    }
}

fn label(path: &Path) -> String {
    let year = path.parent().and_then(|p| p.file_name()).unwrap_or_default();
    format!(
        "{}/{}",
        year.to_string_lossy(),
        path.file_name().unwrap_or_default().to_string_lossy()
    )
}

#[test]
fn the_counter_reads_both_dialects() {
    let src = "spp 4\ncamera eye 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 80 60\n\
               light punctual 0 0 5 1 1 1\nlight quad 0 0 5 1 1 1 1 0 5 0 1 5 4\n\
               mat 1 1 1 1 1 1 1 0 10 0 1\nmesh 3 1\n0 0 0\n1 0 0\n0 1 0\n1 2 3\n\
               s 0 0 0 1 # s p c in a comment\nbox 0 0 0 1 1 1\nnpl 0 1 0 2\n";
    let want = Counts {
        spheres: 1,
        planes: 1,
        boxes: 1,
        meshes: 1,
        mesh_triangles: 1,
        mesh_vertices: 3,
        lights: 2,
        area_lights: 1,
        width: 80,
        height: 60,
        spp: Some(4),
        dialect_2025: true,
        ..Counts::default()
    };
    assert_eq!(count_tokens(src.as_bytes()), want);
}

#[test]
fn info_json_matches_an_independent_token_count_for_every_course_scene() {
    let Some(scenes) = p3f_scenes() else {
        return;
    };
    for path in &scenes {
        let what = label(path);
        let want = count_tokens(&std::fs::read(path).unwrap());
        let json = json_of(&info_json(path), &what);
        assert_eq!(reported(&json), want, "{what}");
        let dialect = json["dialect"].as_str().unwrap_or_default().to_string();
        assert!(dialect.starts_with("p3f-"), "{what}: {dialect}");
    }
}

/// The course's moving-sphere scene (`extensions/ball_motion.p3f`, a 2019/20 file
/// with `sm`) parses, its sphere's nine numbers as the file writes them. (`nffrt`
/// itself refuses to render it: the `skybox` folder it names is not shipped with it.)
#[test]
fn the_course_moving_sphere_scene_parses_with_its_numbers() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/p3f/extensions/ball_motion.p3f");
    if !path.is_file() {
        eprintln!("skipped: {} is absent", path.display());
        return;
    }
    let bytes = std::fs::read(&path).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let tokens = tokens_without_comments(&text);
    let at = tokens.iter().position(|t| *t == "sm").expect("an sm in the file");
    let n: Vec<f32> = tokens[at + 1..at + 10]
        .iter()
        .map(|t| t.parse().unwrap())
        .collect();
    let scene = nffrt::nff::parse_format(&bytes, nffrt::nff::Format::P3f, &Default::default()).unwrap();
    assert_eq!(count_tokens(&bytes).moving_spheres, 1);
    assert_eq!(scene.moving_spheres.len(), 1);
    let m = scene.moving_spheres[0];
    assert_eq!(m.center0.to_array(), [n[0], n[1], n[2]]);
    assert_eq!(m.center1.to_array(), [n[3], n[4], n[5]]);
    assert_eq!([m.radius, m.time0, m.time1], [n[6], n[7], n[8]]);
    assert_eq!(scene.dialect, nffrt::scene::Dialect::P3f2019);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

/// Width and height from a PNG's IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    let be = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn every_course_scene_renders_at_its_resolution_and_samples() {
    let Some(scenes) = p3f_scenes() else {
        return;
    };
    let dir = scratch_dir("p3f_scenes", "render");
    for path in &scenes {
        let what = label(path);
        let want = count_tokens(&std::fs::read(path).unwrap());
        let out = dir.join(format!("{}.png", what.replace('/', "-")));
        let shown = path.to_str().unwrap();
        let run = nffrt(
            &[
                "render",
                shown,
                "-q",
                "-o",
                out.to_str().unwrap(),
                "--stats-json",
                "-",
            ],
            b"",
        );
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(0), "{what}: {stderr}");
        let stats = json_of(&run, &what);
        let png = std::fs::read(&out).unwrap();
        assert_eq!(png_size(&png), (want.width as u32, want.height as u32), "{what}");
        // The file's spp: 0 (or 1) is one sample at each pixel centre; without one,
        // a lens takes 16 samples (docs/p3f.md), anything else one.
        let spp = match (want.spp, want.lens) {
            (Some(n), _) => n.max(1),
            (None, true) => 16,
            (None, false) => 1,
        };
        assert_eq!(field(&stats, "samples_per_pixel"), spp, "{what}");
        assert_eq!(
            field(&stats, "eye_rays"),
            spp * want.width * want.height,
            "{what}"
        );
        // Something was hit, and a scene with an `env` saw its skybox.
        assert!(field(&stats, "eye_hits") > 0, "{what}");
        let has_env = std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .any(|l| l.starts_with("env "));
        assert_eq!(stats["skybox"].as_bool(), Some(has_env), "{what}");
    }
}
