//! Tiles of a render split across machines: the metadata each tile PNG carries and
//! the assembly of tiles into the full image.
//!
//! A tile is an ordinary 8-bit RGB PNG of its region with three text chunks:
//! [`REGION_KEY`] = `X0,Y0,X1,Y1,W,H` (the region, half-open, and the full image
//! size), [`FINGERPRINT_KEY`] = `scene=HEX options=HEX` (see [`crate::fingerprint`]:
//! the scene it was rendered from and every option that changes pixels) and
//! [`OPTIONS_KEY`] (those options in words, for people and error messages); a tile
//! whose 8-bit values are not linear also has [`ENCODING_KEY`] = `srgb` or `gamma2.2`.
//! [`merge_tiles`] checks that the tiles agree on the full size, fingerprint and
//! encoding, lie inside the image, do not overlap and cover it, then copies them
//! into place.

use std::fmt;

use super::region::{parse_u32s, Region};
use super::Encoding;

/// PNG text keyword of a tile's placement: `X0,Y0,X1,Y1,W,H`.
pub const REGION_KEY: &str = "nffrt:region";
/// PNG text keyword of the settings a tile was rendered with (readable; not compared).
pub const OPTIONS_KEY: &str = "nffrt:options";
/// PNG text keyword of a tile's [`TileFingerprint`].
pub const FINGERPRINT_KEY: &str = "nffrt:fingerprint";
/// PNG text keyword of a tile's [`Encoding`] when it is not linear: `srgb` or
/// `gamma2.2` ([`Encoding::name`]).
pub const ENCODING_KEY: &str = "nffrt:encoding";

/// The [`ENCODING_KEY`] chunk of a tile in `encoding`, if it needs one (a tile
/// without it holds linear values, as every tile did before sRGB output).
pub fn encoding_text(encoding: Encoding) -> Option<(&'static str, String)> {
    (encoding != Encoding::Linear).then(|| (ENCODING_KEY, encoding.name().into()))
}

/// The encoding of a tile whose [`ENCODING_KEY`] chunk holds `text` (`None`: none).
pub fn parse_encoding_text(text: Option<&str>) -> Result<Encoding, String> {
    match text {
        None => Ok(Encoding::Linear),
        Some(name) => Encoding::from_name(name)
            .filter(|e| *e != Encoding::Linear)
            .ok_or_else(|| format!("unknown {ENCODING_KEY} '{name}' (nffrt writes 'srgb' or 'gamma2.2')")),
    }
}

/// What a tile was made from: tiles merge only when these are equal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TileFingerprint {
    /// [`crate::fingerprint::scene_fingerprint`] of the scene.
    pub scene: u64,
    /// [`crate::fingerprint::options_fingerprint`] of the render options.
    pub options: u64,
}

impl fmt::Display for TileFingerprint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "scene={:016x} options={:016x}", self.scene, self.options)
    }
}

impl TileFingerprint {
    /// Parses the text of a [`FINGERPRINT_KEY`] chunk (as [`fmt::Display`] writes it).
    pub fn parse(s: &str) -> Result<TileFingerprint, String> {
        let bad = || format!("bad {FINGERPRINT_KEY} '{s}' (expected scene=HEX options=HEX)");
        let (scene, options) = s.split_once(' ').ok_or_else(bad)?;
        let hex = |part: &str, key: &str| {
            part.strip_prefix(key)
                .filter(|h| h.len() == 16)
                .and_then(|h| u64::from_str_radix(h, 16).ok())
                .ok_or_else(bad)
        };
        Ok(TileFingerprint {
            scene: hex(scene, "scene=")?,
            options: hex(options, "options=")?,
        })
    }
}

/// One tile: where it goes, what it was made from and its pixels.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tile {
    /// A name for error messages (the file name).
    pub name: String,
    /// Where the tile lies in the full image.
    pub region: Region,
    /// Full image width.
    pub full_width: u32,
    /// Full image height.
    pub full_height: u32,
    /// The scene and options the tile was rendered from.
    pub fingerprint: TileFingerprint,
    /// The render settings in words, as recorded in the tile (for messages).
    pub settings: String,
    /// How its bytes hold the linear values.
    pub encoding: Encoding,
    /// `region.width() * region.height() * 3` bytes, top row first.
    pub rgb: Vec<u8>,
}

