//! Malformed scenes, each refused at the line (and column) where it goes wrong. The
//! test camera and material take lines 1 and 2, so a body's first line is line 3.

use super::{error, scene, AffError};

/// Asserts that `e` stands at `line`:`column` of the text and says `words`.
fn assert_at(e: &AffError, line: u32, column: u32, words: &str) {
    assert_eq!(
        (e.file.as_str(), e.error.line, e.error.column),
        ("<text>", line, column),
        "{e}"
    );
    assert!(e.to_string().contains(words), "{e}\nshould say: {words}");
}

/// A `transl` block of `rows` rows under a count of `count`.
fn transl(count: usize, rows: usize) -> String {
    let rows: String = (0..rows).map(|i| format!("  {i} 0 0 0 0 0 0\n")).collect();
    format!("x a {{ s 0 0 0 1 }}\nk a\n{{\n transl {count}\n{rows}}}\n")
}

#[test]
fn a_key_count_must_match_its_rows() {
    // The count stands on line 6 (x on 3, k on 4, { on 5), column 9.
    let e = error(&transl(5, 4));
    assert_at(&e, 6, 9, "'transl 5' promises 5 keys, but 4 rows follow");
    let e = error(&transl(4, 5));
    assert_at(&e, 6, 9, "more rows follow (line 11)");
    assert!(scene(&transl(4, 4)).tracks.len() == 1);
}

#[test]
fn curves_need_four_keys_and_blocks_need_keys() {
    assert_at(&error(&transl(3, 3)), 6, 9, "at least 4 keys");
    assert_at(&error("k a { }\n"), 3, 1, "keyframe block 'a' has no keys");
    assert_at(
        &error("k a { transl 4 0 0 0 0 0 0 0 1 0 0 0 0 0 0 2 0 0 0 0 0 0 3 0 0 0 0 0 0 transl 4 }\n"),
        3,
        72,
        "a second 'transl'",
    );
    assert_at(
        &error("k a { spin 4 }\n"),
        3,
        7,
        "expected 'transl', 'rot', 'scale', 'visibility' or '}'",
    );
}

#[test]
fn a_third_key_at_one_time_is_refused() {
    let rows = "rot 4\n 0 0 1 0 0 0 0 0\n 1 0 1 0 0 0 0 0\n 1 0 1 0 9 0 0 0\n 1 0 1 0 0 0 0 0\n";
    assert_at(
        &error(&format!("k a {{ {rows} }}\n")),
        7,
        2,
        "tangent is undefined",
    );
}

#[test]
fn an_index_past_the_vertex_list_is_refused_at_the_index() {
    let mesh = "m\n vertices 3  0 0 0  1 0 0  0 1 0\n triangles 2\n  0 1 2\n  0 2 3\n";
    assert_at(&error(mesh), 7, 7, "vertex index 3 is past the mesh's 3 vertices");
    let normals = "m vertices 3 0 0 0 1 0 0 0 1 0 normals 1 0 0 1\n triangles 1 0 1 2 0 0 1\n";
    assert_at(
        &error(normals),
        4,
        24,
        "normal index 1 is past the mesh's 1 normals",
    );
    assert_at(
        &error("m vertices 1 0 0 0 triangle 1\n"),
        3,
        20,
        "expected 'triangles'",
    );
    assert_at(
        &error("m vertices 0 triangles 1 0 0 0\n"),
        3,
        26,
        "vertex index 0, but the mesh has no vertices",
    );
}

#[test]
fn unknown_keywords_and_bad_numbers_are_located() {
    assert_at(&error("s 0 0 0 1\n  zz 1 2\n"), 4, 3, "unknown keyword \"zz\"");
    assert_at(
        &error("xs 1 1 1 0 0 1 x 0 0 0 { }\n"),
        3,
        16,
        "expected a number ('xs' rotation angle in degrees)",
    );
    assert_at(&error("a 0 1 0\n"), 3, 7, "at least one frame");
    assert_at(
        &error("a 5 1 10\n"),
        3,
        5,
        "the animation ends (1) before it starts (5)",
    );
    assert_at(
        &error("tpa 2 1 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 1\n0 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 1\n"),
        4,
        1,
        "before the previous one",
    );
    assert_at(
        &error("fm 1 1 1 1 1 1 1 1 1 1 1\n"),
        4,
        1,
        "expected a number ('fm' index of refraction), found end of file",
    );
}

#[test]
fn blocks_must_open_and_close_in_their_file() {
    assert_at(
        &error("s 0 0 0 1\n}\n"),
        4,
        1,
        "'}' closes no block opened in this file",
    );
    assert_at(
        &error("xs 1 1 1 0 0 1 0 0 0 0\n{\n s 0 0 0 1\n"),
        3,
        1,
        "not closed",
    );
    assert_at(&error("x a s 0 0 0 1\n"), 3, 5, "expected '{' after 'x a'");
    assert_at(
        &error("xs 1 1 1  0 0 0 30  0 0 0 { }\n"),
        3,
        11,
        "a rotation about a zero axis",
    );
    // Two closing braces in one token close two blocks.
    let s = scene("xs 1 1 1 0 0 1 0 0 0 0 { xs 1 1 1 0 0 1 0 0 0 0 { s 0 0 0 1 }}\ns 1 1 1 1\n");
    assert_eq!(s.objects[1].node, 0);
}

#[test]
fn a_transform_without_keys_and_keys_without_a_transform_are_warned_of() {
    // BART's robot scene has both; the original leaves such a transform the identity.
    let s = scene("x lonely { s 0 0 0 1 }\nk spare { transl 4 0 0 0 0 0 0 0 1 0 0 0 0 0 0 2 0 0 0 0 0 0 3 0 0 0 0 0 0 }\n");
    let warnings: Vec<(u32, &str)> = s
        .warnings
        .iter()
        .map(|w| (w.at.line, w.message.as_str()))
        .collect();
    assert!(
        warnings.contains(&(
            3,
            "no keyframe block 'k lonely': the transform 'x lonely' stays the identity"
        )),
        "{warnings:?}"
    );
    assert!(
        warnings.iter().any(|(l, m)| *l == 4 && m.contains("'spare'")),
        "{warnings:?}"
    );
    assert_eq!(s.flatten(0.0).unwrap().spheres[0].center, crate::math::Vec3::ZERO);
}

#[test]
fn a_sphere_under_a_stretch_is_refused_when_flattened() {
    let s = scene("xs 1 2 1 0 0 1 0 0 0 0 {\n s 0 0 0 1\n}\n");
    let e = s.flatten(0.0).unwrap_err();
    assert_at(&e, 4, 2, "a sphere under a non-uniform scale");
}

#[test]
fn one_vertex_past_f32_refuses_its_mesh() {
    // Only the first vertex overflows when scaled by 1e10: the others stay finite.
    let s =
        scene("xs 1e10 1e10 1e10 0 0 1 0 0 0 0 {\n m vertices 3 1e30 0 0 1 0 0 0 1 0 triangles 1 0 1 2 }\n");
    assert_at(&s.flatten(0.0).unwrap_err(), 4, 2, "past the range of numbers");
}

#[test]
fn transforms_past_f32_are_refused_not_rendered() {
    let s = scene(
        "xs 1e30 1e30 1e30 0 0 1 0 0 0 0 { xs 1e30 1e30 1e30 0 0 1 0 0 0 0 {\n p 3 0 0 0 1 0 0 0 1 0 } }\n",
    );
    assert_at(&s.flatten(0.0).unwrap_err(), 4, 2, "past the range of numbers");
}
