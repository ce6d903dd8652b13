//! A cursor over one block's text: blanks, comments and the byte-level helpers the
//! interpreter's word loop needs. Positions are byte offsets into the whole program; they are
//! turned into character columns only when an alarm is raised.

#[derive(Clone, Copy, Debug)]
pub struct Cursor<'a> {
    pub b: &'a [u8],
    pub i: usize,
    /// End of the block's text (exclusive).
    pub end: usize,
}

impl<'a> Cursor<'a> {
    pub fn new(b: &'a [u8], start: usize, end: usize) -> Self {
        Cursor { b, i: start, end }
    }

    #[inline]
    pub fn peek(&self) -> Option<u8> {
        if self.i < self.end {
            self.b.get(self.i).copied()
        } else {
            None
        }
    }

    #[inline]
    pub fn peek_at(&self, k: usize) -> Option<u8> {
        let j = self.i + k;
        if j < self.end {
            self.b.get(j).copied()
        } else {
            None
        }
    }

    #[inline]
    pub fn skip_blanks(&mut self) {
        while let Some(c) = self.peek() {
            if c == b' ' || c == b'\t' || c == b'\r' {
                self.i += 1;
            } else {
                break;
            }
        }
    }

    /// Upper-cased ASCII letter at the cursor.
    #[inline]
    pub fn letter(&self) -> Option<u8> {
        self.peek()
            .filter(|c| c.is_ascii_alphabetic())
            .map(|c| c.to_ascii_uppercase())
    }

    /// True if the text at the cursor starts with `word` (ASCII, case-insensitive) and the
    /// character after it is not a letter.
    pub fn keyword(&self, word: &str) -> bool {
        let w = word.as_bytes();
        for (k, &c) in w.iter().enumerate() {
            match self.peek_at(k) {
                Some(x) if x.to_ascii_uppercase() == c => {}
                _ => return false,
            }
        }
        !matches!(self.peek_at(w.len()), Some(c) if c.is_ascii_alphabetic())
    }

    /// Skips a parenthesised comment starting at the cursor. Nested parentheses are allowed.
    /// Returns false if it is not closed before the end of the block.
    pub fn skip_comment(&mut self) -> bool {
        let mut depth = 0u32;
        while let Some(c) = self.peek() {
            self.i += 1;
            if c == b'(' {
                depth += 1;
            } else if c == b')' {
                depth -= 1;
                if depth == 0 {
                    return true;
                }
            }
        }
        false
    }

    /// A dotted name (`V.P.LAUF`, `V.G.WZ_AKT.R`), upper-cased.
    pub fn name(&mut self) -> String {
        let start = self.i;
        while let Some(c) = self.peek() {
            if c.is_ascii_alphanumeric() || c == b'_' || c == b'.' {
                self.i += 1;
            } else {
                break;
            }
        }
        let mut s = String::from_utf8_lossy(&self.b[start..self.i]).to_ascii_uppercase();
        while s.ends_with('.') {
            s.pop();
            self.i -= 1;
        }
        s
    }
}

/// Index of the first byte at or after `i` that is one of `set`, or `b.len()`. Reads eight
/// bytes at a time: program lines are short, and a general `memchr` spends more on setting up
/// than on searching them.
#[inline]
pub fn find_byte<const N: usize>(b: &[u8], mut i: usize, set: [u8; N]) -> usize {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGH: u64 = 0x8080_8080_8080_8080;
    while let Some(&chunk) = b.get(i..).and_then(|s| s.first_chunk::<8>()) {
        let v = u64::from_le_bytes(chunk);
        let mut hits = 0;
        for &s in &set {
            // Zero bytes of x are the matches. The lowest set bit of `(x - ONES) & !x & HIGH`
            // marks the first zero byte exactly (a borrow can only give false hits above it).
            let x = v ^ (ONES * s as u64);
            hits |= x.wrapping_sub(ONES) & !x & HIGH;
        }
        if hits != 0 {
            return i + (hits.trailing_zeros() / 8) as usize;
        }
        i += 8;
    }
    while let Some(c) = b.get(i) {
        if set.contains(c) {
            return i;
        }
        i += 1;
    }
    b.len()
}

/// 1-based character column of byte offset `at` in the line starting at `line_start`.
pub fn column(src: &[u8], line_start: usize, at: usize) -> u32 {
    let at = at.min(src.len());
    let start = line_start.min(at);
    let chars = src[start..at]
        .iter()
        .filter(|&&c| (c & 0xC0) != 0x80)
        .count();
    chars as u32 + 1
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn find_byte_finds_the_first(text in proptest::collection::vec(prop_oneof![
            Just(b'\n'), Just(b'('), Just(b')'), Just(b';'), Just(0x8a), Just(0x0b), Just(0x09),
            any::<u8>(), Just(b'X')], 0..40), start in 0usize..45) {
            let naive = |set: &[u8]| {
                (start.min(text.len())..text.len())
                    .find(|&k| set.contains(&text[k]))
                    .unwrap_or(text.len())
            };
            prop_assert_eq!(find_byte(&text, start, [b'\n']), naive(b"\n"));
            prop_assert_eq!(find_byte(&text, start, [b'\n', b'(', b';']), naive(b"\n(;"));
            prop_assert_eq!(find_byte(&text, start, [b'\n', b'(', b')']), naive(b"\n()"));
        }
    }
}
