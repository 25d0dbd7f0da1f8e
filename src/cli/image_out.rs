//! Where `nffrt render` and `nffrt merge` put images: the format chosen by the file
//! extension, `-` for PNG on standard output, and the PNG text chunks they carry.

use std::io::{self, IsTerminal, Write};
use std::path::Path;

use super::output::{cannot_write, AtomicOutput};
use super::CliError;
use nffrt::image::{encode_pfm, encode_png, encode_png_rgb8, encode_ppm, Image};

/// The text chunk every nffrt PNG carries (a tile adds its own, a merged image has
/// exactly this one, like a full render).
pub const SOFTWARE_TEXT: (&str, &str) = ("Software", "nffrt");

/// An output image format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// 8-bit RGB PNG.
    Png,
    /// Binary PPM (P6), 8-bit.
    Ppm,
    /// Little-endian colour PFM, linear floats.
    Pfm,
}

/// The format of `path` by its extension; `-` (standard output) is PNG.
pub fn format_of(path: &Path) -> Result<Format, CliError> {
    if is_stdout(path) {
        return Ok(Format::Png);
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => Ok(Format::Png),
        Some("ppm") => Ok(Format::Ppm),
        Some("pfm") => Ok(Format::Pfm),
        _ => Err(CliError::usage(format!(
            "{}: unknown image format (use .png, .ppm or .pfm)",
            path.display()
        ))),
    }
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

    /// Encodes `image` and completes the output. `text` goes into PNG text chunks.
    pub fn write_image(self, image: &Image, format: Format, text: &[(&str, String)]) -> Result<(), CliError> {
        self.write_with(|w| match format {
            Format::Png => encode_png(image, text, w).map_err(png_error),
            Format::Ppm => encode_ppm(image, w),
            Format::Pfm => encode_pfm(image, w),
        })
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
                let mut out = io::stdout().lock();
                match out.write_all(&bytes).and_then(|()| out.flush()) {
                    Ok(()) => Ok(()),
                    // The reader stopped early: not our failure.
                    Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
                    Err(e) => Err(CliError::io(format!("writing standard output: {e}"))),
                }
            }
        }
    }
}

fn png_error(e: png::EncodingError) -> io::Error {
    match e {
        png::EncodingError::IoError(e) => e,
        e => io::Error::other(e.to_string()),
    }
}
