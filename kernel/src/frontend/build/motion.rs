//! Motion in the block build: the end point from the axis words (units, diameter, absolute
//! or incremental, zero offset), polar coordinates about the pole (880 4.2.5), the arc centre
//! from I J K or a radius ([`arc`]), the feed a motion needs, and the 840C working area
//! limitation G25/G26 that every end point must keep.

use super::super::arc::{self, ArcError, CentreSpec};
use super::super::block::*;
use super::super::fault::{fault, Fault, R};
use super::super::interpreter::Interpreter;
use super::super::words::{Val, Words};
use crate::alarm::AlarmCode;
use crate::machine_data::{DecimalInput, Units, AXES};

/// 840C G25/G26: the working area limitation, in the basic coordinate system.
#[derive(Clone, Debug)]
pub struct WorkingArea {
    pub min: Pos,
    pub max: Pos,
    /// A limit has been programmed (saves the check on every block otherwise).
    pub limited: bool,
}

impl Default for WorkingArea {
    fn default() -> Self {
        WorkingArea {
            min: [f64::NEG_INFINITY; 3],
            max: [f64::INFINITY; 3],
            limited: false,
        }
    }
}

/// The geometry axes' bits in [`Motion::programmed`].
const GEOMETRY: u16 = 0b111;

/// A coordinate the control takes (bounded like the words, with room for offsets).
#[inline(always)]
pub fn in_range(x: f64) -> bool {
    x.is_finite() && x.abs() <= 1e9
}

