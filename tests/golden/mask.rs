//! Two-class masks of pictures ("background or object", "floor or not", ...), how well
//! two of them agree, the picture transforms that a golden test must catch (mirror,
//! shift, zoom), and a picture of where two masks differ. Used by `tests/golden.rs`.

use image::{Rgb, RgbImage};

/// One class bit per pixel, row by row from the top left.
#[derive(Clone, Debug, PartialEq)]
pub struct Mask {
    pub width: usize,
    pub height: usize,
    bits: Vec<bool>,
}

impl Mask {
    /// The mask of `img` by a per-pixel classifier of its 8-bit RGB values.
    pub fn classify(img: &RgbImage, f: impl Fn([u8; 3]) -> bool) -> Mask {
        Mask {
            width: img.width() as usize,
            height: img.height() as usize,
            bits: img.pixels().map(|p| f(p.0)).collect(),
        }
    }

    fn filled(width: usize, height: usize, value: bool) -> Mask {
        Mask {
            width,
            height,
            bits: vec![value; width * height],
        }
    }

    fn get(&self, x: usize, y: usize) -> bool {
        self.bits[y * self.width + x]
    }

    /// The share of pixels in the class, 0 to 1.
    pub fn fraction(&self) -> f64 {
        self.bits.iter().filter(|&&b| b).count() as f64 / self.bits.len() as f64
    }

    fn not(&self) -> Mask {
        Mask {
            bits: self.bits.iter().map(|b| !b).collect(),
            ..self.clone()
        }
    }

    fn and(&self, other: &Mask) -> Mask {
        Mask {
            bits: self.bits.iter().zip(&other.bits).map(|(a, b)| *a && *b).collect(),
            ..self.clone()
        }
    }

    fn or(&self, other: &Mask) -> Mask {
        Mask {
            bits: self.bits.iter().zip(&other.bits).map(|(a, b)| *a || *b).collect(),
            ..self.clone()
        }
    }

    /// Pixels that have a 4-neighbour of the other class: both sides of every edge.
    fn edges(&self) -> Mask {
        let mut e = Mask::filled(self.width, self.height, false);
        for y in 0..self.height {
            for x in 0..self.width {
                let here = self.get(x, y);
                let differs = (x > 0 && self.get(x - 1, y) != here)
                    || (x + 1 < self.width && self.get(x + 1, y) != here)
                    || (y > 0 && self.get(x, y - 1) != here)
                    || (y + 1 < self.height && self.get(x, y + 1) != here);
                e.bits[y * self.width + x] = differs;
            }
        }
        e
    }

    /// Pixels with a set pixel within `r` in x and in y (a square window), in two
    /// separable passes of running counts.
    fn dilate(&self, r: usize) -> Mask {
        let (w, h) = (self.width, self.height);
        let run = |len: usize, at: &dyn Fn(usize) -> bool, out: &mut dyn FnMut(usize, bool)| {
            let mut prefix = vec![0u32; len + 1];
            for i in 0..len {
                prefix[i + 1] = prefix[i] + at(i) as u32;
            }
            for i in 0..len {
                let (lo, hi) = (i.saturating_sub(r), (i + r + 1).min(len));
                out(i, prefix[hi] > prefix[lo]);
            }
        };
        let mut rows = Mask::filled(w, h, false);
        for y in 0..h {
            run(w, &|x| self.get(x, y), &mut |x, v| rows.bits[y * w + x] = v);
        }
        let mut out = Mask::filled(w, h, false);
        for x in 0..w {
            run(h, &|y| rows.get(x, y), &mut |y, v| out.bits[y * w + x] = v);
        }
        out
    }

    /// The part of the mask connected (4-neighbours) to the picture's border once
    /// bridges of one pixel are cut: flood-fills from the border over the mask eroded
    /// by one pixel, grows the result back by one pixel and keeps it inside the mask.
    pub fn reaching_the_border(&self) -> Mask {
        let core = self.not().dilate(1).not();
        let (w, h) = (self.width, self.height);
        let mut seen = Mask::filled(w, h, false);
        let mut stack: Vec<(usize, usize)> = Vec::new();
        let border = (0..w)
            .flat_map(|x| [(x, 0), (x, h - 1)])
            .chain((0..h).flat_map(|y| [(0, y), (w - 1, y)]));
        stack.extend(border);
        while let Some((x, y)) = stack.pop() {
            let i = y * w + x;
            if seen.bits[i] || !core.bits[i] {
                continue;
            }
            seen.bits[i] = true;
            if x > 0 {
                stack.push((x - 1, y));
            }
            if x + 1 < w {
                stack.push((x + 1, y));
            }
            if y > 0 {
                stack.push((x, y - 1));
            }
            if y + 1 < h {
                stack.push((x, y + 1));
            }
        }
        seen.dilate(1).and(self)
    }
}

