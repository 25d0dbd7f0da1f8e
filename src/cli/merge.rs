//! `nffrt merge`: assembles the PNG tiles written by `nffrt render --region` into the
//! full image, byte-identical to rendering it whole.
//!
//! Each tile records its region and the full size in a `nffrt:region` text chunk and
//! the fingerprints of its scene and render options in `nffrt:fingerprint`. The tiles
//! must agree on both, lie inside the image, not overlap and cover it; the merged PNG
//! carries only the text chunks of a full render.

use std::path::{Path, PathBuf};

use clap::Args;

use super::image_out::{display_name, format_of, Destination};
use super::output::{brief, refuse_overwriting, Named};
use super::CliError;
use nffrt::image::decode_png;
use nffrt::image::tiles::{
    merge_tiles, parse_encoding_text, parse_region_text, Tile, TileFingerprint, ENCODING_KEY,
    FINGERPRINT_KEY, OPTIONS_KEY, REGION_KEY,
};
use nffrt::image::{ImageFormat, SOFTWARE_TEXT};
use nffrt::words::count;

/// Arguments of `nffrt merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Tile PNGs from `nffrt render --region`, in any order.
    #[arg(required = true, value_name = "TILES")]
    pub tiles: Vec<PathBuf>,
    /// The full image: a .png file, or `-` for standard output.
    #[arg(short, long, value_name = "FULL.png")]
    pub output: PathBuf,
    /// No closing summary line.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `nffrt merge`.
pub fn run(args: MergeArgs) -> Result<(), CliError> {
    if format_of(&args.output)? != ImageFormat::Png {
        return Err(CliError::usage(format!(
            "{}: merged images are PNG (tiles hold 8-bit pixels)",
            args.output.display()
        )));
    }
    let inputs: Vec<(&Path, &str)> = args.tiles.iter().map(|t| (t.as_path(), "the tile")).collect();
    refuse_overwriting(&[Named::flag("-o", &args.output)], &inputs)?;
    let tiles = args.tiles.iter().map(read_tile).collect::<Result<Vec<_>, _>>()?;
    let (w, h, rgb) = merge_tiles(&tiles).map_err(CliError::scene)?;
    let output = Destination::create(&args.output)?;
    output.write_png_rgb8(w, h, &rgb, &[(SOFTWARE_TEXT.0, SOFTWARE_TEXT.1.to_string())])?;
    if !args.quiet {
        eprintln!(
            "merged {} into {} ({w}x{h})",
            count(tiles.len(), "tile", "tiles"),
            display_name(&args.output)
        );
    }
    Ok(())
}

/// Reads one tile: I/O failures exit with the I/O code, files that are not nffrt
/// tiles with the bad-input code.
fn read_tile(path: &PathBuf) -> Result<Tile, CliError> {
    let name = path.display().to_string();
    if path.is_dir() {
        return Err(CliError::io(format!("{name}: is a directory, not a tile")));
    }
    let bytes =
        std::fs::read(path).map_err(|e| CliError::io(format!("{name}: cannot read tile: {}", brief(&e))))?;
    let png = decode_png(&bytes[..]).map_err(|e| CliError::scene(format!("{name}: not a tile PNG: {e}")))?;
    let text = png.text(REGION_KEY).ok_or_else(|| {
        CliError::scene(format!(
            "{name}: not an nffrt tile (no {REGION_KEY} text chunk; render it with --region)"
        ))
    })?;
    let (region, full_width, full_height) =
        parse_region_text(text).map_err(|e| CliError::scene(format!("{name}: {e}")))?;
    if (png.width, png.height) != (region.width(), region.height()) {
        return Err(CliError::scene(format!(
            "{name}: a {}x{} image cannot be region {region}",
            png.width, png.height
        )));
    }
    let fingerprint = png.text(FINGERPRINT_KEY).ok_or_else(|| {
        CliError::scene(format!(
            "{name}: the tile has no scene fingerprint (no {FINGERPRINT_KEY} text chunk: \
             an older nffrt made it); render it again"
        ))
    })?;
    let fingerprint =
        TileFingerprint::parse(fingerprint).map_err(|e| CliError::scene(format!("{name}: {e}")))?;
    let encoding =
        parse_encoding_text(png.text(ENCODING_KEY)).map_err(|e| CliError::scene(format!("{name}: {e}")))?;
    Ok(Tile {
        name,
        region,
        full_width,
        full_height,
        fingerprint,
        settings: png.text(OPTIONS_KEY).unwrap_or("not recorded").to_string(),
        encoding,
        rgb: png.rgb,
    })
}
