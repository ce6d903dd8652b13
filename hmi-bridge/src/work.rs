//! Work offsets (G54 …) on the HTTP side: the kernel's table as JSON, and an operator's
//! edit checked against it before it goes to the kernel, so a wrong request is answered
//! 422 with its reason (the kernel checks again and has the last word).

use nc_kernel::work_offset_key;
use serde::de::{Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use serde_json::{json, Map, Value};
use softnc_protocol::{AxisList, WorkOffsetsMsg, MAX_AXES};
use std::fmt;

/// `{"set": "G54", "values": {"X": 10.5, "Z": -3}}`: the set by name, a new value per axis
/// letter (either case), mm or degrees.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkOffsetEdit {
    pub set: String,
    pub values: AxisValues,
}

/// The axis values in the order given, repeats kept: a JSON map would keep one of
/// `{"X": 1, "X": 2}` silently, and `"x"` and `"X"` are the same axis here.
#[derive(Debug, Default)]
pub struct AxisValues(pub Vec<(String, f64)>);

impl<'de> Deserialize<'de> for AxisValues {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Pairs;
        impl<'de> Visitor<'de> for Pairs {
            type Value = AxisValues;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an object of axis values like {\"X\": 10.5}")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut m: A) -> Result<AxisValues, A::Error> {
                let mut v = Vec::new();
                while let Some(pair) = m.next_entry::<String, f64>()? {
                    v.push(pair);
                }
                Ok(AxisValues(v))
            }
        }
        d.deserialize_map(Pairs)
    }
}

/// The set's name as the kernel writes it, if the table has it.
fn find_set<'a>(m: &'a WorkOffsetsMsg, name: &str) -> Option<&'a str> {
    let want = work_offset_key(name);
    m.entries()
        .iter()
        .map(|e| e.name())
        .find(|n| work_offset_key(n) == want)
}

/// A name from the request as a message quotes it: at most 24 characters (the body may
/// hold 16 KiB of them).
fn quoted(s: &str) -> String {
    let mut q: String = s.chars().take(24).collect();
    if q.len() < s.len() {
        q.push('…');
    }
    format!("{q:?}")
}

/// The axes' names as text, for messages: "X, Y, Z".
fn axis_names(axes: &AxisList) -> String {
    axes.names()
        .map(String::from)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Where axis `letter` (one letter, either case) is in the table's values.
fn slot(axes: &AxisList, letter: &str) -> Option<usize> {
    let mut chars = letter.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) => axes.index(c.to_ascii_uppercase()),
        _ => None,
    }
}

/// An edit checked against the kernel's table and the operator's limit (machine data
/// `hmi.max_work_offset`): the set's name as the kernel writes it and (slot, value) per
/// axis; otherwise why not. Nothing is sent for a refused edit.
pub fn check(
    m: &WorkOffsetsMsg,
    limit: f64,
    edit: &WorkOffsetEdit,
) -> Result<(String, Vec<(usize, f64)>), String> {
    let name = find_set(m, &edit.set).ok_or_else(|| unknown_set(m, &edit.set))?;
    if edit.values.0.is_empty() {
        return Err(format!(
            "{name}: no axis value given: send e.g. {{\"values\": {{\"X\": 10.5}}}}"
        ));
    }
    let mut out: Vec<(usize, f64)> = Vec::with_capacity(edit.values.0.len());
    for (letter, v) in &edit.values.0 {
        let i = slot(&m.axes, letter).ok_or_else(|| {
            format!(
                "{name}: {} is not an axis of this machine: its axes are {}",
                quoted(letter),
                axis_names(&m.axes)
            )
        })?;
        let axis = letter.to_ascii_uppercase();
        if out.iter().any(|(j, _)| *j == i) {
            return Err(format!("{name}: axis {axis} is given twice"));
        }
        if !v.is_finite() || v.abs() > limit {
            return Err(format!(
                "{name} {axis}: {v} is beyond the limit of ±{limit} (machine data hmi.max_work_offset)"
            ));
        }
        out.push((i, *v));
    }
    Ok((name.to_string(), out))
}

#[cold]
fn unknown_set(m: &WorkOffsetsMsg, name: &str) -> String {
    let e = m.entries();
    match (e.first(), e.last()) {
        (Some(a), Some(b)) => format!(
            "{} is not a work offset of this control: its sets are {} … {}",
            quoted(name),
            a.name(),
            b.name()
        ),
        _ => format!(
            "{} is not a work offset of this control: it has none",
            quoted(name)
        ),
    }
}

/// The active set's name (`index` 1-based into the table, 0: none).
pub fn active_name(m: Option<&WorkOffsetsMsg>, index: u32) -> Option<String> {
    let i = usize::try_from(index).ok()?.checked_sub(1)?;
    m?.entries().get(i).map(|e| e.name().to_string())
}

