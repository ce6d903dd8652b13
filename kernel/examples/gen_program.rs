//! Writes a synthetic benchmark program (nc_kernel::synthetic):
//! `gen_program BLOCKS` — the line/arc front-end program;
//! `gen_program BLOCKS --g41` — the gouge-free G41 serpentine for softnc (D1, radius 10);
//! `gen_program BLOCKS --g41 --rs274` — the same contour with LinuxCNC's `G41.1 D20` header.

use nc_kernel::synthetic::{compensated_program, line_arc_program, Header};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let blocks: usize = args
        .iter()
        .find_map(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let flag = |f: &str| args.iter().any(|a| a == f);
    let text = if flag("--g41") {
        let header = if flag("--rs274") {
            Header::Rs274
        } else {
            Header::Softnc
        };
        compensated_program(blocks, header)
    } else {
        line_arc_program(blocks)
    };
    print!("{text}");
}
