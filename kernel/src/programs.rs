//! The programs a part program can call besides those in its own file: the subprogram files
//! of the program's folder and of the machine data's search path (`program.search_path`).
//! The runtime lists the files and hands them in with the machine data, with the means to
//! read one (the core reads none); a file is read when a program first calls it, so that a
//! folder of long part programs costs nothing until one of them is called (`softnc check`
//! of one program beside fifty others read only its own). Read once, its text stays for the
//! preparation that checks the program and the one that runs it alike.
//!
//! A file is a callable program when its name says which one it is:
//! - Fanuc M98/G65/G66 P: the name without extension is an O number: `O1000`, `O1000.nc`,
//!   `o1000.NC` are program 1000.
//! - SINUMERIK (and 840C `L123`): the extension is `.SPF` (subprogram) or `.MPF` (main
//!   program), any case, and the name before it is a program name (letters, digits, `_`):
//!   `POCKET_A.SPF`, `l123.spf`. Calls find names in any case (Fundamentals, "Subprogram
//!   names": the language does not tell upper from lower case).
//!
//! The program's own folder comes first, then the search path in its order; the first file
//! of a number or of a name and kind wins.

/// What names a program file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ProgramKey {
    /// A Fanuc O number.
    Number(u32),
    /// A SINUMERIK program name (upper case) and whether the file is a main program (`.MPF`)
    /// rather than a subprogram (`.SPF`).
    Named { name: String, main: bool },
}

/// Reads one program file's text, or says why it cannot: given by the runtime for each file
/// it lists. Unwind-safe, so that the machine data stays so (the fuzz tests run the kernel
/// under `catch_unwind`).
pub type ReadText = dyn Fn() -> Result<String, String>
    + Send
    + Sync
    + std::panic::RefUnwindSafe
    + std::panic::UnwindSafe;

/// One program file: what names it, how alarms name it (its path) and its text, read at its
/// first use.
#[derive(Clone)]
pub struct LibraryProgram {
    pub key: ProgramKey,
    pub name: String,
    text: std::sync::OnceLock<Result<String, String>>,
    read: Option<std::sync::Arc<ReadText>>,
}

/// The same file: its key and name (whether its text is read yet does not matter).
impl PartialEq for LibraryProgram {
    fn eq(&self, other: &Self) -> bool {
        self.key == other.key && self.name == other.name
    }
}

impl std::fmt::Debug for LibraryProgram {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LibraryProgram")
            .field("key", &self.key)
            .field("name", &self.name)
            .field("read", &self.text.get().map(|t| t.is_ok()))
            .finish()
    }
}

impl LibraryProgram {
    /// Its text, read now if it was not before; why it cannot be read (the file went, or
    /// cannot be opened).
    pub fn text(&self) -> Result<&str, &str> {
        let read = || match &self.read {
            Some(read) => read(),
            None => Err("no text".to_string()),
        };
        match self.text.get_or_init(read) {
            Ok(t) => Ok(t),
            Err(e) => Err(e),
        }
    }

    /// Its O number, if it is a Fanuc program.
    pub fn number(&self) -> Option<u32> {
        match self.key {
            ProgramKey::Number(n) => Some(n),
            ProgramKey::Named { .. } => None,
        }
    }
}

/// The program files, in search order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProgramLibrary {
    programs: Vec<LibraryProgram>,
}

impl ProgramLibrary {
    /// The program number a file name gives (`O1000.nc` → 1000), if it names one.
    pub fn number_of(file_name: &str) -> Option<u32> {
        let stem = file_name.split('.').next()?;
        let digits = stem.strip_prefix(['O', 'o'])?;
        if digits.is_empty() || digits.len() > 8 || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        digits.parse().ok()
    }

    /// What a file name makes of the file: an O number, a SINUMERIK program, or nothing.
    pub fn key_of(file_name: &str) -> Option<ProgramKey> {
        if let Some((stem, ext)) = file_name.rsplit_once('.') {
            let main = ext.eq_ignore_ascii_case("MPF");
            if (main || ext.eq_ignore_ascii_case("SPF")) && is_program_name(stem) {
                let name = stem.to_ascii_uppercase();
                return Some(ProgramKey::Named { name, main });
            }
        }
        Self::number_of(file_name).map(ProgramKey::Number)
    }

