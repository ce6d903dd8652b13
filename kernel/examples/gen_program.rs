//! Writes the synthetic line/arc benchmark program: `gen_program BLOCKS > prog.mpf`.

fn main() {
    let blocks: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    print!("{}", nc_kernel::synthetic::line_arc_program(blocks));
}
