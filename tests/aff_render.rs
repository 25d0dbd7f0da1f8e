//! AFF scenes rendered: textures sampled as BART's original renderer samples them
//! and `fm` shaded by its rules, checked against pixel values computed by hand; the
//! path tracer's diffuse albedo multiplied by the texel.

mod common;

use std::path::Path;

use common::scratch_dir;
use nffrt::image::Image;
use nffrt::load::{load, LoadOptions, Source};
use nffrt::options::{RenderOptions, Sampling};
use nffrt::prepare::{prepare_with, PrepareOptions};
use nffrt::render::render;
use nffrt::scene::{Accel, IntegratorKind};

/// A 5 x 5 binary PPM whose texel (x, y) (column, row from the top) is
/// `(60 x, 60 y, 255 at (1, 1) else 0)`.
fn ramp_ppm() -> Vec<u8> {
    let mut bytes = b"P6\n5 5\n255\n".to_vec();
    for y in 0..5u8 {
        for x in 0..5u8 {
            bytes.extend([60 * x, 60 * y, if (x, y) == (1, 1) { 255 } else { 0 }]);
        }
    }
    bytes.push(b'\n');
    bytes
}

/// A 4 x 4 camera on the z axis whose outer pixel centres see x, y = ±0.75 on the
/// plane z = 0 (NFF's `angle` spans the outer pixel centres: tan(angle / 2) = 0.15
/// at distance 5), so pixel (c, r) sees x = -0.75 + 0.5 c, y = 0.75 - 0.5 r; lit only by the ambient
/// light `am 1 1 1`, and an `fm` whose ambient colour is white and nothing else: a
/// surface shows its texel.
const HEAD: &str = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 17.0615312199 hither 1 resolution 4 4\n\
                    b 0 0 0\nam 1 1 1\nfm 1 1 1  0 0 0  0 0 0  1 0 1\n";

/// The picture of `text` (with `ramp.ppm` beside it) as 8-bit RGB rows.
fn render_aff(dir: &Path, text: &str) -> Vec<[u8; 3]> {
    render_aff_with(dir, text, None)
}

