//! Tool offsets (`config/tools.toml`): per D number, or per T and D where the dialect has
//! tools with several cutting edges. Effective radius and length are geometry + wear.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::Path;

/// Which value of an offset a program writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OffsetValue {
    Length,
    LengthWear,
    Radius,
    RadiusWear,
}

/// One tool offset (one cutting edge).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToolOffset {
    /// Tool number, for dialects with T/D offsets (808D). Absent: a global D offset.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t: Option<u32>,
    pub d: u32,
    /// Geometry radius, mm. Negative radii are legal (840C 11.9): they swap the side.
    pub radius: f64,
    #[serde(default)]
    pub radius_wear: f64,
    /// Geometry length, mm.
    #[serde(default)]
    pub length: f64,
    #[serde(default)]
    pub length_wear: f64,
    /// Cutting edge position 1..=9 of a turning tool (9 = nose centre).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge: Option<u8>,
}

impl ToolOffset {
    /// One of its four values, to write.
    pub fn value_mut(&mut self, which: OffsetValue) -> &mut f64 {
        match which {
            OffsetValue::Length => &mut self.length,
            OffsetValue::LengthWear => &mut self.length_wear,
            OffsetValue::Radius => &mut self.radius,
            OffsetValue::RadiusWear => &mut self.radius_wear,
        }
    }

    /// One of its four values.
    pub fn value(&self, which: OffsetValue) -> f64 {
        match which {
            OffsetValue::Length => self.length,
            OffsetValue::LengthWear => self.length_wear,
            OffsetValue::Radius => self.radius,
            OffsetValue::RadiusWear => self.radius_wear,
        }
    }

    pub fn effective_radius(&self) -> f64 {
        self.radius + self.radius_wear
    }
    pub fn effective_length(&self) -> f64 {
        self.length + self.length_wear
    }
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToolTable {
    #[serde(default)]
    pub offset: Vec<ToolOffset>,
    /// `--set Dn=R` radius overrides (not part of the file).
    #[serde(skip)]
    pub radius_overrides: Vec<(u32, f64)>,
    /// Edits made while the program runs, shared with its preparation (not part of the file).
    #[serde(skip)]
    pub live: Option<LiveEdits>,
}

/// Whether an operator may enter `value` as a geometry radius (or the radius wear, when
/// `wear`): finite and within `limit` mm either side (machine data `hmi.max_radius` or
/// `hmi.max_wear`, [`crate::machine_data::HmiData::offset_limit`]).
pub fn check_edit(wear: bool, value: f64, limit: f64) -> Result<(), String> {
    let what = if wear { "radius wear" } else { "radius" };
    if !value.is_finite() {
        return Err(format!("{what} {value} is not a number"));
    }
    if value.abs() > limit {
        return Err(format!(
            "{what} {value} mm is beyond the limit of ±{limit} mm (machine data hmi.max_{})",
            if wear { "wear" } else { "radius" }
        ));
    }
    Ok(())
}

/// Offset edits an operator makes while a program runs (machine data
/// `hmi.edit_while_active`): the kernel's control thread adds them, the running program's
/// preparation takes each when that D is next programmed (840C 11.8), in a block it has not
/// read yet. One list per program run; clones of the table share it.
#[derive(Clone, Debug, Default)]
pub struct LiveEdits(std::sync::Arc<std::sync::Mutex<Vec<LiveEdit>>>);

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiveEdit {
    /// The tool on a T/D table (`None`: a D number of its own).
    pub t: Option<u32>,
    pub d: u32,
    pub wear: bool,
    pub value: f64,
}

impl PartialEq for LiveEdits {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0)
    }
}

impl LiveEdits {
    pub fn push(&self, e: LiveEdit) {
        if let Ok(mut v) = self.0.lock() {
            v.push(e);
        }
    }