    /// Adds a file with its text; a number, or a name of the same kind, that is there
    /// already keeps its first file. False if the file names no program or its program was
    /// there.
    pub fn add(&mut self, file_name: &str, name: String, text: String) -> bool {
        self.push(file_name, name, std::sync::OnceLock::from(Ok(text)), None)
    }

    /// Adds a file whose text `read` gives at its first use, as [`Self::add`] does.
    pub fn add_file(
        &mut self,
        file_name: &str,
        name: String,
        read: std::sync::Arc<ReadText>,
    ) -> bool {
        self.push(file_name, name, std::sync::OnceLock::new(), Some(read))
    }

    fn push(
        &mut self,
        file_name: &str,
        name: String,
        text: std::sync::OnceLock<Result<String, String>>,
        read: Option<std::sync::Arc<ReadText>>,
    ) -> bool {
        let Some(key) = Self::key_of(file_name) else {
            return false;
        };
        if self.programs.iter().any(|p| p.key == key) {
            return false;
        }
        let p = LibraryProgram {
            key,
            name,
            text,
            read,
        };
        self.programs.push(p);
        true
    }

    /// Program `number` and its index (1 …; 0 is the main program's file).
    pub fn find(&self, number: u32) -> Option<(u16, &LibraryProgram)> {
        let k = self
            .programs
            .iter()
            .position(|p| p.key == ProgramKey::Number(number))?;
        Some((k as u16 + 1, &self.programs[k]))
    }

    /// The SINUMERIK program `name` (any case) and its index. `main`: `Some(false)` only a
    /// subprogram file, `Some(true)` only a main program file, `None` either: in the first
    /// folder that has one, the subprogram before the main program (Job planning, "Search
    /// path": name_SPF before name_MPF in each directory).
    pub fn find_named(&self, name: &str, main: Option<bool>) -> Option<(u16, &LibraryProgram)> {
        let fits = |p: &LibraryProgram, kind: Option<bool>| match &p.key {
            ProgramKey::Named { name: n, main: m } => {
                n.eq_ignore_ascii_case(name) && kind.is_none_or(|k| k == *m)
            }
            ProgramKey::Number(_) => false,
        };
        let first = self.programs.iter().position(|p| fits(p, main))?;
        let folder = folder_of(&self.programs[first].name);
        // A subprogram of the same folder comes before the main program found first.
        let k = self
            .programs
            .iter()
            .position(|p| folder_of(&p.name) == folder && fits(p, Some(false)))
            .filter(|_| main.is_none())
            .unwrap_or(first);
        Some((k as u16 + 1, &self.programs[k]))
    }

    /// Program file `index` (1 …).
    pub fn find_index(&self, index: u16) -> Option<&LibraryProgram> {
        self.programs.get((index as usize).checked_sub(1)?)
    }

    /// The name of program file `index` (0: none, the main program's file).
    pub fn name(&self, index: u16) -> Option<&str> {
        let k = (index as usize).checked_sub(1)?;
        self.programs.get(k).map(|p| p.name.as_str())
    }

    /// The text of the program file named `name` (to show an alarm's line).
    pub fn text_of(&self, name: &str) -> Option<&str> {
        self.programs
            .iter()
            .find(|p| p.name == name)
            .and_then(|p| p.text().ok())
    }

    /// An alarm as a compiler diagnostic, with the line of the file it is in: a subprogram
    /// file's, or `main` (the main program's text).
    pub fn render(&self, alarm: &crate::Alarm, main: &str) -> String {
        alarm.render(self.text_of(&alarm.program).unwrap_or(main))
    }

    pub fn len(&self) -> usize {
        self.programs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.programs.is_empty()
    }
}

