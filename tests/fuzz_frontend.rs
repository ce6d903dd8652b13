//! Robustness of the front end: no panic and no hang on any input.
//!
//! Random bytes (non-UTF-8 included, read the way `softnc` reads a file), "token soup" — random
//! sequences of words, control statements and separators drawn from every dialect's features —
//! and "block soup" — blocks made mostly of the dialect's own words, so that programs run deeper
//! before they meet a broken word — are interpreted in all four dialects. The Fanuc machines
//! (3-axis and 5-axis) add Custom Macro B to both soups (`#` variables, expressions, IF, GOTO,
//! WHILE … DO, M98/M99, G65/G66 and `O` subprograms in the file), and get "macro programs":
//! structured programs — a main program and one to three subprograms with nested loops, calls,
//! jumps and recursion — that run deep before they end. The 840C's block soup has statement
//! blocks of its own language (R parameter assignments, `@` functions and jumps to the soup's
//! block numbers). Every run must end with blocks or an
//! alarm; an alarm must point into the program (line ≥ 1, column ≥ 1, within the text) and say
//! something. The 840D's structured programs also come with PROCs in files beside them
//! (calls with parameters, VAR, passes, MCALL, recursion); an alarm in one points into it. `program.max_loop_iterations` is set to 100 so that loops stay short; the kernel
//! bounds call nesting (15 calls, 5 macro levels).
//!
//! A watchdog aborts the test binary, printing the input, if one interpretation runs longer
//! than `HANG_SECS` (a hang would otherwise only show up as a stuck CI job).
//!
//! The coverage-guided counterpart is the cargo-fuzz target in fuzz/ (fuzz/README.md).

use nc_kernel::{interpret, Alarm, MachineData, ToolTable};
use proptest::prelude::*;
use std::collections::HashMap;
use std::path::Path;
use std::sync::{Mutex, OnceLock};
use std::thread::ThreadId;
use std::time::{Duration, Instant};

const DIALECTS: [&str; 8] = [
    "siemens-840c",
    "isg",
    "fanuc",
    "siemens-808d",
    "fanuc-5axis",
    "siemens-808d-c",
    "fanuc-lathe",
    "siemens-840d",
];

/// Seconds one interpretation may take before the watchdog calls it a hang.
const HANG_SECS: u64 = 20;

/// The shipped machine data of each dialect, with short loops. The 808D is the lathe (X and Z
/// only, diameter programming), so unconfigured axes are exercised too; the 5-axis mill and
/// the lathe with C add rotary axes (modulo and not); the Fanuc lathe has U/W increments,
/// T aabb and G50; the 840D speaks the SINUMERIK language.
fn machines() -> &'static [MachineData; 8] {
    static M: OnceLock<[MachineData; 8]> = OnceLock::new();
    M.get_or_init(|| {
        DIALECTS.map(|d| {
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("config")
                .join(format!("{d}.toml"));
            MachineData::load(Some(&path), &["program.max_loop_iterations=100".into()])
                .unwrap_or_else(|e| panic!("{e}"))
        })
    })
}

fn tools() -> &'static ToolTable {
    static T: OnceLock<ToolTable> = OnceLock::new();
    T.get_or_init(ToolTable::builtin)
}

/// Inputs being interpreted right now, per test thread, with their start time.
/// Per test thread: when the current input started, its dialect and its text.
type Running = Mutex<HashMap<ThreadId, (Instant, String, String)>>;

fn running() -> &'static Running {
    static R: OnceLock<Running> = OnceLock::new();
    static WATCHDOG: OnceLock<()> = OnceLock::new();
    let r = R.get_or_init(|| Mutex::new(HashMap::new()));
    WATCHDOG.get_or_init(|| {
        std::thread::spawn(|| loop {
            std::thread::sleep(Duration::from_millis(200));
            let map = match running().lock() {
                Ok(m) => m,
                Err(p) => p.into_inner(),
            };
            for (started, dialect, src) in map.values() {
                if started.elapsed() > Duration::from_secs(HANG_SECS) {
                    // Straight to stderr: the test harness captures `eprintln!` (in this
                    // thread too) and would drop it on exit.
                    let msg = format!(
                        "HANG: interpretation ran longer than {HANG_SECS} s\ndialect: {dialect}\ninput: {src:?}\n"
                    );
                    let _ = std::io::Write::write_all(&mut std::io::stderr(), msg.as_bytes());
                    std::process::exit(3);
                }
            }
        });
    });
    r
}

/// Interprets `src` in dialect `which` and checks the properties. Panics propagate to proptest,
/// which shrinks the input.
fn check(which: usize, src: &str) -> Result<(), TestCaseError> {
    let md = &machines()[which];
    let id = std::thread::current().id();
    running().lock().unwrap().insert(
        id,
        (Instant::now(), DIALECTS[which].to_string(), src.to_string()),
    );
    let result = interpret("fuzz.nc", src, md, tools());
    // SINUMERIK: the structure read at load and the one the interpreter does as it goes
    // agree: a fault the first finds, the second meets before the program's end.
    let at_load = nc_kernel::Interpreter::new("fuzz.nc", src, md, tools()).structure_alarm();
    running().lock().unwrap().remove(&id);
    if let Some(a) = &at_load {
        check_alarm(a, src)?;
        prop_assert!(result.is_err(), "ran to its end past {a}");
    }
    match result {
        Ok(blocks) => {
            for b in &blocks {
                prop_assert!(b.line >= 1 && b.col >= 1, "block at {}:{}", b.line, b.col);
            }
        }
        Err(a) => check_alarm(&a, src)?,
    }
    Ok(())
}

/// Interprets `main` on machine `which` with the program files `files` (name, text) beside
/// it; an alarm must point into the file it names.
fn check_files(which: usize, main: &str, files: &[(String, String)]) -> Result<(), TestCaseError> {
    let mut md = machines()[which].clone();
    let mut library = nc_kernel::ProgramLibrary::default();
    for (name, text) in files {
        library.add(name, name.clone(), text.clone());
    }
    md.programs = std::sync::Arc::new(library);
    let id = std::thread::current().id();
    let all: String = files.iter().fold(main.to_string(), |all, (n, t)| {
        format!("{all}\n--- {n}\n{t}")
    });
    running()
        .lock()
        .unwrap()
        .insert(id, (Instant::now(), DIALECTS[which].to_string(), all));
    let result = interpret("fuzz.nc", main, &md, tools());
    running().lock().unwrap().remove(&id);
    match result {
        Ok(blocks) => {
            for b in &blocks {
                prop_assert!(b.line >= 1 && b.col >= 1, "block at {}:{}", b.line, b.col);
            }
        }
        Err(a) => match files.iter().find(|(n, _)| *n == a.program) {
            Some((name, text)) => check_alarm_in(&a, text, name)?,
            None => check_alarm(&a, main)?,
        },
    }
    Ok(())
}

fn check_alarm(a: &Alarm, src: &str) -> Result<(), TestCaseError> {
    check_alarm_in(a, src, "fuzz.nc")
}

/// An alarm of program `program` (text `src`) says something at a place in it.
fn check_alarm_in(a: &Alarm, src: &str, program: &str) -> Result<(), TestCaseError> {
    prop_assert!(a.line >= 1, "line 0: {}", a);
    prop_assert!(a.col >= 1, "column 0: {}", a);
    prop_assert!(!a.message.trim().is_empty(), "empty message: {:?}", a);
    prop_assert_eq!(a.program.as_str(), program);
    // The position lies in the program: an existing line, at most one past its last character.
    // (Lines as the interpreter counts them: split at '\n' only.)
    let lines: Vec<&str> = src.split('\n').collect();
    let line = lines.get(a.line as usize - 1);
    prop_assert!(line.is_some(), "line {} of {}: {}", a.line, lines.len(), a);
    let width = line.unwrap().chars().count() as u32;
    prop_assert!(
        a.col <= width + 1,
        "column {} on a line of {} characters: {}",
        a.col,
        width,
        a
    );
    // Rendering the diagnostic works.
    let shown = a.render(src);
    let prefix = format!("{program}:");
    prop_assert!(shown.starts_with(&prefix));
    Ok(())
}

/// Words and statements of all four dialects, valid and broken.
#[rustfmt::skip]
const VOCABULARY: &[&str] = &[
    // block structure
    "N10", "N20", "N05", "N", "N99999999999", "%PROG", "%", "O100", "/", "/1", ";", "LF", "\n",
    "\r\n", "\n\n", " ", "\t",
    // motion and planes
    "G0", "G1", "G2", "G3", "G00", "G01", "G02", "G03", "G4", "G04", "G9", "G10", "G11", "G12",
    "G13", "G17", "G18", "G19", "G20", "G21", "G70", "G71", "G700", "G710", "G90", "G91", "G1.5",
    "G999", "G1000", "G",
    // compensation and related
    "G40", "G41", "G42", "G05", "G25", "G26", "G53", "G54", "G55", "G57", "G58", "G60", "G61",
    "G64", "G92", "G110", "G111", "G138", "G139", "G140", "G141", "G237", "G238", "G239", "G359",
    "G360", "G450", "G451", "G455", "G456",
    // spindle
    "M3", "M4", "M5", "M19", "S1000", "S0", "S-5", "G94", "G95", "G96", "G97",
    // axis, centre, radius, polar
    "X-1.5", "X10", "X100", "X0", "X1.2.3", "X-", "X", "X99999999999999999999", "Y.5", "Y20",
    "Y-7", "Z-2", "Z5.", "I3", "I5", "J-4", "J0", "K1", "CR=", "CR=5", "CR=-5", "CR = 12.5", "R5",
    "R-10", "A45", "A-90", "U10", "B5", "P500", "3.0", "A-30.", "C400.", "C-0.5", "C",
    "A1e9", "C99999999",
    // technology and aux
    "F100", "F0", "F-5", "F.1", "S1000", "S-1", "H2", "T1", "T2", "D0", "D1", "D2", "D9", "M0",
    "M1", "M2", "M3", "M18", "M30", "DIAMON", "DIAMOF", "@714", "@66250", "@", "@100 K-10",
    "@121 R1 K3 K+20", "@630 R2 K30", "K-10", "K", "P1", ":10", ":",
    // comments
    "(comment", ")", "(a (nested) one)", "(ä)", "ä", "é", "\u{fffd}",
    // ISG variables and control structures
    "$FOR V.P.A = 0,3,1", "$FOR V.P.B = 5,1,-1", "$FOR V.P.A = 0,3,0", "$ENDFOR", "$IF",
    "$IF V.P.A < 2", "$IF 1", "$IF 0", "$ELSEIF V.P.A == 1", "$ELSE", "$ENDIF", "$WHILE 1",
    "$WHILE V.P.A < 3", "$ENDWHILE", "$GOTO", "$", "V.P.A = [1+2]", "V.P.A = [V.P.A + 1]",
    "V.P.A = 0", "V.P.B = [1/0]", "V.P.C = SQRT[-1]", "V.G.WZ_AKT.R = 5", "V.L.X = V.P.A",
    "X[V.P.A*2]", "Y[V.P.NOPE]", "X SIN[30]", "X-V.P.A", "[", "]", "=", "*", "**", "V.", "V.P.",
];

