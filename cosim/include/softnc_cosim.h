/*
 * softnc co-simulation: the NC kernel stepped cycle by cycle from C (crate softnc-cosim,
 * libsoftnc_cosim.so / libsoftnc_cosim.a). docs/interfaces.md, "Co-simulation (C ABI)",
 * describes the functions; cosim/tests/layout.rs checks every offset here against the Rust
 * types, and tests/cosim.rs builds cosim/examples/step.c against this header.
 *
 * A handle runs what `softnc simulate` runs: block preparation in a thread of its own, the
 * channel's IPO cycle, and a simulated operator (NC start after a program stop) and PLC
 * (aux acknowledgements, the spindle's actual speed). Stepped with nothing fed in, its
 * setpoints are those `softnc simulate` writes, bit for bit.
 *
 * Ownership: softnc_cosim_create returns a handle the caller owns and frees with
 * softnc_cosim_destroy. Structs are filled into the caller's memory; text is copied into the
 * caller's buffer snprintf-style. One handle is used from one thread at a time; handles are
 * independent of each other. No function panics or aborts: a NULL pointer or an internal
 * error gives -1 and softnc_cosim_last_error() says why.
 */
#ifndef SOFTNC_COSIM_H
#define SOFTNC_COSIM_H

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SOFTNC_COSIM_AXES 9

/* softnc_cosim_step's answers */
#define SOFTNC_COSIM_RUNNING 0
#define SOFTNC_COSIM_ENDED 1
#define SOFTNC_COSIM_STOPPED 2 /* with an alarm (softnc_cosim_status: alarm) */
#define SOFTNC_COSIM_ERROR (-1)

/* softnc_cosim_setpoint.state and softnc_cosim_status.state */
#define SOFTNC_COSIM_STATE_RESET 0
#define SOFTNC_COSIM_STATE_ACTIVE 1
#define SOFTNC_COSIM_STATE_STOPPED 2
#define SOFTNC_COSIM_STATE_END 3

typedef struct softnc_cosim softnc_cosim; /* opaque */

/* The setpoint of the last cycle stepped: the numbers of a `softnc simulate` row. */
struct softnc_cosim_setpoint {
    uint64_t cycle;                 /*    0: IPO cycle number (CSV: cycle) */
    uint64_t time_us;               /*    8: cycle * IPO cycle, us (CSV: time, in s) */
    double pos[SOFTNC_COSIM_AXES];  /*   16: X Y Z U V W A B C, mm or degrees; 0 if not configured */
    double spindle;                 /*   88: speed setpoint, rev/min, + clockwise (CSV: S1) */
    double v_path;                  /*   96: path speed, mm/min (CSV: v_path) */
    uint32_t line;                  /*  104: source line of the block (0: none yet) */
    uint32_t col;                   /*  108: source column of the block */
    uint32_t block_number;          /*  112: N number of the block */
    uint8_t block_digits;           /*  116: digits of the N number as written (0: no N number) */
    uint8_t state;                  /*  117: SOFTNC_COSIM_STATE_ */
    uint8_t events;                 /*  118: events of the cycle (text: softnc_cosim_events) */
    uint8_t _pad;                   /*  119 */
}; /* size 120, align 8 */

/* Where the channel is, for a caller playing operator or PLC. */
struct softnc_cosim_status {
    uint64_t cycle;                 /*    0: the last cycle stepped */
    uint64_t aux;                   /*    8: auxiliary functions output so far */
    double override_;               /*   16: feed override, fraction (1.0: 100 %) */
    uint32_t line;                  /*   24: source line of the block (0: none yet) */
    uint32_t col;                   /*   28 */
    uint32_t alarm;                 /*   32: first alarm that stopped the channel (0: none) */
    uint32_t alarm_line;            /*   36: its block's line */
    uint32_t alarm_col;             /*   40: its block's column */
    uint32_t acks_due;              /*   44: aux acknowledgements the path waits for */
    uint8_t state;                  /*   48: SOFTNC_COSIM_STATE_ */
    uint8_t waits_for_start;        /*   49: 1: waits for NC start */
    uint8_t single_block;           /*   50: 1: single-block mode */
    uint8_t operator_;              /*   51: 1: the simulated operator gives NC start */
    uint8_t plc;                    /*   52: 1: the simulated PLC acknowledges, spindle follows */
    uint8_t over;                   /*   53: 1: ended or stopped with an alarm */
    uint8_t _pad[2];                /*   54 */
}; /* size 56, align 8 */

