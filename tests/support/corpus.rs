//! The harness of the hand-computed program corpora (tests/corpus/<dialect>/): a program's
//! blocks up to its end or its first alarm, its moves' end points against the values worked
//! out by hand, `softnc check` on the clean ones, and the alarm of those that must stop. The
//! program library (subprogram files beside the program, the search path) is found as
//! `softnc` finds it.
#![allow(dead_code)] // each corpus uses a different part

use nc_kernel::{Alarm, AlarmCode, Block, Interpreter, MachineData, ToolTable};
use std::path::PathBuf;
use std::process::Command;

pub type P = [f64; 3];

/// Hand values agree to this (sums of decimal fractions, and the trigonometry in some).
pub const TOL: f64 = 1e-9;

/// A corpus: its folder and its machine data file, both relative to the repository.
pub struct Corpus {
    pub dir: &'static str,
    pub machine: &'static str,
}

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

impl Corpus {
    pub fn path_of(&self, file: &str) -> PathBuf {
        root().join(self.dir).join(file)
    }

    /// The corpus' machine data, as shipped.
    pub fn machine(&self) -> MachineData {
        MachineData::load(Some(&root().join(self.machine)), &[])
            .unwrap_or_else(|e| panic!("{}: {e:?}", self.machine))
    }

    /// The machine data with the subprogram files beside `file`.
    pub fn machine_for(&self, file: &str) -> MachineData {
        let mut md = self.machine();
        let library = nc_runtime::program_library(&self.path_of(file), &md.program.search_path);
        md.programs = std::sync::Arc::new(library.expect("the corpus folder"));
        md
    }

    /// The blocks up to the end or the first alarm.
    pub fn run(&self, file: &str) -> (Vec<Block>, Option<Alarm>) {
        let text =
            std::fs::read_to_string(self.path_of(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        let (md, tools) = (self.machine_for(file), ToolTable::builtin());
        let mut out = Vec::new();
        for item in Interpreter::new(file, &text, &md, &tools) {
            match item {
                Ok(b) => out.push(b),
                Err(a) => return (out, Some(a)),
            }
        }
        (out, None)
    }

    /// `softnc check PROGRAM --machine MACHINE` passes.
    pub fn check(&self, file: &str) {
        let out = Command::new(env!("CARGO_BIN_EXE_softnc"))
            .current_dir(root())
            .arg("check")
            .arg(self.path_of(file))
            .arg("--machine")
            .arg(self.machine)
            .output()
            .expect("softnc runs");
        assert_eq!(
            out.status.code(),
            Some(0),
            "{file}: {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }

    /// A program that runs to its end: the end points by hand, and `softnc check`.
    pub fn clean(&self, file: &str, want: &[P]) -> Vec<Block> {
        let (b, alarm) = self.run(file);
        if let Some(a) = alarm {
            panic!("{file}: {a}");
        }
        assert_ends(file, &ends(&b), want);
        self.check(file);
        b
    }

    /// A program that stops: the moves before the alarm, and the alarm's code, line and
    /// column.
    pub fn stops(&self, file: &str, want: &[P], code: AlarmCode, line: u32, col: u32) -> Alarm {
        let (b, alarm) = self.run(file);
        assert_ends(file, &ends(&b), want);
        let a = alarm.unwrap_or_else(|| panic!("{file}: no alarm"));
        assert_eq!(
            (a.code, a.line, a.col),
            (code, line, col),
            "{file}: {} {a}",
            a.number()
        );
        a
    }
}

/// The end points of the moves.
pub fn ends(b: &[Block]) -> Vec<P> {
    b.iter().filter_map(|b| b.motion.map(|m| m.end)).collect()
}

pub fn near(a: P, b: P) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() <= TOL)
}

pub fn assert_ends(file: &str, got: &[P], want: &[P]) {
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            near(*g, *w),
            "{file}: move {k}: {g:?}, by hand {w:?}\nall moves: {got:?}"
        );
    }
    assert_eq!(got.len(), want.len(), "{file}: number of moves: {got:?}");
}

/// The block of the program's `N` (or `:`) number `n` (the first one produced).
pub fn block<'a>(file: &str, b: &'a [Block], n: u32) -> &'a Block {
    b.iter()
        .find(|b| b.number.is_some_and(|x| x.value == n))
        .unwrap_or_else(|| panic!("{file}: no block N{n}"))
}