/// The text of a tile's [`REGION_KEY`] chunk.
pub fn region_text(region: &Region, full_width: u32, full_height: u32) -> String {
    format!("{region},{full_width},{full_height}")
}

/// Parses a [`REGION_KEY`] chunk: the region and the full size.
pub fn parse_region_text(s: &str) -> Result<(Region, u32, u32), String> {
    let v = parse_u32s(s, 6).map_err(|e| format!("bad {REGION_KEY} '{s}': {e}"))?;
    let (w, h) = (v[4], v[5]);
    let r = Region::parse_within(&format!("{},{},{},{}", v[0], v[1], v[2], v[3]), w, h)
        .map_err(|e| format!("bad {REGION_KEY} '{s}': {e}"))?;
    Ok((r, w, h))
}

/// The first tile that disagrees with the others on `key`, and a tile it disagrees
/// with: `(odd, reference, odd_is_alone)`. The reference holds the value most tiles
/// share; when no value has a majority over the rest, the odd one cannot be told
/// apart and `odd_is_alone` is false.
fn odd_one_out<K: PartialEq>(tiles: &[Tile], key: impl Fn(&Tile) -> K) -> Option<(usize, usize, bool)> {
    let keys: Vec<K> = tiles.iter().map(&key).collect();
    let count = |k: &K| keys.iter().filter(|o| *o == k).count();
    let (reference, most) = (0..keys.len())
        .map(|i| (i, count(&keys[i])))
        .fold((0, 0), |best, c| if c.1 > best.1 { c } else { best });
    let odd = (0..keys.len()).find(|&i| keys[i] != keys[reference])?;
    let runner_up = (0..keys.len())
        .filter(|&i| keys[i] != keys[reference])
        .map(|i| count(&keys[i]))
        .max()
        .unwrap_or(0);
    Some((odd, reference, most > runner_up))
}

/// Refuses tiles made from different scenes or with different settings, naming the
/// odd tile (the one that differs from most of the others).
fn check_fingerprints(tiles: &[Tile]) -> Result<(), String> {
    if let Some((odd, reference, alone)) = odd_one_out(tiles, |t| t.fingerprint.scene) {
        let (a, b) = (&tiles[odd], &tiles[reference]);
        return Err(if alone {
            format!(
                "{} comes from a different scene (fingerprint {:016x}) than the other tiles, e.g. {} ({:016x})",
                a.name, a.fingerprint.scene, b.name, b.fingerprint.scene
            )
        } else {
            format!(
                "{} and {} come from different scenes (fingerprints {:016x} and {:016x})",
                b.name, a.name, b.fingerprint.scene, a.fingerprint.scene
            )
        });
    }
    if let Some((odd, reference, alone)) = odd_one_out(tiles, |t| t.fingerprint.options) {
        // The odd tile first when it is alone, else the two in the order given.
        let (a, b) = match alone {
            true => (&tiles[odd], &tiles[reference]),
            false => (&tiles[reference], &tiles[odd]),
        };
        let differences = settings_difference(&a.settings, &b.settings)
            .unwrap_or_else(|| format!("{} against {}", a.settings, b.settings));
        return Err(if alone {
            format!(
                "{} was rendered with different settings than the other tiles, e.g. {}: {differences}",
                a.name, b.name
            )
        } else {
            format!(
                "{} and {} were rendered with different settings: {differences}",
                a.name, b.name
            )
        });
    }
    Ok(())
}

/// Refuses tiles of different 8-bit encodings: their bytes mean other colours.
fn check_encodings(tiles: &[Tile]) -> Result<(), String> {
    let Some((odd, reference, _)) = odd_one_out(tiles, |t| t.encoding) else {
        return Ok(());
    };
    let (a, b) = (&tiles[odd], &tiles[reference]);
    Err(format!(
        "{} was written with --encoding {} and {} with --encoding {}: their bytes encode colours \
         differently; render them alike",
        a.name, a.encoding, b.name, b.encoding
    ))
}

