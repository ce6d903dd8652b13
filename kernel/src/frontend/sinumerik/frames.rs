//! SINUMERIK frame statements (Fundamentals, "Coordinate transformations (frames)";
//! docs/sinumerik.md "Frames"): TRANS, ROT, SCALE, MIRROR replace the programmable frame,
//! ATRANS, AROT, ASCALE, AMIRROR chain onto it in the coordinates it has made so far. Each
//! stands in a block of its own; the map itself is frame.rs.

use super::super::fault::{fault, R};
use super::super::frame::Affine;
use super::super::interpreter::Interpreter;
use super::super::lexer::Cursor;
use super::super::number;
use super::super::words::{checked, Val};
use super::statements::Keyword;
use crate::alarm::AlarmCode;
use crate::frontend::block::TrcSide;
use crate::machine_data::AXIS_NAMES;

/// Largest scale factor a frame takes (beyond it a value is a typing error).
const MAX_FACTOR: f64 = 1e4;

/// The words of a frame statement as written: X Y Z and `RPL=`, with their offsets.
#[derive(Default)]
struct FrameWords {
    axis: [Option<Val>; 3],
    rpl: Option<Val>,
}

impl Interpreter<'_> {
    /// The frame statement `word` (the cursor after it; `at` its offset): the new frame.
    pub(in crate::frontend) fn frame_statement(
        &mut self,
        word: Keyword,
        c: &mut Cursor,
        at: usize,
    ) -> R<()> {
        // A frame change under compensation would move the contour under the tool's
        // equidistant (docs/sinumerik.md, "Frames": refused, [unconfirmed]).
        if self.block.modal.trc != TrcSide::Off {
            return Err(self.forbidden_with_trc(word.text(), at));
        }
        let fw = self.frame_statement_words(c, word)?;
        let step = self.frame_step(word, &fw)?;
        let mut frame = self.coords.frame;
        if matches!(
            word,
            Keyword::Trans | Keyword::Rot | Keyword::Scale | Keyword::Mirror
        ) {
            frame.set(step);
        } else {
            frame.chain(&step);
        }
        if let Some(k) = (0..3).find(|&k| !self.md.has_axis(k) && !frame.keeps_axis(k)) {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!(
                    "{}: the frame would move axis {}, which this machine does not have",
                    word.text(),
                    AXIS_NAMES[k]
                ),
            ));
        }
        self.coords.frame = frame;
        Ok(())
    }

    /// The map one statement programs (the identity for a bare TRANS, ROT, SCALE, MIRROR:
    /// they clear the frame).
    fn frame_step(&self, word: Keyword, fw: &FrameWords) -> R<Affine> {
        let units = self.block.modal.units;
        let step = match word {
            Keyword::Trans | Keyword::ATrans => {
                let v = fw.axis.map(|a| a.map_or(0.0, |a| self.length(a, units)));
                Affine::translation(v)
            }
            Keyword::Rot | Keyword::ARot => match fw.rpl {
                // In the working plane: about its normal, the abscissa towards the ordinate.
                Some(a) => Affine::rotation(self.block.modal.plane.normal as usize, a.value),
                // About the axes: Z, then the turned Y, then the twice turned X (RPY).
                None => {
                    let deg = fw.axis.map(|a| a.map_or(0.0, |a| a.value));
                    Affine::rotation(2, deg[2])
                        .after(&Affine::rotation(1, deg[1]))
                        .after(&Affine::rotation(0, deg[0]))
                }
            },
            Keyword::Scale | Keyword::AScale => {
                let mut s = [1.0; 3];
                for (k, a) in fw.axis.iter().enumerate() {
                    if let Some(a) = a {
                        s[k] = factor(*a)?;
                    }
                }
                Affine::scaling(s)
            }
            _ => Affine::scaling(fw.axis.map(|a| if a.is_some() { -1.0 } else { 1.0 })),
        };
        Ok(step)
    }

    /// X Y Z (a number, or `=expression`) and, after ROT and AROT, `RPL=expression`; a
    /// comment may end the block.
    fn frame_statement_words(&mut self, c: &mut Cursor, word: Keyword) -> R<FrameWords> {
        let mut fw = FrameWords::default();
        loop {
            c.skip_blanks();
            let at = c.i;
            match c.peek() {
                None | Some(b';') => break,
                Some(b'(') => {
                    if !c.skip_comment() {
                        return Err(fault(AlarmCode::Syntax, at, "comment not closed with ')'"));
                    }
                    continue;
                }
                _ => {}
            }
            if c.keyword("RPL") {
                self.rpl_word(c, word, &mut fw, at)?;
                continue;
            }
            let letter = c.letter().unwrap_or(b'?');
            // An address, not the start of a longer name.
            let single = !matches!(c.peek_at(1), Some(b) if b.is_ascii_alphabetic() || b == b'_');
            match letter {
                b'X'..=b'Z' if single => {
                    c.i += 1;
                    let v = self.frame_value(c, at)?;
                    let k = (letter - b'X') as usize;
                    if fw.rpl.is_some() {
                        return Err(rpl_and_axes(at));
                    }
                    super::super::words::set_once(&mut fw.axis[k], v, ["X", "Y", "Z"][k])?;
                }
                l if single && self.md.axes.of_letter(l).is_some() => {
                    return Err(fault(
                        AlarmCode::NotSupported,
                        at,
                        format!("{}: softnc's frames act on X, Y and Z only", word.text()),
                    ))
                }
                _ => {
                    return Err(fault(
                        AlarmCode::Syntax,
                        at,
                        format!(
                            "{} stands in a block of its own and takes X, Y, Z{}",
                            word.text(),
                            if matches!(word, Keyword::Rot | Keyword::ARot) {
                                " or RPL="
                            } else {
                                ""
                            }
                        ),
                    ))
                }
            }
        }
        Ok(fw)
    }

    /// `RPL=expression` at the cursor: the rotation in the working plane.
    fn rpl_word(&mut self, c: &mut Cursor, word: Keyword, fw: &mut FrameWords, at: usize) -> R<()> {
        if !matches!(word, Keyword::Rot | Keyword::ARot) {
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!("RPL= belongs to ROT and AROT, not to {}", word.text()),
            ));
        }
        if fw.axis.iter().any(Option::is_some) {
            return Err(rpl_and_axes(at));
        }
        c.i += 3;
        c.skip_blanks();
        if c.peek() != Some(b'=') {
            return Err(fault(AlarmCode::Syntax, at, "RPL must be followed by '='"));
        }
        let v = self.frame_value(c, at)?;
        super::super::words::set_once(&mut fw.rpl, v, "RPL=")
    }

    /// The value after an address of a frame statement: a number, or `=expression`.
    fn frame_value(&mut self, c: &mut Cursor, at: usize) -> R<Val> {
        if c.peek() == Some(b'=') {
            c.i += 1;
            let v = super::expr::eval(c, &self.sinumerik.store)?;
            return checked(Val::computed(v, at));
        }
        match number::parse(c.b, c.i).filter(|(_, e)| *e <= c.end) {
            Some((n, next)) => {
                c.i = next;
                checked(Val::new(n, at))
            }
            None => Err(fault(
                AlarmCode::BadNumber,
                c.i,
                "a number or '=' and an expression expected",
            )),
        }
    }
}