/// What goes between two tokens: nothing (tokens run together), a blank, or a new line.
#[rustfmt::skip]
const SEPARATORS: &[&str] = &[
    " ", " ", " ", "", "\n", "\n", "  ",
];

/// Fanuc Custom Macro B and subprograms, valid and broken: the token soup of the Fanuc machines
/// adds these. Repeat counts stay small (L3 at most): repeats of nested calls multiply.
#[rustfmt::skip]
const MACRO_VOCABULARY: &[&str] = &[
    // variables: local, common, kept, vacant, system, indirect, none at all
    "#1", "#2", "#3", "#24", "#26", "#33", "#34", "#0", "#100", "#101", "#199", "#200", "#500",
    "#999", "#1000", "#2001", "#2201", "#3000", "#3006", "#4001", "#4003", "#4014", "#4109",
    "#4114", "#4115", "#4120", "#5001", "#5003", "#5004", "#5005", "#5021", "#5041", "#5043",
    "#5081", "#5083", "#5221", "#7001", "#10001", "#11001", "#13001", "#99999999999999999999",
    "#", "#[", "#[#1]", "#[#1+100]", "#[-1]", "#[1.5]", "#-1", "##1",
    // assignments
    "#1=", "#1=5", "#1 = 10.", "#2=[#1+2]*3", "#1=#1+1", "#100=#100+1", "#500=#5001", "#24=-#2",
    "#[#1+100]=7", "#0=1", "#5001=1", "#34=1", "#3000=1(ALARM)", "#3000=201", "#3000",
    "#1=1/0", "#1=#1*1000000000000", "#2=10 MOD 0",
    // expressions
    "[", "]", "[[", "]]", "[#1", "+", "-", "*", "/", ",", "MOD", "AND", "OR", "XOR", "EQ", "NE",
    "GT", "GE", "LT", "LE", "1.5", "-2", "0", "SIN[", "COS[", "TAN[", "ASIN[", "ACOS[", "ATAN[",
    "SQRT[", "ABS[", "ROUND[", "FIX[", "FUP[", "LN[", "EXP[", "POW[", "BIN[", "BCD[",
    "SIN[30]", "ATAN[1]/[2]", "ATAN[1,-1]", "ATAN[1]/", "POW[2,10]", "POW[2]", "POW[10,400]",
    "SQRT[-1]", "LN[0]", "ASIN[2]", "TAN[90]", "EXP[1000]", "BIN[26]", "BCD[-1]", "FOO[1]",
    "[1 EQ 1]", "[#1 LT 3]", "[#0 EQ #1]", "[[[[[[1]]]]]]", "[1.5 AND 1]",
    // addresses with macro values
    "X#1", "X-#2", "X[#1+2]", "Y#100", "Z-[#1*2]", "G#3", "M#4", "F#5", "XSIN[30]", "I#6",
    "S#19", "A#1", "C[#2*10]", "X#0", "X#[#1]", "X-[", "G1X#24Y#25F#9",
    // control flow
    "IF", "IF [#1 LT 3] GOTO 10", "IF [#1 EQ #0] THEN #1=0", "IF [1] THEN", "IF [1] GOTO",
    "IF #1", "THEN", "THEN #2=2", "GOTO", "GOTO 10", "GOTO 20", "GOTO #1", "GOTO [#1+10]",
    "GOTO 0", "GOTO 100000", "GOTO -5", "WHILE", "WHILE [#1 LT 3] DO 1", "WHILE [1] DO 2",
    "WHILE [#1 LE 5] DO 3", "WHILE [1]", "DO", "DO 1", "DO 2", "DO 3", "DO 4", "DO #1", "END",
    "END 1", "END 2", "END 3", "END 0", "N10", "N20", "N30",
    // programs and calls
    "O0001", "O1000", "O9000", "O0", "O10000", "O", "M98", "M98 P1000", "M98 P1000 L3",
    "M98 P31000", "M98 P9000 L2", "M98 P2000", "M98 P1000 L0", "M98 P1000 L10000",
    "M98 P1000000", "M98 L2", "M99", "M99 P77", "M99 P0", "M99 P#1", "M99 P10", "L2", "P1000",
    "P9000", "G65 P9000 A1 B2 I3 J4 K5 I6", "G65 P9000 L2 A1.", "G65", "G65 P1000",
    "G65 P9000 G1", "G65 P9000 X1 Y#1 Z[#2+1]",
    // eleven I J K sets: one more than there are
    "G65 P9000 I1 J1 K1 I1 J1 K1 I1 J1 K1 I1 J1 K1 I1 J1 K1 I1 J1 K1 I1 J1 K1 I1 J1 K1 I1 J1 K1 \
     I1 J1 K1 I1",
    "G66 P9000 X1", "G66 P1000", "G66", "G67", "M30",
    // canned cycles, reference point, coordinate settings, frame (the words the soup lacks)
    "G81", "G83", "G73", "G84", "G87", "G80", "G98", "G99", "Q2.", "Q#1", "K3", "G28", "G30",
    "G52", "G92 X#1", "G10 L2 P1", "L20", "L10", "G51", "G51.1", "G50.1", "G50", "G68", "G69",
    "G68 X0 Y0 R#1", "G81 X#24 Z-1. R1. F100.",
    // chamfer and corner words
    ",C", ",R", ",C2.", ",R1.", ",C#1", ",",
];

/// The token soup: words of every dialect (and Macro B on a Fanuc machine) with separators.
fn soup(macro_b: bool) -> impl Strategy<Value = String> {
    let mut tokens = VOCABULARY.to_vec();
    if macro_b {
        tokens.extend_from_slice(MACRO_VOCABULARY);
    }
    let token = prop::sample::select(tokens);
    prop::collection::vec((token, prop::sample::select(SEPARATORS)), 0..60).prop_map(|v| {
        let mut s = String::new();
        for (t, sep) in v {
            s.push_str(t);
            s.push_str(sep);
        }
        s
    })
}

/// The token soup of the SINUMERIK machine: every dialect's tokens and the language's.
fn sinumerik_soup() -> impl Strategy<Value = String> {
    let mut tokens = VOCABULARY.to_vec();
    tokens.extend_from_slice(SINUMERIK_WORDS);
    tokens.extend_from_slice(SINUMERIK_STATEMENTS);
    let token = prop::sample::select(tokens);
    prop::collection::vec((token, prop::sample::select(SEPARATORS)), 0..60).prop_map(|v| {
        v.into_iter().fold(String::new(), |mut s, (t, sep)| {
            s.push_str(t);
            s.push_str(sep);
            s
        })
    })
}

/// Words a program of the dialect may well contain: the block soup draws mostly from these, so
/// that programs run for many blocks (modal state, TRC, loops) before they meet a broken word.
#[rustfmt::skip]
const COMMON: &[&str] = &[
    "G0", "G1", "G1", "G2", "G3", "G17", "G18", "G19", "G40", "G41", "G42", "G90", "G91", "X0",
    "X10", "X-1.5", "X25.", "Y.5", "Y20", "Y-7", "Z-2", "Z5.", "I5", "I-3", "J0", "J-4", "K1",
    "F100", "F250.5", "D1", "D2", "M3", "M5", "M0", "M30", "S1000", "(comment)", "G4", "G9", "G54",
];
#[rustfmt::skip]
const C840_WORDS: &[&str] = &[
    "CR=5", "CR=-10", "G10", "G11", "G12", "G13", "A45", "A-30", "U10", "B5", "G450", "G451",
    "G455", "G456", "@714", "LF", "G25 X-100 Y-100", "G26 X100 Y100", "G60", "G64", "G110", "M18",
    "D0", "G70", "G71", "F2", "G92 S3000", "G92", "G96 S100", "G95 F0.2", "G26 S2000",
    // the 840C's R parameters and @ commands, valid and broken
    "R1=5", "R2=R1*2+1", "R1=-R2/4", "R3=R1/0", "R1300=1", "R1=", "R=1", "R1 2", "R01=3",
    "X R1", "Y-R2", "Z+R1", "XR1", "F R2", "S R1", "CR=R1", "G R1", "X R", "X R1300", "@620 R1",
    "@614 R3 K3 K4", "@613 R4 K-1", "@610 R5 P1", "@622 R2", "@631 R6 R1", "@630 K1 R1",
    "@100 K-10", "@100 K+20", "@100 K1.5", "@100 R1", "@100", "@124 R1 K3 K-10",
    "@121 K1 K2 K3", "@111 R1 K1 K10 K2 K20", "@111 R1 K1", "@302 R1 K2 K3", ":20 X5",
];
/// The 840C's statement blocks: assignments and @ commands, loops by jumps to the block
/// numbers the soup writes (N0 … N199), mostly bounded by a counter.
#[rustfmt::skip]
const C840_STATEMENTS: &[&str] = &[
    "R1=R1+1", "R2=R2*2", "R1=0", "@620 R1", "@621 R2", "@124 R1 K3 K-10", "@124 R1 K3 K-50",
    "@122 R1 K2 K+100", "@126 R2 K5 K-20", "@100 K+150", "@100 K-30", "@111 R1 K1 K40 K2 K60",
    "@630 R3 R1", "@631 R4 K45", "@613 R5 R1", "R6=R1*R3-R4/2", "@714", "R1=R1+1 @123 R1 K2 K-120",
];
#[rustfmt::skip]
const ISG_WORDS: &[&str] = &[
    "R5", "R-10", "G05", "G10", "G11", "G25", "G26", "G138", "G139", "G140", "G141", "G237",
    "G238", "G239", "G359", "G360", "3.0", "X[V.P.A*2]", "Y[V.P.A+1]", "X SIN[30]", "X-V.P.A",
    "V.P.A = [V.P.A + 1]", "V.G.WZ_AKT.R = 5", "G70", "G71",
];
#[rustfmt::skip]
const ISG_STATEMENTS: &[&str] = &[
    "$FOR V.P.A = 0,3,1", "$FOR V.P.B = 5,1,-1", "$ENDFOR", "$IF V.P.A < 2", "$IF 1", "$IF 0",
    "$ELSEIF V.P.A == 1", "$ELSE", "$ENDIF", "$WHILE V.P.A < 3", "$WHILE 1", "$ENDWHILE",
    "V.P.A = 0", "V.P.A = [1+2]",
];
#[rustfmt::skip]
const FANUC_WORDS: &[&str] = &[
    "R5", "R-10", "R500", "G20", "G21", "G61", "G64", "P500", "X100", "Y-2500", "O100", "%",
    "G43 H2", "G44 H1", "G49", "G95 F0.1", "G94", "G96 S200", "G97 S800", "M19", "H0", "H99", "H2", "G53 X0", "G54.1 P1", "G54.1 P48",
    "G54.1 P49", "G54.1", "G54.2", "G59", "G58", "P0", "G80", "G90 G94 G17 G21 G40 G49 G80",
    // canned cycles, reference point, coordinate settings, frame
    "G81 X10. Y10. Z-5. R2. F100.", "G82 Z-3. R1. P500", "G73 Z-10. R1. Q2.", "G83 Z-10. R1. Q3.",
    "G84 Z-5. R2.", "G85 Z-4. R1.", "G86 Z-4. R1.", "G89 Z-4. R1. P100", "G76 Z-4. R1. Q1.",
    "G87 Z-4. R1. Q1.", "G74 Z-4. R1.", "G88 Z-1. R1.", "G83 Z-5. R1.", "G98", "G99", "K2", "K0",
    "G28 Z0", "G28 X0 Y0", "G30 P2 Z0", "G92 X0 Y0", "G52 X10. Y5.", "G52 X0 Y0",
    "G10 L2 P1 X10.", "G10 L20 P2 Y5.", "G10 L10 P1 R5.", "G10 L12 P2 R3.", "G10 L3 P1",
    "G51.1 X0", "G50.1 X0", "G51 X0 Y0 P2000", "G51 I2000 J1000", "G50", "G68 X0 Y0 R30.",
    "G91 G68 R15.", "G69",
    // chamfer and corner words, with the moves they need and without
    ",C1.", ",R2.", ",C#1", ",R[#18+1.]", ",C0", ",C-2.", ",R50.", ",C1. ,R1.", ",r3.",
    "G1 X10. ,C1.", "G2 X20. Y10. R10. ,R2.", "G3 X0 Y0 I-5. ,C0.5", "G0 X5. ,C1.",
];
#[rustfmt::skip]
const D808_WORDS: &[&str] = &[
    "CR=5", "CR=-10", "DIAMON", "DIAMOF", "G450", "G451", "T1", "T2", "T1 D2", "G700", "G710",
    "G60", "G64", "G53", "G500", "G59", "LIMS=3000", "LIMS=", "LIMS", "LIMS=-1", "G96 S180",
    "G95 F0.2",
];

