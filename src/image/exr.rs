//! OpenEXR output: the linear values as traced, unclamped, like PFM — three 32-bit
//! float channels R, G, B (FLOAT, not HALF, so that a file holds exactly the values
//! of the PFM and of the Python arrays), top row first, compressed losslessly with
//! ZIP in blocks of 16 scan lines, the layer's software attribute `nffrt`. Written
//! and read through the `exr` crate; the decoder is for tests and tools.

use std::io::{self, Cursor, Write};

use exr::prelude as x;
use exr::prelude::traits::{ReadChannels, ReadLayers, WritableImage};

use super::format::SOFTWARE_TEXT;
use super::Image;
use crate::math::Vec3;

/// Writes `image` as a single-layer RGB float OpenEXR file.
pub fn encode_exr(image: &Image, w: &mut (impl Write + ?Sized)) -> io::Result<()> {
    encode_exr_layers(image, &[], w)
}

/// Writes `image` as [`encode_exr`] does, with more float channels beside R, G and
/// B in the same part: `extra` holds each one's name (`albedo.R`: the channel R of
/// the layer `albedo`, OpenEXR's naming of layers) and its values, one per pixel,
/// rows top first.
pub fn encode_exr_layers(
    image: &Image,
    extra: &[(String, Vec<f32>)],
    w: &mut (impl Write + ?Sized),
) -> io::Result<()> {
    let n = image.pixels.len();
    let channel = |name: &str, values: Vec<f32>| x::AnyChannel::new(name, x::FlatSamples::F32(values));
    let mut channels: x::SmallVec<[x::AnyChannel<x::FlatSamples>; 4]> = x::SmallVec::new();
    channels.push(channel("R", image.pixels.iter().map(|p| p.x).collect()));
    channels.push(channel("G", image.pixels.iter().map(|p| p.y).collect()));
    channels.push(channel("B", image.pixels.iter().map(|p| p.z).collect()));
    for (name, values) in extra {
        if values.len() != n {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("channel {name} has {} values for {n} pixels", values.len()),
            ));
        }
        channels.push(channel(name, values.clone()));
    }
    let attributes = x::LayerAttributes {
        software_name: Some(x::Text::from(SOFTWARE_TEXT.1)),
        ..Default::default()
    };
    let layer = x::Layer::new(
        (image.width as usize, image.height as usize),
        attributes,
        x::Encoding::SMALL_LOSSLESS,
        x::AnyChannels::sort(channels),
    );
    // Into memory first: the encoder seeks back to fill in its offset table.
    let mut bytes = Cursor::new(Vec::new());
    x::Image::from_layer(layer)
        .write()
        .to_buffered(&mut bytes)
        .map_err(exr_error)?;
    w.write_all(bytes.get_ref())
}

/// Every float channel of the first part of an OpenEXR file by name, in the file's
/// (alphabetical) order, rows top first (for tests and tools).
pub fn decode_exr_channels(bytes: &[u8]) -> Result<Vec<(String, Vec<f32>)>, String> {
    let read = x::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    let channels = read.layer_data.channel_data.list.into_iter();
    Ok(channels
        .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
        .collect())
}

/// Reads the first RGB layer of an OpenEXR file (any sample type, as f32).
pub fn decode_exr(bytes: &[u8]) -> Result<Image, String> {
    let read = x::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| (size.width(), vec![Vec3::ZERO; size.area()]),
            |(width, pixels): &mut (usize, Vec<Vec3>), at, (r, g, b): (f32, f32, f32)| {
                pixels[at.y() * *width + at.x()] = Vec3::new(r, g, b);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    let size = read.layer_data.size;
    let (_, pixels) = read.layer_data.channel_data.pixels;
    let (Ok(width), Ok(height)) = (u32::try_from(size.width()), u32::try_from(size.height())) else {
        return Err(format!("a {}x{} image is too large", size.width(), size.height()));
    };
    Ok(Image::from_pixels(width, height, pixels))
}

/// The `exr` crate's error as an I/O error.
fn exr_error(e: x::Error) -> io::Error {
    match e {
        x::Error::Io(e) => e,
        e => io::Error::other(e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_every_float_bit_for_bit() {
        // Values no 8-bit or half-float file keeps: above 1, negative, tiny, huge.
        let values = [0.0, 1.0, 2.5, -0.25, 1e-30, 3.0e38, 0.1, 1.0 / 3.0];
        let pixels: Vec<Vec3> = (0..40)
            .map(|i| Vec3::new(values[i % 8], values[(i + 3) % 8], values[(i + 5) % 8]))
            .collect();
        // 5 x 8: one block of 16 lines; the 2 x 40 below takes three.
        let image = Image::from_pixels(5, 8, pixels);
        let mut bytes = Vec::new();
        encode_exr(&image, &mut bytes).unwrap();
        assert_eq!(&bytes[..4], &[0x76, 0x2f, 0x31, 0x01], "the OpenEXR magic number");
        assert_eq!(decode_exr(&bytes).unwrap(), image);
        let tall = Image::from_pixels(2, 40, (0..80).map(|i| Vec3::splat(i as f32)).collect());
        let mut bytes = Vec::new();
        encode_exr(&tall, &mut bytes).unwrap();
        assert_eq!(decode_exr(&bytes).unwrap(), tall);
        assert!(decode_exr(b"not an exr").is_err());
    }

    #[test]
    fn extra_channels_sit_beside_the_picture() {
        let image = Image::from_pixels(2, 1, vec![Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0)]);
        let extra = vec![
            ("depth.Z".to_string(), vec![7.5, f32::INFINITY]),
            ("albedo.R".to_string(), vec![0.25, 0.5]),
        ];
        let mut bytes = Vec::new();
        encode_exr_layers(&image, &extra, &mut bytes).unwrap();
        // The picture reads back as it is, whatever else the part holds.
        assert_eq!(decode_exr(&bytes).unwrap(), image);
        let channels = decode_exr_channels(&bytes).unwrap();
        let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["B", "G", "R", "albedo.R", "depth.Z"]);
        assert_eq!(channels[4].1, [7.5, f32::INFINITY]);
        assert_eq!(channels[2].1, [1.0, 4.0]);
        let short = vec![("depth.Z".to_string(), vec![1.0])];
        assert!(encode_exr_layers(&image, &short, &mut Vec::new()).is_err());
    }
}
