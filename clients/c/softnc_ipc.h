/*
 * softnc's payloads in C: the layouts nc-kernel, plc-sim and the HMI exchange over iceoryx2
 * (protocol/src/payload.rs). docs/interfaces.md says which service carries which, how to open
 * them and how to read the sequence numbers; tests/clients.rs checks every offset here against
 * the Rust types, and the protocol's unit tests check docs/interfaces.md against this file.
 *
 * Each struct is `#[repr(C)]` on the Rust side with explicit padding fields: no hidden bytes.
 * The iceoryx2 payload type name to give is the one in each struct's comment
 * (iox2_service_builder_pub_sub_set_payload_type_details), with sizeof and _Alignof; the user
 * header is "()", size 0, alignment 1.
 */
#ifndef SOFTNC_IPC_H
#define SOFTNC_IPC_H

#include <stdint.h>

/* The protocol this header describes: the services' attribute "softnc.abi" has this value. */
#define SOFTNC_PROTOCOL_VERSION 5
#define SOFTNC_ABI_KEY "softnc.abi"
#define SOFTNC_ABI "softnc-ipc/5/2257ae8dd09418d4"

#define SOFTNC_MAX_AXES 8
#define SOFTNC_MAX_SPINDLES 2
#define SOFTNC_AUX_WORDS 12
#define SOFTNC_TEXT 512
#define SOFTNC_TOOL_ENTRIES 64
#define SOFTNC_WORK_OFFSET_ENTRIES 128

/* SetpointMsg.state and KernelStatus.state */
#define SOFTNC_STATE_RESET 0
#define SOFTNC_STATE_ACTIVE 1
#define SOFTNC_STATE_STOPPED 2
#define SOFTNC_STATE_END 3

/* softnc::AxisList: The machine's axes in wire order (X Y Z U V W A B C as configured). */
struct softnc_AxisList {
    uint8_t names[SOFTNC_MAX_AXES]; /*    0: ASCII upper case, 0 past count */
    uint8_t count;                  /*    8: configured axes */
    uint8_t _pad[5];                /*    9 */
    uint16_t kinds;                 /*   14: bit i: axis i rotary; bit 8+i: modulo */
}; /* size 16, align 2 */

/* softnc::SetpointMsg: <instance>/setpoints: kernel -> PLC and anyone, every IPO cycle. */
struct softnc_SetpointMsg {
    uint64_t seq;                              /*    0: 1, 2, ... per kernel run: a gap = lost samples */
    uint64_t cycle;                            /*    8: IPO cycle number */
    uint64_t sent_ns;                          /*   16: CLOCK_MONOTONIC when sent, ns */
    uint64_t deadline_ns;                      /*   24: take it by then (next cycle start), ns */
    uint32_t cycle_us;                         /*   32: IPO cycle, us */
    uint32_t line;                             /*   36: source line of the running block (0: none) */
    double pos[SOFTNC_MAX_AXES];               /*   40: mm or degrees, AxisList order, 0 past axes */
    double v_path;                             /*  104: path speed, mm/s */
    uint8_t state;                             /*  112: 0 RESET, 1 ACTIVE, 2 STOPPED, 3 END */
    uint8_t axes;                              /*  113: entries of pos that count */
    uint8_t spindles;                          /*  114: entries of spindle, spindle_mode that count */
    uint8_t spindle_mode[SOFTNC_MAX_SPINDLES]; /*  115: 0 stop, 1 turn, 2 oriented stop (M19) */
    uint8_t _pad[3];                           /*  117 */
    double spindle[SOFTNC_MAX_SPINDLES];       /*  120: speed setpoint, rev/min, + clockwise */
}; /* size 136, align 8 */

/* softnc::AuxWordMsg: One word of an AuxRequest. */
struct softnc_AuxWordMsg {
    uint8_t address; /*    0: ASCII upper case: M, S, T, H, ... */
    uint8_t _pad[7]; /*    1 */
    double value;    /*    8 */
}; /* size 16, align 8 */