/// The SINUMERIK language (840D), valid and broken: words and expressions among a block's
/// words, and the statements of the block soup.
#[rustfmt::skip]
const SINUMERIK_WORDS: &[&str] = &[
    "R1=5", "R2=R1*2", "R[R1]=1", "R[-1]=1", "R[1.5]=2", "R99=1", "R100=1", "R1=1/0", "R1=",
    "X=R1", "X=-R1", "X=R1+5", "Y=SIN(30)*R2", "Z=AC(5)", "X=IC(2)", "Y=IC(-R1)", "Z=AC(",
    "X=(1+2", "X=ATAN2(1,1)", "X=SQRT(-1)", "X=LN(0)", "X=POT(1EX200)", "X=1.5EX3",
    "X=R1 DIV 0", "X=7 MOD 3", "X=R1 B_AND 3", "X=1.5 B_OR 1", "X=BOUND(1,0,5)", "X=MINVAL(1)",
    "X=TRUE", "X=NOPE", "I=R1", "CR=R1", "F=R2*100", "CR=", "X=", "=", "R", "R1 =2",
    "G1 X=R1 Y=R2 F=100", "G2 X=R1 Y0 CR=R1", "DEF", "LAB1:", "LAB2: G1 X1", "N10 LAB3: X2",
    "I=IC(1)", "X=1<<2", "X=(((((((((1)))))))))", "CHF=2", "CHR=R1", "RND=5", "RND=-1",
    "CHF=", "CHF=1000", "G1 X10 CHF=2", "G2 X0 Y10 CR=10 RND=2", "G0 X5 RND=1", "CHR=1 RND=1",
    "XR1",
];
#[rustfmt::skip]
const SINUMERIK_STATEMENTS: &[&str] = &[
    "R1=R1+1", "R2=R2*2", "DEF INT I=1", "DEF REAL A=2.5, B", "DEF BOOL F=TRUE", "DEF STRING S",
    "DEF INT I[3]", "DEF INT IF", "IF R1<3", "IF (R1>0) AND (R2<5)", "IF", "ELSE", "ENDIF",
    "WHILE R1<3", "WHILE 1", "ENDWHILE", "FOR R3=1 TO 3", "FOR R3=3 TO 1", "FOR I=1 TO", "ENDFOR",
    "REPEAT", "UNTIL R1>2", "UNTIL", "LOOP", "ENDLOOP", "GOTOF LAB1", "GOTOB LAB1", "GOTO LAB2",
    "GOTOC NOWHERE", "GOTOF N10", "GOTOB N20", "GOTOF", "IF R1>2 GOTOF LAB2", "IF R1<1 GOTOB LAB1",
    "STOPRE", "MSG(\"text\")", "MSG()", "MSG(\"open", "SETAL(65000)", "SETAL(1)", "/IF 1",
    "LAB1: IF 1", "LAB1: R1=R1+1", "LAB2: G1 X=R1 F100",
    "CYCLE81(10, 0, 2, -5)", "CYCLE82(R1, 0, 2, , 3, -2)", "CYCLE83(10, 0, 1, -20, , -5, , 2, 1, 1, 0.5, 1)",
    "CYCLE83(10, 0, 1, -20, , , 0.001, 0, , , , 0)", "CYCLE84(10, 0, 2, -8, , 0, 3, 6)", "CYCLE84(10,0,2,-8)",
    "CYCLE840(10, 0, 2, -8, , 0, 0, 5, 0, 0, 1.5)", "CYCLE85(10, 0, 2, -9, , 1, R1, 0)", "CYCLE86(10, 0, 2, -9, , 0, 3, 1, 1, 1)",
    "CYCLE87(10, 0, 2, -9, , 9)", "CYCLE88(10, 0, 2, -9, , -1, 4)", "CYCLE89(0, 0, 2, 0)", "CYCLE81(", "CYCLE81(1,2,3,4,5,6)",
    "CASE(R1) OF 1 GOTOF LAB2 2 GOTOB LAB1 DEFAULT GOTOF LAB2", "CASE(R1) OF", "CASE R1", "CASE(R1) OF 1.5 GOTOF LAB2",
    "R1=$AA_IW[X]", "R2=$P_EP[Y]+$P_TOOL", "X=$TC_DP6[1,1]", "R3=$TC_DP6[", "R4=$AA_IW[Q]", "IF $P_EP[X]>5 GOTOF LAB2", "R5=$NOPE",
    "DEF REAL TB[3,2]=SET(1,2,3)", "DEF INT NA[4]=REP(R1)", "TB[R1,1]=R2", "X=TB[2,1]", "NA[5]=1", "DEF REAL TC[0]",
    "DEF STRING[10] ST=\"AB\" << R1", "ST=ST << \"CDEFGHIJKL\"", "MSG(ST << R2)", "MSG(\"x\" <<)", "R1=ST", "DEF CHAR CH=\"Q\"", "DEF AXIS AV=Y", "AV=Z", "AX[AV]=R1", "AX[Q]=1", "AX[AV]", "X=AV", "R2=$P_EP[AV]",
    "TRANS X10 Y5", "ATRANS X=R1", "ROT RPL=30", "AROT RPL=-R2", "AROT X30", "SCALE X2 Y2", "ASCALE X0.5",
    "SCALE X2 Y3", "MIRROR X0", "AMIRROR Y0", "TRANS", "ROT", "SUPA G0 X0", "G153 X1", "G505", "G500",
    "G111 X0 Y0", "G110 X5", "G112 AP=45 RP=5", "G1 AP=R1 RP=10", "G3 AP=IC(90)", "CIP X10 Y10 I1=5 J1=8",
    "CT X20 Y5", "G2 X0 Y0 I5 TURN=2 Z-1", "RNDM=2", "RNDM=0", "FRC=100",
    "G41 G147 DISR=5 X10 Y10", "G42 G247 DISR=4 DISCL=2 X0 Y20", "G347 G341 DISR=3 FAD=50 X5",
    "G40 G148 DISR=5 X0 Y0", "G248 DISCL=AC(5) X20", "NORM", "KONT", "KONTC", "DISC=50", "DISC=100 G450",
];

/// Words with macro values for the blocks of a Fanuc program (`X#24`: X takes #24's value,
/// left out while #24 is vacant).
#[rustfmt::skip]
const MACRO_WORDS: &[&str] = &[
    "X#24", "Y#25", "Z#26", "X-#1", "Y[#2*2]", "X[#1+2.]", "Z-[#3/2]", "F#9", "F[#9+100.]",
    "XSIN[#1*30]", "YCOS[#1*30]", "Y#100", "R#18", "I#4", "J#5", "G#10", "M#13", "S#19",
    "X#5001", "Y[#5002+1.]", "Z#5043", "X[#1 MOD 3]", "G1 X#24 Y#25 F#9", "G91 X#1", "G90",
];
/// Words of the Fanuc lathe (G-code system A).
#[rustfmt::skip]
const LATHE_WORDS: &[&str] = &[
    "U2.", "W-3.", "U-1.5", "W5.", "U", "W#1", "T0101", "T0100", "T0201", "T0102", "T9999",
    "G50 S2000", "G50 X100. Z50.", "G50 U1.", "G99 F0.2", "G98 F100.", "G96 S180", "G97 S500",
    "G28 U0. W0.", "X40.", "Z-10.", "G1 X20. Z-5. F0.1", "G2 X30. W-5. R5.", "G3 U10. W-5. R5.",
    "G71 U2. R1.", "G90 X20. Z-10. F0.2", "X20. U2.", ",C1.", ",R2.", "G42", "G41", "G40",
    "G4 U1.", "G4 X0.5", "G18", "G17 G0 X10. Y5.",
    "G72 W2. R1.", "G72 P10 Q20 U0.4 W0.2", "G73 U3. W1. R3", "G73 P10 Q20", "G71 P10 Q20",
    "N10 G0 Z-5.", "N10 G0 X20. Z1.", "N20 X40.", "N20 G1 X0.", "G70 P10 Q20",
    "N10 G0 G42 X20. Z1.", "N20 G40 X40.", "G2 Z-5. R3.",
];

/// The rotary axes of the 5-axis machine, with and without macro values.
#[rustfmt::skip]
const FIVE_AXIS_WORDS: &[&str] = &[
    "A30.",
    "A-15.",
    "C90.",
    "C-45.",
    "C400.",
    "A#1",
    "C#2",
    "A[#1*10]",
    "C[#100*15]",
    "C#5005",
    "G1 A10. C20. F500.",
];
/// Macro statements for the blocks of a Fanuc program, mostly valid. Repeat counts are at
/// most 2 (so that runs go deep rather than end on the loop limit).
#[rustfmt::skip]
const FANUC_STATEMENTS: &[&str] = &[
    "#1=#1+1", "#2=[#1*2]+#24", "#100=#100+1", "#500=SIN[#1*30]", "#3=ATAN[#1]/[#2]",
    "#4=SQRT[ABS[#2]]", "#5=ROUND[#5041]", "#6=#5001", "#7=#4001", "#8=#2001", "#[#1+100]=1",
    "#9=FIX[#1] MOD 3", "#24=#24+5.", "#25=-#25", "#18=POW[2,#1]", "#10=1", "#13=3",
    "IF [#1 LT 5] GOTO 10", "IF [#1 GE 3] GOTO 20", "IF [#2 EQ #0] THEN #2=1",
    "IF [#1 GT 2] THEN #1=0", "GOTO 30", "GOTO [#1*10]", "WHILE [#1 LT 3] DO 1",
    "WHILE [#3 LE 2] DO 2", "WHILE [#100 LT 4] DO 3", "END 1", "END 2", "END 3", "DO 3",
    "M98 P1000", "M98 P1000 L2", "M98 P21000", "M98 P9000", "M98 P0002", "M98 P2000",
    "G65 P9000 A1. B2. X#24", "G65 P1000 L2 I1. J2. K3. I4.", "G66 P9000 Z-1.", "G66 P2 X1.",
    "G67", "M99", "M99 P99999", "M99 P10", "M99 P[#1*10]",
];

