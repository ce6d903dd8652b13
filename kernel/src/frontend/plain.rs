//! The plain-block fast path: the common block — at most one motion G code (not polar), axis
//! and centre words with their numbers written out, nothing else — read and built in one pass,
//! without the word loop's collection and the general build. For anything else, and for
//! anything an alarm would come from, it returns `None` with the block untouched, and the full
//! path reads the block from the same place: both ways give the same block (tested below).
//! docs/benchmarks.md measures it.

use super::arc::{self, CentreSpec};
use super::block::*;
use super::build::{in_range, reset};
use super::interpreter::Interpreter;
use super::lexer::{column, Cursor};
use super::number;
use super::words::{Val, MAX_VALUE};
use crate::dialect::{GCodeDef, GEffect, G_CODES};

/// What a byte is to [`Interpreter::plain`]: 0..=5 the words X Y Z I J K (either case),
/// `G_WORD`, or one of the marks below; one table lookup instead of a chain of tests per byte.
const G_WORD: u8 = 6;
const BLANK: u8 = 7;
const LINE_FEED: u8 = 8;
const OTHER: u8 = 9;
static PLAIN_BYTE: [u8; 256] = {
    let mut t = [OTHER; 256];
    let words = *b"XYZIJKG";
    let mut k = 0;
    while k < words.len() {
        t[words[k] as usize] = k as u8;
        t[words[k].to_ascii_lowercase() as usize] = k as u8;
        k += 1;
    }
    t[b' ' as usize] = BLANK;
    t[b'\t' as usize] = BLANK;
    t[b'\r' as usize] = BLANK;
    t[b'\n' as usize] = LINE_FEED;
    t
};

/// A plain block's words as read.
struct PlainWords {
    /// X Y Z I J K.
    vals: [Val; 6],
    /// Bit k: word k written; bit `G_WORD`: a G code.
    seen: u8,
    mode: MotionMode,
    /// Where the reading stopped: the end of the text or a line feed.
    end: usize,
}

