"""softnc's payloads as ctypes structures, for clients in Python.

The layouts nc-kernel, plc-sim and the HMI exchange over iceoryx2 (protocol/src/payload.rs).
docs/interfaces.md says which service carries which, how to open them and how to read the
sequence numbers; tests/clients.rs checks every class here against the Rust types, and the
protocol's unit tests check docs/interfaces.md against this file. This module needs only
ctypes; softnc_subscribe.py beside it shows the iceoryx2 side.

Each class gives iceoryx2 its type name by the static method ``type_name``, as the Python
package asks for: with ctypes' size and alignment it must equal the Rust type's.
"""

import ctypes

# The protocol this module describes: the services' attribute "softnc.abi" has this value.
PROTOCOL_VERSION = 5
ABI_KEY = "softnc.abi"
ABI = "softnc-ipc/5/2257ae8dd09418d4"

MAX_AXES = 8
MAX_SPINDLES = 2
AUX_WORDS = 12
TEXT = 512
TOOL_ENTRIES = 64
WORK_OFFSET_ENTRIES = 128

# SetpointMsg.state and KernelStatus.state
STATES = {0: "RESET", 1: "ACTIVE", 2: "STOPPED", 3: "END"}
STATE_END = 3


class AxisList(ctypes.Structure):
    """softnc::AxisList: The machine's axes in wire order (X Y Z U V W A B C as configured). Size 16, align 2."""

    _fields_ = [
        ("names", ctypes.c_uint8 * MAX_AXES),  # 0: ASCII upper case, 0 past count
        ("count", ctypes.c_uint8),  # 8: configured axes
        ("_pad", ctypes.c_uint8 * 5),  # 9
        ("kinds", ctypes.c_uint16),  # 14: bit i: axis i rotary; bit 8+i: modulo
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::AxisList"


class SetpointMsg(ctypes.Structure):
    """softnc::SetpointMsg: <instance>/setpoints: kernel -> PLC and anyone, every IPO cycle. Size 136, align 8."""

    _fields_ = [
        ("seq", ctypes.c_uint64),  # 0: 1, 2, ... per kernel run: a gap = lost samples
        ("cycle", ctypes.c_uint64),  # 8: IPO cycle number
        ("sent_ns", ctypes.c_uint64),  # 16: CLOCK_MONOTONIC when sent, ns
        ("deadline_ns", ctypes.c_uint64),  # 24: take it by then (next cycle start), ns
        ("cycle_us", ctypes.c_uint32),  # 32: IPO cycle, us
        ("line", ctypes.c_uint32),  # 36: source line of the running block (0: none)
        ("pos", ctypes.c_double * MAX_AXES),  # 40: mm or degrees, AxisList order, 0 past axes
        ("v_path", ctypes.c_double),  # 104: path speed, mm/s
        ("state", ctypes.c_uint8),  # 112: 0 RESET, 1 ACTIVE, 2 STOPPED, 3 END
        ("axes", ctypes.c_uint8),  # 113: entries of pos that count
        ("spindles", ctypes.c_uint8),  # 114: entries of spindle, spindle_mode that count
        ("spindle_mode", ctypes.c_uint8 * MAX_SPINDLES),  # 115: 0 stop, 1 turn, 2 oriented stop (M19)
        ("_pad", ctypes.c_uint8 * 3),  # 117
        ("spindle", ctypes.c_double * MAX_SPINDLES),  # 120: speed setpoint, rev/min, + clockwise
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::SetpointMsg"


class AuxWordMsg(ctypes.Structure):
    """softnc::AuxWordMsg: One word of an AuxRequest. Size 16, align 8."""

    _fields_ = [
        ("address", ctypes.c_uint8),  # 0: ASCII upper case: M, S, T, H, ...
        ("_pad", ctypes.c_uint8 * 7),  # 1
        ("value", ctypes.c_double),  # 8
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::AuxWordMsg"


class AuxRequest(ctypes.Structure):
    """softnc::AuxRequest: <instance>/aux (request): kernel -> PLC, auxiliary functions at an S point. Size 224, align 8."""

    _fields_ = [
        ("id", ctypes.c_uint64),  # 0: 1, 2, ... per kernel run
        ("cycle", ctypes.c_uint64),  # 8: IPO cycle it was output in
        ("line", ctypes.c_uint32),  # 16
        ("count", ctypes.c_uint32),  # 20: entries of words that count
        ("words", AuxWordMsg * AUX_WORDS),  # 24
        ("wait", ctypes.c_uint8),  # 216: 1: the path waits for the acknowledgement
        ("_pad", ctypes.c_uint8 * 7),  # 217
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::AuxRequest"


class AuxAck(ctypes.Structure):
    """softnc::AuxAck: <instance>/aux (response): PLC -> kernel. Size 16, align 8."""

    _fields_ = [
        ("id", ctypes.c_uint64),  # 0: the request's id
        ("alarm", ctypes.c_uint32),  # 8: 0: done; else the PLC alarm that refused it
        ("_pad", ctypes.c_uint32),  # 12
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::AuxAck"


class PlcSignals(ctypes.Structure):
    """softnc::PlcSignals: <instance>/plc.signals: PLC -> kernel and anyone, every PLC cycle. Size 40, align 8."""

    _fields_ = [
        ("seq", ctypes.c_uint64),  # 0: 1, 2, ... per plc-sim run
        ("echo_cycle", ctypes.c_uint64),  # 8: last setpoint cycle consumed (sign of life)
        ("feed_hold", ctypes.c_uint8),  # 16: 1: set
        ("read_in_disable", ctypes.c_uint8),  # 17: 1: set
        ("drives_ready", ctypes.c_uint8),  # 18: 1: all drives ready
        ("emergency_stop", ctypes.c_uint8),  # 19: 1: pressed
        ("alarm", ctypes.c_uint32),  # 20: PLC alarm, 0: none
        ("spindle_rpm", ctypes.c_double * MAX_SPINDLES),  # 24: actual speed, rev/min, signed
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::PlcSignals"


class ActualValues(ctypes.Structure):
    """softnc::ActualValues: <instance>/plc.actuals: PLC -> anyone, every PLC cycle. Size 176, align 8."""

    _fields_ = [
        ("seq", ctypes.c_uint64),  # 0: 1, 2, ... per plc-sim run
        ("cycle", ctypes.c_uint64),  # 8: the setpoint cycle these follow
        ("pos", ctypes.c_double * MAX_AXES),  # 16: actual position, AxisList order
        ("following_error", ctypes.c_double * MAX_AXES),  # 80: setpoint - actual, mm or degrees
        ("spindle_rpm", ctypes.c_double * MAX_SPINDLES),  # 144: actual speed, rev/min, signed
        ("tool", ctypes.c_uint32),  # 160: tool in the spindle
        ("aux_acked", ctypes.c_uint32),  # 164: auxiliary functions acknowledged so far
        ("plc_alarm", ctypes.c_uint32),  # 168: 0: none
        ("_pad", ctypes.c_uint32),  # 172
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::ActualValues"


class KernelStatus(ctypes.Structure):
    """softnc::KernelStatus: <instance>/status: kernel -> anyone, every IPO cycle. Size 200, align 8."""

    _fields_ = [
        ("seq", ctypes.c_uint64),  # 0: 1, 2, ... per kernel run: a gap = lost samples
        ("cycle", ctypes.c_uint64),  # 8: IPO cycle number
        ("program", ctypes.c_uint32),  # 16: changes with every load (0: none loaded)
        ("line", ctypes.c_uint32),  # 20: source line of the running block
        ("pos", ctypes.c_double * MAX_AXES),  # 24: setpoint, mm or degrees, axes order
        ("axes", AxisList),  # 88: names and kinds of pos's entries
        ("v_path", ctypes.c_double),  # 104: path speed, mm/s
        ("override_", ctypes.c_double),  # 112: feed override, 0 < x <= 1.2
        ("alarm", ctypes.c_uint32),  # 120: first alarm standing (0: none)
        ("aux_sent", ctypes.c_uint32),  # 124
        ("aux_acked", ctypes.c_uint32),  # 128
        ("tools_version", ctypes.c_uint32),  # 132: 1 at start, +1 per accepted offset edit
        ("plc_cycle", ctypes.c_uint64),  # 136: kernel cycle of the PLC's last sign of life
        ("state", ctypes.c_uint8),  # 144: 0 RESET, 1 ACTIVE, 2 STOPPED, 3 END
        ("single_block", ctypes.c_uint8),  # 145: 1: on
        ("plc_alive", ctypes.c_uint8),  # 146: 1: the PLC's sign of life is there
        ("role", ctypes.c_uint8),  # 147: running segment's role (0: none)
        ("skipped", ctypes.c_uint32),  # 148: IPO periods skipped after hold-ups
        ("block_seq", ctypes.c_uint32),  # 152: block execution number (0: none)
        ("piece", ctypes.c_uint32),  # 156: segment within the block
        ("along", ctypes.c_double),  # 160: how far along the segment, 0 to 1
        ("work_offsets_version", ctypes.c_uint32),  # 168: 1 at start, +1 per accepted edit
        ("work_offset", ctypes.c_uint32),  # 172: index of the active work offset (0: none)
        ("tool", ctypes.c_uint32),  # 176: T of the path's place (0: none)
        ("edge", ctypes.c_uint32),  # 180: D of the path's place (0: none)
        ("spindle", ctypes.c_double * MAX_SPINDLES),  # 184: speed setpoint, rev/min, signed
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::KernelStatus"


class Command(ctypes.Structure):
    """softnc::Command: <instance>/commands (request): HMI -> kernel; one Reply each. Size 608, align 8."""

    _fields_ = [
        ("kind", ctypes.c_uint32),  # 0: 1 start, 2 stop, 3 reset, 4 load, ... (docs)
        ("d", ctypes.c_uint32),  # 4: D number; PROGRAM_INFO: program number
        ("value", ctypes.c_double),  # 8: override, radius, single block on/off
        ("flag", ctypes.c_uint8),  # 16: SET_OFFSET: 1 for wear
        ("_pad", ctypes.c_uint8),  # 17
        ("text_len", ctypes.c_uint16),  # 18: bytes of text that count
        ("t", ctypes.c_uint32),  # 20: tool number on T/D tables (0: none)
        ("text", ctypes.c_uint8 * TEXT),  # 24: UTF-8: program path, work offset name
        ("axis_mask", ctypes.c_uint32),  # 536: SET_WORK_OFFSET: bit i = axis_values[i] given
        ("_pad2", ctypes.c_uint32),  # 540
        ("axis_values", ctypes.c_double * MAX_AXES),  # 544: AxisList order
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::Command"


class Reply(ctypes.Structure):
    """softnc::Reply: <instance>/commands (response): kernel -> HMI. Size 528, align 4."""

    _fields_ = [
        ("ok", ctypes.c_uint8),  # 0: 1: done; 0: refused, message says why
        ("_pad", ctypes.c_uint8),  # 1
        ("len", ctypes.c_uint16),  # 2: bytes of message that count
        ("alarm", ctypes.c_uint32),  # 4: alarm number when refused for one
        ("tools_version", ctypes.c_uint32),  # 8: tool table version after the command
        ("work_offsets_version", ctypes.c_uint32),  # 12: work-offset table version after it
        ("message", ctypes.c_uint8 * TEXT),  # 16: UTF-8
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::Reply"


class ToolEntry(ctypes.Structure):
    """softnc::ToolEntry: One tool offset. Size 48, align 8."""

    _fields_ = [
        ("t", ctypes.c_uint32),  # 0: tool number on T/D machines (0: global D)
        ("d", ctypes.c_uint32),  # 4
        ("radius", ctypes.c_double),  # 8: mm
        ("radius_wear", ctypes.c_double),  # 16: mm
        ("length", ctypes.c_double),  # 24: mm
        ("length_wear", ctypes.c_double),  # 32: mm
        ("cutting_edge", ctypes.c_uint8),  # 40: cutting edge position 1-9 of a turning tool (0: none)
        ("_pad", ctypes.c_uint8 * 7),  # 41
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::ToolEntry"


class ToolTableMsg(ctypes.Structure):
    """softnc::ToolTableMsg: <instance>/tools: kernel -> anyone when it changes (history 1). Size 3088, align 8."""

    _fields_ = [
        ("version", ctypes.c_uint32),  # 0: as KernelStatus.tools_version
        ("count", ctypes.c_uint32),  # 4: entries that count
        ("saved", ctypes.c_uint8),  # 8: 1: saved to a tool file
        ("truncated", ctypes.c_uint8),  # 9: 1: more offsets than fit
        ("_pad", ctypes.c_uint8 * 6),  # 10
        ("entries", ToolEntry * TOOL_ENTRIES),  # 16
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::ToolTableMsg"


class WorkOffsetEntry(ctypes.Structure):
    """softnc::WorkOffsetEntry: One work offset. Size 80, align 8."""

    _fields_ = [
        ("name", ctypes.c_uint8 * 16),  # 0: ASCII, 0-padded: G54, G54.1 P3
        ("values", ctypes.c_double * MAX_AXES),  # 16: AxisList order, mm or degrees
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::WorkOffsetEntry"


class WorkOffsetsMsg(ctypes.Structure):
    """softnc::WorkOffsetsMsg: <instance>/work-offsets: kernel -> anyone when it changes (history 1). Size 10272, align 8."""

    _fields_ = [
        ("version", ctypes.c_uint32),  # 0: as KernelStatus.work_offsets_version
        ("count", ctypes.c_uint32),  # 4: entries that count
        ("saved", ctypes.c_uint8),  # 8: 1: saved to a work-offset file
        ("_pad", ctypes.c_uint8 * 7),  # 9
        ("axes", AxisList),  # 16
        ("entries", WorkOffsetEntry * WORK_OFFSET_ENTRIES),  # 32
    ]

    @staticmethod
    def type_name() -> str:
        return "softnc::WorkOffsetsMsg"


# Every payload, nested ones first.
PAYLOADS = [
    AxisList,
    SetpointMsg,
    AuxWordMsg,
    AuxRequest,
    AuxAck,
    PlcSignals,
    ActualValues,
    KernelStatus,
    Command,
    Reply,
    ToolEntry,
    ToolTableMsg,
    WorkOffsetEntry,
    WorkOffsetsMsg,
]

# The publish-subscribe services of an instance and their payloads: "<instance>/<name>".
PUBLISHED = {
    "setpoints": SetpointMsg,
    "status": KernelStatus,
    "plc.actuals": ActualValues,
    "plc.signals": PlcSignals,
    "tools": ToolTableMsg,
    "work-offsets": WorkOffsetsMsg,
}


def prefix(instance: str) -> str:
    """The iceoryx2 global prefix of an instance: every file of it starts with this."""
    return f"softnc_{instance}_"


def service_name(instance: str, service: str) -> str:
    """The full service name, e.g. ``softnc/setpoints``."""
    return f"{instance}/{service}"


def axis_names(axes: AxisList) -> str:
    """The configured axes' letters in wire order (the order of every ``pos`` array)."""
    return bytes(axes.names[: min(axes.count, MAX_AXES)]).decode("ascii")
