//! The payloads the processes exchange: plain `#[repr(C)]` values in shared memory, with
//! explicit type names (otherwise iceoryx2 names them by crate path and two binaries built
//! from different trees disagree). Everything is fixed size: no pointers, no heap.

use iceoryx2::prelude::ZeroCopySend;

/// The channel state as sent (the kernel's `ChannelState`).
pub mod state {
    pub const RESET: u8 = 0;
    pub const ACTIVE: u8 = 1;
    pub const STOPPED: u8 = 2;
    pub const END: u8 = 3;

    pub fn name(s: u8) -> &'static str {
        match s {
            RESET => "RESET",
            ACTIVE => "ACTIVE",
            STOPPED => "STOPPED",
            END => "END",
            _ => "?",
        }
    }
}

/// Path axes a setpoint, the actual values and the status carry at most.
pub const MAX_AXES: usize = 8;

/// Spindles a setpoint, the PLC's signals, the actual values and the status carry at most
/// (main spindle and counter-spindle); machine data configures one today.
pub const MAX_SPINDLES: usize = 2;

/// What a spindle is told to do (`SetpointMsg::spindle_mode`).
pub mod spindle_mode {
    pub const STOP: u8 = 0;
    /// Turning at `SetpointMsg::spindle`: positive clockwise (M3), negative counter-clockwise.
    pub const TURN: u8 = 1;
    /// Oriented stop: the PLC positions the spindle (M19).
    pub const ORIENT: u8 = 2;
}

/// The machine's axes as the wire lists them: the configured path axes in the machine's
/// order X Y Z U V W A B C (a lathe with C: X, Z, C), `count` of them; every position array
/// of the payloads uses this order. Names are ASCII upper case, 0 past `count`.
#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::AxisList")]
pub struct AxisList {
    pub names: [u8; MAX_AXES],
    pub count: u8,
    pub _pad: [u8; 5],
    /// Bit i: axis i is rotary (degrees); bit 8 + i: a modulo axis (shown within 0…360°).
    pub kinds: u16,
}

impl AxisList {
    /// The configured axes' names, in wire order.
    pub fn names(&self) -> impl Iterator<Item = char> + '_ {
        self.names[..usize::from(self.count).min(MAX_AXES)]
            .iter()
            .map(|&b| b as char)
    }

    /// Where axis `name` is in the position arrays.
    pub fn index(&self, name: char) -> Option<usize> {
        self.names().position(|c| c == name)
    }

    pub fn rotary(&self, i: usize) -> bool {
        i < MAX_AXES && self.kinds & (1 << i) != 0
    }

    pub fn modulo(&self, i: usize) -> bool {
        i < MAX_AXES && self.kinds & (1 << (8 + i)) != 0
    }
}

/// One IPO cycle's setpoint, kernel → PLC, every cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::SetpointMsg")]
pub struct SetpointMsg {
    /// 1, 2, … per kernel run: a gap means samples were lost.
    pub seq: u64,
    /// The IPO cycle the setpoint belongs to.
    pub cycle: u64,
    /// CLOCK_MONOTONIC, ns, when it was sent.
    pub sent_ns: u64,
    /// The consumer must have taken it by then (the next cycle's start), CLOCK_MONOTONIC ns.
    pub deadline_ns: u64,
    /// IPO cycle, µs.
    pub cycle_us: u32,
    /// Source line of the block being run (0: none).
    pub line: u32,
    /// Every configured axis in [`AxisList`] order (mm, or degrees counted on without
    /// wrapping for a rotary axis); 0 past `axes`.
    pub pos: [f64; MAX_AXES],
    /// Path speed, mm/s.
    pub v_path: f64,
    /// `state::*`.
    pub state: u8,
    /// Configured axes: the entries of `pos` that count.
    pub axes: u8,
    /// Configured spindles: the entries of `spindle` and `spindle_mode` that count.
    pub spindles: u8,
    /// `spindle_mode::*` per spindle.
    pub spindle_mode: [u8; MAX_SPINDLES],
    pub _pad: [u8; 3],
    /// Speed setpoint per spindle, rev/min: positive clockwise, negative counter-clockwise
    /// (under constant surface speed it follows the transverse axis every cycle).
    pub spindle: [f64; MAX_SPINDLES],
}

/// Words an auxiliary-function request carries at most (the front end's limit).
pub const AUX_WORDS: usize = 12;

