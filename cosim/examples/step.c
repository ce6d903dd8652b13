/*
 * Steps a part program cycle by cycle through softnc's co-simulation library and prints
 * every setpoint as a `softnc simulate` CSV row, the numbers as their IEEE-754 bit patterns
 * (0x + 16 hex digits) so that a comparison is exact:
 *
 *   step MACHINE.toml PROGRAM [TOOLS.toml]     (MACHINE "-": the built-in machine)
 *
 * Build: cc step.c -I../include -L<target>/debug -lsoftnc_cosim -Wl,-rpath,<target>/debug
 * Exit status: 0 at the program's end, 1 stopped with an alarm, 2 an error.
 */
#include "softnc_cosim.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

static void print_bits(double x) {
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    printf(",0x%016" PRIx64, b);
}

static void print_row(softnc_cosim *h, const struct softnc_cosim_info *info) {
    struct softnc_cosim_setpoint sp;
    char text[4096];
    softnc_cosim_setpoint(h, &sp);
    printf("%" PRIu64 ",%" PRIu64 ".%06" PRIu64, sp.cycle, sp.time_us / 1000000, sp.time_us % 1000000);
    for (int i = 0; i < info->columns; i++) {
        print_bits(sp.pos[info->column[i]]);
    }
    print_bits(sp.spindle);
    print_bits(sp.v_path);
    softnc_cosim_block(h, text, sizeof text);
    printf(",%s", text);
    softnc_cosim_events(h, text, sizeof text);
    printf(",%s\n", text);
}

int main(int argc, char **argv) {
    if (argc < 3 || argc > 4) {
        fprintf(stderr, "usage: %s MACHINE.toml|- PROGRAM [TOOLS.toml]\n", argv[0]);
        return 2;
    }
    const char *machine = strcmp(argv[1], "-") == 0 ? NULL : argv[1];
    softnc_cosim *h = softnc_cosim_create(machine, argv[2], argc == 4 ? argv[3] : NULL);
    if (h == NULL) {
        fprintf(stderr, "%s\n", softnc_cosim_last_error());
        return 2;
    }
    struct softnc_cosim_info info;
    char header[1024];
    softnc_cosim_info(h, &info);
    softnc_cosim_header(h, header, sizeof header);
    puts(header);
    int r;
    do {
        r = softnc_cosim_step(h);
        if (r == SOFTNC_COSIM_ERROR) {
            fprintf(stderr, "step: %s\n", softnc_cosim_last_error());
            softnc_cosim_destroy(h);
            return 2;
        }
        print_row(h, &info);
    } while (r == SOFTNC_COSIM_RUNNING);
    struct softnc_cosim_status st;
    softnc_cosim_status(h, &st);
    fprintf(stderr, "%s: cycle %" PRIu64 ", line %u, alarm %u (line %u, col %u)\n",
            r == SOFTNC_COSIM_ENDED ? "ended" : "stopped", st.cycle, st.line, st.alarm,
            st.alarm_line, st.alarm_col);
    softnc_cosim_destroy(h);
    return r == SOFTNC_COSIM_ENDED ? 0 : 1;
}