/// A block of the block soup: numbered?, its number, words, dice (statement or words), statement.
type SoupBlock = (bool, u32, Vec<&'static str>, u8, &'static str);

/// A program of blocks: mostly words of the dialect, now and then any token of the vocabulary.
/// On a Fanuc machine (`which` 2, 4 or 6), some blocks are macro statements, and `O`
/// subprograms may follow the main program.
fn block_soup(which: usize) -> impl Strategy<Value = String> {
    let fanuc = matches!(which, 2 | 4 | 6);
    let own: &'static [&'static str] = match which {
        0 => C840_WORDS,
        1 => ISG_WORDS,
        2 | 4 => FANUC_WORDS,
        6 => LATHE_WORDS,
        7 => SINUMERIK_WORDS,
        _ => D808_WORDS,
    };
    let mut words = vec![
        (6, prop::sample::select(COMMON)),
        (4, prop::sample::select(own)),
        (1, prop::sample::select(VOCABULARY)),
    ];
    if fanuc {
        words.push((3, prop::sample::select(MACRO_WORDS)));
    }
    if which == 4 {
        words.push((2, prop::sample::select(FIVE_AXIS_WORDS)));
    }
    let statements = match which {
        0 => C840_STATEMENTS,
        2 | 4 | 6 => FANUC_STATEMENTS,
        7 => SINUMERIK_STATEMENTS,
        _ => ISG_STATEMENTS,
    };
    let block = (
        any::<bool>(),
        0u32..200,
        prop::collection::vec(prop::strategy::Union::new_weighted(words), 0..6),
        0u8..10,
        prop::sample::select(statements),
    );
    let blocks = prop::collection::vec(block.clone(), 0..40);
    let subs = prop::collection::vec(
        prop::collection::vec(block, 0..10),
        0..if fanuc { 4 } else { 1 },
    );
    (blocks, subs, any::<bool>(), any::<bool>()).prop_map(move |(blocks, subs, o_line, m99)| {
        let end = if fanuc { ";\n" } else { "\n" };
        let mut s = String::new();
        if which == 1 {
            // ISG: the variables the words use start defined (mostly).
            s.push_str("V.P.A = 0\nV.P.B = 1\n");
        }
        if fanuc {
            if o_line {
                s.push_str("O0001\n");
            }
            // Macro values for the words (mostly): a position, a feed, counters.
            s.push_str("#1=0;\n#2=1.;\n#3=0;\n#9=500.;\n#24=10.;\n#25=-5.;\n#26=-1.;\n");
        }
        let render = |s: &mut String, blocks: Vec<SoupBlock>| {
            for (numbered, n, words, dice, stmt) in blocks {
                if numbered {
                    s.push_str(&format!("N{n} "));
                }
                if (which <= 1 || which == 7 || fanuc) && dice < 3 {
                    s.push_str(stmt);
                } else {
                    s.push_str(&words.join(" "));
                }
                s.push_str(end);
            }
        };
        render(&mut s, blocks);
        let count = subs.len();
        for (k, sub) in subs.into_iter().enumerate() {
            if k == 0 {
                s.push_str("M30");
                s.push_str(end);
            }
            s.push_str(["O1000\n", "O9000\n", "O0002\n"][k]);
            render(&mut s, sub);
            // The last subprogram sometimes ends without M99 (at the end of the file).
            if k + 1 < count || m99 {
                s.push_str("M99");
                s.push_str(end);
            }
        }
        s
    })
}

/// Macro programs (Fanuc Custom Macro B): a main program O0001 and one to three subprograms
/// in one file, built from a plan of statements so that they mostly run: counted loops, calls
/// down the list of subprograms (O1000 → O9000 → O0002, so calls cannot cycle), recursion
/// guarded by a common variable that only grows, M99 P to a sequence number of the caller.
/// Repeat counts stay at 3 and below, so that runs go deep rather than end on the loop limit.
/// Expressions, conditions, arguments and jumps are random, so a run may also end early in an
/// alarm, which is what the properties check. Every program writes N9990 before its end.
mod macro_programs {
    use proptest::prelude::*;
    use proptest::sample::select;

    /// O numbers of the subprograms, in call order.
    const SUBPROGRAMS: [&str; 3] = ["1000", "9000", "0002"];

    #[rustfmt::skip]
    const NUMBERS: &[&str] = &[
        "0", "1", "2", "3", "5", "10", "2.5", ".5", "100.", "0.001", "45", "90", "360", "-1",
        "-2.5", "1000000",
    ];
    /// Variables an expression reads: the program's own (locals, common, kept, #0)...
    #[rustfmt::skip]
    const READ: &[&str] = &[
        "#1", "#2", "#3", "#4", "#5", "#6", "#9", "#18", "#24", "#25", "#26", "#33", "#100",
        "#101", "#102", "#199", "#500", "#999", "#0", "#[#1+1]", "#[#1+100]", "#[2]",
    ];
    /// ... and system variables, bound or not.
    #[rustfmt::skip]
    const SYSTEM: &[&str] = &[
        "#5001", "#5002", "#5003", "#5004", "#5005", "#5041", "#5043", "#5021", "#5081",
        "#5083", "#5221", "#7001", "#4001", "#4003", "#4014", "#4107", "#4109", "#4111",
        "#4114", "#4115", "#4119", "#4120", "#2001", "#2201", "#10001", "#11002", "#12001",
        "#13001", "#34", "#1000", "#3000",
    ];
    /// Operators, the arithmetic ones more often (AND OR XOR need whole numbers).
    #[rustfmt::skip]
    const OPERATORS: &[&str] = &[
        "+", "-", "*", "/", " + ", "-", "*", "+", " MOD ", " AND ", " OR ", " XOR ",
    ];
    const COMPARISONS: &[&str] = &[" EQ ", " NE ", " GT ", " GE ", " LT ", " LE ", "LT ", "GE "];
    #[rustfmt::skip]
    const FUNCTIONS: &[&str] = &[
        "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "ABS", "ROUND", "FIX", "FUP", "LN",
        "EXP", "BIN", "BCD",
    ];
    /// Variables a statement writes: mostly the program's own, now and then one that cannot
    /// be written (#0, system variables) or an indirect one.
    #[rustfmt::skip]
    const WRITE: &[&str] = &[
        "#1", "#2", "#3", "#4", "#5", "#6", "#9", "#18", "#24", "#25", "#26", "#33", "#100",
        "#101", "#102", "#199", "#500", "#999",
    ];
    const WRITE_BAD: &[&str] = &["#0", "#5001", "#34", "#4001", "#[#1+100]", "#[#2]", "#3006"];
    /// Blocks without motion.
    #[rustfmt::skip]
    const PLAIN: &[&str] = &[
        "G90", "G91", "G17", "G18", "G19", "G20", "G21", "G41 D1", "G42 D2", "G40", "G43 H1",
        "G49", "M3 S1000", "M5", "G4 P100", "G54", "G55", "G54.1 P2", "M0", "M1", "F#9",
        "S[#19+100]", "G94 F[#9+500.]", "G61", "G64", "M8", "M9",
        // canned cycles, reference point, coordinate settings and the frame, with macro values
        "G81 X#24 Y#25 Z-[#18/2] R2. F#9", "G83 Z-10. R1. Q[#18/4] K2", "G73 Z-#4 R1. Q1.",
        "G82 Z-2. R1. P#1", "G98 G84 Z-3. R2.", "G99 G85 Z-3. R#1", "G80", "G80", "G28 Z#26",
        "G30 P2 Z0", "G92 X#24 Y#25", "G52 X#1 Y#2", "G52 X0 Y0", "G10 L2 P1 X#1",
        "G10 L20 P2 Y[#2*2]", "G10 L10 P1 R#18", "G10 L12 P2 R[#1/10]", "G51.1 X#24",
        "G50.1 X0", "G51 X0 Y0 P[#1*1000]", "G50", "G68 X0 Y0 R#5", "G91 G68 R#1", "G69",
    ];
    #[rustfmt::skip]
    const LINEAR: &[&str] = &[
        "G0", "G1", "G1", "", "", "G91 G1", "G90 G0", "G1 G41 D1", "G1 G40", "G91 G0",
    ];
    const RADII: &[&str] = &["50.", "[#18*5]", "-50.", "50.", "#18", "80.", "#0"];
    /// Computed jumps: N10 and N9990 (#1 = 1 in the preamble), a vacant one, a bad one.
    #[rustfmt::skip]
    const GOTOS: &[&str] = &[
        "GOTO [#1*10]", "GOTO [#1*9990]", "GOTO #[#1+100]", "GOTO #0", "GOTO 0", "GOTO #1",
    ];
    /// Argument addresses of G65/G66, and some that cannot be arguments.
    #[rustfmt::skip]
    const ARGUMENTS: &[&str] = &[
        "A", "B", "C", "D", "E", "F", "H", "M", "Q", "R", "S", "T", "U", "V", "W", "X", "Y", "Z",
        "I", "J", "K", "I", "J", "K",
    ];
    const NOT_ARGUMENTS: &[&str] = &["G", "N", "O", "L0", "P"];

    /// Numbers and variables of a tame expression: the preamble of the main program writes
    /// these variables, so that the program mostly runs on; the system variables are bound
    /// (#5041: the present position, a preprocessing stop).
    #[rustfmt::skip]
    const TAME_LEAVES: &[&str] = &[
        "1", "2", "3", "5", "10", "0.5", "2.5", "45", "90", "#1", "#2", "#3", "#4", "#5", "#6",
        "#18", "#24", "#25", "#26", "#100", "#101", "#102", "#500", "1", "2", "#1", "#2", "#5001",
        "#5041", "#5003", "#4001", "#4003", "#4109", "ATAN[#2]/[#1]", "ATAN[#25,#24]",
        "POW[#2,2]", "SQRT[ABS[#18]]", "EXP[1]", "LN[ABS[#18]+1]", "BCD[12]", "BIN[18]",
        "#4 MOD 3", "[ROUND[#1] AND 3]", "[3 OR 4]", "[ROUND[#5] XOR 1]", "ASIN[0.5]",
        "ACOS[-0.5]", "TAN[30]", "#[2]", "[#4 EQ 4.]",
    ];
    const TAME_OPERATORS: &[&str] = &["+", "-", "*", " + ", " - ", "*", "/"];
    const TAME_FUNCTIONS: &[&str] = &["SIN", "COS", "ABS", "ROUND", "FIX", "FUP", "ATAN"];