#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::AuxWordMsg")]
pub struct AuxWordMsg {
    /// Address letter, ASCII upper case (M, S, T, H, …).
    pub address: u8,
    pub _pad: [u8; 7],
    pub value: f64,
}

/// Auxiliary functions output at an S point, kernel → PLC, answered by an [`AuxAck`].
#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::AuxRequest")]
pub struct AuxRequest {
    /// 1, 2, … per kernel run.
    pub id: u64,
    /// The IPO cycle it was output in.
    pub cycle: u64,
    pub line: u32,
    pub count: u32,
    pub words: [AuxWordMsg; AUX_WORDS],
    /// The path waits for the acknowledgement (machine data `ipo.wait_for_ack`).
    pub wait: u8,
    pub _pad: [u8; 7],
}

impl AuxRequest {
    pub fn words(&self) -> &[AuxWordMsg] {
        &self.words[..(self.count as usize).min(AUX_WORDS)]
    }
}

/// The PLC's answer to an [`AuxRequest`]: done, or refused with a PLC alarm.
#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::AuxAck")]
pub struct AuxAck {
    pub id: u64,
    /// 0: done; otherwise the PLC alarm that refused it.
    pub alarm: u32,
    pub _pad: u32,
}

/// The PLC interface signals, PLC → NC, every PLC cycle. A flag is 1 when set.
#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::PlcSignals")]
pub struct PlcSignals {
    pub seq: u64,
    /// The last setpoint cycle the PLC consumed (its sign of life for the kernel).
    pub echo_cycle: u64,
    /// Feed hold: the path brakes and waits; it goes on by itself when the signal drops.
    pub feed_hold: u8,
    /// Read-in disable: no further block starts; the path stops at the next block end.
    pub read_in_disable: u8,
    /// All drives ready: without it NC start is refused, and losing it stops the path.
    pub drives_ready: u8,
    /// Emergency stop (1: pressed).
    pub emergency_stop: u8,
    /// A PLC alarm (0: none), e.g. a software limit switch.
    pub alarm: u32,
    /// Actual speed per spindle, rev/min, signed as the setpoint (feed per revolution).
    pub spindle_rpm: [f64; MAX_SPINDLES],
}

/// The axes' actual values, PLC → anyone, every PLC cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::ActualValues")]
pub struct ActualValues {
    pub seq: u64,
    /// The setpoint cycle these follow.
    pub cycle: u64,
    /// Every configured axis in [`AxisList`] order.
    pub pos: [f64; MAX_AXES],
    /// Setpoint − actual position per axis, mm (degrees).
    pub following_error: [f64; MAX_AXES],
    /// Actual speed per spindle, rev/min (signed as the setpoint).
    pub spindle_rpm: [f64; MAX_SPINDLES],
    /// The tool in the spindle.
    pub tool: u32,
    /// Auxiliary functions acknowledged so far.
    pub aux_acked: u32,
    pub plc_alarm: u32,
    pub _pad: u32,
}

/// The kernel's state for the HMI, kernel → anyone, every IPO cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::KernelStatus")]
pub struct KernelStatus {
    pub seq: u64,
    pub cycle: u64,
    /// Changes with every program load (0: none loaded).
    pub program: u32,
    pub line: u32,
    /// Every configured axis in `axes` order (the setpoint).
    pub pos: [f64; MAX_AXES],
    pub axes: AxisList,
    pub v_path: f64,
    pub override_: f64,
    /// The first alarm standing (0: none).
    pub alarm: u32,
    pub aux_sent: u32,
    pub aux_acked: u32,
    /// The tool table's version: 1 at start, one more with every accepted offset edit.
    pub tools_version: u32,
    /// The kernel cycle in which the PLC's sign of life last arrived.
    pub plc_cycle: u64,
    pub state: u8,
    pub single_block: u8,
    /// The PLC is there (its sign of life arrived within the watchdog time).
    pub plc_alive: u8,
    /// The running segment's role (the kernel's `Role::code`; 0: none).
    pub role: u8,
    /// IPO periods skipped because a cycle started a period or more late (the kernel's
    /// thread or the machine was held up): the path paused for them.
    pub skipped: u32,
    /// Where the path is on the program: the block's execution number (0: none), the
    /// segment's place among the block's segments, and how far along it (0 to 1). After an
    /// NC stop, the interruption point an offset change resumes from.
    pub block_seq: u32,
    pub piece: u32,
    pub along: f64,
    /// The work-offset table's version: 1 at start, one more with every accepted edit.
    pub work_offsets_version: u32,
    /// The active work offset's index in [`WorkOffsetsMsg`] (0: none).
    pub work_offset: u32,
    /// The running block's tool (T, 0: none) and cutting edge or offset number (D, 0: none).
    pub tool: u32,
    pub edge: u32,
    /// Speed setpoint per spindle, rev/min (signed), as in the setpoint.
    pub spindle: [f64; MAX_SPINDLES],
}

