//! Splitting an image into tiles for a split render: bands of whole rows, the unit
//! the renderer parallelises and traces in packets, as even as possible.

use super::region::Region;

/// Splits a `width` x `height` image into `n` bands of whole rows, top to bottom,
/// whose heights differ by at most one (band `k` covers rows `k*h/n .. (k+1)*h/n`,
/// rounded down). `n` goes from 1 to `height`: every band has at least one row.
///
/// ```
/// let bands = nffrt::image::bands(10, 7, 3).unwrap();
/// let rows: Vec<(u32, u32)> = bands.iter().map(|r| (r.y0, r.y1)).collect();
/// assert_eq!(rows, [(0, 2), (2, 4), (4, 7)]);
/// ```
pub fn bands(width: u32, height: u32, n: u32) -> Result<Vec<Region>, String> {
    if width == 0 || height == 0 {
        return Err(format!("a {width}x{height} image has no pixels to split"));
    }
    if !(1..=height).contains(&n) {
        return Err(format!(
            "{n} bands of a {width}x{height} image: the count goes from 1 to the height ({height})"
        ));
    }
    let row = |k: u32| (k as u64 * height as u64 / n as u64) as u32;
    Ok((0..n)
        .map(|k| Region {
            x0: 0,
            y0: row(k),
            x1: width,
            y1: row(k + 1),
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_cover_the_image_in_order_and_evenly() {
        for (w, h, n) in [(1, 1, 1), (5, 7, 7), (61, 47, 5), (512, 512, 8), (3, 32768, 1000)] {
            let b = bands(w, h, n).unwrap();
            assert_eq!(b.len(), n as usize);
            assert_eq!((b[0].y0, b[b.len() - 1].y1), (0, h));
            for pair in b.windows(2) {
                assert_eq!(pair[0].y1, pair[1].y0);
            }
            let heights: Vec<u32> = b.iter().map(|r| r.height()).collect();
            let (lo, hi) = (heights.iter().min().unwrap(), heights.iter().max().unwrap());
            assert!(*lo >= 1 && hi - lo <= 1, "{w}x{h}/{n}: {heights:?}");
            assert!(b.iter().all(|r| (r.x0, r.x1) == (0, w)));
        }
        let rows: Vec<u32> = bands(4, 47, 5).unwrap().iter().map(|r| r.height()).collect();
        assert_eq!(rows, [9, 9, 10, 9, 10]);
    }

    #[test]
    fn impossible_counts_are_refused() {
        assert!(bands(4, 3, 0).unwrap_err().contains("from 1 to the height (3)"));
        assert!(bands(4, 3, 4).is_err());
        assert!(bands(0, 3, 1).unwrap_err().contains("no pixels"));
    }
}
