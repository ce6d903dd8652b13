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

const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// Parses a number at `b[i..]`. Returns the number and the index after it, or `None` if no
/// digit is there. Overlong or overflowing values fall back to the standard parser; an
/// infinite result is rejected.
#[inline(always)]
pub fn parse(b: &[u8], start: usize) -> Option<(Number, usize)> {
    let (neg, int_start) = match b.get(start) {
        Some(b'-') => (true, start + 1),
        Some(b'+') => (false, start + 1),
        _ => (false, start),
    };
    let (mut mantissa, int_end) = digits(b, int_start, 0);
    let mut end = int_end;
    let has_point = b.get(int_end) == Some(&b'.');
    if has_point {
        (mantissa, end) = digits(b, int_end + 1, mantissa);
    }
    let frac = if has_point { end - int_end - 1 } else { 0 };
    let ndigits = (int_end - int_start) + frac;
    if ndigits == 0 {
        return None;
    }
    let value = match POW10.get(frac) {
        // Exact: mantissa < 10^15 < 2^53 and 10^frac with frac <= 15 are exact f64s.
        // (As i64: mantissa < 2^63 here, and the signed conversion is one instruction.)
        Some(&scale) if ndigits <= 15 => mantissa as i64 as f64 / scale,
        _ => {
            let text = std::str::from_utf8(b.get(int_start..end)?).ok()?;
            let v: f64 = text.parse().ok()?;
            if !v.is_finite() {
                return None;
            }
            v
        }
    };
    let value = if neg && value != 0.0 { -value } else { value };
    Some((Number { value, has_point }, end))
}

/// Reads a run of digits starting at `b[i]` into `m`; returns the new mantissa and the index
/// after the run. The mantissa wraps on overflow: callers only use it for at most 15 digits.
/// (A SWAR version reading eight bytes at a time was measured slower on these short numbers.)
#[inline(always)]
fn digits(b: &[u8], mut i: usize, mut m: u64) -> (u64, usize) {
    while let Some(&c) = b.get(i) {
        let d = c.wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        m = m.wrapping_mul(10).wrapping_add(d as u64);
        i += 1;
    }
    (m, i)
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

    /// An independent reference: the extent by iterators, the value by `str::parse` of
    /// `<digits>e-<fraction digits>`.
    fn reference(b: &[u8], start: usize) -> Option<(Number, usize)> {
        let rest = b.get(start..)?;
        let (neg, skip) = match rest.first() {
            Some(b'-') => (true, 1),
            Some(b'+') => (false, 1),
            _ => (false, 0),
        };
        let body = &rest[skip..];
        let int_len = body.iter().take_while(|c| c.is_ascii_digit()).count();
        let has_point = body.get(int_len) == Some(&b'.');
        let frac = if has_point {
            body[int_len + 1..]
                .iter()
                .take_while(|c| c.is_ascii_digit())
                .count()
        } else {
            0
        };
        if int_len + frac == 0 {
            return None;
        }
        let len = if has_point {
            int_len + 1 + frac
        } else {
            int_len
        };
        let text = std::str::from_utf8(&body[..len]).ok()?.replace('.', "");
        let digits = if text.is_empty() { "0" } else { &text };
        let v: f64 = format!("{digits}e-{frac}").parse().ok()?;
        if !v.is_finite() {
            return None;
        }
        let value = if neg && v != 0.0 { -v } else { v };
        Some((Number { value, has_point }, start + skip + len))
    }

    proptest! {
        #[test]
        fn same_as_reference(s in "[-+]?[0-9]{0,20}(\\.[0-9]{0,20})?[ X.;\n0-9a-z\u{e9}]{0,12}", pre in 0usize..3) {
            let text = format!("{}{s}", "G".repeat(pre));
            let got = parse(text.as_bytes(), pre);
            let want = reference(text.as_bytes(), pre);
            prop_assert_eq!(got.map(|(n, e)| (n.value.to_bits(), n.has_point, e)),
                want.map(|(n, e)| (n.value.to_bits(), n.has_point, e)), "{:?}", text);
        }

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
