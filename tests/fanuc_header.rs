//! A Fanuc program as CAM post-processors write it: the safe-start line (G90 G94 G17 G21
//! G40 G49 G80), T M6, G54, S M3, G43 H with the rapid approach, M8 coolant, the cut with
//! cutter compensation, then G49 and M5 M9 before M30. It runs through `softnc simulate` on
//! the shipped Fanuc machine with positions worked out by hand (H1 = D1's length 100 of
//! config/tools.toml, G54 from a work-offset file).

use nc_kernel::simulate::{run, Options};
use nc_kernel::{MachineData, ToolTable, WorkOffsets};

const PROGRAM: &str = "%
O1000 (POCKET - POSTED)
N10 G90 G94 G17 G21 G40 G49 G80
N20 T1 M6
N30 G54 G0 X-20. Y-20.
N40 S3000 M3
N50 G43 H1 Z10. M8
N60 G1 Z-2. F300.
N70 G41 D1 X0. Y0. F600.
N80 Y40.
N90 X60.
N100 Y0.
N110 X0.
N120 G40 X-20. Y-20.
N130 G0 Z10.
N140 G49 M5 M9
N150 G91 G0 Z0.
N160 M30
%
";

#[test]
fn a_posted_fanuc_program_runs_with_its_safe_start_line() {
    let mut md = MachineData::load(Some(std::path::Path::new("config/fanuc.toml")), &[]).unwrap();
    md.work_offsets =
        WorkOffsets::from_toml_str("[G54]\nX = 100.0\nY = 50.0\nZ = -300.0\n", "w.toml", &md)
            .unwrap();
    let mut out = Vec::new();
    let s = run(
        "o1000.nc",
        PROGRAM,
        &md,
        &ToolTable::builtin(),
        &Options::default(),
        &mut out,
    )
    .unwrap();
    assert!(s.alarms.is_empty(), "{:?}", s.alarms);
    assert_eq!(s.end_state, Some(nc_kernel::ipo::ChannelState::End));
    let text = String::from_utf8(out).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|c| *c == n).unwrap();
    let (x, y, z, s1) = (col("X"), col("Y"), col("Z"), col("S1"));
    let rows: Vec<[f64; 4]> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            [x, y, z, s1].map(|i| f[i].parse().unwrap())
        })
        .collect();
    // N60 cuts at Z-2 in G54 (Z -300) with H1 (100): Z = -2 - 300 + 100 = -202, the spindle
    // at 3000 rev/min; the contour's corners lie 10 mm (D1) outside the G54 rectangle
    // (100, 50) … (160, 90).
    let cutting: Vec<&[f64; 4]> = rows
        .iter()
        .filter(|r| (r[2] + 202.0).abs() < 1e-9)
        .collect();
    assert!(cutting.len() > 1000, "{}", cutting.len());
    assert!(cutting.iter().all(|r| r[3] == 3000.0));
    let (xmax, ymax) = cutting
        .iter()
        .fold((f64::MIN, f64::MIN), |(a, b), r| (a.max(r[0]), b.max(r[1])));
    assert!(
        (xmax - 170.0).abs() < 1e-6 && (ymax - 100.0).abs() < 1e-6,
        "{xmax} {ymax}"
    );
    // N130 retracts to Z10 with the length (Z -190); G49 takes it off with the next move of
    // the tool axis (docs/offsets.md): N150 (G91 Z0) moves Z by the length to -290.
    let last = rows.last().unwrap();
    assert_eq!([last[0], last[1]], [80.0, 30.0]);
    assert!((last[2] + 290.0).abs() < 1e-9, "{}", last[2]);
    assert_eq!(last[3], 0.0, "M5, and the program's end");
}
