//! Writes a synthetic benchmark program (nc_kernel::synthetic):
//! `gen_program BLOCKS` — the line/arc front-end program;
//! `gen_program BLOCKS --g41` — the gouge-free, tangent G41 serpentine for softnc (D1,
//! radius 10); `--roughing` or `--bars` instead of `--g41` — the G41 contours with a corner at
//! every block (roughing rows, a row of bars);
//! `... --rs274` — the same contour with LinuxCNC's `G41.1 D20` header.

use nc_kernel::synthetic::{
    bars_program, compensated_program, line_arc_program, roughing_program, Header,
};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let blocks: usize = args
        .iter()
        .find_map(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let flag = |f: &str| args.iter().any(|a| a == f);
    let header = if flag("--rs274") {
        Header::Rs274
    } else {
        Header::Softnc
    };
    let text = if flag("--g41") {
        compensated_program(blocks, header)
    } else if flag("--roughing") {
        roughing_program(blocks, header)
    } else if flag("--bars") {
        bars_program(blocks, header)
    } else {
        line_arc_program(blocks)
    };
    print!("{text}");
}
