//! Thread cutting at a constant lead (Fanuc 0i-TF "Thread cutting (G32)"): a straight move
//! whose lead F is measured along the longer axis — Z for a straight thread and a taper up
//! to 45°, X (a radius) beyond — cut at the lead per spindle revolution.

use super::super::super::block::*;
use super::super::super::fault::{fault, R};
use super::super::super::interpreter::Interpreter;
use super::super::super::words::Words;
use crate::alarm::AlarmCode;

/// The path feed per revolution of a thread move with lead `lead` along its longer axis.
pub fn thread_feed(m: &Motion, lead: f64) -> f64 {
    let d: [f64; 3] = std::array::from_fn(|i| m.end[i] - m.start[i]);
    let long = d.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    if long == 0.0 {
        return lead;
    }
    lead * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() / long
}

impl Interpreter<'_> {
    /// Step 8 under G32: the move, tagged as a thread.
    pub(super) fn thread_cut(&mut self, w: &Words, new: &mut ModalState, at: usize) -> R<()> {
        if w.axis.iter().all(Option::is_none) {
            return self.motion(w, new, at);
        }
        self.lathe_allowed(new, at, "a thread")?;
        self.no_other_words(w, false)?;
        if new.feed <= 0.0 {
            return Err(fault(AlarmCode::NoFeed, at, "a thread needs its lead F"));
        }
        self.motion(w, new, at)?;
        if let Some(m) = self.block.motion {
            self.block.thread = Some(thread_feed(&m, new.feed));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{alarm, moves, moves_with, How::*};
    use crate::alarm::AlarmCode;

    #[test]
    fn a_straight_thread_runs_at_the_lead_and_a_taper_along_its_longer_axis() {
        // From (15, 3) a straight thread to Z-20 at lead 1.5; then a taper X30→X34 over
        // Z-20→Z-28: ΔX 2 (radius), ΔZ 8, Z longer: path √68 = 8.246211251, feed
        // 1.5·8.246211251/8 = 1.54616461.
        let m = moves("G0 X30. Z3.\nG32 Z-20. F1.5\nX34. Z-28.\nG0 X40.\n");
        assert_eq!(
            m,
            [
                (R, 15.0, 3.0),
                (T(1.5), 15.0, -20.0),
                (T(1.54616461), 17.0, -28.0),
                (R, 20.0, -28.0)
            ]
        );
        // A face (scroll) thread: X is the longer axis, lead 2 along it. X40→X20 is 10
        // on the radius, Z 0→-2: path √104 = 10.198039027, feed 2·10.198/10 = 2.039607805.
        let m = moves("G0 X40. Z0.\nG32 X20. W-2. F2.\n");
        assert_eq!(m[1], (T(2.039607805), 10.0, -2.0));
    }

    #[test]
    fn radius_programming_takes_x_as_a_radius() {
        let m = moves_with("G0 X15. Z3.\nG32 U-1. Z-20. F1.\n", true);
        // ΔX −1, ΔZ −23: path √530 = 23.021728866, feed 23.021728866/23 = 1.000944733.
        assert_eq!(m[1], (T(1.000944733), 14.0, -20.0));
    }

    #[test]
    fn every_move_of_straight_taper_and_face_threads_in_radius_programming() {
        // Radius programming, lead F2 (then F1.5). From (12, 5): in to r9.6, a straight
        // thread to Z-30 at 2/rev, out, back; in to r8.9, a taper to (9.9, −30): 1 in X over
        // 35 in Z, Z the longer axis: path feed 2·√(1 + 35²)/35 = 2·√1226/35; out, back.
        // Then from (20, 0) U-8 W-3: 8 on the radius (a diameter would be 4), X the longer
        // axis: lead 1.5 along X, path feed 1.5·√(8² + 3²)/8 = 1.5·√73/8.
        let m = moves_with(
            "G0 X12. Z5.\nX9.6\nG32 Z-30. F2.\nG0 X12.\nZ5.\nX8.9\nG32 X9.9 Z-30.\n\
             G0 X12.\nZ5.\nX20. Z0.\nG32 U-8. W-3. F1.5\nG0 X30. Z20.\n",
            true,
        );
        let r = |v: f64| (v * 1e9).round() / 1e9;
        assert_eq!(
            m,
            [
                (R, 12.0, 5.0),
                (R, 9.6, 5.0),
                (T(2.0), 9.6, -30.0),
                (R, 12.0, -30.0),
                (R, 12.0, 5.0),
                (R, 8.9, 5.0),
                (T(r(2.0 * 1226f64.sqrt() / 35.0)), 9.9, -30.0),
                (R, 12.0, -30.0),
                (R, 12.0, 5.0),
                (R, 20.0, 0.0),
                (T(r(1.5 * 73f64.sqrt() / 8.0)), 12.0, -3.0),
                (R, 30.0, 20.0),
            ]
        );
    }

    #[test]
    fn a_thread_needs_its_lead_and_no_compensation() {
        assert_eq!(
            alarm("G98 G0 X30. Z3.\nG32 Z-20.\n"),
            (AlarmCode::NoFeed, 2, 1)
        );
        assert_eq!(
            alarm("T0101 G0 X30. Z3.\nG42 G1 X28. F0.2\nG32 Z-20. F1.5\n"),
            (AlarmCode::ForbiddenWithTrc, 3, 1)
        );
        // A multiple-start thread's Q is not built; I has no meaning.
        assert_eq!(
            alarm("G0 X30. Z3.\nG32 Z-20. F1.5 Q180000\n"),
            (AlarmCode::NotSupported, 2, 16)
        );
        assert_eq!(
            alarm("G0 X30. Z3.\nG32 Z-20. I1. F1.5\n"),
            (AlarmCode::Syntax, 2, 11)
        );
    }
}
