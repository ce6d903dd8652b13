//! SINUMERIK system variables a part program reads (Job planning / List Manual System
//! Variables; docs/research/sinumerik-language.md §7): the subset of positions, the active
//! tool and its offsets. The interpreter fills a [`SystemValues`] snapshot before a block
//! that holds a `$`, so the expressions read it like any variable.
//!
//! | variable | value |
//! |---|---|
//! | `$P_EP[ax]` | the programmed end point of the last block, workpiece coordinates |
//! | `$AA_IW[ax]` | the axis' actual position, workpiece coordinates: a main-run variable, so the block stops preprocessing (implicit STOPRE) and the position is the last block's end |
//! | `$P_TOOLNO`, `$P_TOOL` | the active T and D numbers |
//! | `$P_F`, `$P_S` | the programmed feed and spindle speed |
//! | `$TC_DP2[t,d]` | the cutting edge position (turning) |
//! | `$TC_DP3[t,d]`, `$TC_DP6[t,d]` | length 1 and radius of edge d of tool t |
//! | `$TC_DP12[t,d]`, `$TC_DP15[t,d]` | their wear |

use super::super::fault::{fault, R};
use crate::alarm::AlarmCode;
use crate::tools::ToolOffset;

/// What the system variables read, taken before the block that reads them.
#[derive(Clone, Debug, Default)]
pub struct SystemValues {
    /// Axis letters and positions (workpiece coordinates) of every path axis.
    pub axes: Vec<(u8, f64)>,
    pub tool: Option<u32>,
    pub d: u32,
    pub feed: f64,
    pub speed: f64,
    /// The tool offsets the program reads (taken only for a block that reads `$TC_`).
    pub tools: Vec<ToolOffset>,
    /// Tool radius compensation is active: the actual position is no programmed point.
    pub trc: bool,
}

/// What a system variable is, by its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SystemName {
    EndPoint,
    ActualWorkpiece,
    ToolNumber,
    EdgeNumber,
    Feed,
    Speed,
    /// `$TC_DPn`: a tool offset parameter.
    ToolData(u8),
}

impl SystemName {
    /// The variable `name` (upper case, with its `$`), if softnc provides it.
    pub fn of(name: &str) -> Option<SystemName> {
        Some(match name {
            "$P_EP" => SystemName::EndPoint,
            "$AA_IW" => SystemName::ActualWorkpiece,
            "$P_TOOLNO" => SystemName::ToolNumber,
            "$P_TOOL" => SystemName::EdgeNumber,
            "$P_F" => SystemName::Feed,
            "$P_S" => SystemName::Speed,
            _ => {
                let n: u8 = name.strip_prefix("$TC_DP")?.parse().ok()?;
                if ![2, 3, 6, 12, 15].contains(&n) {
                    return None;
                }
                SystemName::ToolData(n)
            }
        })
    }

    /// How many indices it takes: an axis, (tool, edge), or none.
    pub fn indices(self) -> usize {
        match self {
            SystemName::EndPoint | SystemName::ActualWorkpiece => 1,
            SystemName::ToolData(_) => 2,
            _ => 0,
        }
    }

    /// A main-run variable: reading it stops preprocessing.
    pub fn main_run(self) -> bool {
        self == SystemName::ActualWorkpiece
    }
}

/// An index as written: an axis letter or a number.
#[derive(Clone, Copy, Debug)]
pub enum Index {
    Axis(u8),
    Number(f64),
}

impl SystemValues {
    /// The value of `name[idx…]` (`name` as written, for messages).
    pub fn read(&self, v: SystemName, name: &str, idx: &[Index], at: usize) -> R<f64> {
        match v {
            SystemName::EndPoint | SystemName::ActualWorkpiece => self.axis(v, name, idx, at),
            SystemName::ToolNumber => Ok(self.tool.map_or(0.0, f64::from)),
            SystemName::EdgeNumber => Ok(f64::from(self.d)),
            SystemName::Feed => Ok(self.feed),
            SystemName::Speed => Ok(self.speed),
            SystemName::ToolData(n) => self.tool_data(n, name, idx, at),
        }
    }

    fn axis(&self, v: SystemName, name: &str, idx: &[Index], at: usize) -> R<f64> {
        if v == SystemName::ActualWorkpiece && self.trc {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("{name} while tool radius compensation is active: the tool centre's position is known only to preparation"),
            ));
        }
        let [Index::Axis(letter)] = idx else {
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!("{name}[axis] expected"),
            ));
        };
        self.axes
            .iter()
            .find(|a| a.0 == *letter)
            .map(|a| a.1)
            .ok_or_else(|| {
                fault(
                    AlarmCode::UndefinedName,
                    at,
                    format!("{name}[{}]: no such axis", *letter as char),
                )
            })
    }

    fn tool_data(&self, n: u8, name: &str, idx: &[Index], at: usize) -> R<f64> {
        let [Index::Number(t), Index::Number(d)] = idx else {
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!("{name}[tool, edge] expected"),
            ));
        };
        let o = self
            .tools
            .iter()
            .find(|o| o.t.is_none_or(|k| f64::from(k) == *t) && f64::from(o.d) == *d)
            .ok_or_else(|| {
                fault(
                    AlarmCode::UnknownOffset,
                    at,
                    format!("{name}[{t},{d}]: no such tool edge in the tool table"),
                )
            })?;
        Ok(match n {
            2 => o.edge.map_or(0.0, f64::from),
            3 => o.length,
            6 => o.radius,
            12 => o.length_wear,
            _ => o.radius_wear,
        })
    }
}

