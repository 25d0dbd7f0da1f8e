//! Command-line values and their errors: every number flag says its range in words,
//! the same way everywhere (`invalid value '-1' for '--spp <N>': must be a whole
//! number from 1 to 4096`), and negative numbers are read as values, not as flags.

use clap::builder::{PossibleValuesParser, TypedValueParser};
use nffrt::denoise::Quality;
use nffrt::image::region::parse_u32s;
use nffrt::image::Encoding;
use nffrt::image::Region;
use nffrt::render::Aov;
use nffrt::scene::IntegratorKind;

/// The one wording of an out-of-range or malformed whole number.
pub fn whole_number_range(lo: u64, hi: u64) -> String {
    if hi == u64::MAX {
        format!("must be a whole number, {lo} or more")
    } else {
        format!("must be a whole number from {lo} to {hi}")
    }
}

/// A clap value parser for a whole number from `lo` to `hi` inclusive (and within
/// `T`), whose error says the range in words.
pub fn whole_number<T: TryFrom<u64>>(
    lo: u64,
    hi: u64,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        s.trim()
            .parse::<u64>()
            .ok()
            .filter(|n| (lo..=hi).contains(n))
            .and_then(|n| T::try_from(n).ok())
            .ok_or_else(|| whole_number_range(lo, hi))
    }
}

/// A clap value parser for a finite number of at least 0 (`--aperture`), whose
/// error says so in the words of [`whole_number_range`].
pub fn number_at_least_zero(s: &str) -> Result<f32, String> {
    finite(s)
        .filter(|&v| v >= 0.0)
        .ok_or_else(|| "must be a number, 0 or more".into())
}

/// A clap value parser for a finite number above 0 (`--focal`).
pub fn number_above_zero(s: &str) -> Result<f32, String> {
    finite(s)
        .filter(|&v| v > 0.0)
        .ok_or_else(|| "must be a number above 0".into())
}

fn finite(s: &str) -> Option<f32> {
    s.trim().parse::<f32>().ok().filter(|v| v.is_finite())
}

/// A clap value parser for `--integrator NAME`: the light transports' own names
/// ([`IntegratorKind::name`]), listed in help and in the error for any other.
pub fn integrator() -> impl TypedValueParser<Value = IntegratorKind> {
    PossibleValuesParser::new(IntegratorKind::ALL.map(IntegratorKind::name))
        .try_map(|name| name.parse::<IntegratorKind>())
}

/// A clap value parser for `--encoding`: one of [`Encoding::ALL`] by name.
pub fn encoding() -> impl TypedValueParser<Value = Encoding> {
    PossibleValuesParser::new(Encoding::ALL.map(Encoding::name))
        .try_map(|name| Encoding::from_name(&name).ok_or("unknown encoding"))
}

/// A clap value parser for `--denoise=QUALITY`: one of [`Quality::ALL`] by name.
pub fn quality() -> impl TypedValueParser<Value = Quality> {
    PossibleValuesParser::new(Quality::ALL.map(Quality::name))
        .try_map(|name| Quality::from_name(&name).ok_or("unknown quality"))
}

/// A clap value parser for each name of `--aov` (a comma-separated list).
pub fn aov() -> impl TypedValueParser<Value = Aov> {
    PossibleValuesParser::new(Aov::ALL.map(Aov::name))
        .try_map(|name| Aov::from_name(&name).ok_or("unknown AOV"))
}

/// A clap value parser for `--pixel X,Y`: a column and a row, counted from 0.
pub fn pixel(s: &str) -> Result<(u32, u32), String> {
    let v = parse_u32s(s, 2).map_err(|e| format!("{e} (X,Y: column and row, from 0)"))?;
    Ok((v[0], v[1]))
}

/// A clap value parser for `--region X0,Y0,X1,Y1` (not empty; whether it fits the
/// image is checked once the size is known).
pub fn region(s: &str) -> Result<Region, String> {
    Region::parse(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_outside_the_range_say_it_in_words() {
        let spp = whole_number::<u32>(1, 4096);
        assert_eq!(spp("4096"), Ok(4096));
        for bad in ["0", "-1", "4097", "2.5", "four", ""] {
            assert_eq!(
                spp(bad),
                Err("must be a whole number from 1 to 4096".into()),
                "{bad}"
            );
        }
        let bytes = whole_number::<u64>(0, u64::MAX);
        assert_eq!(bytes("-3"), Err("must be a whole number, 0 or more".into()));
        // The type's own range counts too.
        assert!(whole_number::<u32>(0, 1 << 40)("4294967296").is_err());
    }

    #[test]
    fn real_numbers_say_their_range_in_words() {
        assert_eq!(number_at_least_zero("0"), Ok(0.0));
        assert_eq!(number_at_least_zero("2.5"), Ok(2.5));
        for bad in ["-3", "-0.1", "inf", "NaN", "x", ""] {
            assert_eq!(
                number_at_least_zero(bad),
                Err("must be a number, 0 or more".into()),
                "{bad}"
            );
        }
        assert_eq!(number_above_zero("1.2"), Ok(1.2));
        for bad in ["0", "-1", "inf", "y"] {
            assert_eq!(
                number_above_zero(bad),
                Err("must be a number above 0".into()),
                "{bad}"
            );
        }
    }

    #[test]
    fn pixels_and_regions_name_the_bad_part() {
        assert_eq!(pixel("3, 4"), Ok((3, 4)));
        assert_eq!(
            pixel("4").unwrap_err(),
            "expected 2 comma-separated whole numbers, found 1 number (X,Y: column and row, from 0)"
        );
        assert!(pixel("-1,2")
            .unwrap_err()
            .starts_with("'-1' is not a whole number"));
        assert!(region("0,0,0,5").unwrap_err().contains("empty"));
    }
}