/// A SINUMERIK program name: letters, digits and `_` (Fundamentals, "Subprogram names").
fn is_program_name(stem: &str) -> bool {
    !stem.is_empty() && stem.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

/// The folder part of a file's path as the library names it.
fn folder_of(path: &str) -> &str {
    path.rfind(['/', '\\']).map_or("", |k| &path[..k])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_give_program_numbers_and_the_first_wins() {
        assert_eq!(ProgramLibrary::number_of("O1000.nc"), Some(1000));
        assert_eq!(ProgramLibrary::number_of("o0042"), Some(42));
        assert_eq!(ProgramLibrary::number_of("main.nc"), None);
        assert_eq!(ProgramLibrary::number_of("O12a.nc"), None);
        let mut l = ProgramLibrary::default();
        assert!(l.add("O1000.nc", "a/O1000.nc".into(), "first".into()));
        assert!(!l.add("O1000.NC", "b/O1000.NC".into(), "second".into()));
        let (k, p) = l.find(1000).unwrap();
        assert_eq!(
            (k, p.text(), l.name(k)),
            (1, Ok("first"), Some("a/O1000.nc"))
        );
        assert_eq!(l.name(0), None);
    }

    #[test]
    fn sinumerik_names_are_found_in_any_case_subprograms_first() {
        let named = |n: &str, main| {
            Some(ProgramKey::Named {
                name: n.into(),
                main,
            })
        };
        assert_eq!(
            ProgramLibrary::key_of("pocket_a.spf"),
            named("POCKET_A", false)
        );
        assert_eq!(ProgramLibrary::key_of("L123.SPF"), named("L123", false));
        assert_eq!(ProgramLibrary::key_of("S40.Mpf"), named("S40", true));
        assert_eq!(ProgramLibrary::key_of("a-b.spf"), None);
        assert_eq!(ProgramLibrary::key_of("O1000.SPF"), named("O1000", false));
        let mut l = ProgramLibrary::default();
        assert!(l.add("PART.MPF", "a/PART.MPF".into(), "main a".into()));
        assert!(l.add("part.spf", "a/part.spf".into(), "sub a".into()));
        assert!(l.add("TOOL.MPF", "a/TOOL.MPF".into(), "main tool".into()));
        assert!(l.add("TOOL.SPF", "b/TOOL.SPF".into(), "sub tool b".into()));
        assert!(!l.add("Part.SPF", "b/Part.SPF".into(), "sub b".into()));
        let text = |name, main| l.find_named(name, main).and_then(|(_, p)| p.text().ok());
        // The folder's subprogram before its main program; the first folder before the next.
        assert_eq!(text("Part", None), Some("sub a"));
        assert_eq!(text("PART", Some(true)), Some("main a"));
        assert_eq!(text("tool", None), Some("main tool"));
        assert_eq!(text("TOOL", Some(false)), Some("sub tool b"));
        assert_eq!(text("NONE", None), None);
        assert_eq!(l.find(1000), None);
    }

    #[test]
    fn a_file_is_read_at_its_first_use_once() {
        use std::sync::atomic::{AtomicU32, Ordering};
        use std::sync::Arc;
        let reads = Arc::new(AtomicU32::new(0));
        let file = |text: Option<&'static str>| -> Arc<ReadText> {
            let counted = reads.clone();
            Arc::new(move || {
                counted.fetch_add(1, Ordering::Relaxed);
                text.map(str::to_string)
                    .ok_or_else(|| "No such file or directory".to_string())
            })
        };
        let mut l = ProgramLibrary::default();
        assert!(l.add_file("O1000.nc", "a/O1000.nc".into(), file(Some("O1000\nM99\n"))));
        assert!(l.add_file("O2000.nc", "a/O2000.nc".into(), file(None)));
        assert_eq!(reads.load(Ordering::Relaxed), 0, "listed, not read");
        let (_, p) = l.find(1000).unwrap();
        assert_eq!(p.text(), Ok("O1000\nM99\n"));
        assert_eq!(p.text(), Ok("O1000\nM99\n"));
        assert_eq!(reads.load(Ordering::Relaxed), 1, "read once");
        let (_, gone) = l.find(2000).unwrap();
        assert_eq!(gone.text(), Err("No such file or directory"));
        assert_eq!(l.text_of("a/O2000.nc"), None);
    }
}