/* softnc::AuxRequest: <instance>/aux (request): kernel -> PLC, auxiliary functions at an S point. */
struct softnc_AuxRequest {
    uint64_t id;                                      /*    0: 1, 2, ... per kernel run */
    uint64_t cycle;                                   /*    8: IPO cycle it was output in */
    uint32_t line;                                    /*   16 */
    uint32_t count;                                   /*   20: entries of words that count */
    struct softnc_AuxWordMsg words[SOFTNC_AUX_WORDS]; /*   24 */
    uint8_t wait;                                     /*  216: 1: the path waits for the acknowledgement */
    uint8_t _pad[7];                                  /*  217 */
}; /* size 224, align 8 */

/* softnc::AuxAck: <instance>/aux (response): PLC -> kernel. */
struct softnc_AuxAck {
    uint64_t id;    /*    0: the request's id */
    uint32_t alarm; /*    8: 0: done; else the PLC alarm that refused it */
    uint32_t _pad;  /*   12 */
}; /* size 16, align 8 */

/* softnc::PlcSignals: <instance>/plc.signals: PLC -> kernel and anyone, every PLC cycle. */
struct softnc_PlcSignals {
    uint64_t seq;                            /*    0: 1, 2, ... per plc-sim run */
    uint64_t echo_cycle;                     /*    8: last setpoint cycle consumed (sign of life) */
    uint8_t feed_hold;                       /*   16: 1: set */
    uint8_t read_in_disable;                 /*   17: 1: set */
    uint8_t drives_ready;                    /*   18: 1: all drives ready */
    uint8_t emergency_stop;                  /*   19: 1: pressed */
    uint32_t alarm;                          /*   20: PLC alarm, 0: none */
    double spindle_rpm[SOFTNC_MAX_SPINDLES]; /*   24: actual speed, rev/min, signed */
}; /* size 40, align 8 */

/* softnc::ActualValues: <instance>/plc.actuals: PLC -> anyone, every PLC cycle. */
struct softnc_ActualValues {
    uint64_t seq;                            /*    0: 1, 2, ... per plc-sim run */
    uint64_t cycle;                          /*    8: the setpoint cycle these follow */
    double pos[SOFTNC_MAX_AXES];             /*   16: actual position, AxisList order */
    double following_error[SOFTNC_MAX_AXES]; /*   80: setpoint - actual, mm or degrees */
    double spindle_rpm[SOFTNC_MAX_SPINDLES]; /*  144: actual speed, rev/min, signed */
    uint32_t tool;                           /*  160: tool in the spindle */
    uint32_t aux_acked;                      /*  164: auxiliary functions acknowledged so far */
    uint32_t plc_alarm;                      /*  168: 0: none */
    uint32_t _pad;                           /*  172 */
}; /* size 176, align 8 */

/* softnc::KernelStatus: <instance>/status: kernel -> anyone, every IPO cycle. */
struct softnc_KernelStatus {
    uint64_t seq;                        /*    0: 1, 2, ... per kernel run: a gap = lost samples */
    uint64_t cycle;                      /*    8: IPO cycle number */
    uint32_t program;                    /*   16: changes with every load (0: none loaded) */
    uint32_t line;                       /*   20: source line of the running block */
    double pos[SOFTNC_MAX_AXES];         /*   24: setpoint, mm or degrees, axes order */
    struct softnc_AxisList axes;         /*   88: names and kinds of pos's entries */
    double v_path;                       /*  104: path speed, mm/s */
    double override_;                    /*  112: feed override, 0 < x <= 1.2 */
    uint32_t alarm;                      /*  120: first alarm standing (0: none) */
    uint32_t aux_sent;                   /*  124 */
    uint32_t aux_acked;                  /*  128 */
    uint32_t tools_version;              /*  132: 1 at start, +1 per accepted offset edit */
    uint64_t plc_cycle;                  /*  136: kernel cycle of the PLC's last sign of life */
    uint8_t state;                       /*  144: 0 RESET, 1 ACTIVE, 2 STOPPED, 3 END */
    uint8_t single_block;                /*  145: 1: on */
    uint8_t plc_alive;                   /*  146: 1: the PLC's sign of life is there */
    uint8_t role;                        /*  147: running segment's role (0: none) */
    uint32_t skipped;                    /*  148: IPO periods skipped after hold-ups */
    uint32_t block_seq;                  /*  152: block execution number (0: none) */
    uint32_t piece;                      /*  156: segment within the block */
    double along;                        /*  160: how far along the segment, 0 to 1 */
    uint32_t work_offsets_version;       /*  168: 1 at start, +1 per accepted edit */
    uint32_t work_offset;                /*  172: index of the active work offset (0: none) */
    uint32_t tool;                       /*  176: T of the path's place (0: none) */
    uint32_t edge;                       /*  180: D of the path's place (0: none) */
    double spindle[SOFTNC_MAX_SPINDLES]; /*  184: speed setpoint, rev/min, signed */
}; /* size 200, align 8 */

