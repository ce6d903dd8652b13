//! The kept macro variables (Fanuc #500 … #999): common to every program and kept between
//! runs, in a file of their own (`--macro-variables FILE`, docs/fanuc.md). The file is TOML,
//! one number per variable: `500 = 12.5`. The core reads and writes the text; the runtime
//! reads the file when it loads a program and writes it when a live run's program ends.

use crate::tools::ToolTableError;

/// The kept variables' numbers.
pub const KEPT: std::ops::RangeInclusive<u32> = 500..=999;

/// The variables of a file's text, `(number, value)` in number order; a key that is no kept
/// variable or a value that is no finite number is an error naming it.
pub fn parse_kept_variables(text: &str, origin: &str) -> Result<Vec<(u32, f64)>, ToolTableError> {
    let err = |key: String, reason: String| ToolTableError {
        file: origin.into(),
        key,
        reason,
    };
    let doc: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| err(String::new(), e.message().trim().to_string()))?;
    let mut out = Vec::new();
    for (key, value) in &doc {
        let n = key
            .parse::<u32>()
            .ok()
            .filter(|n| KEPT.contains(n))
            .ok_or_else(|| err(key.clone(), "not a kept variable number 500 … 999".into()))?;
        let v = match value {
            toml::Value::Float(f) => *f,
            toml::Value::Integer(i) => *i as f64,
            _ => return Err(err(key.clone(), "not a number".into())),
        };
        if !v.is_finite() {
            return Err(err(key.clone(), "not a finite number".into()));
        }
        out.push((n, v));
    }
    out.sort_by_key(|&(n, _)| n);
    Ok(out)
}

/// The file's text for `values` (number order, full precision).
pub fn format_kept_variables(values: &[(u32, f64)]) -> String {
    let mut out = String::from("# Kept macro variables #500 … #999 (docs/fanuc.md).\n");
    for (n, v) in values {
        out.push_str(&format!("{n} = {v:?}\n"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_file_round_trips_and_refuses_what_is_no_kept_variable() {
        let v = vec![(500, 1.5), (731, -2.0), (999, 1e-7)];
        assert_eq!(
            parse_kept_variables(&format_kept_variables(&v), "k").unwrap(),
            v
        );
        assert_eq!(parse_kept_variables("600 = 3", "k").unwrap(), [(600, 3.0)]);
        let e = parse_kept_variables("100 = 1.0", "k.toml").unwrap_err();
        assert_eq!((e.file.as_str(), e.key.as_str()), ("k.toml", "100"));
        assert!(parse_kept_variables("500 = \"x\"", "k").is_err());
    }
}
