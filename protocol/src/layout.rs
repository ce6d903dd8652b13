//! Every payload field by field — name, offset, size — for clients in other languages: the
//! C header and the Python classes in clients/ and docs/interfaces.md are checked against
//! this table (the unit tests below read the doc; tests/clients.rs compiles the header and
//! asks Python's ctypes), so none of them can go stale.

use crate::payload::*;
use iceoryx2::prelude::ZeroCopySend;
use std::mem::{align_of, offset_of, size_of};

/// One field of a payload.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub name: &'static str,
    pub offset: usize,
    pub size: usize,
}

/// One payload type as iceoryx2 sees it: the type name a peer in any language must give,
/// with size and alignment, and its fields in memory order.
#[derive(Clone, Debug, PartialEq)]
pub struct PayloadLayout {
    /// The Rust type's name (`SetpointMsg`).
    pub rust: &'static str,
    /// The iceoryx2 type name (`softnc::SetpointMsg`).
    pub type_name: &'static str,
    pub size: usize,
    pub align: usize,
    pub fields: Vec<Field>,
}

/// The array lengths the payloads use, by the name the C header and the Python module give
/// them.
pub const LENGTHS: [(&str, usize); 6] = [
    ("MAX_AXES", MAX_AXES),
    ("MAX_SPINDLES", MAX_SPINDLES),
    ("AUX_WORDS", AUX_WORDS),
    ("TEXT", TEXT),
    ("TOOL_ENTRIES", TOOL_ENTRIES),
    ("WORK_OFFSET_ENTRIES", WORK_OFFSET_ENTRIES),
];

fn field_size<T, F>(_: fn(&T) -> &F) -> usize {
    size_of::<F>()
}

macro_rules! payload {
    ($t:ident: $($f:ident),* $(,)?) => {
        PayloadLayout {
            rust: stringify!($t),
            // SAFETY: reads the name `#[type_name]` gave; nothing is assumed about a layout.
            type_name: unsafe { <$t as ZeroCopySend>::type_name() },
            size: size_of::<$t>(),
            align: align_of::<$t>(),
            fields: vec![$(Field {
                name: stringify!($f),
                offset: offset_of!($t, $f),
                size: field_size(|p: &$t| &p.$f),
            }),*],
        }
    };
}

/// Every payload, in the order of [`layouts`] (nested ones before the types holding them).
pub fn payloads() -> Vec<PayloadLayout> {
    vec![
        payload!(AxisList: names, count, _pad, kinds),
        payload!(SetpointMsg: seq, cycle, sent_ns, deadline_ns, cycle_us, line, pos, v_path, state,
            axes, spindles, spindle_mode, _pad, spindle),
        payload!(AuxWordMsg: address, _pad, value),
        payload!(AuxRequest: id, cycle, line, count, words, wait, _pad),
        payload!(AuxAck: id, alarm, _pad),
        payload!(PlcSignals: seq, echo_cycle, feed_hold, read_in_disable, drives_ready,
            emergency_stop, alarm, spindle_rpm),
        payload!(ActualValues: seq, cycle, pos, following_error, spindle_rpm, tool, aux_acked,
            plc_alarm, _pad),
        payload!(KernelStatus: seq, cycle, program, line, pos, axes, v_path, override_, alarm,
            aux_sent, aux_acked, tools_version, plc_cycle, state, single_block, plc_alive, role,
            skipped, block_seq, piece, along, work_offsets_version, work_offset, tool, edge,
            spindle),
        payload!(Command: kind, d, value, flag, _pad, text_len, t, text, axis_mask, _pad2,
            axis_values),
        payload!(Reply: ok, _pad, len, alarm, tools_version, work_offsets_version, message),
        payload!(ToolEntry: t, d, radius, radius_wear, length, length_wear, cutting_edge,
            _pad),
        payload!(ToolTableMsg: version, count, saved, truncated, _pad, entries),
        payload!(WorkOffsetEntry: name, values),
        payload!(WorkOffsetsMsg: version, count, saved, _pad, axes, entries),
    ]
}

#[cfg(test)]
#[path = "layout_tests.rs"]
mod tests;