/// The settings in which two tiles' [`OPTIONS_KEY`] texts differ, in words: `spp 4
/// against 16, max_depth 5 against 2` (the first tile's value first); `None` when
/// either text is not the JSON object nffrt writes or no setting differs.
fn settings_difference(a: &str, b: &str) -> Option<String> {
    let (a, b) = (settings_words(a)?, settings_words(b)?);
    let value = |words: &[(String, String)], key: &str| {
        let found = words.iter().find(|(k, _)| k == key);
        found.map_or_else(|| "none".to_string(), |(_, v)| v.clone())
    };
    let mut keys: Vec<&String> = a.iter().chain(&b).map(|(k, _)| k).collect();
    keys.sort();
    keys.dedup();
    let differences: Vec<String> = keys
        .into_iter()
        .map(|key| (key, value(&a, key), value(&b, key)))
        .filter(|(_, x, y)| x != y)
        .map(|(key, x, y)| format!("{key} {x} against {y}"))
        .collect();
    (!differences.is_empty()).then(|| differences.join(", "))
}

/// A tile's settings (the JSON of [`crate::fingerprint::options_text`]) as `(name,
/// value)` words: an enum variant with fields counts as its name plus each field
/// (`"sampling": {"Stratified": {"spp": 4}}` is `sampling Stratified` and `spp 4`),
/// `null` (the scene's value) is `none`.
fn settings_words(text: &str) -> Option<Vec<(String, String)>> {
    fn flatten(key: String, value: serde_json::Value, words: &mut Vec<(String, String)>) {
        use serde_json::Value;
        match value {
            Value::Object(fields) if fields.len() == 1 && fields.values().all(Value::is_object) => {
                for (variant, fields) in fields {
                    words.push((key.clone(), variant));
                    flatten(key.clone(), fields, words);
                }
            }
            Value::Object(fields) => {
                for (k, v) in fields {
                    flatten(k, v, words);
                }
            }
            Value::String(s) => words.push((key, s)),
            Value::Null => words.push((key, "none".into())),
            v => words.push((key, v.to_string())),
        }
    }
    let serde_json::Value::Object(fields) = serde_json::from_str(text).ok()? else {
        return None;
    };
    let mut words = Vec::new();
    for (key, value) in fields {
        flatten(key, value, &mut words);
    }
    Some(words)
}

/// Checks the tiles and assembles them: `(width, height, RGB bytes)` of the full image.
pub fn merge_tiles(tiles: &[Tile]) -> Result<(u32, u32, Vec<u8>), String> {
    let first = tiles.first().ok_or("no tiles to merge")?;
    let (w, h) = (first.full_width, first.full_height);
    for t in tiles {
        if (t.full_width, t.full_height) != (w, h) {
            return Err(format!(
                "{} belongs to a {}x{} image, {} to a {w}x{h} one",
                t.name, t.full_width, t.full_height, first.name
            ));
        }
    }
    check_fingerprints(tiles)?;
    check_encodings(tiles)?;
    for t in tiles {
        let r = &t.region;
        if r.x0 >= r.x1 || r.y0 >= r.y1 || r.x1 > w || r.y1 > h {
            return Err(format!("{}: region {r} does not fit in {w}x{h}", t.name));
        }
        if t.rgb.len() as u64 != r.area() * 3 {
            return Err(format!("{}: pixel data does not match region {r}", t.name));
        }
    }
    for (i, a) in tiles.iter().enumerate() {
        if let Some(b) = tiles[i + 1..].iter().find(|b| a.region.overlaps(&b.region)) {
            return Err(format!(
                "{} ({}) and {} ({}) overlap",
                a.name, a.region, b.name, b.region
            ));
        }
    }
    // Disjoint tiles inside the image cover it exactly when their areas add up.
    let covered: u64 = tiles.iter().map(|t| t.region.area()).sum();
    let total = w as u64 * h as u64;
    if covered != total {
        let hole = first_uncovered(tiles, w, h)
            .map(|(x, y)| format!(", e.g. pixel ({x}, {y}) is in no tile"))
            .unwrap_or_default();
        return Err(format!(
            "the tiles cover {covered} of the {total} pixels of the {w}x{h} image{hole}"
        ));
    }
    let mut out = vec![0u8; total as usize * 3];
    let row_bytes = w as usize * 3;
    for t in tiles {
        let r = &t.region;
        let tw = r.width() as usize * 3;
        for (k, src) in t.rgb.chunks_exact(tw).enumerate() {
            let at = (r.y0 as usize + k) * row_bytes + r.x0 as usize * 3;
            out[at..at + tw].copy_from_slice(src);
        }
    }
    Ok((w, h, out))
}

