//! Where `nffrt render` and `nffrt merge` put images: the format chosen by the file
//! extension ([`ImageFormat`]), `-` for PNG on standard output, 8-bit values linear
//! or sRGB-encoded, files written whole or not at all.

use std::io::{self, IsTerminal, Write};
use std::path::Path;

use super::output::{cannot_write, write_stdout, AtomicOutput};
use super::CliError;
use nffrt::image::{encode_exr_layers, encode_png_rgb8, png_error, Encoding, Image, ImageFormat};

/// The format of `path` by its extension; `-` (standard output) is PNG. A
/// directory is no image file, whatever its name.
pub fn format_of(path: &Path) -> Result<ImageFormat, CliError> {
    if is_stdout(path) {
        return Ok(ImageFormat::Png);
    }
    if path.is_dir() {
        let e = io::Error::new(io::ErrorKind::IsADirectory, "is a directory");
        return Err(cannot_write(path.display(), &e));
    }
    ImageFormat::from_extension(path).ok_or_else(|| CliError::usage(ImageFormat::unknown(path)))
}

/// True for `-`, standard output.
pub fn is_stdout(path: &Path) -> bool {
    path == Path::new("-")
}

/// How `path` is named in messages.
pub fn display_name(path: &Path) -> String {
    if is_stdout(path) {
        "standard output".into()
    } else {
        path.display().to_string()
    }
}

/// An image destination, opened before the work starts.
pub enum Destination {
    /// A file, written through a temporary sibling.
    File(AtomicOutput, String),
    /// Standard output.
    Stdout,
}

impl Destination {
    /// Opens `path` (`-` is standard output, refused when it is a terminal: binary
    /// image data would garble it).
    pub fn create(path: &Path) -> Result<Destination, CliError> {
        if is_stdout(path) {
            if io::stdout().is_terminal() {
                return Err(CliError::usage(
                    "-o -: standard output is a terminal; redirect it to a file or a pipe",
                ));
            }
            Ok(Destination::Stdout)
        } else {
            AtomicOutput::create(path).map(|o| Destination::File(o, path.display().to_string()))
        }
    }

    /// Encodes `image` (8-bit formats in `encoding`) and completes the output.
    /// `text` goes into PNG text chunks.
    pub fn write_image(
        self,
        image: &Image,
        format: ImageFormat,
        encoding: Encoding,
        text: &[(&str, String)],
    ) -> Result<(), CliError> {
        self.write_with(|w| format.encode(image, encoding, text, w))
    }

    /// Encodes `image` as OpenEXR with the `extra` channels beside R, G and B
    /// ([`encode_exr_layers`]) and completes the output.
    pub fn write_exr_layers(self, image: &Image, extra: &[(String, Vec<f32>)]) -> Result<(), CliError> {
        self.write_with(|w| encode_exr_layers(image, extra, w))
    }

    /// Encodes raw 8-bit RGB as PNG and completes the output.
    pub fn write_png_rgb8(
        self,
        width: u32,
        height: u32,
        rgb: &[u8],
        text: &[(&str, String)],
    ) -> Result<(), CliError> {
        self.write_with(|w| encode_png_rgb8(width, height, rgb, text, w).map_err(png_error))
    }

    fn write_with(self, encode: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<(), CliError> {
        match self {
            Destination::File(mut out, name) => {
                encode(out.writer()).map_err(|e| cannot_write(&name, &e))?;
                out.commit()
            }
            Destination::Stdout => {
                // Encode fully first, so a failed encode writes nothing.
                let mut bytes = Vec::new();
                encode(&mut bytes).map_err(|e| CliError::io(format!("encoding the image: {e}")))?;
                write_stdout(|w| w.write_all(&bytes))
            }
        }
    }
}
