//! The programs a part program can call besides those in its own file: the subprogram files
//! of the program's folder and of the machine data's search path (`program.search_path`).
//! The runtime reads the files (the core reads none) and hands them in with the machine
//! data, as it does the work offsets.
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

/// One program file: what names it, how alarms name it (its path) and its text.
#[derive(Clone, Debug, PartialEq)]
pub struct LibraryProgram {
    pub key: ProgramKey,
    pub name: String,
    pub text: String,
}

impl LibraryProgram {
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

    /// Adds a file; a number, or a name of the same kind, that is there already keeps its
    /// first file. False if the file names no program or its program was there.
    pub fn add(&mut self, file_name: &str, name: String, text: String) -> bool {
        let Some(key) = Self::key_of(file_name) else {
            return false;
        };
        if self.programs.iter().any(|p| p.key == key) {
            return false;
        }
        self.programs.push(LibraryProgram { key, name, text });
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
            .map(|p| p.text.as_str())
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
            (k, p.text.as_str(), l.name(k)),
            (1, "first", Some("a/O1000.nc"))
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
        let text = |name, main| l.find_named(name, main).map(|(_, p)| p.text.as_str());
        // The folder's subprogram before its main program; the first folder before the next.
        assert_eq!(text("Part", None), Some("sub a"));
        assert_eq!(text("PART", Some(true)), Some("main a"));
        assert_eq!(text("tool", None), Some("main tool"));
        assert_eq!(text("TOOL", Some(false)), Some("sub tool b"));
        assert_eq!(text("NONE", None), None);
        assert_eq!(l.find(1000), None);
    }
}