/// What an HMI asks the kernel.
pub mod command {
    pub const START: u32 = 1;
    pub const STOP: u32 = 2;
    pub const RESET: u32 = 3;
    /// `text`: the program's path.
    pub const LOAD: u32 = 4;
    /// `value`: 1 on, 0 off.
    pub const SINGLE_BLOCK: u32 = 5;
    /// `value`: 0 < x ≤ 1.2.
    pub const OVERRIDE: u32 = 6;
    /// `t`: the tool (0: a D number of its own, as on the 840C), `d`: the D number,
    /// `value`: the radius, `flag`: 1 for wear.
    pub const SET_OFFSET: u32 = 7;
    /// The kernel process ends (after braking, if the path moves).
    pub const SHUTDOWN: u32 = 8;
    /// `d`: a program number (`KernelStatus::program`); the reply's message is its path.
    pub const PROGRAM_INFO: u32 = 9;
    /// `text`: the work offset's name as the dialect writes it (`G54`, `G54.1 P3`);
    /// `axis_values[i]` for each bit i of `axis_mask` ([`AxisList`] order).
    pub const SET_WORK_OFFSET: u32 = 10;
}

pub const TEXT: usize = 512;

/// An HMI command (request-response: one [`Reply`] each).
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::Command")]
pub struct Command {
    /// `command::*`.
    pub kind: u32,
    pub d: u32,
    pub value: f64,
    pub flag: u8,
    pub _pad: u8,
    pub text_len: u16,
    /// The tool number where offsets are numbered per tool (T/D, 808D); 0: none.
    pub t: u32,
    pub text: [u8; TEXT],
    /// `SET_WORK_OFFSET`: bit i set when `axis_values[i]` is given.
    pub axis_mask: u32,
    pub _pad2: u32,
    pub axis_values: [f64; MAX_AXES],
}

impl Command {
    pub fn new(kind: u32) -> Self {
        Command {
            kind,
            d: 0,
            value: 0.0,
            flag: 0,
            _pad: 0,
            text_len: 0,
            t: 0,
            text: [0; TEXT],
            axis_mask: 0,
            _pad2: 0,
            axis_values: [0.0; MAX_AXES],
        }
    }

    /// With `text` (cut at the first UTF-8 boundary that fits).
    pub fn with_text(mut self, text: &str) -> Self {
        let n = fit(text, TEXT);
        self.text[..n].copy_from_slice(&text.as_bytes()[..n]);
        self.text_len = n as u16;
        self
    }

    pub fn text(&self) -> &str {
        as_text(&self.text, self.text_len as usize)
    }

    /// The tool a `SET_OFFSET` names (`None`: a D number of its own).
    pub fn tool(&self) -> Option<u32> {
        (self.t != 0).then_some(self.t)
    }

    /// `SET_OFFSET` of D`d` (of tool `t` on a T/D table): the geometry radius, or the
    /// radius wear when `wear`.
    pub fn offset(t: Option<u32>, d: u32, value: f64, wear: bool) -> Self {
        let mut c = Command::new(command::SET_OFFSET);
        c.t = t.unwrap_or(0);
        c.d = d;
        c.value = value;
        c.flag = wear as u8;
        c
    }

    /// `SET_WORK_OFFSET` of the set `name`: each `(slot, value)` is an axis in
    /// [`AxisList`] order and its new value, mm or degrees.
    pub fn work_offset(name: &str, values: &[(usize, f64)]) -> Self {
        let mut c = Command::new(command::SET_WORK_OFFSET).with_text(name);
        for &(i, v) in values.iter().filter(|(i, _)| *i < MAX_AXES) {
            c.axis_mask |= 1 << i;
            c.axis_values[i] = v;
        }
        c
    }

    /// The axis values of a `SET_WORK_OFFSET`, as (slot, value).
    pub fn axis_values(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (0..MAX_AXES)
            .filter(|i| self.axis_mask & (1 << i) != 0)
            .map(|i| (i, self.axis_values[i]))
    }
}