    /// An expression, mostly a tame one (in range, rarely an alarm), now and then a wild one.
    pub fn expr(depth: u32) -> BoxedStrategy<String> {
        prop_oneof![25 => tame_expr(depth), 1 => wild_expr(depth)].boxed()
    }

    fn tame_expr(depth: u32) -> BoxedStrategy<String> {
        select(TAME_LEAVES)
            .prop_map(String::from)
            .prop_recursive(depth, 8, 2, |e| {
                prop_oneof![
                    4 => (e.clone(), select(TAME_OPERATORS), e.clone())
                        .prop_map(|(a, op, b)| format!("{a}{op}{b}")),
                    2 => (e.clone(), select(TAME_OPERATORS), e.clone())
                        .prop_map(|(a, op, b)| format!("[{a}{op}{b}]")),
                    2 => (select(TAME_FUNCTIONS), e).prop_map(|(f, a)| format!("{f}[{a}]")),
                ]
            })
            .boxed()
    }

    /// Any expression: every operator and function, system variables, indirection.
    fn wild_expr(depth: u32) -> BoxedStrategy<String> {
        let leaf = prop_oneof![
            4 => select(NUMBERS).prop_map(String::from),
            5 => select(READ).prop_map(String::from),
            1 => select(SYSTEM).prop_map(String::from),
        ];
        leaf.prop_recursive(depth, 16, 2, |e| {
            prop_oneof![
                5 => (e.clone(), select(OPERATORS), e.clone())
                    .prop_map(|(a, op, b)| format!("{a}{op}{b}")),
                3 => (e.clone(), select(OPERATORS), e.clone())
                    .prop_map(|(a, op, b)| format!("[{a}{op}{b}]")),
                3 => (select(FUNCTIONS), e.clone()).prop_map(|(f, a)| format!("{f}[{a}]")),
                1 => (e.clone(), e.clone()).prop_map(|(a, b)| format!("ATAN[{a}]/[{b}]")),
                1 => (select(&["ATAN", "POW"][..]), e.clone(), e.clone())
                    .prop_map(|(f, a, b)| format!("{f}[{a},{b}]")),
                1 => e.clone().prop_map(|a| format!("#[{a}]")),
                1 => e.prop_map(|a| format!("-[{a}]")),
            ]
        })
        .boxed()
    }

    /// An IF or WHILE condition in its brackets.
    fn condition() -> BoxedStrategy<String> {
        let e = || expr(2);
        prop_oneof![
            8 => (e(), select(COMPARISONS), e()).prop_map(|(a, c, b)| format!("[{a}{c}{b}]")),
            1 => e().prop_map(|a| format!("[{a}]")),
            1 => ((e(), select(COMPARISONS), e()), select(&[" AND ", " OR "][..]),
                  (e(), select(COMPARISONS), e()))
                .prop_map(|((a, c, b), l, (d, c2, f))| format!("[[{a}{c}{b}]{l}[{d}{c2}{f}]]")),
        ]
        .boxed()
    }

    /// A word's value: a number, a variable, an expression in brackets, a function.
    fn value() -> BoxedStrategy<String> {
        prop_oneof![
            4 => select(&["10.", "-5.", "0", "25.5", "100", "-1.5", "3."][..]).prop_map(String::from),
            4 => select(&["#24", "#25", "#26", "#1", "-#2", "#100", "#18", "#0", "#[#1+24]"][..])
                .prop_map(String::from),
            2 => expr(2).prop_map(|e| format!("[{e}]")),
            1 => (select(&["SIN", "COS", "ABS", "ROUND"][..]), expr(1))
                .prop_map(|(f, e)| format!("{f}[{e}]")),
        ]
        .boxed()
    }