/// The table as `GET /api/work-offsets` gives it: the axes in the machine's order, every
/// set with a value per axis by letter, the active set's name.
pub fn table_json(m: &WorkOffsetsMsg, active: u32) -> Value {
    let names: Vec<String> = m.axes.names().map(String::from).collect();
    let n = names.len().min(MAX_AXES);
    let sets: Vec<Value> = m
        .entries()
        .iter()
        .map(|e| {
            let values: Map<String, Value> = names
                .iter()
                .zip(&e.values[..n])
                .map(|(a, v)| (a.clone(), json!(v)))
                .collect();
            json!({ "name": e.name(), "values": values })
        })
        .collect();
    json!({
        "version": m.version,
        "saved": m.saved != 0,
        "axes": names,
        "sets": sets,
        "active": active_name(Some(m), active),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use softnc_protocol::WorkOffsetEntry;

    /// A Fanuc-like table on X, Y, Z: G54 … G59 and G54.1 P1 … P48.
    fn fanuc() -> WorkOffsetsMsg {
        let mut m = WorkOffsetsMsg {
            version: 3,
            saved: 1,
            ..Default::default()
        };
        m.axes.names[..3].copy_from_slice(b"XYZ");
        m.axes.count = 3;
        let mut names: Vec<String> = (54..=59).map(|g| format!("G{g}")).collect();
        names.extend((1..=48).map(|p| format!("G54.1 P{p}")));
        for (e, n) in m.entries.iter_mut().zip(&names) {
            *e = WorkOffsetEntry::new(n, [0.0; MAX_AXES]);
        }
        m.entries[1].values[..3].copy_from_slice(&[10.0, -2.5, 0.0]);
        m.count = names.len() as u32;
        m
    }

    fn edit(text: &str) -> Result<WorkOffsetEdit, serde_json::Error> {
        serde_json::from_str(text)
    }

    fn checked(text: &str) -> Result<(String, Vec<(usize, f64)>), String> {
        check(&fanuc(), 1000.0, &edit(text).expect(text))
    }

    #[test]
    fn names_ignore_case_and_spaces_and_letters_their_case() {
        assert_eq!(
            checked(r#"{"set": "g54.1p3", "values": {"z": -3, "X": 10.5}}"#),
            Ok(("G54.1 P3".to_string(), vec![(2, -3.0), (0, 10.5)]))
        );
        assert_eq!(
            checked(r#"{"set": " G55 ", "values": {"Y": 1000}}"#),
            Ok(("G55".to_string(), vec![(1, 1000.0)]))
        );
    }

    #[test]
    fn wrong_edits_say_why() {
        let cases = [
            (r#"{"set": "G60", "values": {"X": 1}}"#, "G54 … G54.1 P48"),
            (
                r#"{"set": "G54.1 P49", "values": {"X": 1}}"#,
                "not a work offset",
            ),
            (r#"{"set": "G54", "values": {}}"#, "no axis value"),
            (
                r#"{"set": "G54", "values": {"A": 1}}"#,
                "its axes are X, Y, Z",
            ),
            (
                r#"{"set": "G54", "values": {"XY": 1}}"#,
                "\"XY\" is not an axis",
            ),
            (r#"{"set": "G54", "values": {"": 1}}"#, "is not an axis"),
            (
                r#"{"set": "G54", "values": {"x": 1, "X": 2}}"#,
                "X is given twice",
            ),
            (
                r#"{"set": "G54", "values": {"X": 1000.001}}"#,
                "hmi.max_work_offset",
            ),
            (r#"{"set": "G54", "values": {"Z": -1e300}}"#, "±1000"),
        ];
        let long = format!(r#"{{"set": "{}", "values": {{"X": 1}}}}"#, "G".repeat(5000));
        let e = checked(&long).expect_err("a long name");
        assert!(e.len() < 200 && e.contains("GGG…\""), "{e}");
        for (text, want) in cases {
            let e = checked(text).expect_err(text);
            assert!(e.contains(want), "{text}: {e}");
        }
        // Not finite: JSON has no NaN, but a caller inside the bridge could build one.
        let nan = WorkOffsetEdit {
            set: "G54".into(),
            values: AxisValues(vec![("X".into(), f64::NAN)]),
        };
        assert!(check(&fanuc(), 1000.0, &nan).is_err());
    }

    #[test]
    fn malformed_edits_do_not_parse() {
        for text in [
            r#"{"set": "G54"}"#,
            r#"{"values": {"X": 1}}"#,
            r#"{"set": "G54", "values": {"X": "1"}}"#,
            r#"{"set": "G54", "values": {"X": null}}"#,
            r#"{"set": "G54", "values": [1, 2]}"#,
            r#"{"set": 54, "values": {"X": 1}}"#,
            r#"{"set": "G54", "values": {"X": 1}, "force": true}"#,
            r#"{"set": "G54", "set": "G55", "values": {"X": 1}}"#,
            r#"{"set": "G54", "values": {"X": 1e999}}"#,
        ] {
            assert!(edit(text).is_err(), "{text}");
        }
    }

    #[test]
    fn the_table_names_its_sets_axes_and_the_active_one() {
        let j = table_json(&fanuc(), 2);
        assert_eq!(j["version"], json!(3));
        assert_eq!(j["saved"], json!(true));
        assert_eq!(j["axes"], json!(["X", "Y", "Z"]));
        assert_eq!(j["sets"].as_array().map(Vec::len), Some(54));
        assert_eq!(
            j["sets"][1],
            json!({ "name": "G55", "values": { "X": 10.0, "Y": -2.5, "Z": 0.0 } })
        );
        assert_eq!(j["sets"][53]["name"], json!("G54.1 P48"));
        assert_eq!(j["active"], json!("G55"));
        assert_eq!(table_json(&fanuc(), 0)["active"], Value::Null);
        assert_eq!(active_name(Some(&fanuc()), 55), None);
        assert_eq!(active_name(None, 1), None);
    }
}
