//! Decimal numbers as NC programs write them: `[+|-]digits[.digits]`, no exponent.
//!
//! The fast path is exact: with at most 15 digits the mantissa is an exact f64 and 10^k
//! (k ≤ 15) is exact too, so one IEEE division gives the correctly rounded value —
//! the same bits as `str::parse`. Longer numbers go through `str::parse`.

/// A number read from the program text.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Number {
    pub value: f64,
    /// A decimal point was written (matters for Fanuc's decimal input switch).
    pub has_point: bool,
}

const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Parses a number at `b[i..]`. Returns the number and the index after it, or `None` if no
/// digit is there. Overlong or overflowing values fall back to the standard parser; an
/// infinite result is rejected.
#[inline]
pub fn parse(b: &[u8], start: usize) -> Option<(Number, usize)> {
    let rest = b.get(start..)?;
    let (neg, skip) = match rest.first() {
        Some(b'-') => (true, 1),
        Some(b'+') => (false, 1),
        _ => (false, 0),
    };
    let body = &rest[skip..];
    let (mut mantissa, int_len) = digits(body, 0);
    let mut len = int_len;
    let mut frac = 0usize;
    let has_point = body.get(int_len) == Some(&b'.');
    if has_point {
        (mantissa, frac) = digits(&body[int_len + 1..], mantissa);
        len = int_len + 1 + frac;
    }
    let ndigits = int_len + frac;
    if ndigits == 0 {
        return None;
    }
    let value = if ndigits <= 15 {
        // Exact: mantissa < 10^15 < 2^53 and 10^frac with frac <= 15 are exact f64s.
        mantissa as f64 / POW10[frac.min(15)]
    } else {
        let text = std::str::from_utf8(&body[..len]).ok()?;
        let v: f64 = text.parse().ok()?;
        if !v.is_finite() {
            return None;
        }
        v
    };
    let value = if neg && value != 0.0 { -value } else { value };
    Some((Number { value, has_point }, start + skip + len))
}

/// Reads a run of digits into `m`; returns the new mantissa and the run length.
#[inline(always)]
fn digits(s: &[u8], mut m: u64) -> (u64, usize) {
    let mut k = 0;
    while k < s.len() {
        let d = s[k].wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        m = m.wrapping_mul(10).wrapping_add(d as u64);
        k += 1;
    }
    (m, k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn p(s: &str) -> Option<f64> {
        parse(s.as_bytes(), 0).map(|(n, _)| n.value)
    }

    #[test]
    fn forms() {
        assert_eq!(p("12.5"), Some(12.5));
        assert_eq!(p("-0.0001"), Some(-0.0001));
        assert_eq!(p("+3"), Some(3.0));
        assert_eq!(p(".5"), Some(0.5));
        assert_eq!(p("5."), Some(5.0));
        assert_eq!(p("-0"), Some(0.0));
        assert_eq!(p("-"), None);
        assert_eq!(p("."), None);
        assert!(!parse(b"100", 0).unwrap().0.has_point);
        assert!(parse(b"100.", 0).unwrap().0.has_point);
    }

    proptest! {
        #[test]
        fn same_bits_as_std(int in 0u64..10_000_000_000, frac in 0u32..100_000_000, fd in 0usize..9, neg: bool) {
            let f = format!("{frac:08}");
            let text = if fd == 0 { format!("{int}") } else { format!("{int}.{}", &f[..fd]) };
            let text = if neg { format!("-{text}") } else { text };
            let want: f64 = text.parse().unwrap();
            let want = if want == 0.0 { 0.0 } else { want };
            let (got, end) = parse(text.as_bytes(), 0).unwrap();
            prop_assert_eq!(end, text.len());
            prop_assert_eq!(got.value.to_bits(), want.to_bits(), "{}", text);
        }

        #[test]
        fn long_numbers_exact(s in "[0-9]{1,30}\\.[0-9]{0,30}") {
            let want: f64 = s.parse().unwrap();
            prop_assert_eq!(p(&s).unwrap().to_bits(), want.to_bits());
        }
    }
}