impl super::super::interpreter::Interpreter<'_> {
    /// Whether the block `src[start..end]` reads system variables (then their values are
    /// taken: a block without `$` costs one search).
    #[inline]
    pub(in crate::frontend) fn reads_system(&mut self, start: usize, end: usize) -> bool {
        let text = &self.src[start..end];
        let Some(k) = memchr::memchr(b'$', text) else {
            return false;
        };
        let tools = memchr::memmem::find(&text[k..], b"$TC_").is_some()
            || memchr::memmem::find(&text[k..], b"$tc_").is_some();
        self.system_snapshot(tools);
        true
    }

    /// Before a block that holds a `$`: what its system variables read. The axes are in
    /// the program's own terms (a diameter axis in diameter; **[unconfirmed]**).
    #[cold]
    #[inline(never)]
    pub(in crate::frontend) fn system_snapshot(&mut self, reads_tools: bool) {
        let modal = self.block.modal;
        let wcs = self.program_position(&modal, 0).unwrap_or(self.cur);
        let zero = self.zero(modal.work_offset);
        let names = crate::machine_data::AXIS_NAMES;
        let mut axes = Vec::new();
        for (i, _) in self.md.axes.configured() {
            let v = if i < 3 {
                wcs[i] * if i == 0 && modal.diameter { 2.0 } else { 1.0 }
            } else {
                self.cur_add[i - 3] - zero[i]
            };
            axes.push((names[i] as u8, v));
        }
        let tools = if reads_tools {
            self.tool_table().offset.clone()
        } else {
            Vec::new()
        };
        self.sinumerik.store.system = Some(Box::new(SystemValues {
            axes,
            tool: modal.tool,
            d: modal.d,
            feed: modal.feed,
            speed: modal.spindle,
            tools,
            trc: modal.trc != super::super::block::TrcSide::Off,
        }));
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;

    #[test]
    fn positions_read_in_workpiece_terms_and_the_actual_one_stops_preprocessing() {
        // After G0 X10 Y20 Z5: $P_EP[X] + $AA_IW[Y] = 30; the block reading $AA_IW is a
        // preprocessing stop, the one reading $P_EP is not.
        let p = "G0 X10 Y20 Z5\nR1=$P_EP[X]+$AA_IW[Y]\nR2=$P_EP[Z]*2\nG1 F100 X=R1 Y=R2\n";
        let b = run("siemens-840d", p).unwrap_or_else(|a| panic!("{a}"));
        assert!(b[1].preprocess_stop);
        assert!(!b[2].preprocess_stop);
        assert_eq!(b[3].motion.map(|m| m.end), Some([30.0, 10.0, 5.0]));
    }

    #[test]
    fn tool_numbers_and_offsets_come_from_the_active_tool_and_the_table() {
        // D1 of the shipped table: radius 10, length 100; D2 radius 5.
        let p = "T3 D2 F250 S1200\nG1 X=$TC_DP6[3,1]+$TC_DP3[3,1]/100 Y=$P_TOOL+$P_TOOLNO Z=$P_F/$TC_DP6[1,2]\n";
        let b = run("siemens-840d", p).unwrap_or_else(|a| panic!("{a}"));
        assert_eq!(
            b.last().and_then(|b| b.motion).map(|m| m.end),
            Some([11.0, 5.0, 50.0])
        );
    }

    #[test]
    fn a_condition_on_the_actual_position_is_an_implicit_stopre() {
        let p = "G0 X10\nIF $AA_IW[X]>5 GOTOF DONE\nX99\nDONE: G1 F100 X1\n";
        let b = run("siemens-840d", p).unwrap_or_else(|a| panic!("{a}"));
        assert!(b[1].preprocess_stop && b[1].motion.is_none());
        assert_eq!(b[2].motion.map(|m| m.end[0]), Some(1.0));
    }

    #[test]
    fn unknown_variables_bad_indices_and_trc_are_alarms() {
        let alarm = |p: &str| {
            let a = run("siemens-840d", p).unwrap_err();
            (a.code, a.line, a.col)
        };
        assert_eq!(alarm("R1=$AA_XYZ\n"), (AlarmCode::UndefinedName, 1, 4));
        assert_eq!(alarm("R1=$P_EP[Q]\n"), (AlarmCode::UndefinedName, 1, 10));
        assert_eq!(alarm("R1=$P_EP[B]\n"), (AlarmCode::UndefinedName, 1, 4));
        assert_eq!(alarm("R1=$TC_DP6[1]\n"), (AlarmCode::Syntax, 1, 13));
        assert_eq!(alarm("R1=$TC_DP6[9,9]\n"), (AlarmCode::UnknownOffset, 1, 4));
        let trc = "T1 D1 G0 X0 Y0\nG41 G1 F100 X10\nR1=$AA_IW[X]\n";
        assert_eq!(alarm(trc), (AlarmCode::NotSupported, 3, 4));
    }
}