    /// Applies the edits of `o`'s T and D, in the order made; whether there was one.
    fn apply(&self, o: &mut ToolOffset) -> bool {
        let Ok(v) = self.0.lock() else {
            return false;
        };
        let mut any = false;
        for e in v.iter().filter(|e| e.d == o.d && e.t == o.t) {
            if e.wear {
                o.radius_wear = e.value;
            } else {
                o.radius = e.value;
            }
            any = true;
        }
        any
    }
}

/// A table file (tool offsets, work offsets) that does not load: which file, which key, why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ToolTableError {
    pub file: String,
    pub key: String,
    pub reason: String,
}

impl fmt::Display for ToolTableError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.key.is_empty() {
            write!(f, "{}: {}", self.file, self.reason)
        } else {
            write!(f, "{}: key `{}`: {}", self.file, self.key, self.reason)
        }
    }
}

impl std::error::Error for ToolTableError {}

/// Writes `text` to `path` so that a crash at any moment leaves the old file or the new
/// one, never a torn one: a temporary file beside it, synced, renamed over it, and the
/// folder synced.
pub fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    use std::io::Write;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other("the path names no file"))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)?;
        std::fs::File::open(&dir)?.sync_all()
    };
    let r = write();
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r
}

/// Largest |radius| or |length| accepted in a tool table, mm.
pub const MAX_OFFSET_MM: f64 = 10_000.0;

