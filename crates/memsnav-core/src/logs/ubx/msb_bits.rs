//! Bit fields of the navigation messages that u-blox hands as whole words
//! packed most significant bit first (Galileo I/NAV page pairs, GPS CNAV
//! messages), and the CRC-24Q both ICDs protect them with.

/// CRC-24Q generator polynomial without its x^24 term (Galileo OS SIS ICD
/// §4.3.2.3, IS-GPS-200 §30.3.5: the same code).
const CRC24Q_POLY: u32 = 0x86_4CFB;

/// CRC-24Q of `bits` bits of `data` from bit `first` (most significant
/// first), computed bit by bit with a zero start (leading zero bits, the
/// ICDs' padding to whole bytes, leave it unchanged).
pub(super) fn crc24q(data: &[u8], first: usize, bits: usize) -> u32 {
    (first..first + bits).fold(0u32, |crc, k| {
        let bit = u32::from(data[k / 8] >> (7 - k % 8) & 1);
        let top = (crc >> 23) & 1;
        let crc = (crc << 1) & 0x00FF_FFFF;
        if top ^ bit == 1 {
            crc ^ CRC24Q_POLY
        } else {
            crc
        }
    })
}

/// `len` bits (≤ 64) from bit `first` of `data` (0-based), most
/// significant first.
pub(super) fn bits(data: &[u8], first: usize, len: usize) -> u64 {
    (first..first + len).fold(0u64, |acc, k| {
        (acc << 1) | u64::from(data[k / 8] >> (7 - k % 8) & 1)
    })
}

/// The two's complement value of the `len` bits (≤ 64) of `value`.
pub(super) fn signed(value: u64, len: usize) -> f64 {
    (((value << (64 - len)) as i64) >> (64 - len)) as f64
}

/// The bits of `data` at `positions` (most significant first), packed
/// from the first bit of the result.
pub(super) fn gather<const N: usize>(
    data: &[u8],
    positions: impl Iterator<Item = usize>,
) -> [u8; N] {
    let mut out = [0u8; N];
    for (k, src) in positions.enumerate() {
        out[k / 8] |= (data[src / 8] >> (7 - src % 8) & 1) << (7 - k % 8);
    }
    out
}

/// Words of 32 bits as their bytes, most significant first (the order the
/// bits were transmitted in).
pub(super) fn word_bytes<const N: usize, const B: usize>(words: &[u32; N]) -> [u8; B] {
    let mut out = [0u8; B];
    for (chunk, w) in out.chunks_mut(4).zip(words) {
        chunk.copy_from_slice(&w.to_be_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc24q_check_value() {
        // The CRC-24Q check value of "123456789" (RTCM 10403 / RFC 4880's
        // polynomial with a zero start): 0xCDE703.
        assert_eq!(crc24q(b"123456789", 0, 72), 0xCD_E703);
        // Leading zero bits change nothing (the ICD pads to whole bytes).
        let mut padded = vec![0u8];
        padded.extend_from_slice(b"123456789");
        assert_eq!(crc24q(&padded, 4, 76), 0xCD_E703);
    }

    #[test]
    fn fields_and_signs() {
        let data = [0b1011_0000, 0xFF, 0x00, 0x01];
        assert_eq!(bits(&data, 0, 4), 0b1011);
        assert_eq!(bits(&data, 2, 8), 0b1100_0011);
        assert_eq!(signed(0b1011, 4), -5.0);
        assert_eq!(signed(0b0111, 4), 7.0);
        // 33-bit fields (CNAV's M₀, e, ω) keep their sign.
        assert_eq!(signed(1 << 32, 33), -(2f64.powi(32)));
        assert_eq!(bits(&data, 31, 1), 1);
        let w: [u8; 8] = word_bytes(&[0x0102_0304u32, 0xA0B0_C0D0]);
        assert_eq!(w, [1, 2, 3, 4, 0xA0, 0xB0, 0xC0, 0xD0]);
    }
}