/* softnc::Command: <instance>/commands (request): HMI -> kernel; one Reply each. */
struct softnc_Command {
    uint32_t kind;                       /*    0: 1 start, 2 stop, 3 reset, 4 load, ... (docs) */
    uint32_t d;                          /*    4: D number; PROGRAM_INFO: program number */
    double value;                        /*    8: override, radius, single block on/off */
    uint8_t flag;                        /*   16: SET_OFFSET: 1 for wear */
    uint8_t _pad;                        /*   17 */
    uint16_t text_len;                   /*   18: bytes of text that count */
    uint32_t t;                          /*   20: tool number on T/D tables (0: none) */
    uint8_t text[SOFTNC_TEXT];           /*   24: UTF-8: program path, work offset name */
    uint32_t axis_mask;                  /*  536: SET_WORK_OFFSET: bit i = axis_values[i] given */
    uint32_t _pad2;                      /*  540 */
    double axis_values[SOFTNC_MAX_AXES]; /*  544: AxisList order */
}; /* size 608, align 8 */

/* softnc::Reply: <instance>/commands (response): kernel -> HMI. */
struct softnc_Reply {
    uint8_t ok;                    /*    0: 1: done; 0: refused, message says why */
    uint8_t _pad;                  /*    1 */
    uint16_t len;                  /*    2: bytes of message that count */
    uint32_t alarm;                /*    4: alarm number when refused for one */
    uint32_t tools_version;        /*    8: tool table version after the command */
    uint32_t work_offsets_version; /*   12: work-offset table version after it */
    uint8_t message[SOFTNC_TEXT];  /*   16: UTF-8 */
}; /* size 528, align 4 */

/* softnc::ToolEntry: One tool offset. */
struct softnc_ToolEntry {
    uint32_t t;           /*    0: tool number on T/D machines (0: global D) */
    uint32_t d;           /*    4 */
    double radius;        /*    8: mm */
    double radius_wear;   /*   16: mm */
    double length;        /*   24: mm */
    double length_wear;   /*   32: mm */
    uint8_t cutting_edge; /*   40: cutting edge position 1-9 of a turning tool (0: none) */
    uint8_t _pad[7];      /*   41 */
}; /* size 48, align 8 */

/* softnc::ToolTableMsg: <instance>/tools: kernel -> anyone when it changes (history 1). */
struct softnc_ToolTableMsg {
    uint32_t version;                                     /*    0: as KernelStatus.tools_version */
    uint32_t count;                                       /*    4: entries that count */
    uint8_t saved;                                        /*    8: 1: saved to a tool file */
    uint8_t truncated;                                    /*    9: 1: more offsets than fit */
    uint8_t _pad[6];                                      /*   10 */
    struct softnc_ToolEntry entries[SOFTNC_TOOL_ENTRIES]; /*   16 */
}; /* size 3088, align 8 */

/* softnc::WorkOffsetEntry: One work offset. */
struct softnc_WorkOffsetEntry {
    uint8_t name[16];               /*    0: ASCII, 0-padded: G54, G54.1 P3 */
    double values[SOFTNC_MAX_AXES]; /*   16: AxisList order, mm or degrees */
}; /* size 80, align 8 */

