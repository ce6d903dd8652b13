//! Work offsets (settable zero offsets: Fanuc G54…G59 and G54.1 P1…P48, Siemens G54…G57
//! or G54…G59, ISG G54…G59): the sets the dialect has, each a value per axis, kept in a
//! file beside the tool table (docs/work-offsets.md). An absolute position is the program's
//! value plus the active set's value for that axis.

use crate::dialect::Dialect;
use crate::machine_data::{MachineData, AXES, AXIS_NAMES};
use crate::tools::write_atomic;
use std::path::Path;

/// Largest |value| a work-offset file may hold, mm or degrees.
pub const MAX_WORK_OFFSET: f64 = 1e6;

/// The table: set 0 is "none" and always zero; sets 1.. are the dialect's, in its order.
/// Sets past the end read as zero (the built-in table is empty).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WorkOffsets {
    sets: Vec<[f64; AXES]>,
}

/// A work-offset file that does not load: which file, which key, why (the tool table's
/// error: the two files fail alike).
pub type WorkOffsetError = crate::tools::ToolTableError;

const ZERO: [f64; AXES] = [0.0; AXES];

impl WorkOffsets {
    /// The value of set `index` for every axis ([`AXIS_NAMES`] order).
    #[inline]
    pub fn get(&self, index: u8) -> &[f64; AXES] {
        self.sets.get(index as usize).unwrap_or(&ZERO)
    }

    pub fn load(path: &Path, md: &MachineData) -> Result<Self, WorkOffsetError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| WorkOffsetError {
            file: origin.clone(),
            key: String::new(),
            reason: format!("cannot read: {e}"),
        })?;
        Self::from_toml_str(&text, &origin, md)
    }

    /// A table from its TOML text: one table per set, named as the program selects it, with
    /// a value per axis letter (`[G54]` `X = 10.0`). Sets and axes not written are zero.
    pub fn from_toml_str(
        text: &str,
        origin: &str,
        md: &MachineData,
    ) -> Result<Self, WorkOffsetError> {
        let err = |key: String, reason: String| WorkOffsetError {
            file: origin.into(),
            key,
            reason,
        };
        let doc: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| err(String::new(), e.message().trim().to_string()))?;
        let d = Dialect::get(md.dialect);
        let mut table = WorkOffsets::zeroed(d);
        for (name, set) in &doc {
            let index = d
                .work_offset_index(name)
                .ok_or_else(|| err(name.clone(), unknown_set(d, name)))?;
            let toml::Value::Table(values) = set else {
                return Err(err(
                    name.clone(),
                    "expected a table of axis values (X = 0.0)".into(),
                ));
            };
            for (letter, v) in values {
                let key = format!("{name}.{letter}");
                let axis = axis_of(md, letter).map_err(|r| err(key.clone(), r))?;
                let v = match v {
                    toml::Value::Float(f) => *f,
                    toml::Value::Integer(i) => *i as f64,
                    _ => return Err(err(key, "expected a number".into())),
                };
                check_value(v, MAX_WORK_OFFSET).map_err(|r| err(key, r))?;
                table.sets[index as usize][axis] = v;
            }
        }
        Ok(table)
    }

    /// Every set of the dialect, all zero.
    pub fn zeroed(d: &Dialect) -> Self {
        WorkOffsets {
            sets: vec![ZERO; d.work_offset_count() as usize + 1],
        }
    }

    /// The table as its file holds it: the sets with a value, in the dialect's order.
    pub fn to_toml(&self, md: &MachineData) -> String {
        let d = Dialect::get(md.dialect);
        let mut out = String::from(
            "# Work offsets (docs/work-offsets.md): one table per set, a value per axis in mm\n\
             # (degrees for a rotary axis). Sets and axes not written are zero.\n",
        );
        for (i, set) in self.sets.iter().enumerate().skip(1) {
            let Some(name) = d.work_offset_name(i as u8) else {
                continue;
            };
            if set.iter().all(|v| *v == 0.0) {
                continue;
            }
            out.push_str(&format!("\n[{}]\n", toml_key(&name)));
            for (a, v) in set.iter().enumerate().filter(|(a, _)| md.has_axis(*a)) {
                out.push_str(&format!("{} = {v:?}\n", AXIS_NAMES[a]));
            }
        }
        out
    }

    /// Writes the table to `path` atomically (a crash leaves the old file or the new one).
    pub fn save_atomic(&self, path: &Path, md: &MachineData) -> std::io::Result<()> {
        write_atomic(path, &self.to_toml(md))
    }

    /// Writes one value (a program's G10); sets past the end are made.
    pub fn set(&mut self, index: u8, axis: usize, value: f64) {
        if self.sets.len() <= index as usize {
            self.sets.resize(index as usize + 1, ZERO);
        }
        if let Some(v) = self.sets[index as usize].get_mut(axis) {
            *v = value;
        }
    }

    /// An operator's edit of set `name`: each (axis, value), all checked before any is
    /// taken; a refusal changes nothing and says why.
    pub fn edit(
        &mut self,
        md: &MachineData,
        name: &str,
        values: &[(usize, f64)],
        limit: f64,
    ) -> Result<u8, String> {
        let d = Dialect::get(md.dialect);
        let index = d
            .work_offset_index(name)
            .ok_or_else(|| unknown_set(d, name))?;
        if values.is_empty() {
            return Err(format!("{name}: no axis value given"));
        }
        for &(axis, v) in values {
            if axis >= AXES || !md.has_axis(axis) {
                return Err(format!(
                    "{name}: axis number {axis} is not configured on this machine"
                ));
            }
            check_value(v, limit).map_err(|r| {
                format!(
                    "{name} {}: {r} (machine data hmi.max_work_offset)",
                    AXIS_NAMES[axis]
                )
            })?;
        }
        if self.sets.len() <= index as usize {
            self.sets.resize(index as usize + 1, ZERO);
        }
        for &(axis, v) in values {
            self.sets[index as usize][axis] = v;
        }
        Ok(index)
    }
}

/// The axis number of `letter`, if the machine has that axis.
fn axis_of(md: &MachineData, letter: &str) -> Result<usize, String> {
    let mut chars = letter.chars();
    match (chars.next().map(|c| c.to_ascii_uppercase()), chars.next()) {
        (Some(c), None) => AXIS_NAMES
            .iter()
            .position(|&n| n == c)
            .filter(|&a| md.has_axis(a))
            .ok_or_else(|| format!("axis {c} is not configured on this machine")),
        _ => Err(format!("{letter:?} is not an axis letter")),
    }
}

fn check_value(v: f64, limit: f64) -> Result<(), String> {
    if !v.is_finite() {
        Err(format!("{v} is not a number"))
    } else if v.abs() > limit {
        Err(format!("{v} is beyond the limit of ±{limit}"))
    } else {
        Ok(())
    }
}

#[cold]
fn unknown_set(d: &Dialect, name: &str) -> String {
    let n = d.work_offset_count();
    let first = d.work_offset_name(1).unwrap_or_default();
    let last = d.work_offset_name(n).unwrap_or_default();
    format!(
        "{name} is not a work offset of the {} dialect: its sets are {first} … {last}",
        d.name.as_str()
    )
}

/// A set's name as a TOML key: bare where it can be, quoted where it has a space.
fn toml_key(name: &str) -> String {
    if name
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        name.to_string()
    } else {
        format!("\"{name}\"")
    }
}
