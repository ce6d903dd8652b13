//! The machine's path axes: the geometry axes X Y Z, in which the contour, its arcs and the
//! tool radius compensation live, and up to six additional axes — linear U V W, rotary A B
//! C — that interpolate with them (840D FB1 "axis types"; Fanuc 0i-MF "controlled axes").
//! Each has its own velocity, acceleration, jerk and software limits; a rotary axis counts in
//! degrees and may be a modulo axis (positions shown within 0…360°).

use serde::{Deserialize, Serialize};

/// Every axis letter in the machine's order: the index is the axis number everywhere in
/// softnc (0..3 geometry, 3..9 additional), and configured axes are listed in this order.
pub const AXIS_NAMES: [char; AXES] = ['X', 'Y', 'Z', 'U', 'V', 'W', 'A', 'B', 'C'];
/// Axis letters softnc knows.
pub const AXES: usize = 9;
/// Path axes a machine may have at most (geometry and additional together).
pub const MAX_PATH_AXES: usize = 8;
/// The additional axes (U V W A B C), one slot each.
pub const ADDITIONAL: usize = AXES - 3;
/// One turn of a modulo axis, degrees.
const TURN: f64 = 360.0;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AxisKind {
    #[default]
    Linear,
    /// Degrees; velocity in °/min, acceleration °/s², jerk °/s³.
    Rotary,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisData {
    #[serde(default)]
    pub kind: AxisKind,
    /// Maximum axis velocity (also the rapid traverse rate), mm/min (rotary: °/min).
    pub max_velocity: f64,
    /// Maximum axis acceleration, mm/s² (rotary: °/s²).
    pub max_acceleration: f64,
    /// Maximum axis jerk, mm/s³ (rotary: °/s³).
    pub max_jerk: f64,
    /// Software limit switches `[min, max]` in machine coordinates; none for an endless
    /// rotary axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub software_limits: Option<[f64; 2]>,
    /// Rotary only: a modulo axis. Absolute positions are taken modulo 360° and shown within
    /// 0…360°; the setpoint runs on without a jump (docs/axes.md).
    #[serde(default)]
    pub modulo: bool,
    /// Rotary modulo only: an absolute position is reached the shorter way round (otherwise
    /// in the direction of the programmed value against the shown one, as a linear axis).
    #[serde(default)]
    pub shortest_way: bool,
    /// The reference positions in machine coordinates: the first for G28, the second to
    /// fourth for G30 P2…P4.
    #[serde(default)]
    pub reference_positions: [f64; 4],
}

impl AxisData {
    /// Where an absolute `value` takes the axis standing at `now`: the value itself; on a
    /// modulo axis the value's place within the turn, reached the shorter way round or, by
    /// default, in the direction of the value against the shown position (as a linear axis
    /// within one turn, docs/axes.md).
    pub fn absolute_target(&self, now: f64, value: f64) -> f64 {
        if !self.modulo {
            return value;
        }
        let mut d = value.rem_euclid(TURN) - now.rem_euclid(TURN);
        if self.shortest_way {
            // Half a turn either way: positive.
            if d > TURN / 2.0 {
                d -= TURN;
            } else if d <= -TURN / 2.0 {
                d += TURN;
            }
        }
        now + d
    }

    /// Whether `p` (machine coordinates) lies within the software limits.
    pub fn within_limits(&self, p: f64) -> bool {
        self.software_limits
            .is_none_or(|[lo, hi]| p >= lo - 1e-9 && p <= hi + 1e-9)
    }
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axes {
    #[serde(rename = "X", skip_serializing_if = "Option::is_none", default)]
    pub x: Option<AxisData>,
    #[serde(rename = "Y", skip_serializing_if = "Option::is_none", default)]
    pub y: Option<AxisData>,
    #[serde(rename = "Z", skip_serializing_if = "Option::is_none", default)]
    pub z: Option<AxisData>,
    #[serde(rename = "U", skip_serializing_if = "Option::is_none", default)]
    pub u: Option<AxisData>,
    #[serde(rename = "V", skip_serializing_if = "Option::is_none", default)]
    pub v: Option<AxisData>,
    #[serde(rename = "W", skip_serializing_if = "Option::is_none", default)]
    pub w: Option<AxisData>,
    #[serde(rename = "A", skip_serializing_if = "Option::is_none", default)]
    pub a: Option<AxisData>,
    #[serde(rename = "B", skip_serializing_if = "Option::is_none", default)]
    pub b: Option<AxisData>,
    #[serde(rename = "C", skip_serializing_if = "Option::is_none", default)]
    pub c: Option<AxisData>,
}

impl Axes {
    /// Axis `axis` (an index into [`AXIS_NAMES`]), if configured.
    pub fn get(&self, axis: usize) -> Option<&AxisData> {
        [
            &self.x, &self.y, &self.z, &self.u, &self.v, &self.w, &self.a, &self.b, &self.c,
        ]
        .get(axis)
        .and_then(|a| a.as_ref())
    }

    /// The configured axes in the machine's order: (axis number, data).
    pub fn configured(&self) -> impl Iterator<Item = (usize, &AxisData)> + '_ {
        (0..AXES).filter_map(|i| self.get(i).map(|a| (i, a)))
    }

    /// The axis of an address letter (upper case), if the machine has it.
    pub fn of_letter(&self, letter: u8) -> Option<usize> {
        let i = AXIS_NAMES.iter().position(|&c| c as u8 == letter)?;
        self.get(i).map(|_| i)
    }

    /// Each axis within its ranges, at most [`MAX_PATH_AXES`], the geometry axes linear:
    /// the first problem as (key, reason).
    pub fn validate(&self) -> Result<(), (String, String)> {
        let mut count = 0;
        for (i, a) in self.configured() {
            count += 1;
            validate_axis(AXIS_NAMES[i], i, a)?;
        }
        if count == 0 {
            return Err(("axes".into(), "at least one axis must be configured".into()));
        }
        if count > MAX_PATH_AXES {
            return Err((
                "axes".into(),
                format!("{count} axes: a machine has at most {MAX_PATH_AXES} path axes"),
            ));
        }
        Ok(())
    }
}

fn validate_axis(name: char, i: usize, a: &AxisData) -> Result<(), (String, String)> {
    let key = |k: &str| format!("axes.{name}.{k}");
    super::range(&key("max_velocity"), a.max_velocity, 1.0, 1e6)?;
    super::range(&key("max_acceleration"), a.max_acceleration, 1.0, 1e5)?;
    super::range(&key("max_jerk"), a.max_jerk, 1.0, 1e8)?;
    for r in a.reference_positions {
        super::range(&key("reference_positions"), r, -1e9, 1e9)?;
    }
    let rotary = a.kind == AxisKind::Rotary;
    if rotary && i < 3 {
        return Err((
            key("kind"),
            format!("{name} is a geometry axis and must be linear"),
        ));
    }
    if (a.modulo || a.shortest_way) && !rotary {
        return Err((
            key(if a.modulo { "modulo" } else { "shortest_way" }),
            "only a rotary axis can be a modulo axis".into(),
        ));
    }
    if a.shortest_way && !a.modulo {
        return Err((
            key("shortest_way"),
            "the shorter way round needs a modulo axis (modulo = true)".into(),
        ));
    }
    if let Some([lo, hi]) = a.software_limits {
        super::range(&key("software_limits"), lo, -1e9, 1e9)?;
        super::range(&key("software_limits"), hi, -1e9, 1e9)?;
        if lo >= hi {
            return Err((
                key("software_limits"),
                format!("[{lo}, {hi}]: the minimum must lie below the maximum"),
            ));
        }
        if a.modulo {
            return Err((
                key("software_limits"),
                "a modulo axis turns endlessly and has no software limits".into(),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::MachineData;

    #[test]
    fn five_axes_with_rotary_ones() {
        let md = MachineData::from_toml_str(
            "dialect = \"fanuc\"\n[axes.X]\nmax_velocity = 1e4\nmax_acceleration = 1e3\nmax_jerk = 1e4\n\
             [axes.Y]\nmax_velocity = 1e4\nmax_acceleration = 1e3\nmax_jerk = 1e4\n\
             [axes.Z]\nmax_velocity = 1e4\nmax_acceleration = 1e3\nmax_jerk = 1e4\n\
             software_limits = [-500.0, 100.0]\n\
             [axes.C]\nkind = \"rotary\"\nmodulo = true\nshortest_way = true\n\
             max_velocity = 3600\nmax_acceleration = 100\nmax_jerk = 1e4\n\
             [axes.A]\nkind = \"rotary\"\nsoftware_limits = [-120.0, 30.0]\n\
             max_velocity = 3600\nmax_acceleration = 100\nmax_jerk = 1e4\n",
            "5ax.toml",
        )
        .unwrap();
        let order: Vec<usize> = md.axes.configured().map(|(i, _)| i).collect();
        assert_eq!(order, [0, 1, 2, 6, 8]);
        assert_eq!(md.axes.of_letter(b'C'), Some(8));
        assert_eq!(md.axes.of_letter(b'B'), None);
        let a = md.axes.get(6).unwrap();
        assert!(a.within_limits(30.0) && !a.within_limits(30.001));
        assert!(md.axes.get(8).unwrap().within_limits(1e5));
    }

    #[test]
    fn bad_axes_are_refused_with_their_key() {
        let base = "[axes.X]\nmax_velocity = 1e4\nmax_acceleration = 1e3\nmax_jerk = 1e4\n\
                    [axes.Y]\nmax_velocity = 1e4\nmax_acceleration = 1e3\nmax_jerk = 1e4\n";
        let ax = |name: &str, extra: &str| {
            format!(
                "[axes.{name}]\nmax_velocity = 1e4\nmax_acceleration = 1e3\nmax_jerk = 1e4\n{extra}"
            )
        };
        for (extra, key) in [
            (ax("Z", "kind = \"rotary\"\n"), "axes.Z.kind"),
            (ax("U", "modulo = true\n"), "axes.U.modulo"),
            (
                ax("A", "kind = \"rotary\"\nshortest_way = true\n"),
                "axes.A.shortest_way",
            ),
            (
                ax("W", "software_limits = [5.0, 1.0]\n"),
                "axes.W.software_limits",
            ),
            (
                ax(
                    "C",
                    "kind = \"rotary\"\nmodulo = true\nsoftware_limits = [0.0, 1.0]\n",
                ),
                "axes.C.software_limits",
            ),
        ] {
            let e = MachineData::from_toml_str(&format!("{base}{extra}"), "m.toml").unwrap_err();
            assert_eq!(e.key, key, "{e}");
        }
        let mut nine = base.to_string();
        for n in ["Z", "U", "V", "W", "A", "B", "C"] {
            nine += &ax(n, "");
        }
        let e = MachineData::from_toml_str(&nine, "m.toml").unwrap_err();
        assert!(e.reason.contains("at most 8"), "{e}");
        let e =
            MachineData::from_toml_str(&format!("{base}{}", ax("Q", "")), "m.toml").unwrap_err();
        assert!(e.key.starts_with("axes"), "{e}");
    }
}
