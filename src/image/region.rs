//! Rectangular crops of an image: the unit of work of a tiled (render-farm) render.
//!
//! A region is half-open, like a slice range: `X0,Y0,X1,Y1` covers columns
//! `X0..X1` and rows `Y0..Y1` (so `0,0,W,H` is the whole image, and two tiles that
//! split at column `a` are `0,0,a,H` and `a,0,W,H`).

use std::fmt;

/// The pixels `x0..x1` x `y0..y1` of an image (raster coordinates, top-left origin).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Region {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column (`x1 > x0`).
    pub x1: u32,
    /// One past the last row (`y1 > y0`).
    pub y1: u32,
}

impl Region {
    /// The whole `width` x `height` image.
    pub fn full(width: u32, height: u32) -> Region {
        Region {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// Number of pixels.
    pub fn area(&self) -> u64 {
        self.width() as u64 * self.height() as u64
    }

    /// True when the two regions share at least one pixel.
    pub fn overlaps(&self, o: &Region) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }

    /// True when pixel `(x, y)` lies in the region.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        (self.x0..self.x1).contains(&x) && (self.y0..self.y1).contains(&y)
    }

    /// Parses `X0,Y0,X1,Y1` and checks it is a non-empty crop of a `width` x `height`
    /// image.
    pub fn parse_within(s: &str, width: u32, height: u32) -> Result<Region, String> {
        let r = Region::parse(s)?;
        r.check_within(width, height)?;
        Ok(r)
    }

    /// Parses `X0,Y0,X1,Y1` and checks the region is not empty.
    pub fn parse(s: &str) -> Result<Region, String> {
        let v = parse_u32s(s, 4).map_err(|e| format!("{e} (X0,Y0,X1,Y1)"))?;
        let r = Region {
            x0: v[0],
            y0: v[1],
            x1: v[2],
            y1: v[3],
        };
        if r.x0 >= r.x1 || r.y0 >= r.y1 {
            return Err(format!(
                "region {r} is empty (need X0 < X1 and Y0 < Y1; X1 and Y1 are exclusive)"
            ));
        }
        Ok(r)
    }

    /// Checks that the region lies inside a `width` x `height` image.
    pub fn check_within(&self, width: u32, height: u32) -> Result<(), String> {
        if self.x1 > width || self.y1 > height {
            return Err(format!(
                "region {self} does not fit in the {width}x{height} image"
            ));
        }
        Ok(())
    }
}

impl fmt::Display for Region {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.y0, self.x1, self.y1)
    }
}

/// Parses exactly `n` comma-separated whole numbers (0 or more); the error says
/// what is wrong in words.
pub fn parse_u32s(s: &str, n: usize) -> Result<Vec<u32>, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != n {
        let found = match parts.len() {
            1 => "1 number".to_string(),
            k => format!("{k} numbers"),
        };
        return Err(format!(
            "expected {n} comma-separated whole numbers, found {found}"
        ));
    }
    parts
        .iter()
        .map(|p| {
            p.parse::<u32>()
                .map_err(|_| format!("'{p}' is not a whole number from 0 to {}", u32::MAX))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_checks_bounds() {
        let r = Region::parse_within("10, 20,30,40", 64, 64).unwrap();
        assert_eq!((r.x0, r.y0, r.x1, r.y1), (10, 20, 30, 40));
        assert_eq!((r.width(), r.height(), r.area()), (20, 20, 400));
        assert_eq!(r.to_string(), "10,20,30,40");
        assert!(Region::parse_within("0,0,65,10", 64, 64)
            .unwrap_err()
            .contains("does not fit"));
        assert!(Region::parse_within("5,0,5,10", 64, 64)
            .unwrap_err()
            .contains("empty"));
        assert!(Region::parse_within("1,2,3", 64, 64)
            .unwrap_err()
            .contains("expected 4 comma-separated whole numbers, found 3 numbers"));
        assert!(Region::parse_within("1,2,3,-4", 64, 64)
            .unwrap_err()
            .contains("'-4' is not a whole number"));
        assert_eq!(
            parse_u32s("4", 2).unwrap_err(),
            "expected 2 comma-separated whole numbers, found 1 number"
        );
    }

    #[test]
    fn overlap_is_half_open() {
        let a = Region::parse_within("0,0,8,8", 16, 16).unwrap();
        let b = Region::parse_within("8,0,16,8", 16, 16).unwrap();
        let c = Region::parse_within("7,7,9,9", 16, 16).unwrap();
        assert!(!a.overlaps(&b));
        assert!(a.overlaps(&c) && b.overlaps(&c));
        assert!(a.contains(7, 7) && !a.contains(8, 7));
    }
}