/// How well two masks of the same size agree, with one pixel of slack: a pixel agrees
/// when its class in each mask occurs within one pixel (its 3x3 block) in the other.
/// Renderers sample a pixel differently (nffrt's `--spd` averages its four corners),
/// so a pixel on an edge may fall either way; a shift of two pixels or more is not
/// forgiven.
#[derive(Clone, Copy, Debug)]
pub struct Agreement {
    /// Share of all pixels that agree.
    pub picture: f64,
    /// Share of the pixels within [`EDGE_BAND`] of an edge of either mask that agree
    /// (1 when neither mask has an edge): what a shift, mirror or zoom disturbs,
    /// measured where it shows rather than diluted by the plain areas.
    pub edges: f64,
}

/// Half-width in pixels of the band around the masks' edges that [`Agreement::edges`]
/// counts.
pub const EDGE_BAND: usize = 8;

/// The [`Agreement`] of `a` and `b` (same size).
pub fn agreement(a: &Mask, b: &Mask) -> Agreement {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "masks of different sizes"
    );
    let ok = agreeing_pixels(a, b);
    let band = a.edges().or(&b.edges()).dilate(EDGE_BAND);
    let share = |sel: &dyn Fn(usize) -> bool| {
        let n = (0..ok.bits.len()).filter(|&i| sel(i)).count();
        let good = (0..ok.bits.len()).filter(|&i| sel(i) && ok.bits[i]).count();
        if n == 0 {
            1.0
        } else {
            good as f64 / n as f64
        }
    };
    Agreement {
        picture: share(&|_| true),
        edges: share(&|i| band.bits[i]),
    }
}

/// Pixels whose class in each mask occurs within one pixel in the other.
fn agreeing_pixels(a: &Mask, b: &Mask) -> Mask {
    let (a_set, a_clear) = (a.dilate(1), a.not().dilate(1));
    let (b_set, b_clear) = (b.dilate(1), b.not().dilate(1));
    let bits = (0..a.bits.len())
        .map(|i| {
            let b_in_a = if b.bits[i] { a_set.bits[i] } else { a_clear.bits[i] };
            let a_in_b = if a.bits[i] { b_set.bits[i] } else { b_clear.bits[i] };
            b_in_a && a_in_b
        })
        .collect();
    Mask { bits, ..a.clone() }
}

/// Where two masks differ, as a picture: in the class in both grey, in neither white,
/// in `ours` only blue, in `reference` only red; pixels within one pixel of agreement
/// (see [`Agreement`]) are drawn pale.
pub fn diff_picture(ours: &Mask, reference: &Mask) -> RgbImage {
    let ok = agreeing_pixels(ours, reference);
    RgbImage::from_fn(ours.width as u32, ours.height as u32, |x, y| {
        let (x, y) = (x as usize, y as usize);
        let c = match (ours.get(x, y), reference.get(x, y)) {
            (true, true) => [96, 96, 96],
            (false, false) => [255, 255, 255],
            (true, false) => [0, 0, 255],
            (false, true) => [255, 0, 0],
        };
        if ok.get(x, y) && c[0] != c[2] {
            Rgb(c.map(|v| v / 2 + 128))
        } else {
            Rgb(c)
        }
    })
}

/// `img` mirrored left to right.
pub fn mirrored(img: &RgbImage) -> RgbImage {
    image::imageops::flip_horizontal(img)
}

/// `img` moved `dx` pixels right and `dy` down (negative: left, up); the rows and
/// columns uncovered repeat the picture's edge.
pub fn shifted(img: &RgbImage, dx: i64, dy: i64) -> RgbImage {
    let (w, h) = (img.width() as i64, img.height() as i64);
    RgbImage::from_fn(w as u32, h as u32, |x, y| {
        let sx = (x as i64 - dx).clamp(0, w - 1);
        let sy = (y as i64 - dy).clamp(0, h - 1);
        *img.get_pixel(sx as u32, sy as u32)
    })
}

/// `img` scaled by `s` about its centre (nearest pixel), cropped or edge-padded to
/// its own size: what a render at another field of view or resolution, resized to
/// match, would look like.
pub fn zoomed(img: &RgbImage, s: f64) -> RgbImage {
    let (w, h) = (img.width() as f64, img.height() as f64);
    let source =
        |i: u32, n: f64| (((i as f64 + 0.5 - n / 2.0) / s + n / 2.0).floor()).clamp(0.0, n - 1.0) as u32;
    RgbImage::from_fn(img.width(), img.height(), |x, y| {
        *img.get_pixel(source(x, w), source(y, h))
    })
}
