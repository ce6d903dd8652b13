//! The programs a part program can call by number besides those in its own file (Fanuc
//! M98/G65/G66 P): the subprogram files of the program's folder and of the machine data's
//! search path (`program.search_path`). The runtime reads the files (the core reads none)
//! and hands them in with the machine data, as it does the work offsets.
//!
//! A file is a subprogram when its name without extension is an O number: `O1000`,
//! `O1000.nc`, `o1000.NC` are program 1000. The program's own folder comes first, then the
//! search path in its order; the first file of a number wins.

/// One subprogram file: its number, how alarms name it (its path) and its text.
#[derive(Clone, Debug, PartialEq)]
pub struct LibraryProgram {
    pub number: u32,
    pub name: String,
    pub text: String,
}

/// The subprogram files, in search order.
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

    /// Adds a file; a number that is there already keeps its first file. False if the
    /// name is no program number or the number was there.
    pub fn add(&mut self, file_name: &str, name: String, text: String) -> bool {
        let Some(number) = Self::number_of(file_name) else {
            return false;
        };
        if self.find(number).is_some() {
            return false;
        }
        self.programs.push(LibraryProgram { number, name, text });
        true
    }

    /// Program `number` and its index (1 …; 0 is the main program's file).
    pub fn find(&self, number: u32) -> Option<(u16, &LibraryProgram)> {
        let k = self.programs.iter().position(|p| p.number == number)?;
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
}
