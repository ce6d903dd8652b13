//! Auxiliary functions, feeds and stops at the S points (840C 11.10), with the seed's
//! N5–N30 example (programs/siemens-840c/11_10_aux_functions.mpf). Positions worked out here:
//! D1 = R10, tool length 100 (so Z2 is 102 and the N25 infeed Z-5 is 95); N20 G41 X50 Y50
//! from (0,0) ends in the normal position (50,50) + 10·(−1,1)/√2 = S1; N30 runs down X50, its
//! equidistant is x = 60, so it starts at (60,50).

use nc_kernel::AuxOutput;
use nc_kernel::Role;
use nc_kernel::{MachineData, Preparation, ToolTable};
use nc_kernel::{Prepared, Stop};
use std::path::PathBuf;

fn program(file: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("programs/siemens-840c")
        .join(file);
    std::fs::read_to_string(p).unwrap()
}

fn items(src: &str, md: &[&str]) -> Vec<Prepared> {
    let over: Vec<String> = md.iter().map(|s| s.to_string()).collect();
    let md = MachineData::load(None, &over).unwrap();
    let tools = ToolTable::builtin();
    let mut p = Preparation::new("t", src, &md, &tools);
    let mut v = Vec::new();
    while let Some(x) = p.next_item().unwrap_or_else(|a| panic!("{a}")) {
        v.push(x);
    }
    v
}

/// (block, S point, words, position) of every aux record that goes to the PLC (a record
/// that only carries the block's new tool or spindle has no words).
fn aux(items: &[Prepared]) -> Vec<(String, u32, Vec<String>, [f64; 3])> {
    items
        .iter()
        .filter_map(|x| match x {
            Prepared::Aux(a) if !a.words.is_empty() => Some((
                a.source.number.map(|n| n.to_string()).unwrap_or_default(),
                a.at,
                a.words.iter().map(|w| w.to_string()).collect(),
                a.pos,
            )),
            _ => None,
        })
        .collect()
}

fn near(p: [f64; 3], q: [f64; 3]) -> bool {
    (0..3).all(|i| (p[i] - q[i]).abs() < 1e-9)
}

#[test]
fn aux_functions_at_s_points_11_10_g451() {
    let it = items(&program("11_10_aux_functions.mpf"), &[]);
    let a = aux(&it);
    let h = 10.0 / 2f64.sqrt();
    assert_eq!(a.len(), 3, "{a:?}");
    // H1 of the first plane block at S0, where N20 starts.
    assert_eq!((a[0].0.as_str(), a[0].1), ("N20", 0));
    assert_eq!(a[0].2, ["H1"]);
    assert!(near(a[0].3, [0.0, 0.0, 102.0]));
    // The outside-plane block's functions (and its infeed) at S1, the end of N20.
    assert_eq!((a[1].0.as_str(), a[1].1), ("N25", 1));
    assert_eq!(a[1].2, ["M3", "S2000", "H2"]);
    assert!(near(a[1].3, [50.0 - h, 50.0 + h, 102.0]), "{:?}", a[1].3);
    // G451: two inserted blocks S1→S2→S3, then H3 of N30 at S3, at N30's start (60,50).
    assert_eq!((a[2].0.as_str(), a[2].1), ("N30", 3));
    assert_eq!(a[2].2, ["H3"]);
    assert!(near(a[2].3, [60.0, 50.0, 95.0]), "{:?}", a[2].3);
    // Nothing between the inserted blocks, and they run with N30's F2000.
    let inserted: Vec<usize> = it
        .iter()
        .enumerate()
        .filter(|(_, x)| matches!(x, Prepared::Segment(s) if s.role == Role::Intermediate))
        .map(|(i, _)| i)
        .collect();
    assert_eq!(inserted.len(), 2);
    assert_eq!(inserted[1], inserted[0] + 1);
    for &i in &inserted {
        let Prepared::Segment(s) = &it[i] else {
            unreachable!()
        };
        assert_eq!(s.feed, 2000.0);
    }
    // M30 ends the program after N40's retract: S4 is N30's end, S5 the G40 block's end;
    // N40 moves along Z only.
    match it.last() {
        Some(Prepared::End(Stop { code, at, pos, .. })) => {
            assert_eq!(code.code(), "M30");
            assert_eq!(*at, 5);
            assert!(near(*pos, [50.0, -20.0, 150.0]));
        }
        other => panic!("last record {other:?}"),
    }
}

#[test]
fn aux_of_the_second_block_at_s2_with_g450_and_timing_from_machine_data() {
    let src = program("11_10_aux_functions.mpf").replace("N5  G451", "N5  G450");
    let it = items(&src, &["trc.aux_output=during-motion"]);
    let a = aux(&it);
    // One transition circle S1→S2: H3 at S2, still at (60,50).
    assert_eq!((a[2].0.as_str(), a[2].1), ("N30", 2));
    assert!(near(a[2].3, [60.0, 50.0, 95.0]));
    assert!(it.iter().all(|x| match x {
        Prepared::Aux(a) => a.timing == AuxOutput::DuringMotion,
        _ => true,
    }));
}

#[test]
fn non_modal_g09_of_the_next_block_acts_in_every_inserted_block() {
    let src = program("11_10_aux_functions.mpf").replace("N30  Y0", "N30  G09 Y0");
    let it = items(&src, &[]);
    let segs: Vec<_> = it
        .iter()
        .filter_map(|x| match x {
            Prepared::Segment(s) => Some(s),
            _ => None,
        })
        .collect();
    for s in &segs {
        let n30 = s.source.number.map(|n| n.value) == Some(30);
        assert_eq!(s.exact_stop, n30, "{s:?}");
    }
}

#[test]
fn stops_act_at_block_end_and_aux_only_blocks_at_the_current_point() {
    let src = "N1 G0 G17 G90 X0 Y0 Z0\nN2 M8\nN3 G1 X10 F100 M0 H5\nN4 M1\nN5 X20\nN6 M30\n";
    let it = items(src, &[]);
    let kinds: Vec<String> = it
        .iter()
        .map(|x| match x {
            Prepared::Segment(s) => format!("seg {}", s.source.number.unwrap()),
            Prepared::Aux(a) => format!("aux {} S{}", a.source.number.unwrap(), a.at),
            Prepared::Stop(s) => format!(
                "stop {} {} S{}",
                s.source.number.unwrap(),
                s.code.code(),
                s.at
            ),
            Prepared::End(s) => format!("end {} S{}", s.code.code(), s.at),
            Prepared::Warning(a) => format!("warning {}", a.number()),
            Prepared::Axes(_, s) => format!("axes {}", s.number.unwrap()),
        })
        .collect();
    // N1 does not move, so M8 is output at S0; H5 before N3 moves, M0 at N3's end (S1), M1
    // nothing (optional stop off), M30 last.
    assert_eq!(
        kinds,
        [
            "seg N1",
            "aux N2 S0",
            "aux N3 S0",
            "seg N3",
            "stop N3 M0 S1",
            "seg N5",
            "end M30 S2"
        ],
        "{kinds:?}"
    );
    let it = items(src, &["program.optional_stop=true"]);
    assert!(it
        .iter()
        .any(|x| matches!(x, Prepared::Stop(s) if s.code.code() == "M1" && s.at == 1)));
}
