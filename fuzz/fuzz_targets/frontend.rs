//! Fuzz target for the part-program front end: no panic, no hang, sane alarms on any input.
//!
//! The first byte picks the machine (one per dialect, from the shipped config/*.toml), the rest
//! is the program, read the way `softnc parse` reads a file (lossy UTF-8). Loops are limited to
//! 100 iterations so that endless loops end in alarm 12650 quickly: on the Fanuc machine that
//! bounds WHILE … DO, backward GOTOs and M99 restarts, and the kernel bounds call nesting (15
//! calls, 5 macro levels), so a file of several `O` programs with Custom Macro B (`#`
//! variables, IF, WHILE, M98/M99, G65/G66; words in frontend.dict) ends too.
//!
//! With `SOFTNC_FUZZ_STRICT=1` in the environment the target also requires every coordinate of
//! every motion to be finite (block preparation relies on it).

#![no_main]

use libfuzzer_sys::fuzz_target;
use nc_kernel::{Interpreter, MachineData, ToolTable};
use std::sync::OnceLock;

const CONFIGS: [(&str, &str); 4] = [
    (
        "siemens-840c",
        include_str!("../../config/siemens-840c.toml"),
    ),
    ("isg", include_str!("../../config/isg.toml")),
    ("fanuc", include_str!("../../config/fanuc.toml")),
    (
        "siemens-808d",
        include_str!("../../config/siemens-808d.toml"),
    ),
];

struct Setup {
    machines: Vec<MachineData>,
    tools: ToolTable,
    strict: bool,
}

fn setup() -> &'static Setup {
    static S: OnceLock<Setup> = OnceLock::new();
    S.get_or_init(|| Setup {
        machines: CONFIGS
            .iter()
            .map(|(name, text)| {
                let mut md = MachineData::from_toml_str(text, name).expect("shipped machine data");
                md.program.max_loop_iterations = 100;
                md
            })
            .collect(),
        tools: ToolTable::builtin(),
        strict: std::env::var_os("SOFTNC_FUZZ_STRICT").is_some_and(|v| v == "1"),
    })
}

fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let s = setup();
    let md = &s.machines[first as usize % s.machines.len()];
    let src = String::from_utf8_lossy(rest);
    for item in Interpreter::new("fuzz.nc", &src, md, &s.tools) {
        match item {
            Ok(block) => {
                assert!(
                    block.line >= 1 && block.col >= 1,
                    "block at {}:{}",
                    block.line,
                    block.col
                );
                if s.strict {
                    if let Some(m) = block.motion {
                        let all = m.start.iter().chain(&m.end).chain(&m.center);
                        assert!(
                            all.into_iter().all(|v| v.is_finite()),
                            "non-finite motion {m:?}"
                        );
                    }
                }
            }
            Err(a) => {
                assert!(
                    a.line >= 1 && a.col >= 1,
                    "alarm at {}:{}: {a}",
                    a.line,
                    a.col
                );
                assert!(!a.message.trim().is_empty(), "empty message: {a:?}");
                // The alarm points into the program: an existing line (split at '\n', as the
                // interpreter counts), at most one column past its last character.
                let line = src.split('\n').nth(a.line as usize - 1);
                let width = line.map(|l| l.chars().count() as u32);
                assert!(
                    width.is_some_and(|w| a.col <= w + 1),
                    "alarm outside the program text ({} lines; line width {width:?}): {a}",
                    src.split('\n').count()
                );
                let _ = a.render(&src);
                break;
            }
        }
    }
});