/// The kernel's answer to a [`Command`].
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::Reply")]
pub struct Reply {
    /// 1: done; 0: refused, `message` says why.
    pub ok: u8,
    pub _pad: u8,
    pub len: u16,
    /// An alarm number when refused for one (0: none).
    pub alarm: u32,
    /// The tool table's version after the command (the kernel sets it on every reply).
    pub tools_version: u32,
    /// The work-offset table's version after the command (set on every reply).
    pub work_offsets_version: u32,
    pub message: [u8; TEXT],
}

impl Reply {
    pub fn new(ok: bool, alarm: u32, message: &str) -> Self {
        let mut r = Reply {
            ok: ok as u8,
            _pad: 0,
            len: 0,
            alarm,
            tools_version: 0,
            work_offsets_version: 0,
            message: [0; TEXT],
        };
        let n = fit(message, TEXT);
        r.message[..n].copy_from_slice(&message.as_bytes()[..n]);
        r.len = n as u16;
        r
    }

    pub fn message(&self) -> &str {
        as_text(&self.message, self.len as usize)
    }
}

/// Offsets a [`ToolTableMsg`] carries at most.
pub const TOOL_ENTRIES: usize = 64;

/// One tool offset.
#[derive(Clone, Copy, Debug, Default, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::ToolEntry")]
pub struct ToolEntry {
    /// Tool number on T/D machines (0: a global D offset).
    pub t: u32,
    pub d: u32,
    pub radius: f64,
    pub radius_wear: f64,
    pub length: f64,
    pub length_wear: f64,
    /// Cutting edge position 1–9 of a turning tool (docs/turning.md: where the tip P lies
    /// from the nose centre); 0: none given (P is the nose centre, as for a milling cutter).
    pub cutting_edge: u8,
    pub _pad: [u8; 7],
}

/// The kernel's tool table, kernel → anyone, when it changes (the newest kept for late
/// subscribers).
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::ToolTableMsg")]
pub struct ToolTableMsg {
    /// 1 at start, one more with every accepted edit (as `KernelStatus::tools_version`).
    pub version: u32,
    pub count: u32,
    /// Saved to a tool file (0: the built-in table, not saved).
    pub saved: u8,
    /// More offsets than fit (`TOOL_ENTRIES`) were left out.
    pub truncated: u8,
    pub _pad: [u8; 6],
    pub entries: [ToolEntry; TOOL_ENTRIES],
}

impl Default for ToolTableMsg {
    fn default() -> Self {
        ToolTableMsg {
            version: 0,
            count: 0,
            saved: 0,
            truncated: 0,
            _pad: [0; 6],
            entries: [ToolEntry::default(); TOOL_ENTRIES],
        }
    }
}

impl ToolTableMsg {
    pub fn entries(&self) -> &[ToolEntry] {
        &self.entries[..(self.count as usize).min(TOOL_ENTRIES)]
    }
}

/// Work offsets a [`WorkOffsetsMsg`] carries at most (Fanuc: G54…G59 and G54.1 P1…P48).
pub const WORK_OFFSET_ENTRIES: usize = 128;

/// One work offset (settable zero offset): its name and its value per axis.
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::WorkOffsetEntry")]
pub struct WorkOffsetEntry {
    /// The name as the dialect writes it (`G54`, `G54.1 P3`), ASCII, 0-padded.
    pub name: [u8; 16],
    /// Every configured axis in [`AxisList`] order, mm or degrees.
    pub values: [f64; MAX_AXES],
}

impl Default for WorkOffsetEntry {
    fn default() -> Self {
        WorkOffsetEntry {
            name: [0; 16],
            values: [0.0; MAX_AXES],
        }
    }
}

impl WorkOffsetEntry {
    pub fn new(name: &str, values: [f64; MAX_AXES]) -> Self {
        let mut e = WorkOffsetEntry {
            name: [0; 16],
            values,
        };
        let n = fit(name, 16);
        e.name[..n].copy_from_slice(&name.as_bytes()[..n]);
        e
    }

    pub fn name(&self) -> &str {
        let len = self.name.iter().position(|&b| b == 0).unwrap_or(16);
        as_text(&self.name, len)
    }
}

/// The kernel's work-offset table, kernel → anyone, when it changes (the newest kept for
/// late subscribers): every set the dialect has, in its order.
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend)]
#[repr(C)]
#[type_name("softnc::WorkOffsetsMsg")]
pub struct WorkOffsetsMsg {
    /// 1 at start, one more with every accepted edit (as `KernelStatus::work_offsets_version`).
    pub version: u32,
    pub count: u32,
    /// Saved to a work-offset file (0: the built-in table, not saved).
    pub saved: u8,
    pub _pad: [u8; 7],
    pub axes: AxisList,
    pub entries: [WorkOffsetEntry; WORK_OFFSET_ENTRIES],
}