/// A scale factor: not 0 (the frame could not be undone), at most [`MAX_FACTOR`].
fn factor(v: Val) -> R<f64> {
    if v.value == 0.0 || v.value.abs() > MAX_FACTOR {
        return Err(fault(
            AlarmCode::BadNumber,
            v.at,
            format!(
                "scale factor {} out of range (not 0, at most {MAX_FACTOR})",
                v.value
            ),
        ));
    }
    Ok(v.value)
}

#[cold]
fn rpl_and_axes(at: usize) -> Box<super::super::fault::Fault> {
    fault(
        AlarmCode::Syntax,
        at,
        "a rotation takes RPL= (in the working plane) or angles about X, Y, Z, not both",
    )
}

#[cfg(test)]
mod tests {
    use crate::alarm::{Alarm, AlarmCode};
    use crate::frontend::{interpret, Block, MotionKind, TrcSide};
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;

    fn md(over: &[&str]) -> MachineData {
        let mut o = vec!["dialect=siemens-840d".to_string()];
        o.extend(over.iter().map(|s| s.to_string()));
        MachineData::load(None, &o).expect("machine data")
    }

    fn run_md(md: &MachineData, src: &str) -> Result<Vec<Block>, Alarm> {
        interpret("p", src, md, &ToolTable::builtin())
    }