impl ToolTable {
    pub fn load(path: &Path) -> Result<Self, ToolTableError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ToolTableError {
            file: origin.clone(),
            key: String::new(),
            reason: format!("cannot read: {e}"),
        })?;
        Self::from_toml_str(&text, &origin)
    }

    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, ToolTableError> {
        let de = toml::Deserializer::new(text);
        let table: ToolTable =
            serde_path_to_error::deserialize(de).map_err(|e| ToolTableError {
                file: origin.into(),
                key: e.path().to_string(),
                reason: e.inner().message().trim().to_string(),
            })?;
        table.validate().map_err(|(key, reason)| ToolTableError {
            file: origin.into(),
            key,
            reason,
        })?;
        Ok(table)
    }

    fn validate(&self) -> Result<(), (String, String)> {
        for (i, o) in self.offset.iter().enumerate() {
            let key = |k: &str| format!("offset[{i}].{k}");
            if o.d == 0 {
                return Err((
                    key("d"),
                    "D0 means \"no offset\" and cannot be defined".into(),
                ));
            }
            for (name, v) in [
                ("radius", o.radius),
                ("radius_wear", o.radius_wear),
                ("length", o.length),
                ("length_wear", o.length_wear),
            ] {
                if !v.is_finite() || v.abs() > MAX_OFFSET_MM {
                    return Err((
                        key(name),
                        format!("{v} is not a finite value within ±{MAX_OFFSET_MM} mm"),
                    ));
                }
            }
            if let Some(e) = o.edge {
                if !(1..=9).contains(&e) {
                    return Err((
                        key("edge"),
                        format!("cutting edge position {e} is not in 1..=9"),
                    ));
                }
            }
            if self.offset[..i].iter().any(|p| p.t == o.t && p.d == o.d) {
                return Err((key("d"), format!("{} is defined twice", o.label())));
            }
        }
        Ok(())
    }

    /// The offset for D `d` with tool `t` active. With a T/D entry for that tool it is used;
    /// otherwise the global D entry (no `t`).
    pub fn find(&self, t: Option<u32>, d: u32) -> Option<&ToolOffset> {
        if let Some(t) = t {
            if let Some(o) = self.offset.iter().find(|o| o.t == Some(t) && o.d == d) {
                return Some(o);
            }
        }
        self.offset.iter().find(|o| o.t.is_none() && o.d == d)
    }

    /// The entry named exactly: tool `t` (`None`: a D number of its own) and D `d`. An
    /// operator's edit names one entry; it does not fall back as `find` does for a program.
    fn exact_mut(&mut self, t: Option<u32>, d: u32) -> Option<&mut ToolOffset> {
        self.offset.iter_mut().find(|o| o.t == t && o.d == d)
    }

    /// A program's write of one value of offset number `d` (Fanuc G10 L10…L13): the entry
    /// is made if the table has none (the control's offset memory has every number).
    pub fn write_value(&mut self, d: u32, which: OffsetValue, value: f64) {
        if self.exact_mut(None, d).is_none() {
            self.offset.push(ToolOffset {
                t: None,
                d,
                radius: 0.0,
                radius_wear: 0.0,
                length: 0.0,
                length_wear: 0.0,
                edge: None,
            });
        }
        if matches!(which, OffsetValue::Radius | OffsetValue::RadiusWear) {
            self.radius_overrides.retain(|(k, _)| *k != d);
        }
        if let Some(o) = self.exact_mut(None, d) {
            *o.value_mut(which) = value;
        }
    }

    /// `--set` as written on a command line: "Dn=R" (also "dn=R").
    pub fn apply_set(&mut self, arg: &str) -> Result<(), String> {
        let (d, r) = arg
            .split_once('=')
            .and_then(|(k, v)| {
                let d = k.trim().strip_prefix(['D', 'd'])?.parse::<u32>().ok()?;
                Some((d, v.trim().parse::<f64>().ok()?))
            })
            .ok_or_else(|| format!("--set {arg}: expected Dn=RADIUS, e.g. D1=10.0"))?;
        self.set_radius(d, r)
            .map_err(|e| format!("--set {arg}: {e}"))
    }

    /// `--set Dn=R`: offset n gets radius R (wear 0) whatever tool is active; an offset that
    /// is not in the table is created with length 0.
    pub fn set_radius(&mut self, d: u32, radius: f64) -> Result<(), String> {
        if d == 0 {
            return Err("D0 means \"no offset\" and cannot be set".into());
        }
        if !radius.is_finite() || radius.abs() > MAX_OFFSET_MM {
            return Err(format!(
                "radius {radius} is not a finite value within ±{MAX_OFFSET_MM} mm"
            ));
        }
        self.radius_overrides.retain(|(k, _)| *k != d);
        self.radius_overrides.push((d, radius));
        Ok(())
    }

    /// An operator's edit of offset D`d` (tool `t` on T/D machines): the geometry radius,
    /// or the radius wear when `wear`. The offset must exist, the value be finite and within
    /// `limit` mm either side. A `--set` override of that D gives way to the edit.
    pub fn edit(
        &mut self,
        t: Option<u32>,
        d: u32,
        wear: bool,
        value: f64,
        limit: f64,
    ) -> Result<(), String> {
        check_edit(wear, value, limit)?;
        let label = offset_label(t, d);
        let Some(o) = self.exact_mut(t, d) else {
            // On a T/D table a D alone names no entry: say which tools have it.
            let tools: Vec<String> = self
                .offset
                .iter()
                .filter(|o| o.d == d && o.t.is_some())
                .map(|o| o.label())
                .collect();
            return Err(if t.is_none() && !tools.is_empty() {
                format!(
                    "D{d} is numbered per tool in this table: name the tool ({})",
                    tools.join(", ")
                )
            } else {
                format!("{label} is not in the tool table")
            });
        };
        if wear {
            o.radius_wear = value;
        } else {
            o.radius = value;
        }
        self.radius_overrides.retain(|(k, _)| *k != d);
        Ok(())
    }

    /// The table as TOML, as `load` reads it (without `--set` overrides).
    pub fn to_toml(&self) -> Result<String, String> {
        toml::to_string(self).map_err(|e| e.to_string())
    }

    /// Writes the table to `path` atomically ([`write_atomic`]).
    pub fn save_atomic(&self, path: &Path) -> std::io::Result<()> {
        let text = self.to_toml().map_err(std::io::Error::other)?;
        write_atomic(path, &text)
    }

    /// Effective (radius, length, cutting edge) of D `d` with tool `t` active, `--set`
    /// overrides applied.
    pub fn resolve(&self, t: Option<u32>, d: u32) -> Option<(f64, f64, Option<u8>)> {
        let over = self
            .radius_overrides
            .iter()
            .find(|(k, _)| *k == d)
            .map(|(_, r)| *r);
        let mut found = self.find(t, d).cloned();
        let mut over = over;
        if let (Some(l), Some(o)) = (&self.live, found.as_mut()) {
            // An edit made while running outranks a `--set` override of the same D.
            if l.apply(o) {
                over = None;
            }
        }
        match (found.as_ref(), over) {
            (Some(o), Some(r)) => Some((r, o.effective_length(), o.edge)),
            (Some(o), None) => Some((o.effective_radius(), o.effective_length(), o.edge)),
            (None, Some(r)) => Some((r, 0.0, None)),
            (None, None) => None,
        }
    }

    /// The tool table shipped as `config/tools.toml`, used when no `--tools` file is given.
    pub fn builtin() -> Self {
        Self::from_toml_str(BUILTIN_TOOLS, "<built-in tools>")
            .expect("built-in tool table is valid")
    }
}

