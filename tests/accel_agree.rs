//! `--accel none`, `grid` and `bvh` give the same picture byte for byte on every
//! course scene under `../shared/scenes/p3f/` (2019 and 2025, skyboxes and all, and
//! the motion-blur extension), and `--stats` reports the structure used. Each renders
//! small, at 4 samples per pixel (lenses, area lights and motion sampled); scenes of
//! more than [`BIG`] primitives render at 32x24 with 1 sample, so that `none`, which
//! tests every primitive for every ray, takes seconds rather than minutes on them.

mod common;

use std::path::PathBuf;

use common::{json_of, nffrt, scratch_dir};

/// Primitives above which a scene renders at the smallest size.
const BIG: u64 = 20_000;

fn p3f_scenes() -> Option<Vec<PathBuf>> {
    let all = common::shared_p3f_scenes(&["2019", "2025", "extensions"])?;
    assert!(all.len() >= 15, "only {} P3F scenes", all.len());
    Some(all)
}

#[test]
fn none_grid_and_bvh_render_every_course_scene_identically() {
    let Some(scenes) = p3f_scenes() else { return };
    let dir = scratch_dir(file!(), "agree");
    for scene in &scenes {
        let name = scene.file_stem().unwrap().to_string_lossy().to_string();
        let parent = scene
            .parent()
            .unwrap()
            .file_name()
            .unwrap()
            .to_string_lossy()
            .to_string();
        let text = std::fs::read_to_string(scene).unwrap();
        // The extension names a skybox folder the course did not ship: its `env` line
        // is left out.
        let (source, stdin): (&str, Vec<u8>) = if parent == "extensions" {
            let kept: Vec<&str> = text
                .lines()
                .filter(|l| !l.trim_start().starts_with("env "))
                .collect();
            ("-", kept.join("\n").into_bytes())
        } else {
            (scene.to_str().unwrap(), Vec::new())
        };
        let info = json_of(
            &nffrt(&["info", "--json", "--format", "p3f", source], &stdin),
            "info",
        );
        let primitives: u64 = [
            "spheres",
            "moving_spheres",
            "polygons",
            "patches",
            "cones",
            "planes",
            "boxes",
            "mesh_triangles",
        ]
        .iter()
        .map(|k| {
            info[k]
                .as_u64()
                .unwrap_or_else(|| panic!("{parent}/{name}: info has no {k}"))
        })
        .sum();
        let big = primitives > BIG;
        let size: [&str; 6] = if big {
            ["--width", "32", "--height", "24", "--spp", "1"]
        } else {
            ["--width", "96", "--height", "72", "--spp", "4"]
        };
        let mut pictures = Vec::new();
        for accel in ["bvh", "grid", "none"] {
            let out = dir.join(format!("{parent}-{name}-{accel}.png"));
            let mut args = vec!["render", "--format", "p3f", source, "--accel", accel];
            args.extend(["-o", out.to_str().unwrap(), "--stats-json", "-", "-q"]);
            args.extend(size);
            let run = nffrt(&args, &stdin);
            let stats = json_of(&run, &format!("{parent}/{name} --accel {accel}"));
            assert_eq!(stats["accel"]["accel"], accel, "{parent}/{name}");
            pictures.push(std::fs::read(&out).unwrap());
        }
        assert!(
            pictures[1] == pictures[0],
            "{parent}/{name}: grid differs from bvh"
        );
        assert!(
            pictures[2] == pictures[0],
            "{parent}/{name}: none differs from bvh"
        );
    }
}

/// A path-traced scene (an emissive sphere and a quad, rough metal, glass and a
/// triangle fan) gives the same bytes with each structure: paths, light samples and
/// the emitters' order do not depend on it.
#[test]
fn path_tracing_is_the_same_with_each_structure() {
    const SCENE: &str = "integrator path\nspp 4\nbclr 0.1 0.1 0.15\n\
        camera\neye 0 1.5 6\nat 0 0.5 0\nup 0 1 0\nangle 40\nhither 0.1\nresolution 48 36\naperture 0\nfocal 1\n\
        mat 1 1 1 0 0 0 0 0 1 0 1 4 4 3.5\ns 0 3 0 0.6\n\
        mat 0.8 0.8 0.8 1 0 0 0 0 1 0 1\np 4 -4 0 -4 4 0 -4 4 0 4 -4 0 4\n\
        mat 0.9 0.6 0.3 0 0.9 0.6 0.3 1 1 0 1 roughness 0.3\ns -1 0.7 0 0.7\n\
        mat 1 1 1 0 1 1 1 0 1 1 1.5\ns 1 0.7 0.5 0.7\n\
        mat 0.2 0.8 0.3 1 0 0 0 0 1 0 1\np 3 -2 0 -1 -1 1.5 -1 -2.5 0 -2\n";
    let dir = scratch_dir(file!(), "path");
    let mut pictures = Vec::new();
    for accel in ["bvh", "grid", "none"] {
        let out = dir.join(format!("path-{accel}.png"));
        let args = [
            "render",
            "--format",
            "p3f",
            "-",
            "--accel",
            accel,
            "-q",
            "-o",
            out.to_str().unwrap(),
        ];
        let run = nffrt(&args, SCENE.as_bytes());
        assert!(
            run.status.success(),
            "{accel}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        pictures.push(std::fs::read(&out).unwrap());
    }
    assert!(pictures[1] == pictures[0], "grid differs from bvh");
    assert!(pictures[2] == pictures[0], "none differs from bvh");
}
