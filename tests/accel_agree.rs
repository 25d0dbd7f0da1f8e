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