/// The shipped tool table (config/tools.toml).
pub const BUILTIN_TOOLS: &str = include_str!("../../config/tools.toml");

/// An offset's name as operators and alarms write it: `T1 D2` on a table numbered per tool,
/// `D2` for a D number of its own.
pub fn offset_label(t: Option<u32>, d: u32) -> String {
    match t {
        Some(t) => format!("T{t} D{d}"),
        None => format!("D{d}"),
    }
}

impl ToolOffset {
    pub fn label(&self) -> String {
        offset_label(self.t, self.d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edits_are_checked_and_saved_whole() {
        let mut t = ToolTable::builtin();
        let r0 = t.find(None, 1).unwrap().radius;
        assert!(t
            .edit(None, 1, false, f64::NAN, 500.0)
            .unwrap_err()
            .contains("not a number"));
        assert!(t
            .edit(None, 1, false, 501.0, 500.0)
            .unwrap_err()
            .contains("hmi.max_radius"));
        assert!(t
            .edit(None, 1, true, 1.5, 1.0)
            .unwrap_err()
            .contains("hmi.max_wear"));
        assert!(t
            .edit(None, 99, false, 1.0, 500.0)
            .unwrap_err()
            .contains("D99 is not"));
        assert_eq!(
            t.find(None, 1).unwrap().radius,
            r0,
            "refused edits change nothing"
        );
        t.edit(None, 1, false, 12.0, 500.0).unwrap();
        t.edit(None, 1, true, -0.02, 1.0).unwrap();
        let dir = std::env::temp_dir().join(format!("softnc-tools-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("tools.toml");
        t.save_atomic(&p).unwrap();
        let back = ToolTable::load(&p).unwrap();
        assert_eq!(back.find(None, 1).unwrap().effective_radius(), 12.0 - 0.02);
        assert_eq!(back.offset, t.offset);
        // Nothing but the file itself is left beside it.
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name())
            .collect();
        assert_eq!(names, ["tools.toml"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// On a T/D table (808D) an edit names the tool: it changes that entry only, never a
    /// global D of the same number or another tool's edge.
    #[test]
    fn edits_on_a_table_numbered_per_tool_name_the_tool() {
        let text = "[[offset]]\nd = 2\nradius = 5.0\n\n\
                    [[offset]]\nt = 1\nd = 1\nradius = 0.8\n\n\
                    [[offset]]\nt = 1\nd = 2\nradius = 0.4\n\n\
                    [[offset]]\nt = 2\nd = 1\nradius = 1.2\n";
        let mut t = ToolTable::from_toml_str(text, "test").unwrap();
        t.edit(Some(1), 2, false, 0.5, 500.0).unwrap();
        let radius = |t: &ToolTable, tool: Option<u32>, d| {
            t.offset
                .iter()
                .find(|o| o.t == tool && o.d == d)
                .unwrap()
                .radius
        };
        assert_eq!(radius(&t, Some(1), 2), 0.5);
        assert_eq!((radius(&t, None, 2), radius(&t, Some(1), 1)), (5.0, 0.8));
        // D1 exists only per tool: the answer says which.
        let e = t.edit(None, 1, false, 1.0, 500.0).unwrap_err();
        assert!(e.contains("name the tool (T1 D1, T2 D1)"), "{e}");
        // T2 has no D2: a program's T2 D2 would take the global D2, an edit does not.
        let e = t.edit(Some(2), 2, false, 1.0, 500.0).unwrap_err();
        assert!(e.contains("T2 D2 is not in the tool table"), "{e}");
        assert_eq!(radius(&t, None, 2), 5.0);

        // While running (hmi.edit_while_active): the edit of T2 D1 reaches T2's D1 only.
        let live = LiveEdits::default();
        t.live = Some(live.clone());
        live.push(LiveEdit {
            t: Some(2),
            d: 1,
            wear: true,
            value: -0.1,
        });
        assert_eq!(t.resolve(Some(2), 1).unwrap().0, 1.2 - 0.1);
        assert_eq!(t.resolve(Some(1), 1).unwrap().0, 0.8);
    }

    #[test]
    fn effective_values_add_wear() {
        let t = ToolTable::from_toml_str(
            "[[offset]]\nd = 1\nradius = 10.0\nradius_wear = -0.02\nlength = 50\nlength_wear = 0.5\n",
            "t.toml",
        )
        .unwrap();
        let o = t.find(None, 1).unwrap();
        assert_eq!(o.effective_radius(), 10.0 - 0.02);
        assert_eq!(o.effective_length(), 50.5);
    }

    #[test]
    fn negative_radius_is_legal_and_t_d_lookup_falls_back() {
        let t = ToolTable::from_toml_str(
            "[[offset]]\nd = 1\nradius = -2.5\n[[offset]]\nt = 3\nd = 1\nradius = 0.4\nedge = 3\n",
            "t.toml",
        )
        .unwrap();
        assert_eq!(t.find(None, 1).unwrap().radius, -2.5);
        assert_eq!(t.find(Some(3), 1).unwrap().edge, Some(3));
        assert_eq!(t.find(Some(4), 1).unwrap().radius, -2.5);
    }

    #[test]
    fn set_overrides_radius_of_any_tool() {
        let mut t = ToolTable::builtin();
        t.set_radius(1, 12.0).unwrap();
        assert_eq!(t.resolve(None, 1).unwrap().0, 12.0);
        assert_eq!(t.resolve(Some(1), 1).unwrap().0, 12.0);
        assert_eq!(t.resolve(None, 42), None);
        t.set_radius(42, 3.0).unwrap();
        assert_eq!(t.resolve(None, 42), Some((3.0, 0.0, None)));
        assert!(t.set_radius(1, f64::NAN).is_err());
    }

    #[test]
    fn bad_values_name_the_key() {
        let e = ToolTable::from_toml_str("[[offset]]\nd = 1\nradius = 1\nedge = 12\n", "t.toml")
            .unwrap_err();
        assert_eq!(e.key, "offset[0].edge");
        let e = ToolTable::from_toml_str("[[offset]]\nd = 1\nradius = 1\ncolour = 2\n", "t.toml")
            .unwrap_err();
        assert!(e.reason.contains("unknown field"), "{e}");
        let e =
            ToolTable::from_toml_str("[[offset]]\nd = 1\nradius = 1e9\n", "t.toml").unwrap_err();
        assert_eq!(e.key, "offset[0].radius");
    }
}
