//! The set bits of a lane mask (a SIMD comparison's bitmask, a packet's rays), as
//! lane indices: `for k in lanes(mask)` for the `while mask != 0` loop that takes
//! the lowest set bit and clears it.

use std::iter::FusedIterator;

/// The indices of the set bits of `bits`, lowest first.
#[inline(always)]
pub(crate) fn lanes(bits: u32) -> SetBits {
    SetBits(bits)
}

/// The iterator of [`lanes`]: the bits not yet visited.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SetBits(u32);

impl Iterator for SetBits {
    type Item = usize;

    /// The lowest set bit, cleared (`tzcnt` and `blsr` where the CPU has them): the
    /// loop compiles as the one written out by hand.
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let k = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(k)
    }

    #[inline(always)]
    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.0.count_ones() as usize;
        (n, Some(n))
    }
}

impl ExactSizeIterator for SetBits {}

impl FusedIterator for SetBits {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_bits_lowest_first() {
        assert_eq!(lanes(0).count(), 0);
        assert_eq!(lanes(0b1010_0101).collect::<Vec<_>>(), [0, 2, 5, 7]);
        assert_eq!(lanes(1 << 31).collect::<Vec<_>>(), [31]);
        assert_eq!(lanes(u32::MAX).collect::<Vec<_>>(), (0..32).collect::<Vec<_>>());
        assert_eq!(lanes(0b1011).len(), 3);
    }
}