    /// A statement of the plan; loops carry their body.
    #[derive(Clone, Debug)]
    pub enum Stmt {
        Assign(&'static str, String),
        /// A motion block: its G codes and words.
        Move(&'static str, Vec<(&'static str, String)>),
        Plain(&'static str),
        IfGoto(String, u8),
        IfThen(String, &'static str, String),
        Goto(u8),
        GotoComputed(&'static str),
        /// WHILE [#c LT passes] with a counter, or (passes 0) with a random condition.
        While(u8, String, u8, Vec<Line>),
        /// DO m … END m left by IF … GOTO after `passes` passes.
        Do(u8, u8, Vec<Line>),
        Call(Call),
        /// G67.
        Cancel,
        /// M99 (0…3), M99 P9990 (4…6: the caller's end), M99 P10 … P60 (7…9: a sequence
        /// number the caller may have, before or after the call).
        Return(u8),
        /// #3000 = n.
        Alarm(u8),
    }

    /// A block of the plan with its sequence number (N10 … N60).
    pub type Line = (Option<u8>, Stmt);

    #[derive(Clone, Debug)]
    pub struct Call {
        /// M98 P, M98 P L, M98 P with the count, G65, G65 L, G66.
        how: u8,
        /// Which program: a later subprogram, this one (recursion, guarded or not), a
        /// missing one.
        target: u8,
        repeats: u8,
        /// Recursion stops after this many calls.
        limit: u8,
        args: Vec<(&'static str, String)>,
    }

    fn call() -> impl Strategy<Value = Call> {
        let repeats = prop_oneof![6 => Just(1u8), 4 => Just(2u8), 2 => Just(3u8), 1 => Just(0u8)];
        let letter = prop_oneof![150 => select(ARGUMENTS), 1 => select(NOT_ARGUMENTS)];
        let args = prop::collection::vec((letter, value()), 0..5);
        (0u8..6, 0u8..20, repeats, 1u8..4, args).prop_map(|(how, target, repeats, limit, args)| {
            Call {
                how,
                target,
                repeats,
                limit,
                args,
            }
        })
    }

    fn statement(which: usize) -> BoxedStrategy<Stmt> {
        let axes: &'static [&'static str] = if which == 4 {
            &["X", "Y", "Z", "X", "Y", "A", "C"]
        } else {
            &["X", "Y", "Z", "X", "Y"]
        };
        let write = prop_oneof![50 => select(WRITE), 1 => select(WRITE_BAD)];
        let linear = (
            select(LINEAR),
            prop::collection::vec((select(axes), value()), 1..4),
        )
            .prop_map(|(g, w)| Stmt::Move(g, w));
        let arc = (select(&["G2", "G3"][..]), value(), value(), select(RADII))
            .prop_map(|(g, x, y, r)| Stmt::Move(g, vec![("X", x), ("Y", y), ("R", r.into())]));
        let leaf = prop_oneof![
            6 => (write.clone(), expr(3)).prop_map(|(v, e)| Stmt::Assign(v, e)),
            6 => linear,
            1 => arc,
            2 => select(PLAIN).prop_map(Stmt::Plain),
            2 => (condition(), any::<u8>()).prop_map(|(c, l)| Stmt::IfGoto(c, l)),
            2 => (condition(), write, expr(2)).prop_map(|(c, v, e)| Stmt::IfThen(c, v, e)),
            1 => any::<u8>().prop_map(Stmt::Goto),
            1 => select(GOTOS).prop_map(Stmt::GotoComputed),
            6 => call().prop_map(Stmt::Call),
            1 => Just(Stmt::Cancel),
            1 => (0u8..10).prop_map(Stmt::Return),
        ];
        let rare = prop_oneof![200 => leaf, 1 => (0u8..202).prop_map(Stmt::Alarm)];
        rare.prop_recursive(3, 12, 3, |inner| {
            let body = prop::collection::vec((prop::option::weighted(0.2, 1u8..7), inner), 1..4);
            prop_oneof![
                5 => (1u8..5, any::<u8>(), body.clone())
                    .prop_map(|(n, m, b)| Stmt::While(n, String::new(), m, b)),
                1 => (condition(), any::<u8>(), body.clone())
                    .prop_map(|(c, m, b)| Stmt::While(0, c, m, b)),
                1 => (1u8..4, any::<u8>(), body).prop_map(|(n, m, b)| Stmt::Do(n, m, b)),
            ]
        })
        .boxed()
    }

    /// Writes a plan as program text.
    struct Writer {
        out: String,
        /// The program being written: 0 main, 1… the subprograms.
        prog: usize,
        subs: usize,
        /// End of block: ";\n", "\n" or "; " (several blocks on a line).
        eob: &'static str,
        /// Loop numbers at random rather than by nesting depth.
        chaos: bool,
        loops: u32,
        /// The sequence numbers of the program being written (N10 … N60), and how many of
        /// them are written already.
        labels: Vec<u32>,
        seen: usize,
    }

    /// The sequence numbers a plan writes.
    fn labels(lines: &[Line], out: &mut Vec<u32>) {
        for (label, s) in lines {
            out.extend(label.map(|l| l as u32 * 10));
            if let Stmt::While(.., body) | Stmt::Do(.., body) = s {
                labels(body, out);
            }
        }
    }

    impl Writer {
        fn block(&mut self, n: Option<u32>, text: &str) {
            if let Some(n) = n {
                self.out.push_str(&format!("N{n} "));
                if n < 100 {
                    self.seen += 1;
                }
            }
            self.out.push_str(text);
            self.out.push_str(self.eob);
        }

        /// An O line starts a line of its own.
        fn o_line(&mut self, number: &str) {
            if !self.out.is_empty() && !self.out.ends_with('\n') {
                self.out.push('\n');
            }
            self.out.push_str(&format!("O{number}\n"));
        }

        fn lines(&mut self, lines: &[Line], depth: usize) {
            for (label, s) in lines {
                self.statement(label.map(|l| l as u32 * 10), s, depth);
            }
        }

        fn statement(&mut self, n: Option<u32>, s: &Stmt, depth: usize) {
            match s {
                Stmt::Assign(v, e) => self.block(n, &format!("{v}={e}")),
                Stmt::Move(g, words) => {
                    let mut t = g.to_string();
                    let mut seen = String::new();
                    for (a, v) in words {
                        if seen.contains(a) {
                            continue;
                        }
                        seen.push_str(a);
                        if !t.is_empty() {
                            t.push(' ');
                        }
                        t.push_str(a);
                        t.push_str(v);
                    }
                    self.block(n, &t)
                }
                Stmt::Plain(w) => self.block(n, w),
                Stmt::IfGoto(c, l) => self.block(n, &format!("IF {c} GOTO {}", self.label(*l))),
                Stmt::IfThen(c, v, e) => self.block(n, &format!("IF {c} THEN {v}={e}")),
                Stmt::Goto(l) => self.block(n, &format!("GOTO {}", self.label(*l))),
                Stmt::GotoComputed(g) => self.block(n, g),
                Stmt::While(passes, cond, m, body) => {
                    let m = self.loop_number(*m, depth);
                    let c = self.counter(depth);
                    if *passes > 0 {
                        self.block(None, &format!("{c}=0"));
                        self.block(n, &format!("WHILE [{c} LT {passes}] DO {m}"));
                    } else {
                        self.block(n, &format!("WHILE {cond} DO {m}"));
                    }
                    self.lines(body, depth + 1);
                    if *passes > 0 {
                        self.block(None, &format!("{c}={c}+1"));
                    }
                    self.block(None, &format!("END {m}"));
                }
                Stmt::Do(passes, m, body) => {
                    let m = self.loop_number(*m, depth);
                    let c = self.counter(depth);
                    let exit = self.exit_label();
                    self.block(None, &format!("{c}=0"));
                    self.block(n, &format!("DO {m}"));
                    self.lines(body, depth + 1);
                    self.block(None, &format!("{c}={c}+1"));
                    self.block(None, &format!("IF [{c} GE {passes}] GOTO {exit}"));
                    self.block(None, &format!("END {m}"));
                    self.block(Some(exit), "");
                }
                Stmt::Call(call) => self.call(n, call),
                Stmt::Cancel => self.block(n, "G67"),
                Stmt::Return(0..=3) => self.block(n, "M99"),
                Stmt::Return(4..=6) => self.block(n, "M99 P9990"),
                Stmt::Return(k) => self.block(n, &format!("M99 P{}", (k % 6 + 1) * 10)),
                Stmt::Alarm(k) => self.block(n, &format!("#3000={k}(FUZZ ALARM {k})")),
            }
        }

        /// A jump target: mostly a sequence number of the program ahead of the jump (a jump
        /// back runs until the loop limit unless its condition turns false), else any of its
        /// sequence numbers or its end (N9990), now and then one it does not have (N70).
        fn label(&self, l: u8) -> u32 {
            let ahead = &self.labels[self.seen.min(self.labels.len())..];
            match l % 8 {
                0 => 70,
                1..=4 if !ahead.is_empty() => ahead[l as usize % ahead.len()],
                1..=6 if !self.labels.is_empty() => self.labels[l as usize % self.labels.len()],
                _ => 9990,
            }
        }

        /// DO m: 1, 2, 3 by nesting depth (3 loops nest at most), or at random.
        fn loop_number(&self, m: u8, depth: usize) -> usize {
            if self.chaos {
                m as usize % 4
            } else {
                depth % 3 + 1
            }
        }

        /// The counter of a loop at `depth` in this program: common, so that calls do not
        /// touch it (#120 … #135).
        fn counter(&self, depth: usize) -> String {
            format!("#{}", 120 + self.prog * 4 + depth.min(3))
        }

        fn exit_label(&mut self) -> u32 {
            self.loops += 1;
            8000 + self.prog as u32 * 100 + self.loops
        }

        fn call(&mut self, n: Option<u32>, c: &Call) {
            let callees = self.prog + 1..=self.subs;
            let own = match self.prog {
                0 => "0001",
                k => SUBPROGRAMS[k - 1],
            };
            // (program number, guarded by the recursion counter)
            let (number, guarded) = match c.target {
                0 => ("2000", false),
                1 => (own, false),
                2..=4 => (own, true),
                t if !callees.is_empty() => {
                    let k = callees.start() + t as usize % callees.clone().count();
                    (SUBPROGRAMS[k - 1], false)
                }
                _ => (own, true),
            };
            // A guard: #15x counts the calls of this program and skips the call from the
            // limit on. It only grows, so the recursion ends.
            let skip = self.exit_label();
            if guarded {
                let g = format!("#{}", 150 + self.prog);
                self.block(n, &format!("{g}={g}+1"));
                self.block(None, &format!("IF [{g} GT {}] GOTO {skip}", c.limit));
            }
            let r = c.repeats;
            let args: String = c.args.iter().map(|(a, v)| format!(" {a}{v}")).collect();
            let text = match c.how {
                0 => format!("M98 P{number}"),
                1 => format!("M98 P{number} L{r}"),
                2 if number.len() == 4 && r > 0 => format!("M98 P{r}{number}"),
                2 => format!("M98 P{number} L{r}"),
                3 => format!("G65 P{number}{args}"),
                4 => format!("G65 P{number} L{r}{args}"),
                _ => format!("G66 P{number}{args}"),
            };
            self.block(if guarded { None } else { n }, &text);
            if guarded {
                self.block(Some(skip), "");
            }
        }
    }

    /// Flags of a whole file.
    #[derive(Clone, Debug)]
    struct Style {
        percent: bool,
        preamble: bool,
        chaos: bool,
        eob: &'static str,
        /// How the main program ends: M30, M99 (starts again), nothing.
        main_end: u8,
        /// How the last subprogram ends: M99, M30, nothing.
        sub_end: u8,
    }

    fn style() -> impl Strategy<Value = Style> {
        (
            prop::bool::weighted(0.1),
            prop::bool::weighted(0.95),
            prop::bool::weighted(0.05),
            select(&[";\n", ";\n", "\n", "; "][..]),
            0u8..12,
            0u8..12,
        )
            .prop_map(|(percent, preamble, chaos, eob, main_end, sub_end)| Style {
                percent,
                preamble,
                chaos,
                eob,
                main_end,
                sub_end,
            })
    }

    /// A file: main program and one to three subprograms.
    pub fn program(which: usize) -> impl Strategy<Value = String> {
        let line = (prop::option::weighted(0.3, 1u8..7), statement(which));
        let main = prop::collection::vec(line.clone(), 1..8);
        let subs = prop::collection::vec(prop::collection::vec(line, 1..6), 1..4);
        (main, subs, style()).prop_map(|(main, subs, st)| {
            let mut w = Writer {
                out: String::new(),
                prog: 0,
                subs: subs.len(),
                eob: st.eob,
                chaos: st.chaos,
                loops: 0,
                labels: Vec::new(),
                seen: 0,
            };
            labels(&main, &mut w.labels);
            if st.percent {
                w.out.push_str("%\n");
            }
            w.o_line("0001 (MAIN)");
            if st.preamble {
                w.block(None, "G21 G17 G90 G40 G49 G80");
                w.block(None, "G0 X0 Y0 Z10.");
                w.block(None, "#9=800.");
                w.block(None, "G1 F#9");
                // The variables of tame expressions.
                for (v, x) in [
                    (1, "1"),
                    (2, "2."),
                    (3, "3"),
                    (4, "4."),
                    (5, "5"),
                    (6, "6."),
                ]
                .into_iter()
                .chain([
                    (18, "10."),
                    (24, "10."),
                    (25, "20."),
                    (26, "-1."),
                    (100, "1"),
                ])
                .chain([(101, "2."), (102, "3."), (500, "0.5")])
                {
                    w.block(None, &format!("#{v}={x}"));
                }
            }
            w.lines(&main, 0);
            match st.main_end {
                0 => w.block(Some(9990), "M99"),
                1 => {}
                _ => w.block(Some(9990), "M30"),
            }
            let count = subs.len();
            for (k, sub) in subs.iter().enumerate() {
                w.prog = k + 1;
                w.loops = 0;
                w.labels.clear();
                w.seen = 0;
                labels(sub, &mut w.labels);
                w.o_line(SUBPROGRAMS[k]);
                w.lines(sub, 0);
                match st.sub_end {
                    0 if k + 1 == count => {}
                    1 if k + 1 == count => w.block(Some(9990), "M30"),
                    _ => w.block(Some(9990), "M99"),
                }
            }
            if st.percent {
                w.out.push_str("\n%\n");
            }
            w.out
        })
    }
}

/// Structured SINUMERIK programs: nested IF/ELSE, WHILE, FOR, REPEAT and LOOP with R-parameter
/// counters, moves whose values are expressions, labels and jumps out of loops and back. Every
/// structure is closed; what ends a run is the program's end, an alarm (an expression out of
/// range, a jump to a missing label) or the loop budget.
mod sinumerik_programs {
    use proptest::prelude::*;
    use proptest::sample::select;

    #[derive(Clone, Debug)]
    pub enum Stmt {
        Move(&'static str),
        Assign(&'static str),
        If(&'static str, Vec<Stmt>, Vec<Stmt>),
        While(&'static str, Vec<Stmt>),
        For(Vec<Stmt>),
        Repeat(&'static str, Vec<Stmt>),
        /// LOOP with an exit to a label after ENDLOOP once R9 passes 2.
        Loop(Vec<Stmt>),
        Jump(&'static str),
        /// A call of a PROC beside the program (`{}` is the callee's number): one further
        /// down the list, or the program itself (recursion, bounded by the program levels).
        Call(u8, &'static str),
    }

    /// Calls of SUB_n (`PROC SUB_n(REAL AA, INT NN, VAR REAL OUT)`), valid and broken.
    const CALLS: &[&str] = &[
        "SUB_{}(R1, R2+1, R5)",
        "SUB_{}(R1*2, , R6)",
        "SUB_{}(1.5, 2, R7) P2",
        "SUB_{}(, , R[R4])",
        "SUB_{}(R1, 2, 3)",
        "SUB_{}",
        "MCALL SUB_{}(R3, 1, R8)",
        "MCALL",
        "SUB_{}(1, 2, R9, 4)",
        "_N_SUB_{}_SPF(R2, 0, R5)",
        "SUB_{}(R1, 1, CNT)",
        "RET",
    ];

    const MOVES: &[&str] = &[
        "G1 X=R1 Y=R2 F=100+R3",
        "G1 X=R1*2 Y=-R2",
        "G0 Z=AC(R3+1)",
        "X=IC(R1) Y=AC(R2)",
        "G2 X=R1 Y0 CR=R1+10",
        "G1 X=SIN(R1*30)*10 Y=COS(R1*30)*10",
        "G1 X=R[R4] F100",
        "G41 D1 G1 X=R1+20 Y=R2",
        "G40 G1 X0 Y0",
        "G1 X=1/R0",
        "STOPRE",
        "MSG(\"pass\")",
        "CYCLE81(10, 0, 2, -R1-1)",
        "R6=$P_EP[X]+$AA_IW[Y]",
        "AROT RPL=R1*10",
        "TRANS X=R2",
        "G1 AP=R1*30 RP=R2+5",
        "MIRROR X0",
        "TAB[R4 MOD 3]=R1",
        "G1 X=TAB[R4 MOD 3]",
        "MSG(\"pass \" << R1 << \" of \" << R2)",
        "CYCLE83(10, 0, 1, -20, , -R1-1, , 2, , , 0.5, R4 MOD 2)",
    ];
    const ASSIGNS: &[&str] = &[
        "R1=R1+1",
        "R2=R2*2+1",
        "R3=R3-1",
        "R4=(R4+1) MOD 5",
        "R5=SQRT(ABS(R2))",
        "R6=ATAN2(R1,R2+1)",
        "CNT=CNT+1",
        "R7=R1 DIV 2",
        "R8=R1 B_AND 3",
        "R1=R[R4]+1",
        "R9=R9+1",
        "R2=ROUND(R2/3)",
    ];
    const CONDITIONS: &[&str] = &[
        "R1<3",
        "R2>=R1",
        "(R1>0) AND (R3<2)",
        "NOT (R1==R2)",
        "R4<>2",
        "R1 MOD 2==0",
        "(R2>1) OR (R3<0)",
        "CNT<4",
        "TRUE",
        "FALSE",
        "R5<2.5",
    ];
    const JUMPS: &[&str] = &[
        "GOTOF END_1",
        "GOTOF END_2",
        "IF R1>2 GOTOF END_1",
        "IF R1<2 GOTOB TOP",
        "GOTOC NOWHERE",
        "GOTO END_2",
        "IF R2>40 GOTOF MISSING",
        "GOTOF N9000",
        "CASE(R4) OF 1 GOTOF END_1 2 GOTOB TOP DEFAULT GOTOF END_2",
        "CASE(R1 MOD 3) OF 0 GOTOF END_1",
    ];

    fn stmt(calls: bool) -> impl Strategy<Value = Stmt> {
        let leaf = prop_oneof![
            4 => select(MOVES).prop_map(Stmt::Move),
            4 => select(ASSIGNS).prop_map(Stmt::Assign),
            1 => select(JUMPS).prop_map(Stmt::Jump),
            if calls { 3 } else { 0 } => (any::<u8>(), select(CALLS)).prop_map(|(k, c)| Stmt::Call(k, c)),
        ];
        leaf.prop_recursive(4, 40, 4, |inner| {
            let body = || prop::collection::vec(inner.clone(), 0..4);
            prop_oneof![
                2 => (select(CONDITIONS), body(), body()).prop_map(|(c, a, b)| Stmt::If(c, a, b)),
                1 => (select(CONDITIONS), body()).prop_map(|(c, b)| Stmt::While(c, b)),
                1 => body().prop_map(Stmt::For),
                1 => (select(CONDITIONS), body()).prop_map(|(c, b)| Stmt::Repeat(c, b)),
                1 => body().prop_map(Stmt::Loop),
            ]
        })
    }

    struct Out {
        text: String,
        labels: u32,
        /// The program being written (0 the main program) and how many PROCs there are.
        program: usize,
        subs: usize,
    }

    impl Out {
        fn line(&mut self, depth: usize, text: &str) {
            self.text.push_str(&"  ".repeat(depth));
            self.text.push_str(text);
            self.text.push('\n');
        }

        fn all(&mut self, stmts: &[Stmt], depth: usize) {
            for s in stmts {
                self.one(s, depth);
            }
        }

        fn one(&mut self, s: &Stmt, depth: usize) {
            match s {
                Stmt::Move(t) | Stmt::Assign(t) | Stmt::Jump(t) => self.line(depth, t),
                Stmt::Call(k, t) => {
                    // Down the list of PROCs; now and then the program itself.
                    let later = self.subs - self.program;
                    let callee = if later == 0 || k % 5 == 0 {
                        self.program.max(1)
                    } else {
                        self.program + 1 + *k as usize % later
                    };
                    self.line(depth, &t.replace("{}", &callee.to_string()));
                }
                Stmt::If(c, a, b) => {
                    self.line(depth, &format!("IF {c}"));
                    self.all(a, depth + 1);
                    if !b.is_empty() {
                        self.line(depth, "ELSE");
                        self.all(b, depth + 1);
                    }
                    self.line(depth, "ENDIF");
                }
                Stmt::While(c, b) => {
                    self.line(depth, &format!("WHILE {c}"));
                    self.all(b, depth + 1);
                    self.line(depth + 1, "R1=R1+1");
                    self.line(depth, "ENDWHILE");
                }
                Stmt::For(b) => {
                    let v = ["R10", "R11", "R12", "R13", "R14"][depth.min(4)];
                    self.line(depth, &format!("FOR {v}=1 TO 3"));
                    self.all(b, depth + 1);
                    self.line(depth, "ENDFOR");
                }
                Stmt::Repeat(c, b) => {
                    self.line(depth, "REPEAT");
                    self.all(b, depth + 1);
                    self.line(depth + 1, "R1=R1+1");
                    self.line(depth, &format!("UNTIL {c}"));
                }
                Stmt::Loop(b) => {
                    self.labels += 1;
                    let exit = format!("OUT_{}", self.labels);
                    self.line(depth, "LOOP");
                    self.line(depth + 1, "R9=R9+1");
                    self.line(depth + 1, &format!("IF R9>2 GOTOF {exit}"));
                    self.all(b, depth + 1);
                    self.line(depth, "ENDLOOP");
                    self.line(depth, &format!("{exit}: R9=0"));
                }
            }
        }
    }

    pub fn program() -> impl Strategy<Value = String> {
        (prop::collection::vec(stmt(false), 1..8), any::<bool>()).prop_map(|(stmts, end_label)| {
            let mut out = Out {
                text: "DEF INT CNT=0\nDEF REAL TAB[3]=SET(1,2)\nN1 G17 G90 G0 X0 Y0 Z5 F500\nR1=1 R2=2 R3=0 R4=1\nTOP: R0=R0+1\n".into(),
                labels: 0,
                program: 0,
                subs: 0,
            };
            out.all(&stmts, 0);
            out.line(0, "END_1: G0 Z10");
            if end_label {
                out.line(0, "END_2: G0 X0 Y0");
            }
            out.line(0, "M30");
            out.text
        })
    }

    /// A main program and one to three PROCs SUB_1 … in files of their own (name, text), each
    /// a structured program as above that calls the ones after it, or itself.
    pub fn call_program() -> impl Strategy<Value = (String, Vec<(String, String)>)> {
        let body = || (prop::collection::vec(stmt(true), 1..6), any::<bool>());
        (body(), prop::collection::vec(body(), 1..4)).prop_map(|(main, subs)| {
            let n = subs.len();
            let write =
                |program: usize, head: &str, (stmts, end_label): &(Vec<Stmt>, bool), end: &str| {
                    let mut out = Out {
                        text: head.into(),
                        labels: 0,
                        program,
                        subs: n,
                    };
                    out.line(0, "TOP: R0=R0+1");
                    out.all(stmts, 0);
                    out.line(0, "END_1: G0 Z10");
                    if *end_label {
                        out.line(0, "END_2: G0 X0 Y0");
                    }
                    out.line(0, end);
                    out.text
                };
            let main_head = "DEF INT CNT=0\nDEF REAL TAB[3]=SET(1,2)\nN1 G17 G90 G0 X0 Y0 Z5 F500\nR1=1 R2=2 R3=0 R4=1\n";
            let files = subs
                .iter()
                .enumerate()
                .map(|(k, b)| {
                    let head = format!(
                        "PROC SUB_{}(REAL AA, INT NN, VAR REAL OUT)\nDEF INT CNT=NN\nOUT=OUT+AA\n",
                        k + 1
                    );
                    let end = if k % 2 == 0 { "M17" } else { "" };
                    (format!("SUB_{}.SPF", k + 1), write(k + 1, &head, b, end))
                })
                .collect();
            (write(0, main_head, &main, "M30"), files)
        })
    }
}

/// Cases per property: `default`, or `PROPTEST_CASES` from the environment (a longer hunt:
/// `PROPTEST_CASES=20000 cargo test --release --test fuzz_frontend`).
fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(2000), ..ProptestConfig::default() })]

    /// Arbitrary bytes, read the way `softnc parse` reads a file.
    #[test]
    fn random_bytes(which in 0..8usize, bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        check(which, &String::from_utf8_lossy(&bytes))?;
    }

    /// Printable ASCII and line ends: reaches deeper than raw bytes.
    #[test]
    fn random_ascii(which in 0..8usize, src in "[ -~\t\r\n]{0,200}") {
        check(which, &src)?;
    }

    #[test]
    fn token_soup_840c(src in soup(false)) {
        check(0, &src)?;
    }

    #[test]
    fn token_soup_isg(src in soup(false)) {
        check(1, &src)?;
    }

    #[test]
    fn token_soup_fanuc(src in soup(true)) {
        check(2, &src)?;
    }

    #[test]
    fn token_soup_808d(src in soup(false)) {
        check(3, &src)?;
    }

    #[test]
    fn token_soup_5axis(src in soup(true)) {
        check(4, &src)?;
    }

    #[test]
    fn token_soup_808d_c(src in soup(false)) {
        check(5, &src)?;
    }

    #[test]
    fn block_soup_840c(src in block_soup(0)) {
        check(0, &src)?;
    }

    #[test]
    fn block_soup_isg(src in block_soup(1)) {
        check(1, &src)?;
    }

    #[test]
    fn block_soup_fanuc(src in block_soup(2)) {
        check(2, &src)?;
    }

    #[test]
    fn block_soup_808d(src in block_soup(3)) {
        check(3, &src)?;
    }

    #[test]
    fn block_soup_5axis(src in block_soup(4)) {
        check(4, &src)?;
    }

    #[test]
    fn token_soup_fanuc_lathe(src in soup(true)) {
        check(6, &src)?;
    }

    #[test]
    fn token_soup_840d(src in sinumerik_soup()) {
        check(7, &src)?;
    }

    #[test]
    fn block_soup_840d(src in block_soup(7)) {
        check(7, &src)?;
    }

    #[test]
    fn sinumerik_programs_840d(src in sinumerik_programs::program()) {
        check(7, &src)?;
    }

    /// Structured SINUMERIK programs that call PROCs in files beside them.
    #[test]
    fn sinumerik_calls_840d((main, files) in sinumerik_programs::call_program()) {
        check_files(7, &main, &files)?;
    }

    #[test]
    fn block_soup_fanuc_lathe(src in block_soup(6)) {
        check(6, &src)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(1000), ..ProptestConfig::default() })]

    /// Structured macro programs: main program, subprograms, loops, calls, recursion.
    #[test]
    fn macro_programs_fanuc(src in macro_programs::program(2)) {
        check(2, &src)?;
    }

    #[test]
    fn macro_programs_5axis(src in macro_programs::program(4)) {
        check(4, &src)?;
    }

    #[test]
    fn macro_programs_fanuc_lathe(src in macro_programs::program(6)) {
        check(6, &src)?;
    }
}

/// Fixed inputs that once were, or could be, troublesome; cheap to keep.
#[test]
fn edge_cases() {
    let long_digits = format!("X{}", "9".repeat(400));
    let deep = format!("X{}1{}", "[".repeat(500), "]".repeat(500));
    let minus = format!("X{}1", "-".repeat(500));
    let parens = "(".repeat(1000);
    let macro_deep = format!("#1={}1{}", "[".repeat(500), "]".repeat(500));
    let macro_if = format!("IF {}1 EQ 1{} GOTO 1\nN1", "[".repeat(300), "]".repeat(300));
    let macro_index = format!("#{}1{}=1", "#[".repeat(200), "]".repeat(200));
    let macro_number = format!("#{}=1\nX#{}", "9".repeat(400), "9".repeat(400));
    let macro_args = format!("O1\nG65 P2 {}\nM30\nO2\nM99", "I1 J2 K3 ".repeat(20));
    let macro_calls = format!(
        "O1\n{}M30\nO2\nG91 G0 X1.\nM99\n",
        "M98 P2 L3\n".repeat(200)
    );
    let cases: Vec<&str> = vec![
        "",
        "\n",
        ";",
        "%",
        "N",
        "/",
        "(",
        ")",
        "$",
        "@",
        "LF",
        "CR=",
        "V.",
        "V.P.",
        "V....=1",
        "\u{0}",
        "\r",
        "N10\r\n",
        "G1 X1 F100;;;;",
        "$FOR V.P.A = 0,3,1\n$ENDFOR\n$ENDFOR",
        "$WHILE 1\n$IF 1\n$ENDWHILE\n$ENDIF",
        "$IF 0\n$ELSEIF [1/0]\n$ENDIF",
        "$IF 0\n$ELSE\n$ELSE\n$ENDIF",
        &long_digits,
        &deep,
        &minus,
        &parens,
        // Fanuc Custom Macro B and subprograms
        "#",
        "#1",
        "#1=",
        "#=1",
        "#[",
        "#[]=1",
        "#0=1",
        "#1=#",
        "#1=[",
        "#1=1]",
        "#1=SIN",
        "#1=SIN[",
        "#1=ATAN[1]/",
        "#1=ATAN[1]/[",
        "#1=POW[1,",
        "#1=1 EQ",
        "#1=1 MOD",
        "#1=#[#[#[#[#[1]]]]]",
        "#1=[[[[[1]]]]]",
        "#1=[[[[[[1]]]]]]",
        "#-1=1",
        "#3000",
        "#3000=",
        "#3000=1(",
        "#3000=1()",
        "#3000=0.5",
        "#5041=1",
        "X#",
        "X-#",
        "X#[",
        "X[",
        "X#1(",
        "G#",
        "G#[1/0]",
        "M#1",
        "G1 X#5041 Y#5042 Z#5043 F100.",
        "IF",
        "IF [",
        "IF [1]",
        "IF [1] GOTO",
        "IF [1] THEN",
        "IF [0] THEN #",
        "IF [1] THEN X1",
        "GOTO",
        "GOTO #",
        "GOTO [",
        "GOTO 1",
        "N1 GOTO 1",
        "N1 GOTO 1;N1",
        "GOTO 99999999999999999999",
        "WHILE",
        "WHILE [1]",
        "WHILE [1] DO",
        "WHILE [1] DO 1",
        "WHILE [0] DO 1",
        "WHILE [1] DO 1\nEND 1",
        "WHILE [1] DO 1\nEND 2",
        "DO 1\nEND 1",
        "DO 1\nDO 2\nDO 3\nDO 1\nEND 1",
        "DO 1\nDO 2\nEND 1\nEND 2",
        "END 1",
        "END",
        "DO",
        "O",
        "O0\nM98 P0",
        "M98",
        "M98 P",
        "M98 P1",
        "M98 P1 L99999",
        "M99",
        "M99 P1",
        "N1 M99 P1",
        "O1\nM98 P1\nM30",
        "O1\nG65 P1\nM30",
        "O1\nG66 P1\nG1 X1. F100.\nM30",
        "O1\nG66 P2\nG1 X1. F100.\nG1 X2.\nG67\nG1 X3.\nM30\nO2\nG1 X#24\nM99",
        "O1\nM98 P31000\nM30\nO1000\nG91 G0 X1.\nM99",
        "O1\nM98 P2\nM30\nO2\nWHILE [1] DO 1\nM99\nEND 1",
        "O1\nM98 P2\nM30\nO2\nDO 1\nM99",
        "O1\nM98 P2\nM30\nO2\nEND 1",
        "O1\nM98 P2\nM30\nO2\nGOTO 10\nM99",
        "O1\nM98 P2\nN10 M30\nO2\nM99 P10",
        "O1\nN10 M98 P2\nM30\nO2\nM99 P10",
        "O1\nN10 G65 P2 L3\nM30\nO2\nM99 P10",
        "O1\nM98 P2\nM30\nO2",
        "O1\nM98 P2\nM30\nO2\nO3",
        "O1\nM98 P2 M98 P2\nM30\nO2\nM99",
        "O1\nG65 P2 A1 B2 C3 D4 E5 F6 H7 M8 Q9 R10 S11 T12 U13 V14 W15 X16 Y17 Z18\nM30\nO2\nM99",
        "O1\nG65 P2 G1\nM30\nO2\nM99",
        "O1\nG65 P2 L0\nM30\nO2\nM99",
        "%\nO0001\nN10 #1=#1+1\nIF [#1 LT 3] GOTO 10\nM30\n%",
        &macro_deep,
        &macro_if,
        &macro_index,
        &macro_number,
        &macro_args,
        &macro_calls,
    ];
    for (which, dialect) in DIALECTS.iter().enumerate() {
        for src in &cases {
            check(which, src).unwrap_or_else(|e| panic!("{dialect}: {src:?}: {e}"));
        }
    }
}

/// Repeat counts multiplied down the calls (found by the macro generators): every
/// repetition of M98 L, G65 L and a cycle's K is a loop pass, so with 100 passes allowed each
/// ends in alarm 12650 after a few blocks instead of running 9999^3 times. Loops left by a
/// GOTO close when their number is used again, so correctly nested loops after them run.
#[test]
fn repeat_counts_are_loop_passes_and_jumps_leave_loops() {
    let hangs = [
        "O0001\nM98 P2 L9999\nM30\nO0002\nM98 P3 L9999\nM99\nO0003\nM98 P4 L9999\nM99\nO0004\nM99\n",
        "O0001\nG65 P2 L9999\nM30\nO0002\nG65 P3 L9999\nM99\nO0003\nG65 P4 L9999\nM99\nO0004\nM99\n",
        "O0001\nM98 P2 L9999\nM30\nO0002\nG91 G81 X0.001 Z-1. R1. K9999 F100.\nM99\n",
    ];
    for src in hangs {
        let a = nc_kernel::interpret("fuzz.nc", src, &machines()[2], tools()).unwrap_err();
        assert_eq!(a.code, nc_kernel::AlarmCode::LoopLimit, "{src:?}: {a}");
    }
    let left = [
        "WHILE [#1 LT 2] DO 1\n#1=#1+1\nDO 2\nGOTO 5\nEND 2\nN5 END 1\nM30\n",
        "DO 2\nGOTO 5\nEND 2\nN5 WHILE [#1 LT 1] DO 1\nWHILE [#2 LT 1] DO 2\n#2=1\nEND 2\n#1=1\nEND 1\nM30\n",
    ];
    for src in left {
        let r = nc_kernel::interpret("fuzz.nc", src, &machines()[2], tools());
        assert!(r.is_ok(), "{src:?}: {:?}", r.err());
    }
}

/// The macro program generator reaches deep: of 1000 programs (a fixed seed) at least a tenth
/// run to their end and a tenth make 50 blocks or more, so the properties above test more
/// than first statements. `--nocapture` prints how they end (alarms by code, blocks per run).
#[test]
fn macro_programs_reach_deep() {
    reach_deep(macro_programs::program(2), 2, 50);
}

/// The structured SINUMERIK programs run deep: many reach their end, the others stop on an
/// alarm of the language (a missing label, the loop budget, a value out of range).
#[test]
fn sinumerik_programs_reach_deep() {
    reach_deep(sinumerik_programs::program(), 7, 30);
}

/// The SINUMERIK programs with calls reach into their PROCs: of 1000, at least a tenth run to
/// their end, a fifth make blocks in a PROC, and the 90th percentile of blocks per run is at
/// least 30.
#[test]
fn sinumerik_calls_reach_deep() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strategy = sinumerik_programs::call_program();
    let (mut ended, mut blocks, mut called) = (0, Vec::new(), 0);
    let mut outcomes: HashMap<String, usize> = HashMap::new();
    for _ in 0..1000 {
        let (main, files) = strategy.new_tree(&mut runner).unwrap().current();
        let mut md = machines()[7].clone();
        let mut library = nc_kernel::ProgramLibrary::default();
        for (name, text) in &files {
            library.add(name, name.clone(), text.clone());
        }
        md.programs = std::sync::Arc::new(library);
        let (mut n, mut inside) = (0, false);
        let mut end = "end of program".to_string();
        for item in nc_kernel::Interpreter::new("fuzz.nc", &main, &md, tools()) {
            match item {
                Ok(b) => {
                    n += 1;
                    inside |= b.program != 0;
                }
                Err(a) => {
                    end = format!("{:?}", a.code);
                    break;
                }
            }
        }
        ended += usize::from(end == "end of program");
        called += usize::from(inside);
        *outcomes.entry(end).or_default() += 1;
        blocks.push(n);
    }
    let mut outcomes: Vec<_> = outcomes.into_iter().collect();
    outcomes.sort_by_key(|o| std::cmp::Reverse(o.1));
    println!("{outcomes:?}");
    blocks.sort_unstable();
    let p90 = blocks[blocks.len() * 9 / 10];
    println!("blocks per run: 90th percentile {p90}; runs with blocks of a PROC: {called}");
    assert!(ended >= 100, "only {ended} of 1000 runs reach their end");
    assert!(called >= 200, "only {called} of 1000 runs get into a PROC");
    assert!(p90 >= 30, "90th percentile of blocks per run: {p90}");
}

/// 1000 programs of `strategy` on machine `which`: at least 100 reach their end, and the 90th
/// percentile of blocks per run is at least `p90_at_least` (the outcomes are printed).
fn reach_deep(strategy: impl Strategy<Value = String>, which: usize, p90_at_least: usize) {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let mut outcomes: HashMap<String, usize> = HashMap::new();
    let mut blocks = Vec::new();
    for _ in 0..1000 {
        let src = strategy.new_tree(&mut runner).unwrap().current();
        let mut n = 0;
        let mut end = "end of program".to_string();
        for item in nc_kernel::Interpreter::new("fuzz.nc", &src, &machines()[which], tools()) {
            match item {
                Ok(_) => n += 1,
                Err(a) => {
                    end = format!("{:?}", a.code);
                    break;
                }
            }
        }
        *outcomes.entry(end).or_default() += 1;
        blocks.push(n);
    }
    let ended = outcomes.get("end of program").copied().unwrap_or(0);
    let mut outcomes: Vec<_> = outcomes.into_iter().collect();
    outcomes.sort_by_key(|o| std::cmp::Reverse(o.1));
    println!("{outcomes:?}");
    blocks.sort_unstable();
    let p90 = blocks[blocks.len() * 9 / 10];
    println!(
        "blocks per run: median {}, 90th percentile {p90}, most {}",
        blocks[blocks.len() / 2],
        blocks[blocks.len() - 1]
    );
    assert!(ended >= 100, "only {ended} of 1000 runs reach their end");
    assert!(
        p90 >= p90_at_least,
        "90th percentile of blocks per run: {p90}"
    );
}