    fn ends(src: &str) -> Vec<[f64; 3]> {
        ends_md(&md(&[]), src)
    }

    fn ends_md(md: &MachineData, src: &str) -> Vec<[f64; 3]> {
        run_md(md, src)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| b.motion.map(|m| m.end))
            .collect()
    }

    fn alarm(src: &str) -> (AlarmCode, u32, u32) {
        let a = run_md(&md(&[]), src).unwrap_err();
        (a.code, a.line, a.col)
    }

    #[track_caller]
    fn near(got: [f64; 3], want: [f64; 3]) {
        assert!(
            (0..3).all(|i| (got[i] - want[i]).abs() < 1e-9),
            "{got:?} != {want:?}"
        );
    }

    #[test]
    fn additive_statements_act_in_the_coordinates_made_so_far() {
        // TRANS X10: zero at (10, 0). AROT RPL=90: the axes turn, X now along +Y. ATRANS X5:
        // 5 along the turned X, zero at (10, 5). G1 X2 Y3: (2, 3) turned (−3, 2), plus the
        // zero: (7, 7). G91 X5: 5 along the turned X: (7, 12).
        let e = ends(
            "N10 G0 X0 Y0 Z0\nN20 TRANS X10\nN30 AROT RPL=90\nN40 ATRANS X5\n\
             N50 G1 X2 Y3 F100\nN60 G91 X5\n",
        );
        near(e[1], [7.0, 7.0, 0.0]);
        near(e[2], [7.0, 12.0, 0.0]);
        // The other order: ATRANS X5 first, then AROT, then ATRANS X10 along the turned X:
        // zero (5, 10); X0 Y0 goes there.
        let e = ends("TRANS X5\nAROT RPL=90\nATRANS X10\nG0 X0 Y0\n");
        near(e[0], [5.0, 10.0, 0.0]);
    }

    #[test]
    fn absolute_statements_replace_the_frame_and_bare_ones_clear_it() {
        // ROT RPL=90 then TRANS X10: the turn is gone, X1 → 11. TRANS alone: X1 → 1.
        // SCALE X2 Y2 then ATRANS X5: the shift is scaled too, zero at 10; X1 → 12.
        // ROT alone clears: X1 → 1.
        let e = ends(
            "ROT RPL=90\nTRANS X10\nG0 X1 Y0\nTRANS\nX1\nSCALE X2 Y2\nATRANS X5\nX1\nROT\nX1\n",
        );
        near(e[0], [11.0, 0.0, 0.0]);
        near(e[1], [1.0, 0.0, 0.0]);
        near(e[2], [12.0, 0.0, 0.0]);
        near(e[3], [1.0, 0.0, 0.0]);
        // X=expression in a frame statement; ASCALE multiplies.
        let e = ends("R1=4\nTRANS X=R1*2 Y=-R1\nASCALE X3\nASCALE X0.5 Y2\nG0 X2 Y1\n");
        near(e[0], [8.0 + 3.0, -4.0 + 2.0, 0.0]);
    }

    #[test]
    fn rotations_about_the_axes_and_in_the_plane() {
        // ROT Z90 = ROT RPL=90 in G17: X10 → (0, 10). In G18 RPL turns Z towards X:
        // Z10 → X10. ROT Y90 X90 (Z, Y', X''): the turn about X acts first.
        // (0, 1, 0) turned about X by 90° is (0, 0, 1), about Y by 90° (Z towards X) (1, 0, 0).
        let e =
            ends("ROT Z90\nG0 X10 Y0 Z0\nG18\nROT RPL=90\nG0 X0 Y0 Z10\nROT X90 Y90\nX0 Y1 Z0\n");
        near(e[0], [0.0, 10.0, 0.0]);
        near(e[1], [10.0, 0.0, 0.0]);
        near(e[2], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn a_mirror_turns_circles_and_the_side_chosen_after_it() {
        // MIRROR X0: X10 → −10; G2 becomes G3; G41 becomes G42 (selected after the mirror).
        // AMIRROR X0 mirrors back: X10 → 10.
        let b = run_md(
            &md(&[]),
            "MIRROR X0\nG0 X0 Y0\nT1 D1 G41 G1 X10 Y0 F100\nG2 X20 Y-10 CR=10\n\
             G40 G1 X30 Y-20\nAMIRROR X0\nG0 X10\n",
        )
        .unwrap();
        let m: Vec<_> = b.iter().filter_map(|b| b.motion).collect();
        near(m[1].end, [-10.0, 0.0, 0.0]);
        assert_eq!(b[2].modal.trc, TrcSide::Right);
        assert_eq!(m[2].kind, MotionKind::ArcCcw);
        near(m[2].end, [-20.0, -10.0, 0.0]);
        near(m[2].center, [-10.0, -10.0, 0.0]);
        near(m[4].end, [10.0, -20.0, 0.0]);
    }

    #[test]
    fn the_frame_acts_before_the_settable_zero_and_supa_g53_g153_suppress_it() {
        // G54 X100: ROT RPL=90 about the G54 zero, X10 → (100, 10). G500: the frame stays,
        // about the machine zero: X10 Y0 → (0, 10). SUPA, G53, G153: X5 Y5 in machine coordinates,
        // this block only.
        let mut m = md(&[]);
        m.work_offsets.set(1, 0, 100.0);
        m.work_offsets.set(5, 1, 7.0);
        let e = ends_md(
            &m,
            "G54\nROT RPL=90\nG0 X10 Y0\nG500 X10 Y0\nSUPA X5 Y5\nX10 Y0\nG53 X5 Y5\nG153 X6\n\
             G505 X10 Y0\n",
        );
        near(e[0], [100.0, 10.0, 0.0]);
        near(e[1], [0.0, 10.0, 0.0]);
        near(e[2], [5.0, 5.0, 0.0]);
        near(e[3], [0.0, 10.0, 0.0]);
        near(e[4], [5.0, 5.0, 0.0]);
        near(e[5], [6.0, 5.0, 0.0]);
        // G505: set 5 (Y 7), the frame on top: (0, 10 + 7).
        near(e[6], [0.0, 17.0, 0.0]);
    }

    #[test]
    fn ac_ic_and_diameters_under_a_frame() {
        // TRANS X10, G91: X=AC(5) is absolute in the frame (15), Y=5 incremental.
        let e = ends("TRANS X10\nG0 X0 Y0\nG91 X=AC(5) Y5\nG90 X=IC(2)\n");
        near(e[1], [15.0, 5.0, 0.0]);
        near(e[2], [17.0, 5.0, 0.0]);
        // 808D lathe, DIAMON: X40 is radius 20; TRANS Z-5 (the offset in radius terms).
        let lathe = MachineData::load(
            Some(
                &std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                    .join("../config/siemens-808d.toml"),
            ),
            &[],
        )
        .unwrap();
        let e = ends_md(&lathe, "TRANS Z-5\nG0 X40 Z0\nG1 X50 Z-10 F0.2\n");
        near(e[0], [20.0, 0.0, -5.0]);
        near(e[1], [25.0, 0.0, -15.0]);
    }

    #[test]
    fn a_rounding_turns_with_the_frame() {
        // Program: (0, 0) → (10, 0) RND=2 → (10, 10), a left turn: tangent points (8, 0) and
        // (10, 2), centre (8, 2), counter-clockwise. ROT RPL=90 maps (x, y) to (−y, x):
        // (0, 8), then the arc to (−2, 10) about (−2, 8), then (−10, 10).
        let b = run_md(
            &md(&[]),
            "ROT RPL=90\nG0 X0 Y0\nG1 X10 Y0 RND=2 F100\nX10 Y10\n",
        )
        .unwrap();
        let m: Vec<_> = b.iter().filter_map(|b| b.motion).collect();
        near(m[1].end, [0.0, 8.0, 0.0]);
        assert_eq!(m[2].kind, MotionKind::ArcCcw);
        near(m[2].end, [-2.0, 10.0, 0.0]);
        near(m[2].center, [-2.0, 8.0, 0.0]);
        near(m[3].end, [-10.0, 10.0, 0.0]);
    }

    #[test]
    fn a_lathe_turns_in_its_plane_only() {
        // 808D, G18 (Z abscissa, X ordinate), no Y axis: RPL=90 turns Z towards X, so Z10
        // goes to X10 (radius); a frame that would move Y is refused at its statement.
        let lathe = MachineData::load(
            Some(
                &std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                    .join("../config/siemens-808d.toml"),
            ),
            &[],
        )
        .unwrap();
        let e = ends_md(&lathe, "ROT RPL=90\nG0 X0 Z10\n");
        near(e[0], [10.0, 0.0, 0.0]);
        for src in ["ROT Z30\n", "TRANS Y5\n", "N5 AROT X10\n"] {
            let a = run_md(&lathe, src).unwrap_err();
            assert_eq!(a.code, AlarmCode::NotSupported, "{src}");
        }
    }

    #[test]
    fn what_the_frame_statements_refuse() {
        // Under compensation: alarm 10754 at the statement.
        let (code, line, col) = alarm("T1 D1 G41 G1 X0 Y0 F100\nN20 ATRANS X5\n");
        assert_eq!((code, line, col), (AlarmCode::ForbiddenWithTrc, 2, 5));
        // Not in a block with other words, neither before nor after.
        assert_eq!(alarm("G1 TRANS X10\n").0, AlarmCode::UndefinedName);
        assert_eq!(alarm("TRANS X10 G1\n"), (AlarmCode::Syntax, 1, 11));
        assert_eq!(alarm("TRANS RPL=5\n"), (AlarmCode::Syntax, 1, 7));
        assert_eq!(alarm("ROT X10 RPL=5\n"), (AlarmCode::Syntax, 1, 9));
        assert_eq!(alarm("TRANS X1 X2\n"), (AlarmCode::AddressTwice, 1, 10));
        assert_eq!(alarm("TRANS X1 (shift\n"), (AlarmCode::Syntax, 1, 10));
        assert!(run_md(&md(&[]), "TRANS X1 (shift) ; zero\nG0 X0\n").is_ok());
        assert_eq!(alarm("SCALE X0\n"), (AlarmCode::BadNumber, 1, 7));
        // Unequal scale on the plane's axes: no circle (the line is fine).
        assert_eq!(
            alarm("SCALE X2 Y3\nG1 X10 Y0 F100\nG2 X0 Y10 CR=10\n"),
            (AlarmCode::NotSupported, 3, 1)
        );
        // A turn about X tilts the XY plane: lines go, circles and compensation do not.
        assert!(run_md(&md(&[]), "ROT X30\nG1 X10 Y10 Z0 F100\n").is_ok());
        assert_eq!(
            alarm("ROT X30\nG1 X10 F100\nG3 X0 Y10 CR=10\n"),
            (AlarmCode::NotSupported, 3, 1)
        );
        assert_eq!(
            alarm("ROT X30\nT1 D1 G41 G1 X10 F100\n"),
            (AlarmCode::NotSupported, 2, 7)
        );
    }
}
