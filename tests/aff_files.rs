//! AFF scenes of several files, written here: includes found from the including
//! file, a mesh read again through a second include stored once, textures found
//! and checked, and every refusal located at its file and line — a missing include,
//! a cycle, nesting past the limit, an error inside an included file, a missing or
//! broken texture.

mod common;

use std::path::{Path, PathBuf};

use common::scratch_dir;
use nffrt::load::{load, LoadError, LoadOptions, Loaded, Source};

const HEAD: &str = "v from 0 0 10 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\nf 1 1 1 1 0 1 0 1\n";

/// Writes `files` (relative path, text) into a fresh folder; returns the first's path.
fn write(test: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = scratch_dir("aff_files", test);
    for (name, text) in files {
        let path = dir.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
    }
    dir.join(files[0].0)
}

fn load_path(path: &Path) -> Result<Loaded, LoadError> {
    load(Source::File(path), &LoadOptions::default())
}

/// The parse error of loading `path`: the file it names, its line and its message.
fn refusal(path: &Path) -> (String, u32, String) {
    match load_path(path) {
        Err(LoadError::Parse { name, error }) => (name, error.line, error.kind.to_string()),
        Err(e) => panic!("not a parse error: {e}"),
        Ok(_) => panic!("{} loaded", path.display()),
    }
}

/// `dir/relative` as the loader names it in messages.
fn shown(top: &Path, relative: &str) -> String {
    top.parent().unwrap().join(relative).display().to_string()
}

#[test]
fn includes_are_found_from_the_including_file_and_a_mesh_read_twice_is_stored_once() {
    let top = write(
        "twice",
        &[
            (
                "main.aff",
                &format!(
                    "{HEAD}xs 1 1 1 0 0 1 0 0 0 0 {{ i 0 parts/part.aff }}\nxs 1 1 1 0 0 1 0 5 0 0 {{ i 0 parts/part.aff }}\n"
                ),
            ),
            ("parts/part.aff", "i 0 mesh.aff\n"),
            ("parts/mesh.aff", "m vertices 3 0 0 0 1 0 0 0 1 0 triangles 1 0 1 2\n"),
        ],
    );
    let loaded = load_path(&top).unwrap();
    let aff = loaded.aff.as_ref().unwrap();
    assert_eq!(
        (
            aff.objects.len(),
            aff.meshes.geometries.len(),
            aff.inclusions,
            aff.files.len()
        ),
        (2, 1, 4, 3)
    );
    let s = aff.summary();
    assert_eq!((s.instanced_triangles, s.flattened_triangles), (1, 2));
    // The frame holds both, the second 5 along x.
    let frame = &loaded.scene;
    assert_eq!(frame.mesh_triangles.len(), 2);
    assert_eq!(frame.mesh_vertices[3].x, 5.0);
}

#[test]
fn the_primitive_limit_counts_a_mesh_each_time_it_is_placed() {
    // Two triangles stored once, placed three times: six in a frame.
    let top = write(
        "placed",
        &[
            (
                "main.aff",
                &format!("{HEAD}i 0 quad.aff\ni 0 quad.aff\ni 0 quad.aff\n"),
            ),
            (
                "quad.aff",
                "m vertices 4 0 0 0 1 0 0 1 1 0 0 1 0 triangles 2 0 1 2 0 2 3\n",
            ),
        ],
    );
    let with = |max_primitives| LoadOptions {
        limits: nffrt::nff::Limits {
            max_primitives,
            ..Default::default()
        },
        ..LoadOptions::default()
    };
    assert!(load(Source::File(&top), &with(6)).is_ok());
    match load(Source::File(&top), &with(5)) {
        Err(LoadError::Parse { name, error }) => {
            assert_eq!((name.as_str(), error.line), (shown(&top, "quad.aff").as_str(), 1));
            assert!(
                error.kind.to_string().contains("more than 5 primitives"),
                "{}",
                error.kind
            );
        }
        other => panic!("{:?}", other.map(|l| l.name)),
    }
    // The bytes parsed count a file each time it is included: room for two quads.
    let size = |name: &str| std::fs::metadata(top.parent().unwrap().join(name)).unwrap().len();
    let opts = LoadOptions {
        max_bytes: size("main.aff") + 2 * size("quad.aff"),
        ..LoadOptions::default()
    };
    match load(Source::File(&top), &opts) {
        Err(LoadError::Parse { name, error }) => {
            assert_eq!((name, error.line), (top.display().to_string(), 5));
            assert!(
                error
                    .kind
                    .to_string()
                    .contains("each file counted as often as it is included"),
                "{}",
                error.kind
            );
        }
        other => panic!("{:?}", other.map(|l| l.name)),
    }
}

#[test]
fn a_missing_include_is_refused_at_the_include() {
    let top = write(
        "missing",
        &[("main.aff", &format!("{HEAD}s 0 0 0 1\ni 0 nothere.aff\n"))],
    );
    let (file, line, message) = refusal(&top);
    assert_eq!((file, line), (top.display().to_string(), 4));
    assert!(
        message.contains("cannot include nothere.aff: no such file or directory"),
        "{message}"
    );
    // Above the detail level (d), it is skipped, not read.
    let top = write("detail", &[("main.aff", &format!("{HEAD}i 1 nothere.aff\n"))]);
    assert_eq!(load_path(&top).unwrap().aff.unwrap().skipped_inclusions, 1);
}

#[test]
fn an_error_in_an_included_file_names_that_file() {
    let top = write(
        "nested_error",
        &[
            ("main.aff", &format!("{HEAD}i 0 sub/a.aff\n")),
            ("sub/a.aff", "s 0 0 0 1\n  zz\n"),
        ],
    );
    let (file, line, message) = refusal(&top);
    assert_eq!((file.as_str(), line), (shown(&top, "sub/a.aff").as_str(), 2));
    assert!(message.contains("unknown keyword \"zz\""), "{message}");
}