/* What does not change during a run. */
struct softnc_cosim_info {
    uint32_t cycle_us;                    /*    0: IPO cycle, us */
    uint8_t columns;                      /*    4: position columns of a CSV row (X Y Z, additional axes) */
    uint8_t column[SOFTNC_COSIM_AXES];    /*    5: index into pos of each column */
    uint8_t _pad[2];                      /*   14 */
}; /* size 16, align 4 */

/* Loads machine data (TOML; NULL: the built-in machine), the tool table (TOML; NULL: the
 * built-in one) and the part program with the subprogram files beside it, as `softnc
 * simulate` does; preparation starts. NULL on failure (softnc_cosim_last_error). */
softnc_cosim *softnc_cosim_create(const char *machine, const char *program, const char *tools);
/* Frees the handle and stops its preparation thread. NULL is ignored. */
void softnc_cosim_destroy(softnc_cosim *h);
/* Why the last failing call on this thread failed ("" after a good create). The library's
 * string: valid until the next softnc_cosim_ call on this thread. */
const char *softnc_cosim_last_error(void);

/* One IPO cycle: SOFTNC_COSIM_RUNNING, _ENDED, _STOPPED (alarm; also every step after the
 * end), or _ERROR. */
int softnc_cosim_step(softnc_cosim *h);

/* Fill the caller's struct: 0, or -1 for a NULL pointer. */
int softnc_cosim_setpoint(softnc_cosim *h, struct softnc_cosim_setpoint *out);
int softnc_cosim_status(softnc_cosim *h, struct softnc_cosim_status *out);
int softnc_cosim_info(softnc_cosim *h, struct softnc_cosim_info *out);

/* Text as `softnc simulate` writes it, without newline, snprintf-style: at most cap - 1
 * bytes and a NUL into buf; returns the whole length (>= cap: cut), -1 for a NULL handle. */
ssize_t softnc_cosim_header(softnc_cosim *h, char *buf, size_t cap); /* CSV header */
ssize_t softnc_cosim_row(softnc_cosim *h, char *buf, size_t cap);    /* last setpoint's row */
ssize_t softnc_cosim_block(softnc_cosim *h, char *buf, size_t cap);  /* N10, L3 or empty */
ssize_t softnc_cosim_events(softnc_cosim *h, char *buf, size_t cap); /* aux M3 @S1;... */

/* Operator and PLC signals, taken before the next step: 0, or -1 (NULL, refused). */
int softnc_cosim_set_override(softnc_cosim *h, double fraction); /* 0 < f <= 1.2 */
int softnc_cosim_set_single_block(softnc_cosim *h, int on);
int softnc_cosim_nc_start(softnc_cosim *h);
int softnc_cosim_nc_stop(softnc_cosim *h);
int softnc_cosim_set_read_in_disable(softnc_cosim *h, int on);
int softnc_cosim_emergency_stop(softnc_cosim *h); /* alarm 3000 */
/* The simulated operator (NC start after a stop without alarm): on at create. */
int softnc_cosim_set_operator(softnc_cosim *h, int on);
/* The simulated PLC (aux acknowledged a cycle after output, spindle actual speed following
 * the setpoint): on at create. Off, the caller calls these two: */
int softnc_cosim_set_plc(softnc_cosim *h, int on);
int softnc_cosim_ack(softnc_cosim *h);
int softnc_cosim_set_spindle_actual(softnc_cosim *h, double rpm);

#ifdef __cplusplus
}
#endif

#endif /* SOFTNC_COSIM_H */