/// [`render_aff`] with the acceleration structure `accel` (`None`: the default).
fn render_aff_with(dir: &Path, text: &str, accel: Option<Accel>) -> Vec<[u8; 3]> {
    std::fs::write(dir.join("ramp.ppm"), ramp_ppm()).unwrap();
    let path = dir.join("scene.aff");
    std::fs::write(&path, text).unwrap();
    let loaded = load(Source::File(&path), &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let options = PrepareOptions {
        accel,
        ..PrepareOptions::default()
    };
    let scene = prepare_with(loaded.scene, &loaded.assets, &options);
    let opts = RenderOptions::from_view(scene.view());
    let (image, _): (Image, _) = render(&scene, scene.view(), &opts).unwrap();
    image.to_rgb8().chunks(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// The expected picture. The quad |x|, |y| <= 1 maps u = (x + 1) / 2, v = (1 - y) / 2, so u = 0.125 + 0.25 c; the original
/// scales by W - 3 = 2: texel coordinate 0.25 + 0.5 c (rows likewise). Red is the
/// bilinear mix of 60 x: 15, 45, 75, 105 across; green 60 y the same down; blue is
/// texel (1, 1)'s weight times 255, (1 - |1 - X|)(1 - |1 - Y|): per axis 0.25 at 0.25
/// and 1.75, 0.75 at 0.75 and 1.25, so 16 of 255 in the corners, 143 in the middle
/// four, 48 on the others.
fn expected() -> Vec<[u8; 3]> {
    let weight = [0.25f32, 0.75, 0.75, 0.25];
    let mut out = Vec::new();
    for r in 0..4 {
        for c in 0..4 {
            let b = (255.0 * weight[c] * weight[r]).round() as u8;
            out.push([[15, 45, 75, 105][c], [15, 45, 75, 105][r], b]);
        }
    }
    out
}

/// Asserts that `got` is [`expected`] within one level (the float rounding of the
/// camera's rays and of the mix).
fn assert_shows_the_ramp(got: &[[u8; 3]]) {
    for (i, (g, w)) in got.iter().zip(&expected()).enumerate() {
        let off = g.iter().zip(w).any(|(a, b)| a.abs_diff(*b) > 1);
        assert!(!off, "pixel ({}, {}): {g:?}, expected {w:?}", i % 4, i / 4);
    }
}

/// The quad |x|, |y| <= 1 as two `tt` triangles: corners (x, y, 0) with
/// u = (x + 1) / 2, v = (1 - y) / 2.
const QUAD: &str = "tt ramp.ppm -1 -1 0 0 1   1 -1 0 1 1   1 1 0 1 0\n\
                    tt ramp.ppm -1 -1 0 0 1   1 1 0 1 0   -1 1 0 0 0\n";

#[test]
fn a_textured_quad_shows_its_texels_bilinearly_on_the_originals_scale() {
    let dir = scratch_dir("aff_render", "tt");
    // The same picture through each acceleration structure.
    for accel in [None, Some(Accel::Grid), Some(Accel::None)] {
        assert_shows_the_ramp(&render_aff_with(&dir, &format!("{HEAD}{QUAD}"), accel));
    }
}

#[test]
fn a_textured_mesh_wraps_its_coordinates_by_their_fraction() {
    let dir = scratch_dir("aff_render", "mesh");
    // The same quad as a mesh with normals, its coordinates moved by -1 in u and +2
    // in v: negative ones wrap to their fraction plus 1, others to their fraction, so
    // the picture is unchanged.
    let text = format!(
        "{HEAD}m vertices 4  -1 -1 0  1 -1 0  1 1 0  -1 1 0\n\
         normals 1  0 0 1\n\
         texturecoords 4 ramp.ppm  -1 3  0 3  0 2  -1 2\n\
         triangles 2  0 1 2  0 0 0  0 1 2   0 2 3  0 0 0  0 2 3\n"
    );
    assert_shows_the_ramp(&render_aff(&dir, &text));
}

/// `fm` as BART's original renderer shades it, at the centre pixel of a 3 x 3 view
/// of a quad facing the camera, a white light behind the camera (`l` without a
/// colour: intensity 1, not NFF's shared default): n = l = v = h, so
/// colour = am * Ka + I * (Kd + Ks * 1^shine) + Ks * (1 - T) * background
///        = (0.05, 0.1, 0.15) + (0.5, 0.25, 0) + (0.2, 0.2, 0.2) + 0.2 * (0.5, 0.5, 0.5)
///        = (0.85, 0.65, 0.45), 8-bit (217, 166, 115).
#[test]
fn fill_materials_shade_with_their_ambient_diffuse_and_specular_colours() {
    let dir = scratch_dir("aff_render", "fm");
    let text = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 10 hither 1 resolution 3 3\n\
                b 0.5 0.5 0.5\nam 0.5 0.5 0.5\nl 0 0 10\n\
                fm 0.1 0.2 0.3  0.5 0.25 0  0.2 0.2 0.2  5 0 1\n\
                p 4 -1 -1 0  1 -1 0  1 1 0  -1 1 0\n";
    let got = render_aff(&dir, text);
    assert_eq!(got[4], [217, 166, 115]);
}

/// The path tracer multiplies a textured surface's diffuse albedo by its texel: the
/// ramp quad, white `fm` diffuse and nothing else, under a white sky (`b 1 1 1`)
/// and no light. Each camera ray meets the quad, and its one bounce leaves the
/// plane for the sky: a Lambertian sample's weight is its albedo exactly (f cos /
/// pdf), so a pixel is its texel times 1, the values [`expected`] gives (the
/// pixel centres: one sample each). Without the texel every pixel would be white.
#[test]
fn the_path_tracer_shows_the_texels_in_the_diffuse_albedo() {
    let dir = scratch_dir("aff_render", "path");
    std::fs::write(dir.join("ramp.ppm"), ramp_ppm()).unwrap();
    let path = dir.join("scene.aff");
    let head = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 17.0615312199 hither 1 resolution 4 4\n\
                b 1 1 1\nfm 0 0 0  1 1 1  0 0 0  1 0 1\n";
    std::fs::write(&path, format!("{head}{QUAD}")).unwrap();
    let loaded = load(Source::File(&path), &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let scene = prepare_with(loaded.scene, &loaded.assets, &PrepareOptions::default());
    let opts = RenderOptions {
        integrator: IntegratorKind::Path,
        sampling: Sampling::PixelCenters,
        ..RenderOptions::from_view(scene.view())
    };
    let (image, _): (Image, _) = render(&scene, scene.view(), &opts).unwrap();
    let got: Vec<[u8; 3]> = image.to_rgb8().chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    assert_shows_the_ramp(&got);
}