#[test]
fn an_include_cycle_is_refused_where_it_closes() {
    let top = write(
        "cycle",
        &[
            ("a.aff", &format!("{HEAD}i 0 b.aff\n")),
            ("b.aff", "s 0 0 0 1\n\ni 0 a.aff\n"),
        ],
    );
    let (file, line, message) = refusal(&top);
    assert_eq!((file.as_str(), line), (shown(&top, "b.aff").as_str(), 3));
    assert!(message.contains("include cycle"), "{message}");
}

#[test]
fn includes_nested_past_the_limit_are_refused() {
    // f0 includes f1, which includes f2, ...: the 32nd file open may not include.
    let depth = nffrt::limits::MAX_INCLUDE_DEPTH;
    let texts: Vec<(String, String)> = (0..depth + 5)
        .map(|i| {
            let head = if i == 0 { HEAD } else { "" };
            (format!("f{i}.aff"), format!("{head}i 0 f{}.aff\n", i + 1))
        })
        .collect();
    let files: Vec<(&str, &str)> = texts.iter().map(|(n, t)| (n.as_str(), t.as_str())).collect();
    let top = write("deep", &files);
    let (file, line, message) = refusal(&top);
    let last = format!("f{}.aff", depth - 1);
    assert_eq!((file.as_str(), line), (shown(&top, &last).as_str(), 1));
    assert!(message.contains(&format!("deeper than {depth}")), "{message}");
}

#[test]
fn keyframes_may_come_from_another_file_than_their_transform() {
    let keys = "k slide { transl 4 -1 0 0 0 0 0 0 0 0 0 0 0 0 0 1 2 0 0 0 0 0 2 2 0 0 0 0 0 }\n";
    let top = write(
        "keys_elsewhere",
        &[
            (
                "main.aff",
                &format!("{HEAD}a 0 2 2\nx slide {{ s 0 0 0 1 }}\ni 0 keys.aff\n"),
            ),
            ("keys.aff", keys),
        ],
    );
    let aff = load_path(&top).unwrap().aff.unwrap();
    assert_eq!(
        aff.flatten(aff.time_of_frame(1)).unwrap().spheres[0].center.x,
        2.0
    );
    // A block opened in one file cannot be closed in another.
    let top = write(
        "brace_elsewhere",
        &[
            (
                "main.aff",
                &format!("{HEAD}xs 1 1 1 0 0 1 0 0 0 0 {{\ni 0 close.aff\n}}\n"),
            ),
            ("close.aff", "}\n"),
        ],
    );
    let (file, line, message) = refusal(&top);
    assert_eq!((file.as_str(), line), (shown(&top, "close.aff").as_str(), 1));
    assert!(
        message.contains("closes no block opened in this file"),
        "{message}"
    );
}

/// A binary PPM of 2 x 1 texels followed by `extra`.
fn ppm(extra: &[u8]) -> Vec<u8> {
    let mut bytes = b"P6\n2 1\n255\n\xff\x00\x00\x00\x00\xff".to_vec();
    bytes.extend_from_slice(extra);
    bytes
}

const TEXTURED: &str = "tt wall.ppm 0 0 0 0 0  1 0 0 1 0  0 1 0 0 1\n";

#[test]
fn textures_are_found_beside_the_file_or_in_texture_files_and_checked() {
    // Beside the file naming it.
    let top = write(
        "texture_beside",
        &[("aff/main.aff", &format!("{HEAD}{TEXTURED}"))],
    );
    std::fs::write(top.parent().unwrap().join("wall.ppm"), ppm(b"\n")).unwrap();
    let aff = load_path(&top).unwrap().aff.unwrap();
    assert_eq!(
        (
            aff.textures.len(),
            aff.textures[0].image.width(),
            aff.textures[0].image.rgb()[0]
        ),
        (1, 2, 255)
    );
    assert!(aff.warnings.is_empty(), "{:?}", aff.warnings);
    // In TextureFiles beside its folder, as BART's scenes keep them; bytes after the
    // image beyond a line break are warned of.
    let top = write(
        "texture_folder",
        &[("aff/main.aff", &format!("{HEAD}{TEXTURED}"))],
    );
    let folder = top.parent().unwrap().join("../TextureFiles");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(folder.join("wall.ppm"), ppm(b"junk")).unwrap();
    let aff = load_path(&top).unwrap().aff.unwrap();
    assert_eq!(aff.textures[0].image.height(), 1);
    assert!(
        aff.warnings[0].message.contains("4 bytes after its image"),
        "{:?}",
        aff.warnings
    );
}

#[test]
fn a_missing_or_broken_texture_is_refused_where_it_is_named() {
    let top = write(
        "texture_missing",
        &[("main.aff", &format!("{HEAD}s 0 0 0 1\n{TEXTURED}"))],
    );
    let (file, line, message) = refusal(&top);
    assert_eq!((file, line), (top.display().to_string(), 4));
    assert!(message.contains("texture wall.ppm not found"), "{message}");
    let mesh =
        "m vertices 3 0 0 0 1 0 0 0 1 0\n texturecoords 3 wall.ppm 0 0 1 0 0 1\n triangles 1 0 1 2 0 1 2\n";
    let top = write(
        "texture_broken",
        &[
            ("main.aff", &format!("{HEAD}{mesh}")),
            ("wall.ppm", "P3 not binary\n"),
        ],
    );
    let (file, line, message) = refusal(&top);
    assert_eq!((file, line), (top.display().to_string(), 4));
    assert!(
        message.contains("is not a usable PPM: not a binary PPM"),
        "{message}"
    );
}