impl Default for WorkOffsetsMsg {
    fn default() -> Self {
        WorkOffsetsMsg {
            version: 0,
            count: 0,
            saved: 0,
            _pad: [0; 7],
            axes: AxisList::default(),
            entries: [WorkOffsetEntry::default(); WORK_OFFSET_ENTRIES],
        }
    }
}

impl WorkOffsetsMsg {
    pub fn entries(&self) -> &[WorkOffsetEntry] {
        &self.entries[..(self.count as usize).min(WORK_OFFSET_ENTRIES)]
    }
}

/// The longest prefix of `s` within `max` bytes that ends on a character boundary.
fn fit(s: &str, max: usize) -> usize {
    let mut n = s.len().min(max);
    while !s.is_char_boundary(n) {
        n -= 1;
    }
    n
}

fn as_text(bytes: &[u8], len: usize) -> &str {
    let b = &bytes[..len.min(bytes.len())];
    match std::str::from_utf8(b) {
        Ok(s) => s,
        // A peer wrote bytes that are not UTF-8: show what is valid.
        Err(e) => std::str::from_utf8(&b[..e.valid_up_to()]).unwrap_or(""),
    }
}

/// Size and alignment of every payload, in a fixed order: part of the ABI string, so a peer
/// whose layout differs in any way is refused by name.
pub fn layouts() -> [(&'static str, usize, usize); 14] {
    use std::mem::{align_of, size_of};
    macro_rules! l {
        ($t:ty) => {
            (stringify!($t), size_of::<$t>(), align_of::<$t>())
        };
    }
    [
        l!(AxisList),
        l!(SetpointMsg),
        l!(AuxWordMsg),
        l!(AuxRequest),
        l!(AuxAck),
        l!(PlcSignals),
        l!(ActualValues),
        l!(KernelStatus),
        l!(Command),
        l!(Reply),
        l!(ToolEntry),
        l!(ToolTableMsg),
        l!(WorkOffsetEntry),
        l!(WorkOffsetsMsg),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_cut_on_a_character_boundary() {
        let long = "ä".repeat(400); // 800 bytes
        let c = Command::new(command::LOAD).with_text(&long);
        assert_eq!(c.text().len(), 512);
        assert!(c.text().chars().all(|ch| ch == 'ä'));
        assert_eq!(Reply::new(false, 7, "no").message(), "no");
    }

    #[test]
    fn payloads_have_no_hidden_padding() {
        // Explicit padding fields keep the bytes defined; the sizes are what the fields add
        // up to.
        assert_eq!(
            std::mem::size_of::<SetpointMsg>(),
            4 * 8 + 2 * 4 + MAX_AXES * 8 + 8 + 8 + MAX_SPINDLES * 8
        );
        assert_eq!(std::mem::size_of::<AxisList>(), MAX_AXES + 1 + 5 + 2);
        assert_eq!(std::mem::size_of::<AuxRequest>(), 16 + 8 + 12 * 16 + 8);
        assert_eq!(std::mem::size_of::<PlcSignals>(), 24 + MAX_SPINDLES * 8);
        // Every byte a named field: no implicit padding.
        assert_eq!(
            std::mem::size_of::<KernelStatus>(),
            2 * 8
                + 2 * 4
                + MAX_AXES * 8
                + 16
                + 2 * 8
                + 4 * 4
                + 8
                + 4
                + 4
                + 2 * 4
                + 8
                + 4 * 4
                + MAX_SPINDLES * 8
        );
        assert_eq!(std::mem::size_of::<Command>(), 24 + TEXT + 8 + MAX_AXES * 8);
        assert_eq!(std::mem::size_of::<WorkOffsetEntry>(), 16 + MAX_AXES * 8);
        let c = Command::work_offset("G54.1 P3", &[(0, 1.5), (2, -3.0), (9, 1.0)]);
        assert_eq!(c.text(), "G54.1 P3");
        assert_eq!(c.axis_values().collect::<Vec<_>>(), [(0, 1.5), (2, -3.0)]);
        assert_eq!(WorkOffsetEntry::new("G55", [0.0; MAX_AXES]).name(), "G55");
        assert_eq!(std::mem::size_of::<Reply>(), 16 + TEXT);
    }
}