/* softnc::WorkOffsetsMsg: <instance>/work-offsets: kernel -> anyone when it changes (history 1). */
struct softnc_WorkOffsetsMsg {
    uint32_t version;                                                  /*    0: as KernelStatus.work_offsets_version */
    uint32_t count;                                                    /*    4: entries that count */
    uint8_t saved;                                                     /*    8: 1: saved to a work-offset file */
    uint8_t _pad[7];                                                   /*    9 */
    struct softnc_AxisList axes;                                       /*   16 */
    struct softnc_WorkOffsetEntry entries[SOFTNC_WORK_OFFSET_ENTRIES]; /*   32 */
}; /* size 10272, align 8 */

_Static_assert(sizeof(struct softnc_AxisList) == 16, "softnc::AxisList: size");
_Static_assert(_Alignof(struct softnc_AxisList) == 2, "softnc::AxisList: alignment");
_Static_assert(sizeof(struct softnc_SetpointMsg) == 136, "softnc::SetpointMsg: size");
_Static_assert(_Alignof(struct softnc_SetpointMsg) == 8, "softnc::SetpointMsg: alignment");
_Static_assert(sizeof(struct softnc_AuxWordMsg) == 16, "softnc::AuxWordMsg: size");
_Static_assert(_Alignof(struct softnc_AuxWordMsg) == 8, "softnc::AuxWordMsg: alignment");
_Static_assert(sizeof(struct softnc_AuxRequest) == 224, "softnc::AuxRequest: size");
_Static_assert(_Alignof(struct softnc_AuxRequest) == 8, "softnc::AuxRequest: alignment");
_Static_assert(sizeof(struct softnc_AuxAck) == 16, "softnc::AuxAck: size");
_Static_assert(_Alignof(struct softnc_AuxAck) == 8, "softnc::AuxAck: alignment");
_Static_assert(sizeof(struct softnc_PlcSignals) == 40, "softnc::PlcSignals: size");
_Static_assert(_Alignof(struct softnc_PlcSignals) == 8, "softnc::PlcSignals: alignment");
_Static_assert(sizeof(struct softnc_ActualValues) == 176, "softnc::ActualValues: size");
_Static_assert(_Alignof(struct softnc_ActualValues) == 8, "softnc::ActualValues: alignment");
_Static_assert(sizeof(struct softnc_KernelStatus) == 200, "softnc::KernelStatus: size");
_Static_assert(_Alignof(struct softnc_KernelStatus) == 8, "softnc::KernelStatus: alignment");
_Static_assert(sizeof(struct softnc_Command) == 608, "softnc::Command: size");
_Static_assert(_Alignof(struct softnc_Command) == 8, "softnc::Command: alignment");
_Static_assert(sizeof(struct softnc_Reply) == 528, "softnc::Reply: size");
_Static_assert(_Alignof(struct softnc_Reply) == 4, "softnc::Reply: alignment");
_Static_assert(sizeof(struct softnc_ToolEntry) == 48, "softnc::ToolEntry: size");
_Static_assert(_Alignof(struct softnc_ToolEntry) == 8, "softnc::ToolEntry: alignment");
_Static_assert(sizeof(struct softnc_ToolTableMsg) == 3088, "softnc::ToolTableMsg: size");
_Static_assert(_Alignof(struct softnc_ToolTableMsg) == 8, "softnc::ToolTableMsg: alignment");
_Static_assert(sizeof(struct softnc_WorkOffsetEntry) == 80, "softnc::WorkOffsetEntry: size");
_Static_assert(_Alignof(struct softnc_WorkOffsetEntry) == 8, "softnc::WorkOffsetEntry: alignment");
_Static_assert(sizeof(struct softnc_WorkOffsetsMsg) == 10272, "softnc::WorkOffsetsMsg: size");
_Static_assert(_Alignof(struct softnc_WorkOffsetsMsg) == 8, "softnc::WorkOffsetsMsg: alignment");

#endif /* SOFTNC_IPC_H */
