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

/// A program file's text (the main program's, or a called one's): part programs are ASCII;
/// anything else is kept and reported where the lexer meets it, and a valid file is taken as
/// it is (no copy of a multi-megabyte program).
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
    for path in entries {
        let Some(file) = path.file_name().and_then(|f| f.to_str()) else {
            continue;
        };
        let small = path
            .metadata()
            .is_ok_and(|m| m.is_file() && m.len() <= MAX_FILE);
        if !small || ProgramLibrary::key_of(file).is_none() || same_file(&path, program) {
            continue;
        }
        let (file, name) = (file.to_string(), path.display().to_string());
        let read: Arc<ReadText> = Arc::new(move || read_text(&path));
        library.add_file(&file, name, read);
    }
    Ok(())
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
