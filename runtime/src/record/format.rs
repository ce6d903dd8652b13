//! The record's lines (docs/interfaces.md, "Record and replay"): one JSON object a line,
//! its one key naming the kind. Floating-point values are strings in the shortest decimal
//! form that reads back to the same bits, so no JSON reader can round them.

use nc_kernel::cycle::{ChannelAlarm, PlcInput};
use nc_kernel::AxisPos;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The record format's version.
pub const VERSION: u32 = 1;

/// An `f64` that reads back to the same bits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct F(pub f64);

impl Serialize for F {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(ryu::Buffer::new().format(self.0))
    }
}

impl<'de> Deserialize<'de> for F {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<F, D::Error> {
        let s = String::deserialize(d)?;
        s.parse::<f64>()
            .map(F)
            .map_err(|_| serde::de::Error::custom(format!("not a number: {s:?}")))
    }
}

/// Every path axis (X Y Z U V W A B C) as the record writes it.
pub fn axes(p: &AxisPos) -> [F; 9] {
    let mut a = [F(0.0); 9];
    for (i, x) in a.iter_mut().enumerate() {
        *x = F(p.axis(i));
    }
    a
}

/// The position a record's axes stand for.
pub fn axis_pos(a: &[F; 9]) -> AxisPos {
    let mut p = AxisPos::default();
    for (i, x) in a.iter().enumerate() {
        if i < 3 {
            p.geo[i] = x.0;
        } else {
            p.add[i - 3] = x.0;
        }
    }
    p
}

/// The first line: what the run started with. A replay refuses other machine data, tools
/// or work offsets (their fingerprints differ) or another program text.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Header {
    pub version: u32,
    /// The program loaded at start-up (empty: none).
    pub program: String,
    pub program_fingerprint: String,
    pub machine_fingerprint: String,
    pub tools_fingerprint: String,
    pub work_offsets_fingerprint: String,
    pub cycle_us: u32,
    /// Where the axes stood when the IPO started.
    pub start: [F; 9],
}

/// An HMI command as the IPO cycle took it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Cmd {
    Start,
    Stop,
    Reset,
    SingleBlock(bool),
    Override(F),
    /// The program with this number (a `load` line describes it).
    Load(u32),
    /// The re-prepared program with this number (a `resume` line describes it).
    Resume(u32),
    Shutdown,
}

impl Cmd {
    /// The command as the record keeps it (a program by its number).
    pub fn of(c: &nc_kernel::cycle::Control) -> Cmd {
        use nc_kernel::cycle::Control;
        match c {
            Control::Start => Cmd::Start,
            Control::Stop => Cmd::Stop,
            Control::Reset => Cmd::Reset,
            Control::SingleBlock(on) => Cmd::SingleBlock(*on),
            Control::Override(f) => Cmd::Override(F(*f)),
            Control::Load(p) => Cmd::Load(p.id),
            Control::Resume(p) => Cmd::Resume(p.id),
            Control::Shutdown => Cmd::Shutdown,
        }
    }
}

/// One line of a record.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Line {
    Header(Header),
    /// The PLC's signals from cycle `k` on (written when they change).
    Plc {
        k: u64,
        feed_hold: bool,
        read_in_disable: bool,
        drives_ready: bool,
        emergency_stop: bool,
        /// PLC alarm standing, 0 for none.
        alarm: u32,
        spindle_rpm: F,
    },
    /// No PLC signals arrived in cycles `k .. k + cycles`.
    NoPlc {
        k: u64,
        cycles: u64,
    },
    /// The PLC acknowledged aux request `id` in cycle `k` (refused with `alarm` if not 0).
    Ack {
        k: u64,
        id: u64,
        alarm: u32,
    },
    /// An aux request could not be sent in cycle `k` (the PLC's queue was full).
    AuxFull {
        k: u64,
    },
    /// Cycle `k` took `records` prepared records into its lookahead.
    Prep {
        k: u64,
        records: u32,
    },
    /// An HMI command taken before cycle `k`; `ok`: not refused.
    Command {
        k: u64,
        command: Cmd,
        ok: bool,
    },
    /// Program `id` was prepared from `path` with the axes at `at` (`None`: its own start).
    Load {
        id: u32,
        path: String,
        program_fingerprint: String,
        at: Option<[F; 9]>,
    },
    /// Program `id` is program `of` prepared again from its interruption point (NC start
    /// after an offset edit in NC stop), the axes at `pos`.
    Resume {
        id: u32,
        of: u32,
        seq: u32,
        role: u8,
        nth: u32,
        along: F,
        pos: [F; 9],
    },
    /// A tool offset edit (in reset or NC stop); `running`: while the program ran.
    ToolEdit {
        t: Option<u32>,
        d: u32,
        wear: bool,
        value: F,
        running: bool,
    },
    /// A work-offset edit: `values` are (axis index of X Y Z U V W A B C, value).
    WorkEdit {
        name: String,
        values: Vec<(usize, F)>,
    },
    /// The run's end: `cycles` cycles; `lost`: the record is incomplete.
    End {
        cycles: u64,
        lost: bool,
    },
}

impl Line {
    pub fn plc(k: u64, s: &PlcInput) -> Line {
        Line::Plc {
            k,
            feed_hold: s.feed_hold,
            read_in_disable: s.read_in_disable,
            drives_ready: s.drives_ready,
            emergency_stop: s.emergency_stop,
            alarm: ChannelAlarm::wire(s.alarm),
            spindle_rpm: F(s.spindle_rpm),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_to_the_same_bits() {
        let tricky = [
            0.1 + 0.2,
            -0.0,
            5e-324,
            f64::MAX,
            1.0 / 3.0,
            -21.697_232_959_460_298,
        ];
        for x in tricky {
            let text = serde_json::to_string(&F(x)).unwrap();
            let back: F = serde_json::from_str(&text).unwrap();
            assert_eq!(back.0.to_bits(), x.to_bits(), "{text}");
        }
        assert!(serde_json::from_str::<F>("\"x\"").is_err());
    }

    #[test]
    fn a_line_reads_back_as_written() {
        let l = Line::Command {
            k: 514,
            command: Cmd::Override(F(0.6)),
            ok: true,
        };
        let text = serde_json::to_string(&l).unwrap();
        assert_eq!(
            text,
            r#"{"command":{"k":514,"command":{"override":"0.6"},"ok":true}}"#
        );
        match serde_json::from_str::<Line>(&text).unwrap() {
            Line::Command { k, command, ok } => {
                assert_eq!((k, command, ok), (514, Cmd::Override(F(0.6)), true))
            }
            other => panic!("{other:?}"),
        }
    }
}
