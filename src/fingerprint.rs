//! Fingerprints that tie a render-farm tile to what made it: the scene it was
//! rendered from and every render option that changes its pixels. `nffrt merge`
//! refuses tiles whose fingerprints differ.
//!
//! The hash is 64-bit FNV-1a, defined by two constants and one loop, so the same
//! input has the same fingerprint on every platform, Rust version and nffrt build
//! (`std`'s `DefaultHasher` promises none of that).

use crate::options::RenderOptions;

/// 64-bit FNV-1a, fed in pieces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fnv1a64(u64);

impl Fnv1a64 {
    /// FNV's 64-bit offset basis.
    const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
    /// FNV's 64-bit prime.
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    /// The hash of nothing.
    pub const fn new() -> Self {
        Fnv1a64(Self::OFFSET_BASIS)
    }

    /// Feeds `bytes`.
    pub fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(Self::PRIME);
        }
    }

    /// The hash of everything fed so far.
    pub fn finish(&self) -> u64 {
        self.0
    }
}

impl Default for Fnv1a64 {
    fn default() -> Self {
        Self::new()
    }
}

/// The 64-bit FNV-1a hash of `bytes`.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h = Fnv1a64::new();
    h.update(bytes);
    h.finish()
}

/// The fingerprint of a scene: the hash of its file's bytes, exactly as read. A
/// scene format whose files name other files (images, say) feeds their bytes here
/// too, each after its length, so that changing any of them changes the fingerprint
/// ([`scene_fingerprint_with`]).
pub fn scene_fingerprint(scene_bytes: &[u8]) -> u64 {
    fnv1a64(scene_bytes)
}

/// The fingerprint of a scene file and the files it names (`named`, in order: the
/// decoded pixels of a P3F skybox's faces, each preceded by its size): the scene's
/// bytes, then each named piece's length and bytes. With nothing named it is
/// [`scene_fingerprint`].
pub fn scene_fingerprint_with(scene_bytes: &[u8], named: &[&[u8]]) -> u64 {
    let mut h = Fnv1a64::new();
    h.update(scene_bytes);
    for piece in named {
        h.update(&(piece.len() as u64).to_le_bytes());
        h.update(piece);
    }
    h.finish()
}

/// The canonical text of render options: every field of [`RenderOptions`] as
/// JSON, in declaration order. It comes from serde's derive, so a field added to
/// the struct later is part of it without anyone listing it here.
pub fn options_text(opts: &RenderOptions) -> String {
    serde_json::to_string(opts).expect("render options serialize")
}

/// The fingerprint of the options that change pixels: the hash of [`options_text`].
pub fn options_fingerprint(opts: &RenderOptions) -> u64 {
    fnv1a64(options_text(opts).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::Sampling;

    /// Published FNV-1a test vectors (Fowler, Noll and Vo's reference code).
    #[test]
    fn matches_the_published_test_vectors() {
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
        let mut pieces = Fnv1a64::new();
        pieces.update(b"foo");
        pieces.update(b"bar");
        assert_eq!(pieces.finish(), fnv1a64(b"foobar"));
    }

    #[test]
    fn named_files_change_the_scene_fingerprint() {
        let scene = b"s 0 0 0 1";
        assert_eq!(scene_fingerprint_with(scene, &[]), scene_fingerprint(scene));
        let a = scene_fingerprint_with(scene, &[b"ab", b"c"]);
        assert_ne!(a, scene_fingerprint(scene));
        // The same bytes cut elsewhere are other files.
        assert_ne!(a, scene_fingerprint_with(scene, &[b"a", b"bc"]));
        assert_ne!(a, scene_fingerprint_with(scene, &[b"ab", b"d"]));
    }

    #[test]
    fn options_text_names_every_field() {
        let opts = RenderOptions {
            width: 61,
            height: 47,
            max_depth: 3,
            sampling: Sampling::Stratified { spp: 9 },
            ..RenderOptions::default()
        };
        let text = options_text(&opts);
        for field in ["\"width\":61", "\"height\":47", "\"max_depth\":3", "\"spp\":9"] {
            assert!(text.contains(field), "{field} in {text}");
        }
        // Each field changes the fingerprint, the lens and light options included.
        let variants = [
            RenderOptions {
                sampling: Sampling::SpdCorners,
                ..opts
            },
            RenderOptions {
                aperture: Some(2.0),
                ..opts
            },
            RenderOptions {
                focal: Some(1.5),
                ..opts
            },
            RenderOptions {
                light_samples: Some(3),
                ..opts
            },
            RenderOptions {
                soft_shadows: !opts.soft_shadows,
                ..opts
            },
        ];
        for v in variants {
            assert_ne!(options_fingerprint(&v), options_fingerprint(&opts), "{v:?}");
        }
    }
}
