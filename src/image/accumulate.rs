//! An accumulation buffer: the mean of pictures of one size, pixel by pixel, in
//! linear floats (motion blur over an animation frame's interval averages its
//! sub-frames so, before any encoding). The pictures are summed in the order they
//! come and the sum divided by their count once: the same bits whatever the threads
//! that rendered them.

use super::Image;
use crate::math::Vec3;

/// The running sum of the pictures added so far.
#[derive(Clone, Debug, Default)]
pub struct Accumulator {
    /// The sum, `None` before the first picture (which it then is, bit for bit).
    sum: Option<Image>,
    /// Pictures added.
    count: u32,
}

impl Accumulator {
    /// An empty buffer.
    pub fn new() -> Accumulator {
        Accumulator::default()
    }

    /// Adds `image`, of the size of those before it.
    pub fn add(&mut self, image: Image) {
        self.count += 1;
        match &mut self.sum {
            None => self.sum = Some(image),
            Some(sum) => {
                assert!(
                    (sum.width, sum.height) == (image.width, image.height),
                    "accumulated pictures have one size"
                );
                for (s, p) in sum.pixels.iter_mut().zip(&image.pixels) {
                    *s += *p;
                }
            }
        }
    }

    /// The mean of the pictures added (`None` if none was): their sum divided by
    /// their count, channel by channel; one picture is itself.
    pub fn mean(self) -> Option<Image> {
        let mut sum = self.sum?;
        if self.count > 1 {
            let n = self.count as f32;
            for p in &mut sum.pixels {
                *p = Vec3::new(p.x / n, p.y / n, p.z / n);
            }
        }
        Some(sum)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(v: f32) -> Image {
        Image::from_pixels(2, 1, vec![Vec3::splat(v), Vec3::new(v, 0.0, -0.0)])
    }

    #[test]
    fn the_mean_of_pictures_and_of_one() {
        assert!(Accumulator::new().mean().is_none());
        let mut one = Accumulator::new();
        one.add(flat(0.3));
        assert_eq!(one.mean().unwrap(), flat(0.3));
        let mut three = Accumulator::new();
        for v in [0.25, 0.5, 1.5] {
            three.add(flat(v));
        }
        let mean = three.mean().unwrap();
        // (0.25 + 0.5 + 1.5) / 3 = 0.75, exact in binary at each step.
        assert_eq!(mean.get(0, 0), Vec3::splat(0.75));
        assert_eq!(mean.get(1, 0), Vec3::new(0.75, 0.0, 0.0));
    }
}
