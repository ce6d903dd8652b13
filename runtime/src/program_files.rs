//! The subprogram files a program can call (kernel/src/programs.rs): listed from the
//! program's own folder, then from each folder of `program.search_path`: Fanuc O-number files
//! and SINUMERIK `.SPF`/`.MPF` files. A file is read when the program first calls it.

use nc_kernel::{ProgramLibrary, ReadText};
use std::path::Path;
use std::sync::Arc;

/// Largest subprogram file read (a part program larger than this is no subprogram).
const MAX_FILE: u64 = 64 << 20;

/// The library for the program at `program`. A search-path folder that cannot be read is
/// an error naming it; files that name no program (`O1000.nc`, `POCKET.SPF`) are passed over.
pub fn program_library(program: &Path, search_path: &[String]) -> Result<ProgramLibrary, String> {
    let mut library = ProgramLibrary::default();
    let own = program.parent().filter(|p| !p.as_os_str().is_empty());
    add_folder(&mut library, own.unwrap_or(Path::new(".")), program)
        .map_err(|e| format!("{}: {e}", program.display()))?;
    for folder in search_path {
        add_folder(&mut library, Path::new(folder), program)
            .map_err(|e| format!("program.search_path {folder}: {e}"))?;
    }
    Ok(library)
}

/// A program file's text (the main program's, or a called one's), read the same way wherever
/// softnc reads a part program (`softnc check`, the control's processes, replay, the HMI), so
/// that what the check passes the control loads: part programs are ASCII; a byte that is not
/// UTF-8 (an old editor's Latin-1 `Ø` in a comment) becomes U+FFFD, harmless in a comment and
/// reported with its line and column where the lexer meets it in a word; a valid file is taken
/// as it is (no copy of a multi-megabyte program).
pub fn read_program(path: &Path) -> std::io::Result<String> {
    let file = std::fs::File::open(path)?;
    let len = file.metadata()?.len();
    let bytes = crate::os::read_file(&file, len)?;
    Ok(String::from_utf8(bytes)
        .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned()))
}

/// A subprogram file's text, at its first call.
fn read_text(path: &Path) -> Result<String, String> {
    let len = std::fs::metadata(path).map_err(|e| e.to_string())?.len();
    if len > MAX_FILE {
        return Err(format!(
            "{len} bytes, more than a subprogram file may have ({MAX_FILE})"
        ));
    }
    read_program(path).map_err(|e| e.to_string())
}

fn add_folder(library: &mut ProgramLibrary, folder: &Path, program: &Path) -> std::io::Result<()> {
    let mut entries: Vec<_> = std::fs::read_dir(folder)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    // A fixed order, so that the first file of a number is always the same one.
    entries.sort();
    // The names first: a folder may hold many other files, each a system call to look at.
    let program = program.canonicalize().ok();
    for path in entries {
        let Some(file) = path.file_name().and_then(|f| f.to_str()) else {
            continue;
        };
        if ProgramLibrary::key_of(file).is_none() {
            continue;
        }
        let small = path
            .metadata()
            .is_ok_and(|m| m.is_file() && m.len() <= MAX_FILE);
        if !small || (program.is_some() && path.canonicalize().ok() == program) {
            continue;
        }
        let (file, name) = (file.to_string(), path.display().to_string());
        let read: Arc<ReadText> = Arc::new(move || read_text(&path));
        library.add_file(&file, name, read);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The folder's files that name a program are listed, the main program itself (however
    /// its path is written) and files that name none are not.
    #[test]
    fn a_folder_lists_its_programs_but_the_main_one() {
        let dir = std::env::temp_dir().join(format!("softnc-library-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, text) in [
            ("O0001.nc", "G0 X1\nM30\n"),
            ("O0002.nc", "G0 X2\nM99\n"),
            ("notes.txt", "not a program\n"),
        ] {
            std::fs::write(dir.join(name), text).unwrap();
        }
        let main = dir.join(".").join("O0001.nc");
        let library = program_library(&main, &[]).unwrap();
        let listed = library.len();
        let (two, one) = (library.find(2).is_some(), library.find(1).is_some());
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(listed, 1);
        assert!(two && !one);
    }
}