impl Interpreter<'_> {
    /// A plain block that is a line of its own, read without looking for the line's end
    /// first: it starts with one of the plain block's words and stops at the line feed.
    /// Anything else is left to [`Self::next_segment`], nothing changed but the block's line
    /// fields, which it sets again.
    #[inline]
    pub(super) fn plain_line(&mut self) -> bool {
        let b = self.src;
        let mut i = self.pos;
        while matches!(b.get(i), Some(b' ' | b'\t' | b'\r')) {
            i += 1;
        }
        if b.get(i).is_none_or(|&c| PLAIN_BYTE[c as usize] > G_WORD) {
            return false;
        }
        self.blk_line = self.line;
        self.blk_line_start = self.line_start;
        self.blk_number = None;
        let Some(end) = self.plain(Cursor::new(b, i, b.len()), i) else {
            return false;
        };
        self.block.program = self.calls.running.program;
        let start = self.pos;
        // As `next_segment` leaves it after a line.
        self.pos = end + 1;
        self.line += 1;
        self.line_start = self.pos;
        if start == self.frontier.0 && self.calls.running.program == 0 {
            // SINUMERIK: a plain block holds no structure word and no label: read.
            self.frontier = (self.pos, self.line, self.line_start);
        }
        true
    }

    /// Reads and builds a plain block at the cursor; returns where it stopped, or `None`
    /// (block untouched) for anything that is not plain.
    #[inline]
    pub(super) fn plain(&mut self, c: Cursor, block_col: usize) -> Option<usize> {
        if self.area.limited {
            return None;
        }
        let w = self.plain_words(c)?;
        let (mode, seen) = (w.mode, w.seen);
        let programmed = seen & 7;
        let arc = mode.is_arc();
        if !mode.is_plain() || programmed == 0 || (seen & 0x38 != 0) != arc {
            return None;
        }
        if mode != MotionMode::Rapid && self.block.modal.feed <= 0.0 {
            return None;
        }
        let start = self.cur;
        let end = self.plain_end(&w.vals, programmed, start)?;
        let centre = if arc {
            self.plain_centre(&w, start, end)?
        } else {
            end
        };
        // Nothing fails from here on.
        self.calls.running.started = true;
        let col = column(self.src, self.blk_line_start, block_col);
        reset(&mut self.block, self.blk_line, col, self.blk_number);
        let blk = &mut self.block;
        blk.words.clear();
        blk.modal.motion = mode;
        self.vars.tool_length = blk.modal.length;
        self.vars.tool_radius = blk.modal.radius;
        blk.motion = Some(Motion {
            kind: mode.kind(),
            plane: blk.modal.plane,
            start,
            end,
            center: centre,
            programmed: programmed.into(),
        });
        self.cur = end;
        Some(w.end)
    }

    /// The words up to the end of the text or a line feed, if they are all plain ones.
    #[inline(always)]
    fn plain_words(&self, c: Cursor) -> Option<PlainWords> {
        let mut w = PlainWords {
            vals: [Val {
                value: 0.0,
                at: 0,
                has_point: false,
            }; 6],
            seen: 0,
            mode: self.block.modal.motion,
            end: c.i,
        };
        // The block's text alone: a number cannot run past its end.
        let text = c.b.get(..c.end)?;
        let mut i = c.i;
        while let Some(&ch) = text.get(i) {
            let k = PLAIN_BYTE[ch as usize];
            if k > G_WORD {
                match k {
                    BLANK => {
                        i += 1;
                        continue;
                    }
                    LINE_FEED => break,
                    _ => return None,
                }
            }
            if w.seen & (1 << k) != 0 {
                return None;
            }
            w.seen |= 1 << k;
            let at = i;
            let (n, next) = number::parse(text, at + 1)?;
            if n.value.abs() > MAX_VALUE {
                return None;
            }
            i = next;
            if k == G_WORD {
                w.mode = self.plain_motion(n.value)?;
            } else {
                w.vals[k as usize] = Val::new(n, at);
            }
        }
        w.end = i;
        Some(w)
    }

    /// The motion mode of a G number, if it is a motion code allowed with TRC.
    #[inline(always)]
    fn plain_motion(&self, v: f64) -> Option<MotionMode> {
        if !((0.0..G_CODES as f64).contains(&v) && v as u16 as f64 == v) {
            return None;
        }
        match self.d.gcode(v as u16) {
            Some(GCodeDef {
                effect: GEffect::Motion(m),
                forbidden_with_trc: false,
                ..
            }) => Some(*m),
            _ => None,
        }
    }

    /// The end point, if every programmed axis exists and lands in range.
    #[inline(always)]
    fn plain_end(&self, vals: &[Val; 6], programmed: u8, start: Pos) -> Option<Pos> {
        let modal = &self.block.modal;
        let offset = self.zero(modal.work_offset);
        let mut end = start;
        for i in 0..3 {
            if programmed & (1 << i) != 0 {
                if !self.md.has_axis(i) {
                    return None;
                }
                end[i] = self.axis_target(vals[i], i, modal, start[i], offset[i]);
                if !in_range(end[i]) {
                    return None;
                }
            }
        }
        Some(end)
    }

    /// The arc centre from I J K, if they lie in the plane and the end point is on the circle.
    #[inline(always)]
    fn plain_centre(&self, w: &PlainWords, start: Pos, end: Pos) -> Option<Pos> {
        let modal = &self.block.modal;
        let plane = modal.plane;
        let mut off = [0.0; 3];
        for (i, o) in off.iter_mut().enumerate() {
            if w.seen & (8 << i) != 0 {
                if !plane.contains(i) {
                    return None;
                }
                *o = self.length(w.vals[3 + i], modal.units);
            }
        }
        let tol = self.md.program.arc_endpoint_tolerance;
        let ccw = w.mode == MotionMode::ArcCcw;
        arc::centre(start, end, plane, ccw, CentreSpec::Offsets(off), tol).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::alarm::Alarm;
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;
    use proptest::prelude::*;

    /// Every block and the alarm that ends a program, read with and without the plain path.
    fn both(
        src: &str,
        md: &MachineData,
        tools: &ToolTable,
    ) -> [Vec<Result<(Block, Pos), Alarm>>; 2] {
        let run = |mut it: Interpreter| {
            let mut got = Vec::new();
            loop {
                match it.next_block() {
                    Ok(Some(b)) => {
                        let b = b.clone();
                        got.push(Ok((b, it.position())));
                    }
                    Ok(None) => break,
                    Err(a) => {
                        got.push(Err(a));
                        break;
                    }
                }
            }
            got
        };
        [
            run(Interpreter::new("p", src, md, tools)),
            run(Interpreter::new("p", src, md, tools).without_plain_path()),
        ]
    }

    /// Words near the plain block's edges: what it takes, and what must send a block to the
    /// full path (other words, comments, doubled words, odd G codes, numbers out of range,
    /// expressions, lower case, no blank between words).
    fn word() -> impl Strategy<Value = String> {
        let num = prop_oneof![
            (-300i32..300, 0u32..10000).prop_map(|(i, f)| format!("{i}.{f:04}")),
            (-300i32..300).prop_map(|i| format!("{i}")),
            Just("2000000000".to_string()),
            Just("-.5".to_string()),
            Just("1.".to_string()),
            Just("".to_string()),
            Just("=5".to_string()),
            Just("0000000000000000012.5".to_string()),
        ];
        let letter = prop_oneof![
            8 => prop::sample::select(vec!["X", "Y", "Z", "I", "J", "K", "x", "y", "i"]),
            1 => prop::sample::select(vec!["F", "R", "M", "S", "D", "A", "U", "N", "P", "T"]),
        ];
        prop_oneof![
            8 => (letter, num).prop_map(|(l, n)| format!("{l}{n}")),
            3 => prop::sample::select(vec![0u32, 1, 2, 3, 1, 2, 3, 4, 17, 18, 19, 40, 41, 42, 90,
                91, 20, 21, 70, 71, 10, 12, 25, 26, 110, 141, 999, 1000])
                .prop_map(|g| format!("G{g}")),
            1 => prop::sample::select(vec!["G1.5", "g01", "(c)", ";c", "X[1+2]", "$IF", "@714"])
                .prop_map(str::to_string),
        ]
    }

    fn line() -> impl Strategy<Value = String> {
        (
            prop::collection::vec(
                (word(), prop::sample::select(vec![" ", "", "  ", "\t"])),
                0..6,
            ),
            prop::option::of(0u32..100),
            prop::sample::select(vec!["", " ", "\t", "/"]),
            prop::sample::select(vec!["", "\r", ";", " "]),
        )
            .prop_map(|(words, n, lead, tail)| {
                let mut l = lead.to_string();
                if let Some(n) = n {
                    l.push_str(&format!("N{n} "));
                }
                for (w, sep) in words {
                    l.push_str(&w);
                    l.push_str(sep);
                }
                l.push_str(tail);
                l
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1000))]
        /// The plain path is a shortcut, not a second interpreter: blocks, positions and
        /// alarms are the same with it and without it, in every dialect.
        #[test]
        fn plain_path_reads_as_the_word_loop(
            lines in prop::collection::vec(line(), 1..12),
            header in prop::sample::select(vec!["G1 F500", "G90 F100 G17", "G91 G1 F100", "G18 F10", "G0", "G70 F1", "G2 F7", "G12 F100", "G26 X100 Y100 Z100 F9"]),
            dialect in prop::sample::select(vec!["siemens-840c", "isg", "fanuc", "siemens-808d"]),
            diameter in any::<bool>(),
        ) {
            let mut set = vec![format!("dialect={dialect}")];
            if diameter {
                set.push("program.diameter_programming=true".into());
            }
            let md = MachineData::load(None, &set).unwrap();
            let tools = ToolTable::builtin();
            let src = format!("{header}\n{}\nM30\n", lines.join("\n"));
            let [fast, full] = both(&src, &md, &tools);
            prop_assert_eq!(fast, full, "{}", src);
        }
    }

    #[test]
    fn plain_blocks_take_the_plain_path() {
        // Guards the test above against a plain path that never runs: the serpentine's
        // blocks are all plain, and reading them that way gives the same blocks.
        let md = MachineData::default();
        let tools = ToolTable::builtin();
        let src = "G1 F100\nG1 X10 Y0\nG2 X10 Y-20 I0 J-10\ng1 x0 y-20\nG3 X0 Y-40 I0.0 J-10.0\n";
        let mut it = Interpreter::new("p", src, &md, &tools);
        it.next_block().unwrap();
        let mut plain = 0;
        for _ in 0..4 {
            let mut probe = it.clone();
            let (start, end) = probe.next_segment().unwrap();
            if probe
                .plain(Cursor::new(probe.src, start, end), start)
                .is_some()
            {
                plain += 1;
            }
            let mut full = it.clone().without_plain_path();
            let b = full.next_block().unwrap().unwrap().clone();
            assert_eq!(it.next_block().unwrap().unwrap(), &b);
        }
        assert_eq!(plain, 4);
    }
}
