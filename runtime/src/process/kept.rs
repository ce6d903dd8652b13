//! The file of kept macro variables (#500 … #999, docs/fanuc.md): read when the kernel
//! starts, written atomically when a program's preparation has ended.

use std::path::Path;

/// The variables in the file; a missing file is none (it is made at the first save).
pub fn load(path: &Path) -> Result<Vec<(u32, f64)>, String> {
    match std::fs::read_to_string(path) {
        Ok(text) => nc_kernel::parse_kept_variables(&text, &path.display().to_string())
            .map_err(|e| e.to_string()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
        Err(e) => Err(format!("{}: cannot read: {e}", path.display())),
    }
}

/// Writes the variables (all of them, replacing the file).
pub fn save(path: &Path, values: &[(u32, f64)]) -> Result<(), String> {
    nc_kernel::write_atomic(path, &nc_kernel::format_kept_variables(values)).map_err(|e| {
        format!(
            "{}: cannot save the kept macro variables: {e}",
            path.display()
        )
    })
}
