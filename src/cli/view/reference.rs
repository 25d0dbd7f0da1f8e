//! A reference picture beside the live one (`nffrt view --reference REF`, or a file
//! the page's picker sends): read once, shown for flipping between the two, and
//! every finished pass of a picture of its size measured against it by NVIDIA's
//! FLIP (`nffrt::compare`), as `nffrt diff` measures: LDR-FLIP against the picture
//! as shown for an 8-bit reference, HDR-FLIP against the linear values for a float
//! one.

use std::path::Path;

use super::protocol::{encode_binary, ServerMessage};
use nffrt::compare::{compare, magma_image, Metric, Picture, Range};
use nffrt::image::{Encoding, Image, ImageFormat};
use nffrt::math::Vec3;

/// A reference picture and what the page is sent of it.
pub struct Reference {
    /// Its file name.
    pub name: String,
    /// Its values.
    pub picture: Picture,
    /// It as 8-bit RGB for the page (a float picture in the live picture's
    /// encoding).
    pub display: Vec<u8>,
}

/// The format of a picture file by its first bytes.
fn sniff(bytes: &[u8]) -> Option<ImageFormat> {
    match bytes {
        [0x89, b'P', b'N', b'G', ..] => Some(ImageFormat::Png),
        [b'P', b'6', ..] => Some(ImageFormat::Ppm),
        [b'P', b'F', ..] => Some(ImageFormat::Pfm),
        [0x76, 0x2f, 0x31, 0x01, ..] => Some(ImageFormat::Exr),
        _ => None,
    }
}

impl Reference {
    /// The reference in `bytes`, a PNG, PPM, PFM or OpenEXR file (told apart by
    /// their first bytes) named `name`; a float one shown in `encoding`.
    pub fn decode(name: &str, bytes: &[u8], encoding: Encoding) -> Result<Reference, String> {
        let format = sniff(bytes).ok_or_else(|| format!("{name}: not a PNG, PPM, PFM or OpenEXR picture"))?;
        let picture =
            Picture::decode(bytes, format).map_err(|e| format!("{name}: not a usable picture: {e}"))?;
        let display = match picture.range {
            Range::Display => picture
                .pixels
                .iter()
                .flat_map(|p| p.map(|v| (v * 255.0).round() as u8))
                .collect(),
            Range::Linear => {
                let pixels = picture.pixels.iter().map(|p| Vec3::from_array(*p)).collect();
                Image::from_pixels(picture.width, picture.height, pixels).to_rgb8_as(encoding)
            }
        };
        Ok(Reference {
            name: name.to_string(),
            picture,
            display,
        })
    }

    /// The reference in the file at `path`.
    pub fn read(path: &Path, encoding: Encoding) -> Result<Reference, String> {
        let name = path.display().to_string();
        let bytes = std::fs::read(path)
            .map_err(|e| format!("{name}: cannot read picture: {}", nffrt::io_reason(&e)))?;
        Reference::decode(&name, &bytes, encoding)
    }

    /// The message that announces it.
    pub fn message(&self) -> ServerMessage {
        ServerMessage::Reference {
            name: self.name.clone(),
            width: self.picture.width,
            height: self.picture.height,
            mode: match self.picture.range {
                Range::Display => "ldr",
                Range::Linear => "hdr",
            },
        }
    }

    /// The binary message that carries it to the page.
    pub fn display_message(&self) -> Vec<u8> {
        let header = serde_json::json!({
            "kind": "reference",
            "width": self.picture.width,
            "height": self.picture.height,
        });
        encode_binary(&header, &self.display)
    }

    /// FLIP's mean of the picture `image` (linear), shown as `rgb`, against the
    /// reference, and its map in magma colours; `None` when the sizes differ or
    /// FLIP cannot view the reference (HDR-FLIP of a black one).
    pub fn measure(&self, image: &Image, rgb: &[u8]) -> Option<(f64, Vec<u8>)> {
        let (w, h) = (image.width, image.height);
        if (w, h) != (self.picture.width, self.picture.height) {
            return None;
        }
        let test = match self.picture.range {
            Range::Display => Picture::from_rgb8(w, h, rgb).ok()?,
            Range::Linear => {
                let values: Vec<f32> = image.pixels.iter().flat_map(|p| p.to_array()).collect();
                Picture::new(w, h, &values, Range::Linear).ok()?
            }
        };
        let c = compare(&test, &self.picture, Metric::Flip).ok()?;
        Some((c.value, magma_image(&c.map, w, h, 1.0).to_rgb8()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pictures_are_told_apart_by_their_first_bytes_and_garbage_is_refused() {
        let image = Image::from_pixels(2, 1, vec![Vec3::new(0.5, 0.25, 1.0), Vec3::ZERO]);
        for format in [
            ImageFormat::Png,
            ImageFormat::Ppm,
            ImageFormat::Pfm,
            ImageFormat::Exr,
        ] {
            let mut bytes = Vec::new();
            format.encode(&image, Encoding::Linear, &[], &mut bytes).unwrap();
            let r = Reference::decode("r", &bytes, Encoding::Linear).unwrap();
            assert_eq!((r.picture.width, r.picture.height), (2, 1), "{format:?}");
            assert_eq!(r.display, [128, 64, 255, 0, 0, 0], "{format:?}");
        }
        let e = Reference::decode("junk.bin", b"GIF89a", Encoding::Linear)
            .err()
            .unwrap();
        assert!(e.contains("not a PNG, PPM, PFM or OpenEXR"), "{e}");
        let e = Reference::decode("cut.png", &[0x89, b'P', b'N', b'G', 0, 1], Encoding::Linear)
            .err()
            .unwrap();
        assert!(e.contains("not a usable picture"), "{e}");
    }

    #[test]
    fn a_picture_equal_to_the_reference_has_no_error_and_another_size_none() {
        let image = Image::from_pixels(3, 2, (0..6).map(|i| Vec3::splat(i as f32 / 6.0)).collect());
        let rgb = image.to_rgb8();
        let mut png = Vec::new();
        ImageFormat::Png
            .encode(&image, Encoding::Linear, &[], &mut png)
            .unwrap();
        let r = Reference::decode("r.png", &png, Encoding::Linear).unwrap();
        let (mean, map) = r.measure(&image, &rgb).unwrap();
        assert_eq!(mean, 0.0);
        assert_eq!(map.len(), 18);
        let other = Image::from_pixels(2, 3, image.pixels.clone());
        assert!(r.measure(&other, &rgb).is_none());
        // A different picture has an error above 0.
        let dark = Image::from_pixels(3, 2, vec![Vec3::ZERO; 6]);
        assert!(r.measure(&dark, &dark.to_rgb8()).unwrap().0 > 0.1);
    }
}
