//! The image file formats nffrt writes, chosen by file extension, and the one PNG
//! text chunk every nffrt PNG carries: the command line and the Python bindings
//! both go through here, so a file's format and bytes never depend on which wrote it.

use std::io::{self, Write};
use std::path::Path;

use super::{encode_exr, encode_pfm, encode_png_rgb8, encode_ppm_rgb8, Encoding, Image};

/// The PNG text chunk every nffrt PNG carries (a tile adds its own, a merged image
/// has exactly this one, like a full render).
pub const SOFTWARE_TEXT: (&str, &str) = ("Software", "nffrt");

/// An output image format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit RGB PNG.
    Png,
    /// Binary PPM (P6), 8-bit.
    Ppm,
    /// Little-endian colour PFM, linear floats.
    Pfm,
    /// OpenEXR, linear 32-bit floats.
    Exr,
}

impl ImageFormat {
    /// The format named by `path`'s extension (`.png`, `.ppm`, `.pfm`, `.exr`, any
    /// case).
    pub fn from_extension(path: &Path) -> Option<ImageFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(ImageFormat::Png),
            "ppm" => Some(ImageFormat::Ppm),
            "pfm" => Some(ImageFormat::Pfm),
            "exr" => Some(ImageFormat::Exr),
            _ => None,
        }
    }

    /// The message for a path whose extension names no format.
    pub fn unknown(path: &Path) -> String {
        format!(
            "{}: unknown image format (use .png, .ppm, .pfm or .exr)",
            path.display()
        )
    }

    /// True for the 8-bit formats (PNG, PPM), which hold values in an
    /// [`Encoding`]; the float formats hold the linear values as they are.
    pub fn is_8bit(self) -> bool {
        matches!(self, ImageFormat::Png | ImageFormat::Ppm)
    }

    /// Encodes `image` in this format into `w`, 8-bit formats in `encoding` (float
    /// formats take only [`Encoding::Linear`]); `text` goes into PNG text chunks
    /// (the other formats have none).
    pub fn encode(
        self,
        image: &Image,
        encoding: Encoding,
        text: &[(&str, String)],
        w: &mut dyn Write,
    ) -> io::Result<()> {
        if !self.is_8bit() && encoding != Encoding::Linear {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "float images hold linear values: no sRGB encoding",
            ));
        }
        let (width, height) = (image.width, image.height);
        match self {
            ImageFormat::Png => {
                encode_png_rgb8(width, height, &image.to_rgb8_as(encoding), text, w).map_err(png_error)
            }
            ImageFormat::Ppm => encode_ppm_rgb8(width, height, &image.to_rgb8_as(encoding), w),
            ImageFormat::Pfm => encode_pfm(image, w),
            ImageFormat::Exr => encode_exr(image, w),
        }
    }
}

/// A PNG encoder's error as the I/O error it mostly is.
pub fn png_error(e: ::png::EncodingError) -> io::Error {
    match e {
        ::png::EncodingError::IoError(e) => e,
        e => io::Error::other(e.to_string()),
    }
}