impl Interpreter<'_> {
    /// A length that must not be negative (a cycle's retract, relief or allowance R), in
    /// mm: else alarm 12160 at the word, naming it (`what`).
    pub(in crate::frontend) fn non_negative(
        &self,
        v: Val,
        units: Units,
        what: &str,
    ) -> super::super::fault::R<f64> {
        let d = self.length(v, units);
        if d < 0.0 {
            return Err(super::super::fault::fault(
                crate::alarm::AlarmCode::BadNumber,
                v.pos(),
                format!("{what} must not be negative"),
            ));
        }
        Ok(d)
    }

    /// A length value in mm: decimal-input switch, inch conversion.
    pub(in crate::frontend) fn length(&self, v: Val, units: Units) -> f64 {
        let x = self.in_program_units(v, units);
        if units == Units::Inch {
            x * 25.4
        } else {
            x
        }
    }

    /// A value in program units with the decimal-input switch applied (Fanuc: without a
    /// decimal point, least input increments), not yet converted from inch.
    #[inline(always)]
    pub(in crate::frontend) fn in_program_units(&self, v: Val, units: Units) -> f64 {
        if self.d.decimal_switch
            && !v.has_point
            && self.md.program.decimal_input == DecimalInput::Increment
        {
            v.value
                * match units {
                    Units::Mm => self.md.program.least_input_increment_mm,
                    Units::Inch => self.md.program.least_input_increment_inch,
                }
        } else {
            v.value
        }
    }

    /// Where axis `i` goes for its word `a`: in mm, a diameter halved, absolute (plus the zero
    /// offset) or incremental.
    #[inline(always)]
    pub(in crate::frontend) fn axis_target(
        &self,
        a: Val,
        i: usize,
        new: &ModalState,
        start: f64,
        offset: f64,
    ) -> f64 {
        let v = self.length(a, new.units) * diameter_factor(i, new, new.distance);
        match new.distance {
            Distance::Absolute => v + offset,
            Distance::Incremental => start + v,
        }
    }

    /// Step 8: the block's motion, if it has one (written in place: `Motion` is large).
    pub(super) fn motion(&mut self, w: &Words, new: &mut ModalState, block_col: usize) -> R<()> {
        let programmed = self.programmed_axes(w)?;
        if w.path.polar() {
            self.polar_move(w, new, programmed, block_col)?;
        } else if new.motion.is_polar() {
            self.polar(w, new, programmed, block_col)?;
        } else if new.motion == MotionMode::ArcThrough {
            self.arc_through(w, new, programmed, block_col)?;
        } else if new.motion == MotionMode::ArcTangent {
            self.arc_tangent(w, new, programmed, block_col)?;
        } else {
            self.cartesian(w, new, programmed, block_col)?;
        }
        if programmed & !GEOMETRY != 0 {
            self.additional_motion(w, new, programmed, block_col)?;
        }
        Ok(())
    }

    /// The additional axes' move beside the block's motion (docs/axes.md). A block with
    /// only additional axes gets a motion that stands still in X Y Z: a straight move at the
    /// feed, or at rapid under G0 (a circular mode in force does not make it an arc).
    fn additional_motion(
        &mut self,
        w: &Words,
        new: &ModalState,
        programmed: u16,
        block_col: usize,
    ) -> R<()> {
        let add_end = self.additional_end(w, new)?;
        if self.block.motion.is_none() {
            feed_programmed(new, block_col)?;
            let here = self.cur;
            self.set_motion(new, here, here, here, programmed, block_col)?;
            if let Some(m) = &mut self.block.motion {
                if m.kind != MotionKind::Rapid {
                    m.kind = MotionKind::Linear;
                }
            }
        }
        if add_end != self.cur_add {
            self.block.axes = Some(AxisMove {
                from: self.cur_add,
                to: add_end,
            });
        }
        Ok(())
    }

    /// The axes written, as bits (bit i = axis i of [`AXIS_NAMES`]); each must exist on the
    /// machine.
    fn programmed_axes(&self, w: &Words) -> R<u16> {
        let mut programmed = 0u16;
        for (i, a) in w.axis.iter().enumerate() {
            if let Some(a) = a {
                if !self.md.has_axis(i) {
                    return Err(fault(
                        AlarmCode::UnknownAddress,
                        a.at,
                        format!("axis {} is not configured on this machine", AXIS_NAMES[i]),
                    ));
                }
                programmed |= 1 << i;
            }
        }
        for (k, a) in w.additional.iter().enumerate() {
            if a.is_some() {
                programmed |= 1 << (k + 3);
            }
        }
        Ok(programmed)
    }

    /// The work offset absolute positions take: none in a block in machine coordinates.
    pub(super) fn work_offset(&self, new: &ModalState) -> [f64; AXES] {
        if self.machine_coordinates {
            // Fanuc G53 cancels the tool length vector of the axes it moves (0i-MB 14.1.2:
            // the spindle goes to the machine position), as G28 does; Siemens keeps it.
            let mut o = [0.0; AXES];
            if self.d.length_offset == crate::dialect::LengthOffset::HRegister {
                o[new.plane.normal as usize] = -new.length;
            }
            o
        } else {
            self.zero(new.work_offset)
        }
    }

    /// Where the additional axes go for their words: mm (inch converted) or degrees,
    /// absolute (plus the work offset; a modulo axis within its turn, axes.rs) or
    /// incremental.
    pub(super) fn additional_end(&self, w: &Words, new: &ModalState) -> R<Additional> {
        let offset = self.work_offset(new);
        let mut end = self.cur_add;
        for (k, a) in w.additional.iter().enumerate() {
            let (Some(a), Some(ax)) = (a, self.md.axes.get(k + 3)) else {
                continue;
            };
            let rotary = ax.kind == crate::machine_data::AxisKind::Rotary;
            let v = self.length(*a, if rotary { Units::Mm } else { new.units });
            end[k] = match new.distance {
                Distance::Absolute => ax.absolute_target(self.cur_add[k], v + offset[k + 3]),
                Distance::Incremental => self.cur_add[k] + v,
            };
            if !in_range(end[k]) {
                return Err(fault(AlarmCode::BadNumber, a.at, "coordinate out of range"));
            }
        }
        Ok(end)
    }

    /// A block that moves nothing may not name an additional axis: it would be ignored.
    pub(super) fn no_additional_axes(&self, w: &Words, what: &str) -> R<()> {
        match w
            .additional
            .iter()
            .enumerate()
            .find_map(|(k, a)| a.map(|a| (k, a)))
        {
            Some((k, a)) => Err(fault(
                AlarmCode::Syntax,
                a.at,
                format!("axis {} has no place in {what}", AXIS_NAMES[k + 3]),
            )),
            None => Ok(()),
        }
    }

    /// A spindle limit block (840C G92 S) has no axis words: the same code as a "set actual
    /// value" is not built, and its axes must not be read as a move.
    pub(super) fn no_set_actual_value(&self, w: &Words) -> R<()> {
        let written = |axes: &[Option<Val>], first: usize| {
            let mut it = axes.iter().enumerate();
            it.find_map(|(k, a)| a.map(|a| (k + first, a)))
        };
        match written(&w.axis, 0).or_else(|| written(&w.additional, 3)) {
            Some((k, a)) => {
                let code = self.d.codes_of(&[crate::dialect::GEffect::SpindleLimit]);
                Err(fault(
                    AlarmCode::NotSupported,
                    a.at,
                    format!(
                        "{code} with axis words ({} here: setting the actual value) is not supported; with S it is the spindle speed limit",
                        AXIS_NAMES[k]
                    ),
                ))
            }
            None => Ok(()),
        }
    }

    /// Additional axes move only in blocks neither inside a compensation run nor selecting
    /// or deselecting one: the tool radius compensation works in the plane of the geometry
    /// axes, and its inserted pieces could not share out a rotary move (docs/axes.md).
    pub(super) fn additional_outside_trc(&self, new: &ModalState, w: &Words) -> R<()> {
        if self.block.axes.is_none()
            || (new.trc == TrcSide::Off && self.block.modal.trc == TrcSide::Off)
        {
            return Ok(());
        }
        let (k, at) = w
            .additional
            .iter()
            .enumerate()
            .find_map(|(k, a)| a.map(|a| (k, a.pos())))
            .unwrap_or((0, 0));
        Err(fault(
            AlarmCode::ForbiddenWithTrc,
            at,
            format!(
                "axis {} cannot move while tool radius compensation is active",
                AXIS_NAMES[k + 3]
            ),
        ))
    }

    /// A line or an arc to the axis words' end point; under a frame (frames.rs) the points
    /// are worked out in program coordinates and then mapped.
    fn cartesian(
        &mut self,
        w: &Words,
        new: &ModalState,
        programmed: u16,
        block_col: usize,
    ) -> R<()> {
        let arc = new.motion.is_arc();
        let vector = !arc && self.exit_vector(w, new);
        let framed = self.coords.frame.active() && !self.machine_coordinates;
        let (start, end) = if framed {
            self.framed_points(w, new, block_col)?
        } else {
            (self.cur, self.end_point(w, new, self.cur)?)
        };
        let has_centre = w.centre.iter().any(Option::is_some) || w.radius.is_some();
        if has_centre && !arc && !vector {
            let at = w
                .centre
                .iter()
                .flatten()
                .map(|v| v.pos())
                .chain(w.radius.map(Val::pos))
                .next()
                .unwrap_or(block_col);
            if self.block.trc == Some(TrcSide::Off) && w.radius.is_none() {
                // Controls without Fanuc's exit vector (Self::exit_vector).
                return Err(fault(
                    AlarmCode::NotSupported,
                    at,
                    "I J K in the compensation cancel block (an exit vector) are not supported by this control",
                ));
            }
            return Err(fault(
                AlarmCode::Syntax,
                at,
                "circle parameters without a circular motion",
            ));
        }
        if programmed & GEOMETRY == 0 && !(arc && has_centre) {
            return Ok(());
        }
        feed_programmed(new, block_col)?;
        if framed && arc {
            self.frame_keeps_circles(new, block_col)?;
        }
        let centre = if arc {
            self.arc_centre(w, new, start, end, block_col)?
        } else {
            end
        };
        if framed {
            return self.set_framed_motion(new, end, centre, programmed, block_col);
        }
        self.set_motion(new, start, end, centre, programmed, block_col)
    }

    /// Fanuc: I J K in a straight block that cancels the compensation are the direction of a
    /// virtual block the last corner is built against (0i-MF, "Tool movement in offset mode
    /// cancel"). Always incremental; mapped by the frame like a move. False if not taken.
    fn exit_vector(&mut self, w: &Words, new: &ModalState) -> bool {
        if !self.d.trc.exit_vector
            || self.block.trc != Some(TrcSide::Off)
            || w.radius.is_some()
            || w.centre.iter().all(Option::is_none)
        {
            return false;
        }
        let mut v = [0.0; 3];
        for (i, c) in w.centre.iter().enumerate() {
            if let Some(c) = c {
                v[i] = self.length(*c, new.units);
            }
        }
        if self.coords.frame.active() && !self.machine_coordinates {
            v = self.coords.frame.turn(v);
        }
        self.block.exit_vector = Some(Box::new(v));
        true
    }

    /// The end point of the axis words; the axes not written stay where they are.
    pub(super) fn end_point(&self, w: &Words, new: &ModalState, start: Pos) -> R<Pos> {
        let offset = self.work_offset(new);
        let mut end = start;
        for (i, a) in w.axis.iter().enumerate() {
            if let Some(a) = a {
                end[i] = if w.incremental & (1 << i) != 0 {
                    // U/W: incremental whatever the distance mode.
                    let inc = ModalState {
                        distance: Distance::Incremental,
                        ..*new
                    };
                    self.axis_target(*a, i, &inc, start[i], offset[i])
                } else if w.absolute & (1 << i) != 0 {
                    // SINUMERIK AC(): absolute whatever the distance mode.
                    let abs = ModalState {
                        distance: Distance::Absolute,
                        ..*new
                    };
                    self.axis_target(*a, i, &abs, start[i], offset[i])
                } else {
                    self.axis_target(*a, i, new, start[i], offset[i])
                };
                if !in_range(end[i]) {
                    return Err(fault(AlarmCode::BadNumber, a.at, "coordinate out of range"));
                }
            }
        }
        Ok(end)
    }

    /// The centre of an arc from `start` to `end`, from I J K in the plane or a radius.
    pub(super) fn arc_centre(
        &self,
        w: &Words,
        new: &ModalState,
        start: Pos,
        end: Pos,
        block_col: usize,
    ) -> R<Pos> {
        let plane = new.plane;
        for (i, v) in w.centre.iter().enumerate() {
            if let (Some(v), false) = (v, plane.contains(i)) {
                return Err(fault(
                    AlarmCode::Syntax,
                    v.at,
                    format!(
                        "{} is not a centre coordinate in the {} plane",
                        ['I', 'J', 'K'][i],
                        plane.name()
                    ),
                ));
            }
        }
        let mut spec = self.centre_spec(w, new.units, block_col)?;
        if let (CentreSpec::Offsets(off), true) = (&mut spec, w.centre_absolute != 0) {
            // SINUMERIK I=AC(…): the centre's coordinate itself (Fundamentals, "Absolute
            // and incremental dimensions"), X as a diameter where X is one.
            let zero = self.work_offset(new);
            for (i, v) in w.centre.iter().enumerate() {
                if let (Some(v), true) = (v, w.centre_absolute & 1 << i != 0) {
                    let c =
                        self.length(*v, new.units) * diameter_factor(i, new, Distance::Absolute);
                    off[i] = c + zero[i] - start[i];
                }
            }
        }
        let at = w
            .radius
            .map(Val::pos)
            .or_else(|| w.centre.iter().flatten().next().map(|v| v.pos()))
            .unwrap_or(block_col);
        let tol = self.md.program.arc_endpoint_tolerance;
        let ccw = new.motion == MotionMode::ArcCcw;
        arc::centre(start, end, plane, ccw, spec, tol).map_err(|e| arc_fault(e, tol, at))
    }

    /// How the block gives the circle: centre offsets or a radius, one of them.
    pub(super) fn centre_spec(&self, w: &Words, units: Units, block_col: usize) -> R<CentreSpec> {
        match (w.radius, w.centre.iter().any(Option::is_some)) {
            (Some(r), false) => Ok(CentreSpec::Radius(self.length(r, units))),
            (None, true) => {
                let mut off = [0.0; 3];
                for (i, v) in w.centre.iter().enumerate() {
                    if let Some(v) = v {
                        off[i] = self.length(*v, units);
                    }
                }
                Ok(CentreSpec::Offsets(off))
            }
            (Some(r), true) => Err(fault(
                AlarmCode::Syntax,
                r.at,
                "a circle takes either a centre or a radius, not both",
            )),
            (None, false) => Err(fault(
                AlarmCode::MissingValue,
                block_col,
                "a circle needs its centre (I, J, K) or its radius",
            )),
        }
    }

    /// 880 4.2.5: plane-axis words give the pole, A the angle, U or B the radius, the normal
    /// axis moves as written; a polar circle is centred on the pole.
    fn polar(
        &mut self,
        w: &Words,
        new: &mut ModalState,
        programmed: u16,
        block_col: usize,
    ) -> R<()> {
        self.pole(w, new);
        let start = self.cur;
        let normal = new.plane.normal as usize;
        let mut end = start;
        if let Some(a) = w.axis[normal] {
            let offset = self.work_offset(new);
            let v = self.length(a, new.units);
            end[normal] = match new.distance {
                Distance::Absolute => v + offset[normal],
                Distance::Incremental => start[normal] + v,
            };
        }
        if w.angle.is_none() && w.polar_radius.is_none() && w.axis[normal].is_none() {
            return Ok(());
        }
        let (pa, po) = (new.plane.abscissa as usize, new.plane.ordinate as usize);
        let (r, angle) = self.polar_target(w, new, start, block_col)?;
        end[pa] = new.pole[pa] + r * libm::cos(angle);
        end[po] = new.pole[po] + r * libm::sin(angle);
        let mut centre = start;
        centre[pa] = new.pole[pa];
        centre[po] = new.pole[po];
        feed_programmed(new, block_col)?;
        let centre = if new.motion.is_arc() { centre } else { end };
        self.set_motion(new, start, end, centre, programmed, block_col)
    }

    /// The pole from the plane-axis words: absolute plus the zero offset, or added to the
    /// last pole (880 4.2.5).
    fn pole(&self, w: &Words, new: &mut ModalState) {
        let offset = self.work_offset(new);
        let (pa, po) = (new.plane.abscissa as usize, new.plane.ordinate as usize);
        for i in [pa, po] {
            if let Some(a) = w.axis[i] {
                let factor = if i == 0 && new.diameter { 0.5 } else { 1.0 };
                let v = self.length(a, new.units) * factor;
                new.pole[i] = match new.distance {
                    Distance::Absolute => v + offset[i],
                    Distance::Incremental => new.pole[i] + v,
                };
            }
        }
    }

    /// Radius and angle (radians) of the polar end point about the pole. A or U/B not
    /// written keep the start point's; a circle keeps the start radius.
    fn polar_target(
        &self,
        w: &Words,
        new: &ModalState,
        start: Pos,
        block_col: usize,
    ) -> R<(f64, f64)> {
        let (pa, po) = (new.plane.abscissa as usize, new.plane.ordinate as usize);
        let (rx, ry) = (start[pa] - new.pole[pa], start[po] - new.pole[po]);
        let r_now = libm::hypot(rx, ry);
        let ang_now = libm::atan2(ry, rx).to_degrees();
        let ang = match w.angle {
            Some(a) if new.distance == Distance::Incremental => ang_now + a.value,
            Some(a) => a.value,
            None => ang_now,
        };
        let r = match w.polar_radius {
            Some(u) => {
                let r = self.length(u, new.units);
                if r < 0.0 {
                    return Err(fault(
                        AlarmCode::BadNumber,
                        u.at,
                        "the polar radius U/B is written without sign",
                    ));
                }
                r
            }
            None => r_now,
        };
        if new.motion.is_arc() {
            self.polar_circle(w, r, r_now, block_col)?;
            return Ok((r_now, ang.to_radians()));
        }
        Ok((r, ang.to_radians()))
    }

    /// A polar circle: its start off the pole, a written radius equal to the start radius.
    fn polar_circle(&self, w: &Words, r: f64, r_now: f64, block_col: usize) -> R<()> {
        if r_now <= 1e-9 {
            return Err(fault(
                AlarmCode::ArcEndPoint,
                block_col,
                "polar circle: the start point lies on the pole",
            ));
        }
        if (r - r_now).abs() > self.md.program.arc_endpoint_tolerance {
            return Err(fault(
                AlarmCode::ArcEndPoint,
                w.polar_radius.map_or(block_col, Val::pos),
                format!("polar circle: radius {r:.4} differs from the start radius {r_now:.4}"),
            ));
        }
        Ok(())
    }

    /// The motion, once its end point is checked against the working area.
    #[inline(always)]
    pub(super) fn set_motion(
        &mut self,
        new: &ModalState,
        start: Pos,
        end: Pos,
        centre: Pos,
        programmed: u16,
        block_col: usize,
    ) -> R<()> {
        self.check_area(&end, block_col)?;
        self.block.motion = Some(Motion {
            kind: new.motion.kind(),
            plane: new.plane,
            start,
            end,
            center: centre,
            programmed,
        });
        Ok(())
    }

    /// Step 8, 840C G25 (min) / G26 (max): the axis words are limits, in mm without zero
    /// offset (docs/dialects.md, "Working area G25/G26").
    pub(super) fn working_area(&mut self, w: &Words, max: bool, units: Units) {
        for (i, a) in w.axis.iter().enumerate() {
            if let Some(a) = a {
                // Only a limit written takes the plain path away (G26 S alone limits nothing).
                self.area.limited = true;
                let v = self.length(*a, units);
                if max {
                    self.area.max[i] = v;
                } else {
                    self.area.min[i] = v;
                }
            }
        }
    }

    /// 840C G25/G26: end points must stay inside the working area.
    fn check_area(&self, p: &Pos, at: usize) -> R<()> {
        let area = &self.area;
        if !area.limited {
            return Ok(());
        }
        for i in 0..3 {
            if p[i] < area.min[i] || p[i] > area.max[i] {
                return Err(fault(
                    AlarmCode::WorkingArea,
                    at,
                    format!(
                        "{} {:.4} lies outside the working area limitation {} .. {}",
                        AXIS_NAMES[i], p[i], area.min[i], area.max[i]
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// What a value of axis `i` written under `distance` is multiplied by: ½ for X as a
/// diameter (808D DIAMON; DIAM90 only where X is absolute, 808D Turning "Positional data").
#[inline(always)]
pub(in crate::frontend) fn diameter_factor(i: usize, new: &ModalState, distance: Distance) -> f64 {
    if i == 0 && new.diameter && !(new.radius_incremental && distance == Distance::Incremental) {
        0.5
    } else {
        1.0
    }
}

/// A feed motion needs a feed.
pub(super) fn feed_programmed(new: &ModalState, block_col: usize) -> R<()> {
    let feed_needed = !matches!(new.motion, MotionMode::Rapid | MotionMode::PolarRapid);
    if feed_needed && new.feed <= 0.0 {
        return Err(fault(
            AlarmCode::NoFeed,
            block_col,
            "no feed programmed (F)",
        ));
    }
    Ok(())
}

/// Why no circle fits, as the alarm at `at`.
#[cold]
pub(super) fn arc_fault(e: ArcError, tol: f64, at: usize) -> Box<Fault> {
    let msg = match e {
        ArcError::EndPointOff { r_start, r_end } => format!(
            "end point not on the circle: start radius {r_start:.4}, end radius {r_end:.4} (tolerance {tol})"
        ),
        ArcError::ZeroRadius => "the centre lies on the start point".to_string(),
        ArcError::FullCircleByRadius => {
            "a full circle cannot be programmed with a radius; give the centre".to_string()
        }
        ArcError::RadiusTooSmall { radius, half_chord } => format!(
            "radius {:.4} is smaller than half the distance to the end point ({half_chord:.4})",
            radius.abs()
        ),
    };
    fault(AlarmCode::ArcEndPoint, at, msg)
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use super::*;

    fn end(b: &Block) -> Pos {
        b.motion.unwrap().end
    }

    /// Fanuc 0i-MF, G40 with I J K: the words are the exit vector, always incremental, in
    /// mm (G20: ×25.4), turned by the frame (G68 R90: (10, 0) → (0, 10)); the next block
    /// has none. On the lathe too. Other controls refuse them (alarm 12580 at the I word).
    #[test]
    fn i_j_k_in_a_fanuc_cancel_block_are_the_exit_vector() {
        let b = run(
            "fanuc",
            "G41 D1 G1 X0. Y10. F100.\nX40.\nG91 G40 X20. Y-10. I10. J-5.\nG90 X0.\n",
        )
        .unwrap();
        assert_eq!(b[2].exit_vector.as_deref(), Some(&[10.0, -5.0, 0.0]));
        assert_eq!(end(&b[2]), [60.0, 0.0, 0.0]);
        assert_eq!(b[3].exit_vector, None);
        let b = run(
            "fanuc",
            "G20 G41 D1 G1 X0. Y1. F10.\nG40 X2. Y0. I0.5 K1.\n",
        )
        .unwrap();
        assert_eq!(b[1].exit_vector.as_deref(), Some(&[12.7, 0.0, 25.4]));
        let b = run(
            "fanuc",
            "G68 X0. Y0. R90.\nG41 D1 G1 X0. Y10. F100.\nG40 X0. Y0. I10. J0.\n",
        )
        .unwrap();
        let v = b[2].exit_vector.as_deref().unwrap();
        assert!(v[0].abs() < 1e-12 && (v[1] - 10.0).abs() < 1e-12, "{v:?}");
        // The lathe (G18): I K, I as a radius like a circle's.
        let b = run(
            "fanuc-lathe",
            "G42 G1 X20. Z0. F0.2\nG40 X40. Z5. I1. K-1.\n",
        )
        .unwrap();
        assert_eq!(b[1].exit_vector.as_deref(), Some(&[1.0, 0.0, -1.0]));
        let a = run("siemens-840c", "G41 D1 G1 X0 Y10 F100\nG40 X0 Y0 I10 J0\n").unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::NotSupported, 2, 11));
    }

    #[test]
    fn diam90_is_a_diameter_where_x_is_absolute_only() {
        // DIAMON: X20 → r 10, G91 X2 → +1. DIAM90: G91 X2 → +2, X=IC(2) → +2, G90 X30 →
        // r 15, X=AC(40) → r 20. DIAMOF: X30 → 30.
        let xs = super::super::super::end_xs(
            "siemens-808d",
            "DIAMON\nG1 X20 F1\nG91 X2\nDIAM90\nX2\nG90 X=IC(2)\nX30\nG91 X=AC(40)\nG90 DIAMOF\nX30\n",
        );
        assert_eq!(xs, [10.0, 11.0, 13.0, 15.0, 15.0, 20.0, 30.0]);
    }

    #[test]
    fn working_area_bounds_end_points() {
        // G25/G26 move nothing; an end point outside is alarm 10630.
        let b = run(
            "siemens-840c",
            "G25 X-10 Y-10\nG26 X10 Y10\nG1 X10 Y-10 F100\n",
        )
        .unwrap();
        assert_eq!((b[0].motion, b[1].motion), (None, None));
        assert_eq!(end(&b[2]), [10.0, -10.0, 0.0]);
        let a = run("siemens-840c", "G26 X10\nG1 X10.5 F100\n").unwrap_err();
        assert_eq!((a.code, a.line), (AlarmCode::WorkingArea, 2));
    }

    #[test]
    fn polar_end_points_lie_about_the_pole() {
        // Pole (10, 0); radius 5 at 90°: (10, 5). Then G91 A90 about the same pole: (5, 0).
        let b = run("siemens-840c", "G11 X10 Y0 F100\nA90 U5\nG91 A90\n").unwrap();
        assert_eq!(b[0].motion, None);
        let p = end(&b[1]);
        assert!(
            (p[0] - 10.0).abs() < 1e-12 && (p[1] - 5.0).abs() < 1e-12,
            "{p:?}"
        );
        let p = end(&b[2]);
        assert!((p[0] - 5.0).abs() < 1e-12 && p[1].abs() < 1e-12, "{p:?}");
        // A polar circle keeps its start radius.
        let a = run("siemens-840c", "G1 X10 F100\nG13 X0 Y0 A90 U4\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::ArcEndPoint);
    }

    #[test]
    fn arcs_need_a_centre_or_a_radius_in_the_plane() {
        let a = run("isg", "G2 X10 Y0 F100\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::MissingValue);
        let a = run("isg", "G2 X10 Y0 I5 R5 F100\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::Syntax, 14));
        let a = run("isg", "G2 X10 Y0 K5 F100\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::Syntax, 11));
        let a = run("isg", "G1 X10 I5 F100\n").unwrap_err();
        assert_eq!(a.message, "circle parameters without a circular motion");
    }
}
