//! `nffrt gen` as a user runs it: standard output, `-o FILE`, refused sizes and names.

mod common;

use std::path::PathBuf;
use std::process::Output;

fn nffrt(args: &[&str]) -> Output {
    common::nffrt(args, b"")
}

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("gen_cli", name)
}

#[test]
fn writes_nff_to_standard_output() {
    let out = nffrt(&["gen", "tetra", "--size", "2"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let scene = nffrt::nff::parse_bytes(&out.stdout).unwrap();
    assert_eq!(scene.polygons.len(), 16);
    assert!(out
        .stdout
        .starts_with(b"b 0.078 0.361 0.753\nv\nfrom 1.02285 -3.17715 -2.17451\n"));
}

#[test]
fn default_size_is_the_spds() {
    let out = nffrt(&["gen", "balls"]);
    assert!(out.status.success());
    assert_eq!(nffrt::nff::parse_bytes(&out.stdout).unwrap().spheres.len(), 7381);
}

#[test]
fn output_file_is_complete_and_leaves_no_temporary_behind() {
    let dir = scratch("file");
    let dest = dir.join("rings.nff");
    std::fs::write(&dest, "old contents").unwrap();
    let out = nffrt(&["gen", "rings", "-s", "2", "-o", dest.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stdout.is_empty());
    let written = std::fs::read(&dest).unwrap();
    assert_eq!(written, nffrt(&["gen", "rings", "--size", "2"]).stdout);
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["rings.nff"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unwritable_destination_fails_with_the_io_code_and_no_file() {
    let dir = scratch("bad");
    let dest = dir.join("missing").join("x.nff");
    let out = nffrt(&["gen", "tree", "-s", "1", "-o", dest.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(4));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot write"));
    let out = nffrt(&["gen", "tree", "-s", "1", "-o", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(4));
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn absurd_sizes_are_refused_with_the_limit() {
    let out = nffrt(&["gen", "balls", "--size", "8"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("from 1 to 7") && err.contains("over the limit of 10000000"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
    assert_eq!(nffrt(&["gen", "mount", "--size", "0"]).status.code(), Some(2));
}

#[test]
fn unknown_scene_names_list_the_real_ones() {
    let out = nffrt(&["gen", "teapots"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("balls, gears, mount, rings, teapot, tetra, tree"));
}

#[test]
fn help_states_defaults_and_limits() {
    let out = nffrt(&["gen", "--help"]);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(help.contains("10000000 primitives"), "{help}");
    let balls = help
        .lines()
        .find(|l| l.trim_start().starts_with("balls"))
        .expect("a balls row");
    assert!(
        balls.contains("default  4") && balls.contains("at most   7"),
        "{balls}"
    );
}
