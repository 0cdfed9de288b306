//! The Joe & Kuo (2008) direction numbers of the Sobol' sequence: the embedded
//! `new-joe-kuo-6.21201` table, parsed on first use only as far as a sampler needs, and
//! extended to 32 direction words per dimension.

use crate::error::{Error, Result};
use std::sync::OnceLock;

/// The Joe-Kuo table, one line per dimension 2..=21201 after a header line.
const JOE_KUO: &str = include_str!("../../../data/sobol/new-joe-kuo-6.21201.txt");

/// Dimensions available: van der Corput plus the 21200 dimensions of the table.
pub(super) const MAX_DIMS: usize = 21201;

/// Direction words of one dimension; bit `31 - k` is the leading bit of word `k`.
pub(super) type Directions = [u32; 32];

/// Table sizes parsed on demand: a sampler of `d` dimensions uses the smallest that covers `d`,
/// so low-dimensional use never parses the whole file.
const TIERS: [usize; 4] = [64, 256, 1024, MAX_DIMS];

/// A parsed table, or why it could not be parsed (which the tests rule out).
type Parsed = std::result::Result<Vec<Directions>, String>;

/// The parsed tiers.
static TABLES: [OnceLock<Parsed>; TIERS.len()] = [const { OnceLock::new() }; TIERS.len()];

/// Direction words of (at least) the first `dims` dimensions, parsed once per tier.
pub(super) fn table(dims: usize) -> Result<&'static [Directions]> {
    let tier = TIERS
        .iter()
        .position(|&t| dims <= t)
        .unwrap_or(TIERS.len() - 1);
    match TABLES[tier].get_or_init(|| parse_joe_kuo(JOE_KUO, TIERS[tier])) {
        Ok(table) if table.len() >= dims => Ok(table),
        Ok(_) => Err(Error::invalid("dims", dims, format!("1 to {MAX_DIMS}"))),
        Err(message) => Err(Error::invalid(
            "sobol direction table",
            "the embedded Joe-Kuo file",
            format!("a well-formed table ({message})"),
        )),
    }
}

/// Parses the unsigned decimal numbers of one line (`None` on any other character, or on a
/// number above `u32::MAX`).
fn numbers(line: &[u8], out: &mut Vec<u32>) -> Option<()> {
    out.clear();
    let mut value = 0u64;
    let mut digits = 0u32;
    for &byte in line {
        if byte.is_ascii_digit() {
            value = value * 10 + u64::from(byte - b'0');
            digits += 1;
            if digits > 10 {
                return None;
            }
        } else if matches!(byte, b' ' | b'\t' | b'\r') {
            if digits > 0 {
                out.push(u32::try_from(value).ok()?);
            }
            value = 0;
            digits = 0;
        } else {
            return None;
        }
    }
    if digits > 0 {
        out.push(u32::try_from(value).ok()?);
    }
    Some(())
}

/// Parses the first `dims` dimensions of Joe & Kuo's format (`d s a m_1 .. m_s` per line after
/// a header) into 32 direction words each, with dimension 1 (van der Corput) first.
///
/// The initial values `m_1..m_s` (odd, `m_k < 2^k`) are extended by the recurrence of the
/// primitive polynomial `x^s + a_1 x^(s-1) + ... + a_(s-1) x + 1` (Bratley & Fox 1988):
/// `m_k = 2 a_1 m_(k-1) ^ 4 a_2 m_(k-2) ^ ... ^ 2^(s-1) a_(s-1) m_(k-s+1) ^ 2^s m_(k-s) ^
/// m_(k-s)`. In terms of the words `v_k = m_k 2^(32-k)` this reads
/// `v_k = v_(k-s) ^ (v_(k-s) >> s) ^ XOR_i a_i v_(k-i)`.
fn parse_joe_kuo(text: &str, dims: usize) -> Parsed {
    let mut table = Vec::with_capacity(dims);
    table.push(std::array::from_fn(|k| 1u32 << (31 - k)));
    let mut fields = Vec::with_capacity(24);
    for (line_number, line) in text.as_bytes().split(|&b| b == b'\n').enumerate().skip(1) {
        if table.len() == dims {
            break;
        }
        let bad = |what: &str| format!("line {}: {what}", line_number + 1);
        numbers(line, &mut fields).ok_or_else(|| bad("not a list of numbers"))?;
        let [dim, degree, coefficients, initial @ ..] = fields.as_slice() else {
            return Err(bad("fewer than four fields"));
        };
        let s = *degree as usize;
        if *dim as usize != table.len() + 1 {
            return Err(bad("dimensions out of order"));
        }
        if !(1..32).contains(&s) || coefficients >> (s - 1) != 0 || initial.len() != s {
            return Err(bad(
                "degree, coefficients or count of initial numbers out of range",
            ));
        }
        let mut v = [0u32; 32];
        for (k, (slot, &m)) in v.iter_mut().zip(initial).enumerate() {
            if m % 2 == 0 || m >> (k + 1) != 0 {
                return Err(bad("initial direction number not odd and below 2^k"));
            }
            *slot = m << (31 - k);
        }
        // Offsets i with a_i = 1 (bit s - 1 - i of the coefficients).
        let mut taps = [0usize; 32];
        let mut tap_count = 0;
        for i in 1..s {
            taps[tap_count] = i;
            tap_count += ((coefficients >> (s - 1 - i)) & 1) as usize;
        }
        for k in s..32 {
            let mut word = v[k - s] ^ (v[k - s] >> s);
            for &i in &taps[..tap_count] {
                word ^= v[k - i];
            }
            v[k] = word;
        }
        table.push(v);
    }
    if table.len() != dims {
        return Err(format!("{} dimensions instead of {dims}", table.len()));
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sobol_table_parses_and_first_dimensions_match_the_definition() {
        let t = table(MAX_DIMS).unwrap();
        assert_eq!(t.len(), MAX_DIMS);
        // Dimension 2: s = 1, m_1 = 1, polynomial x + 1: m_k = 2 m_(k-1) ^ m_(k-1), so the
        // words are 2^31, 2^31 + 2^30, ... (Pascal's triangle mod 2).
        assert_eq!(t[1][0], 1 << 31);
        assert_eq!(t[1][1], 0xc000_0000);
        assert_eq!(t[1][2], 0xa000_0000);
        assert_eq!(t[1][3], 0xf000_0000);
        // m_k is odd, so word k's lowest set bit is bit 31 - k: the generator matrices have a
        // unit diagonal and every coordinate is a (0, 1)-sequence.
        for dirs in t {
            for (k, &v) in dirs.iter().enumerate() {
                assert_eq!(v.trailing_zeros() as usize, 31 - k);
            }
        }
    }

    #[test]
    fn sobol_parser_rejects_malformed_lines() {
        assert!(parse_joe_kuo("header\n2 1 0 2\n", 2).is_err());
        assert!(parse_joe_kuo("header\n3 1 0 1\n", 2).is_err());
        assert!(parse_joe_kuo("header\n2 1 0 1 1\n", 2).is_err());
        assert!(parse_joe_kuo("header\n2 1 0\n", 2).is_err());
        // Well formed but short.
        assert!(parse_joe_kuo("header\n2 1 0 1\n", 3).is_err());
        assert_eq!(parse_joe_kuo("header\n2 1 0 1\n", 2).unwrap().len(), 2);
        assert!(parse_joe_kuo("header\n2 1 0 x\n", 2).is_err());
    }
}