/// The top-most, then left-most pixel in no tile. It lies at a column that is 0 or
/// some tile's `x1`, and a row that is 0 or some tile's `y1`, so only those are
/// tried (skipped for very many tiles, where it would be slow).
fn first_uncovered(tiles: &[Tile], w: u32, h: u32) -> Option<(u32, u32)> {
    if tiles.len() > 256 {
        return None;
    }
    let mut xs: Vec<u32> = std::iter::once(0)
        .chain(tiles.iter().map(|t| t.region.x1))
        .collect();
    let mut ys: Vec<u32> = std::iter::once(0)
        .chain(tiles.iter().map(|t| t.region.y1))
        .collect();
    xs.sort_unstable();
    xs.dedup();
    ys.sort_unstable();
    ys.dedup();
    ys.iter()
        .filter(|&&y| y < h)
        .flat_map(|&y| xs.iter().filter(|&&x| x < w).map(move |&x| (x, y)))
        .find(|&(x, y)| !tiles.iter().any(|t| t.region.contains(x, y)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tile of the 4x3 image whose pixel (x, y) has bytes (x, y, 7).
    fn tile(name: &str, x0: u32, y0: u32, x1: u32, y1: u32) -> Tile {
        let mut rgb = Vec::new();
        for y in y0..y1 {
            for x in x0..x1 {
                rgb.extend_from_slice(&[x as u8, y as u8, 7]);
            }
        }
        Tile {
            name: name.into(),
            region: Region { x0, y0, x1, y1 },
            full_width: 4,
            full_height: 3,
            fingerprint: TileFingerprint { scene: 1, options: 2 },
            settings: "spp=1".into(),
            encoding: Encoding::Linear,
            rgb,
        }
    }

    #[test]
    fn uneven_tiles_assemble_in_place() {
        let tiles = [
            tile("c", 3, 0, 4, 3),
            tile("a", 0, 0, 3, 1),
            tile("b", 0, 1, 3, 3),
        ];
        let (w, h, rgb) = merge_tiles(&tiles).unwrap();
        assert_eq!((w, h), (4, 3));
        assert_eq!(rgb, tile("full", 0, 0, 4, 3).rgb);
    }

    #[test]
    fn overlaps_gaps_and_mismatches_are_named() {
        let e = merge_tiles(&[tile("a", 0, 0, 3, 3), tile("b", 2, 0, 4, 3)]).unwrap_err();
        assert!(e.contains("a (0,0,3,3) and b (2,0,4,3) overlap"), "{e}");
        let e = merge_tiles(&[tile("a", 0, 0, 4, 1), tile("b", 0, 2, 4, 3)]).unwrap_err();
        assert!(
            e.contains("cover 8 of the 12") && e.contains("pixel (0, 1)"),
            "{e}"
        );
        let e = merge_tiles(&[tile("a", 0, 0, 4, 3), tile("b", 0, 0, 1, 1)]).unwrap_err();
        assert!(e.contains("overlap"), "{e}");
        let mut other = tile("b", 2, 0, 4, 3);
        other.full_width = 5;
        let e = merge_tiles(&[tile("a", 0, 0, 2, 3), other]).unwrap_err();
        assert!(e.contains("5x3"), "{e}");
        let mut other = tile("b", 2, 0, 4, 3);
        other.fingerprint.options = 3;
        other.settings = "spp=4".into();
        let e = merge_tiles(&[tile("a", 0, 0, 2, 3), other]).unwrap_err();
        assert!(
            e.contains("a and b were rendered with different settings: spp=1 against spp=4"),
            "{e}"
        );
        assert!(merge_tiles(&[]).is_err());
    }

    #[test]
    fn a_tile_of_another_scene_is_named() {
        // Three tiles, the middle one from another scene: it is the odd one, wherever
        // it comes in the list.
        let mut odd = tile("odd", 0, 1, 4, 2);
        odd.fingerprint.scene = 9;
        let (top, bottom) = (tile("top", 0, 0, 4, 1), tile("bottom", 0, 2, 4, 3));
        for order in [
            [odd.clone(), top.clone(), bottom.clone()],
            [top.clone(), odd.clone(), bottom.clone()],
            [top.clone(), bottom.clone(), odd.clone()],
        ] {
            let e = merge_tiles(&order).unwrap_err();
            assert!(
                e.starts_with("odd comes from a different scene (fingerprint 0000000000000009)"),
                "{e}"
            );
        }
        // Two tiles that disagree: neither can be called the odd one, both are named.
        let e = merge_tiles(&[top, odd]).unwrap_err();
        assert!(e.contains("top and odd come from different scenes"), "{e}");
    }

    #[test]
    fn srgb_and_linear_tiles_do_not_mix() {
        let mut srgb = tile("b", 2, 0, 4, 3);
        srgb.encoding = Encoding::Srgb;
        for tiles in [
            [tile("a", 0, 0, 2, 3), srgb.clone()],
            [srgb.clone(), tile("a", 0, 0, 2, 3)],
        ] {
            let e = merge_tiles(&tiles).unwrap_err();
            assert!(
                e.contains("with --encoding srgb") && e.contains("with --encoding linear"),
                "{e}"
            );
        }
        let mut both = tile("a", 0, 0, 2, 3);
        both.encoding = Encoding::Srgb;
        assert!(merge_tiles(&[both.clone(), srgb]).is_ok());
        assert_eq!(parse_encoding_text(None), Ok(Encoding::Linear));
        let (key, text) = encoding_text(Encoding::Srgb).unwrap();
        assert_eq!(key, ENCODING_KEY);
        assert_eq!(parse_encoding_text(Some(&text)), Ok(Encoding::Srgb));
        assert!(parse_encoding_text(Some("gamma")).is_err());
        assert!(
            parse_encoding_text(Some("linear")).is_err(),
            "linear tiles carry no chunk"
        );
        let (_, text) = encoding_text(Encoding::Gamma22).unwrap();
        assert_eq!(parse_encoding_text(Some(&text)), Ok(Encoding::Gamma22));
        let mut gamma = tile("b", 2, 0, 4, 3);
        gamma.encoding = Encoding::Gamma22;
        let e = merge_tiles(&[both.clone(), gamma]).unwrap_err();
        assert!(e.contains("gamma2.2") && e.contains("srgb"), "{e}");
    }

    #[test]
    fn differing_settings_are_named_in_words() {
        let options = |sampling: &str, depth: u32| {
            format!(
                r#"{{"width":4,"height":3,"max_depth":{depth},"sampling":{sampling},"aperture":null,"focal":1.5}}"#
            )
        };
        let spp = |n: u32| options(&format!(r#"{{"Stratified":{{"spp":{n}}}}}"#), 5);
        assert_eq!(
            settings_difference(&spp(4), &spp(16)).as_deref(),
            Some("spp 4 against 16")
        );
        assert_eq!(
            settings_difference(&options(r#""PixelCenters""#, 2), &spp(16)).as_deref(),
            Some("max_depth 2 against 5, sampling PixelCenters against Stratified, spp none against 16")
        );
        assert_eq!(settings_difference(&spp(4), &spp(4)), None);
        assert_eq!(settings_difference("not recorded", &spp(4)), None);
        // Three tiles, one odd: it is named, with one of the others.
        let mut tiles = [
            tile("top", 0, 0, 4, 1),
            tile("mid", 0, 1, 4, 2),
            tile("bot", 0, 2, 4, 3),
        ];
        for t in &mut tiles {
            t.settings = spp(16);
        }
        tiles[2].settings = spp(4);
        tiles[2].fingerprint.options = 3;
        let e = merge_tiles(&tiles).unwrap_err();
        assert_eq!(
            e,
            "bot was rendered with different settings than the other tiles, e.g. top: spp 4 against 16"
        );
    }

    #[test]
    fn fingerprint_text_round_trips() {
        let f = TileFingerprint {
            scene: 0x0123_4567_89ab_cdef,
            options: 42,
        };
        assert_eq!(f.to_string(), "scene=0123456789abcdef options=000000000000002a");
        assert_eq!(TileFingerprint::parse(&f.to_string()), Ok(f));
        for bad in [
            "",
            "scene=12 options=34",
            "options=0123456789abcdef scene=0123456789abcdef",
        ] {
            assert!(TileFingerprint::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn region_text_round_trips() {
        let r = Region {
            x0: 1,
            y0: 2,
            x1: 3,
            y1: 4,
        };
        assert_eq!(region_text(&r, 10, 20), "1,2,3,4,10,20");
        assert_eq!(parse_region_text("1,2,3,4,10,20").unwrap(), (r, 10, 20));
        assert!(parse_region_text("1,2,3,4,2,20").is_err());
        assert!(parse_region_text("1,2,3,4").is_err());
    }
}
