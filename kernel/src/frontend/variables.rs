//! The variable store: the program's own variables and the system variables the front end
//! binds to its state — the ISG ones (TF5200 "variables": V.P., V.L., V.S. and the V.G. tool
//! values). Each language's variables are a namespace of this store.

use super::fault::{fault, R};
use crate::alarm::AlarmCode;
use std::collections::HashMap;

/// Program variables (V.P., V.L., V.S.) and the system variables the front end binds.
#[derive(Clone, Debug, Default)]
pub struct Variables {
    values: HashMap<String, f64>,
    /// V.G.WZ_AKT.R: the active tool radius.
    pub tool_radius: f64,
    /// V.G.WZ_AKT.L: the active tool length.
    pub tool_length: f64,
}

/// What a write changed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Written {
    Program,
    ToolRadius,
}

const TOOL_RADIUS: &str = "V.G.WZ_AKT.R";
const TOOL_RADIUS_SHORT: &str = "V.G.WZR";
const TOOL_LENGTH: &str = "V.G.WZ_AKT.L";

impl Variables {
    pub fn get(&self, name: &str) -> Option<f64> {
        match name {
            TOOL_RADIUS | TOOL_RADIUS_SHORT => Some(self.tool_radius),
            TOOL_LENGTH => Some(self.tool_length),
            _ => self.values.get(name).copied(),
        }
    }

    /// Writes a variable; `at` is where the program names it (for the alarm). V.P./V.L./V.S.
    /// are created on first write (TF5200 allows this for V.P./V.S.; softnc extends it to
    /// V.L.); of the V.G. variables only the tool radius is writable.
    pub fn set(&mut self, name: &str, value: f64, at: usize) -> R<Written> {
        match name {
            TOOL_RADIUS | TOOL_RADIUS_SHORT => {
                self.tool_radius = value;
                Ok(Written::ToolRadius)
            }
            _ if is_program_var(name) => {
                self.values.insert(name.to_string(), value);
                Ok(Written::Program)
            }
            _ if name.starts_with("V.G.") => Err(fault(
                AlarmCode::UndefinedName,
                at,
                format!("system variable {name} is read-only or unknown"),
            )),
            _ => Err(fault(
                AlarmCode::UndefinedName,
                at,
                format!("{name} is not a variable name (V.P., V.L., V.S. or V.G.)"),
            )),
        }
    }
}

fn is_program_var(name: &str) -> bool {
    ["V.P.", "V.L.", "V.S."]
        .iter()
        .any(|p| name.len() > p.len() && name.starts_with(p))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_variables_are_created_on_write_and_system_ones_are_bound() {
        let mut v = Variables::default();
        assert_eq!(v.get("V.P.A"), None);
        assert_eq!(v.set("V.P.A", 2.5, 0).unwrap(), Written::Program);
        assert_eq!(v.get("V.P.A"), Some(2.5));
        // The short and the long name of the tool radius are one variable.
        assert_eq!(v.set("V.G.WZR", 4.0, 0).unwrap(), Written::ToolRadius);
        assert_eq!(v.get("V.G.WZ_AKT.R"), Some(4.0));
        v.tool_length = 100.0;
        assert_eq!(v.get("V.G.WZ_AKT.L"), Some(100.0));
    }

    #[test]
    fn read_only_and_unknown_names_point_at_the_name() {
        let mut v = Variables::default();
        let f = v.set("V.G.WZ_AKT.L", 1.0, 7).unwrap_err();
        assert_eq!((f.code, f.at), (AlarmCode::UndefinedName, 7));
        // A prefix alone names no variable.
        let f = v.set("V.P.", 1.0, 3).unwrap_err();
        assert_eq!((f.code, f.at), (AlarmCode::UndefinedName, 3));
    }
}
