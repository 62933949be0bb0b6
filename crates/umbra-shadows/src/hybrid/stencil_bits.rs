//! Why the `stencil` mask counts right: a model of the Vulkan stencil update with a write mask
//! (spec §"Stencil Test": `s' = (s & ~write_mask) | (op(s) & write_mask)`), used to prove that
//! wrap-counting in the low seven bits is exact modulo 128 and never touches the silhouette
//! bit, whatever the order of increments and decrements.

/// One stencil update of 8-bit value `s`: INCREMENT_AND_WRAP (`up`) or DECREMENT_AND_WRAP,
/// written through `write_mask`.
pub fn wrap_update(s: u8, up: bool, write_mask: u8) -> u8 {
    let op = if up { s.wrapping_add(1) } else { s.wrapping_sub(1) };
    (s & !write_mask) | (op & write_mask)
}

#[cfg(test)]
mod tests {
    use super::super::settings::{COUNT_BITS, SILHOUETTE_BIT};
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Any sequence of crossings: the silhouette bit survives, and the low bits hold the
        /// net count modulo 128 — zero exactly when the net count is a multiple of 128.
        #[test]
        fn low_bits_count_modulo_128(steps in proptest::collection::vec(any::<bool>(), 0..600)) {
            let mut s = SILHOUETTE_BIT as u8;
            let mut net: i64 = 0;
            for &up in &steps {
                s = wrap_update(s, up, COUNT_BITS as u8);
                net += if up { 1 } else { -1 };
                prop_assert_eq!(u32::from(s) & SILHOUETTE_BIT, SILHOUETTE_BIT);
            }
            prop_assert_eq!(i64::from(s & COUNT_BITS as u8), net.rem_euclid(128));
        }
    }

    #[test]
    fn counts_past_127_wrap_without_losing_the_mark() {
        let mut s = SILHOUETTE_BIT as u8;
        for _ in 0..130 {
            s = wrap_update(s, true, COUNT_BITS as u8);
        }
        assert_eq!(s, 0x80 | 2);
        for _ in 0..131 {
            s = wrap_update(s, false, COUNT_BITS as u8);
        }
        assert_eq!(s, 0x80 | 127);
    }
}
