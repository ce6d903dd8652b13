//! Robustness of the front end: no panic and no hang on any input.
//!
//! Random bytes (non-UTF-8 included, read the way `softnc` reads a file), "token soup" — random
//! sequences of words, control statements and separators drawn from every dialect's features —
//! and "block soup" — blocks made mostly of the dialect's own words, so that programs run deeper
//! before they meet a broken word — are interpreted in all four dialects. Every run must end with blocks or an alarm; an alarm
//! must point into the program (line ≥ 1, column ≥ 1, within the text) and say something.
//! `program.max_loop_iterations` is set to 100 so that loops stay short.
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

const DIALECTS: [&str; 6] = [
    "siemens-840c",
    "isg",
    "fanuc",
    "siemens-808d",
    "fanuc-5axis",
    "siemens-808d-c",
];

/// Seconds one interpretation may take before the watchdog calls it a hang.
const HANG_SECS: u64 = 20;

/// The shipped machine data of each dialect, with short loops. The 808D is the lathe (X and Z
/// only, diameter programming), so unconfigured axes are exercised too; the 5-axis mill and
/// the lathe with C add rotary axes (modulo and not).
fn machines() -> &'static [MachineData; 6] {
    static M: OnceLock<[MachineData; 6]> = OnceLock::new();
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
    running().lock().unwrap().remove(&id);
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

fn check_alarm(a: &Alarm, src: &str) -> Result<(), TestCaseError> {
    prop_assert!(a.line >= 1, "line 0: {}", a);
    prop_assert!(a.col >= 1, "column 0: {}", a);
    prop_assert!(!a.message.trim().is_empty(), "empty message: {:?}", a);
    prop_assert_eq!(a.program.as_str(), "fuzz.nc");
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
    prop_assert!(shown.starts_with("fuzz.nc:"));
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
    "M1", "M2", "M3", "M18", "M30", "DIAMON", "DIAMOF", "@714", "@66250", "@",
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

fn soup() -> impl Strategy<Value = String> {
    prop::collection::vec((0..VOCABULARY.len(), 0..SEPARATORS.len()), 0..60).prop_map(|v| {
        let mut s = String::new();
        for (t, sep) in v {
            s.push_str(VOCABULARY[t]);
            s.push_str(SEPARATORS[sep]);
        }
        s
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
    "D0", "G70", "G71", "F2", "G92 S3000", "G92", "G96 S100", "G95 F0.2",
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
];
#[rustfmt::skip]
const D808_WORDS: &[&str] = &[
    "CR=5", "CR=-10", "DIAMON", "DIAMOF", "G450", "G451", "T1", "T2", "T1 D2", "G700", "G710",
    "G60", "G64", "G53", "G500", "G59", "LIMS=3000", "LIMS=", "LIMS", "LIMS=-1", "G96 S180",
    "G95 F0.2",
];

/// A program of blocks: mostly words of the dialect, now and then any token of the vocabulary.
fn block_soup(which: usize) -> impl Strategy<Value = String> {
    let own: &'static [&'static str] = match which {
        0 => C840_WORDS,
        1 => ISG_WORDS,
        2 => FANUC_WORDS,
        _ => D808_WORDS,
    };
    let word = prop_oneof![
        6 => prop::sample::select(COMMON),
        4 => prop::sample::select(own),
        1 => prop::sample::select(VOCABULARY),
    ];
    let block = (
        any::<bool>(),
        0u32..200,
        prop::collection::vec(word, 0..6),
        0u8..10,
        prop::sample::select(ISG_STATEMENTS),
    );
    let end = if which == 2 { ";\n" } else { "\n" };
    prop::collection::vec(block, 0..40).prop_map(move |blocks| {
        // ISG: the variables the words use start defined (mostly).
        let mut s = String::from(if which == 1 {
            "V.P.A = 0\nV.P.B = 1\n"
        } else {
            ""
        });
        for (numbered, n, words, dice, stmt) in blocks {
            if numbered {
                s.push_str(&format!("N{n} "));
            }
            if which == 1 && dice < 3 {
                s.push_str(stmt);
            } else {
                s.push_str(&words.join(" "));
            }
            s.push_str(end);
        }
        s
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// Arbitrary bytes, read the way `softnc parse` reads a file.
    #[test]
    fn random_bytes(which in 0..6usize, bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        check(which, &String::from_utf8_lossy(&bytes))?;
    }

    /// Printable ASCII and line ends: reaches deeper than raw bytes.
    #[test]
    fn random_ascii(which in 0..6usize, src in "[ -~\t\r\n]{0,200}") {
        check(which, &src)?;
    }

    #[test]
    fn token_soup_840c(src in soup()) {
        check(0, &src)?;
    }

    #[test]
    fn token_soup_isg(src in soup()) {
        check(1, &src)?;
    }

    #[test]
    fn token_soup_fanuc(src in soup()) {
        check(2, &src)?;
    }

    #[test]
    fn token_soup_808d(src in soup()) {
        check(3, &src)?;
    }

    #[test]
    fn token_soup_5axis(src in soup()) {
        check(4, &src)?;
    }

    #[test]
    fn token_soup_808d_c(src in soup()) {
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
}

/// Fixed inputs that once were, or could be, troublesome; cheap to keep.
#[test]
fn edge_cases() {
    let long_digits = format!("X{}", "9".repeat(400));
    let deep = format!("X{}1{}", "[".repeat(500), "]".repeat(500));
    let minus = format!("X{}1", "-".repeat(500));
    let parens = "(".repeat(1000);
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
    ];
    for (which, dialect) in DIALECTS.iter().enumerate() {
        for src in &cases {
            check(which, src).unwrap_or_else(|e| panic!("{dialect}: {src:?}: {e}"));
        }
    }
}
