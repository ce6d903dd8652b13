//! Machine data: everything a machine builder sets once per machine (serde + TOML).
//!
//! A machine data file is read over the built-in defaults (an 840C milling machine), so a file
//! names only what differs; `--md KEY=VALUE` overrides one value afterwards. Unknown keys and
//! out-of-range values are rejected with the file, the key and the reason. Every key is
//! documented in docs/machine-data.md.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::Path;

mod axes;
pub use axes::{Axes, AxisData, AxisKind, ADDITIONAL, AXES, AXIS_NAMES, MAX_PATH_AXES};

/// The built-in machine data: a three-axis SINUMERIK 840C milling machine. The shipped
/// `config/siemens-840c.toml` holds the same values (a test keeps them equal).
pub const BUILTIN_DEFAULTS: &str = include_str!("../../../config/siemens-840c.toml");

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DialectName {
    #[serde(rename = "siemens-840c")]
    Siemens840C,
    Isg,
    Fanuc,
    #[serde(rename = "siemens-808d")]
    Siemens808D,
    #[serde(rename = "fanuc-lathe")]
    FanucLathe,
    #[serde(rename = "siemens-840d")]
    Siemens840D,
}

impl DialectName {
    pub fn as_str(self) -> &'static str {
        match self {
            DialectName::Siemens840C => "siemens-840c",
            DialectName::Isg => "isg",
            DialectName::Fanuc => "fanuc",
            DialectName::Siemens808D => "siemens-808d",
            DialectName::FanucLathe => "fanuc-lathe",
            DialectName::Siemens840D => "siemens-840d",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MachineKind {
    Milling,
    Turning,
}

/// Where a lathe's tool works: behind the centre of rotation (X up in the operator's view,
/// the 840C's "clockwise coordinate system") or in front of it (X mirrored about Z). The
/// program, the offsets and the setpoints are the same either way (rotation symmetry, 840C
/// ch. 11); the view, and with it how G41/G42 look to the operator, is mirrored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ToolPost {
    Behind,
    InFront,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Units {
    Mm,
    Inch,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlaneName {
    Xy,
    Zx,
    Yz,
}

/// How a number without a decimal point is read where the dialect leaves it to the machine
/// (Fanuc): as a count of least input increments (`X100` = 0.1 mm), or as is (`X100` = 100 mm,
/// "pocket calculator" input).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DecimalInput {
    Increment,
    Calculator,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CornerModeSetting {
    TransitionCircle,
    Intersection,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ViolationReaction {
    /// Alarm 3021 and stop before the violating block.
    Stop,
    /// Alarm 3021 as a warning; the path continues (and may gouge).
    Warn,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AuxOutput {
    BeforeMotion,
    DuringMotion,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProgramData {
    pub units: Units,
    pub initial_plane: PlaneName,
    /// X programmed as a diameter (lathes; 808D DIAMON as the switch-on state).
    pub diameter_programming: bool,
    pub decimal_input: DecimalInput,
    /// Least input increment in mm (metric programs, decimal_input = increment).
    pub least_input_increment_mm: f64,
    /// Least input increment in inch (inch programs, decimal_input = increment).
    pub least_input_increment_inch: f64,
    /// Start and end radius of a circle may differ by this much (mm).
    pub arc_endpoint_tolerance: f64,
    /// The operator's "skip block" switch: blocks starting with `/` are left out when on.
    pub block_skip: bool,
    /// The optional-stop switch (M01 stops only when on).
    pub optional_stop: bool,
    /// Iterations one program loop may run before alarm 12650 (endless loops are an error).
    pub max_loop_iterations: u32,
    /// SINUMERIK R parameters R0 … R(n − 1) (840C R0 … R1299; 840D MD28050 MM_NUM_R_PARAM).
    #[serde(default = "default_r_parameters")]
    pub r_parameters: u32,
    /// Canned cycles: the high-speed peck cycle's retraction after each peck, mm (Fanuc
    /// G73 d, parameter 5114).
    #[serde(default = "default_peck")]
    pub peck_retract: f64,
    /// Canned cycles: the peck cycle's clearance above the last depth when it goes down
    /// again, mm (Fanuc G83 d, parameter 5115).
    #[serde(default = "default_peck")]
    pub peck_clearance: f64,
    /// Canned cycles: the direction the fine-boring and back-boring cycles shift the tool
    /// away from the wall after orienting the spindle (Fanuc G76/G87, parameter RD1/RD2).
    #[serde(default)]
    pub boring_shift: BoringShift,
    /// Folders searched for subprogram files (`O1000.nc`, `NAME.SPF`) after the program's
    /// own folder, in order (Fanuc M98/G65 P, SINUMERIK calls; kernel/src/programs.rs).
    /// Relative paths count from the working directory.
    #[serde(default)]
    pub search_path: Vec<String>,
}

/// The fine-boring shift direction, as seen in the G17 plane (in G18/G19 the same roles:
/// X is the plane's first axis, Y its second).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum BoringShift {
    #[default]
    #[serde(rename = "+X")]
    PlusX,
    #[serde(rename = "-X")]
    MinusX,
    #[serde(rename = "+Y")]
    PlusY,
    #[serde(rename = "-Y")]
    MinusY,
}

fn default_r_parameters() -> u32 {
    100
}

fn default_peck() -> f64 {
    1.0
}

fn default_feed_rmin() -> f64 {
    1.0
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrcData {
    /// Corner mode at program start (840C 11.1: G450/G451 initial setting).
    pub corner_mode: CornerModeSetting,
    /// Reaction to alarm 3021 (840C 11.12).
    pub violation_reaction: ViolationReaction,
    /// Distance |AC| below which intermediate blocks at obtuse circle transitions are
    /// suppressed (840C 11.14), mm.
    pub suppression_distance: f64,
    /// Blocks that may stand outside the compensation plane between two plane blocks
    /// (840C 11.11: 3; 1 for software 1 and 2).
    pub max_blocks_outside_plane: u32,
    /// Blocks over which the tool-centre path is checked for crossing itself (bottleneck
    /// detection beyond 11.12; 840D CDON, TNC M120); 0 = off (ISG: P-CHAN-00219 default).
    pub bottleneck_window: u32,
    /// Every tool-centre segment of a compensation run checked against every programmed
    /// element of the run before the path gets there (prep/whole.rs): `softnc check`, and a
    /// checker that runs ahead of the path in the kernel and `softnc simulate`.
    pub whole_program_check: bool,
    /// A program is checked this far (blocks) before its load is answered: a violation
    /// within it refuses the load; beyond it the check runs ahead of the path.
    pub check_at_load_blocks: u32,
    /// ISG G11 feed adaption: arcs below this contour radius keep the programmed feed, and
    /// transition blocks at corners take it as their contour radius (TF5200 #TANGFEED RMIN).
    #[serde(default = "default_feed_rmin")]
    pub feed_adaption_rmin: f64,
    /// Auxiliary functions output before or during the axis motion (840C 11.10).
    pub aux_output: AuxOutput,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IpoData {
    /// Interpolation cycle in microseconds.
    pub cycle_us: u32,
    /// Segments the planner looks ahead (1 ..= 128).
    pub lookahead: u32,
    /// Auxiliary functions the path waits at until the PLC acknowledges them, e.g. "M6"
    /// (tool change), "M3" (spindle at speed): they act as exact stops.
    pub wait_for_ack: Vec<String>,
}

impl IpoData {
    /// `wait_for_ack` as (address letter in upper case, value): "M6" is (b'M', 6.0).
    pub fn ack_words(&self) -> impl Iterator<Item = (u8, f64)> + '_ {
        self.wait_for_ack.iter().filter_map(|w| {
            let a = w.as_bytes().first()?.to_ascii_uppercase();
            Some((a, w.get(1..)?.parse::<f64>().ok()?))
        })
    }

    /// Whether `word` (address letter, value) is one the path waits for.
    pub fn waits_for(&self, address: u8, value: f64) -> bool {
        let address = address.to_ascii_uppercase();
        self.ack_words().any(|w| w == (address, value))
    }
}

/// The PLC and the drives (plc-sim's axis models) and the supervision between kernel and PLC.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlcData {
    /// IPO cycles without the peer's sign of life before its watchdog acts: the kernel
    /// stops the path (alarm 2000), plc-sim brakes the axes (PLC alarm 700000).
    pub watchdog_cycles: u32,
    /// Position-loop gain kv, 1/s (16.67/s is the 840D's kv = 1 (m/min)/mm).
    pub kv: f64,
    /// Cycles between a setpoint's arrival and the position loop acting on it.
    pub dead_time_cycles: u32,
    /// How long a tool change (M6) takes, ms.
    pub tool_change_ms: u32,
    /// Spindle acceleration, rpm/s: M3/M4 are acknowledged at speed.
    pub spindle_acceleration: f64,
}

/// The operator's side: the HMI bridge and what offset edits it may make (840C 11.8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HmiData {
    /// TCP port of hmi-bridge on 127.0.0.1.
    pub port: u16,
    /// Largest geometry radius an operator may enter, mm (either sign).
    pub max_radius: f64,
    /// Largest wear value an operator may enter, mm (either sign).
    pub max_wear: f64,
    /// Offset edits while the program runs: false refuses them (840C 11.8: immediately
    /// effective only in NC stop); true stores them: a tool offset acts when that D is next
    /// programmed, a work offset from the next program start (docs/work-offsets.md).
    pub edit_while_active: bool,
    /// Largest work-offset value an operator may enter, mm or degrees (either sign).
    pub max_work_offset: f64,
}

impl HmiData {
    /// The largest value an operator may enter for the radius wear (`wear`) or the geometry
    /// radius.
    pub fn offset_limit(&self, wear: bool) -> f64 {
        if wear {
            self.max_wear
        } else {
            self.max_radius
        }
    }
}

/// The main spindle (docs/spindle.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpindleData {
    /// Highest speed, rev/min: every speed setpoint is limited to it (under constant
    /// surface speed too, with the program's limit below it).
    pub max_speed: f64,
}

/// `softnc simulate`, which no operator watches: where a run that would not end is ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulateData {
    /// Machine time after which the path brakes and the run stops with alarm 90001, s.
    pub max_machine_time: f64,
    /// Machine time the path may stand still with nothing happening (no motion, no output,
    /// no state change) before the run stops with alarm 90002, s.
    pub max_rest_time: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MachineData {
    pub dialect: DialectName,
    pub machine: MachineKind,
    pub tool_post: ToolPost,
    pub program: ProgramData,
    pub trc: TrcData,
    pub ipo: IpoData,
    pub plc: PlcData,
    pub hmi: HmiData,
    pub simulate: SimulateData,
    pub spindle: SpindleData,
    pub axes: Axes,
    /// The work offsets in force (setting data, not machine data: from the work-offset file
    /// or all zero, docs/work-offsets.md).
    #[serde(skip)]
    pub work_offsets: crate::work_offsets::WorkOffsets,
    /// The subprogram files a program can call (read by the runtime from the program's
    /// folder and `program.search_path`; kernel/src/programs.rs).
    #[serde(skip)]
    pub programs: std::sync::Arc<crate::programs::ProgramLibrary>,
    /// The kept macro variables (#500 … #999) a run starts with (setting data: from the
    /// `--macro-variables` file, kernel/src/macro_variables.rs).
    #[serde(skip)]
    pub kept_variables: std::sync::Arc<Vec<(u32, f64)>>,
}

/// A machine data problem: which file, which key, why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MachineDataError {
    pub file: String,
    pub key: String,
    pub reason: String,
}

impl fmt::Display for MachineDataError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.key.is_empty() {
            write!(f, "{}: {}", self.file, self.reason)
        } else {
            write!(f, "{}: key `{}`: {}", self.file, self.key, self.reason)
        }
    }
}

impl std::error::Error for MachineDataError {}

impl Default for MachineData {
    fn default() -> Self {
        // The built-in text is checked by a unit test; failing here would be a build defect.
        Self::from_value(builtin_value(), "<built-in>").expect("built-in machine data is valid")
    }
}

fn builtin_value() -> toml::Value {
    toml::from_str(BUILTIN_DEFAULTS).expect("built-in machine data is valid TOML")
}

impl MachineData {
    /// Built-in defaults, then `file` (if any), then each `KEY=VALUE` override.
    pub fn load(file: Option<&Path>, overrides: &[String]) -> Result<Self, MachineDataError> {
        let mut value = builtin_value();
        let mut origin = "<built-in>".to_string();
        if let Some(path) = file {
            origin = path.display().to_string();
            let text = std::fs::read_to_string(path).map_err(|e| MachineDataError {
                file: origin.clone(),
                key: String::new(),
                reason: format!("cannot read: {e}"),
            })?;
            let layer: toml::Value = toml::from_str(&text).map_err(|e| MachineDataError {
                file: origin.clone(),
                key: String::new(),
                reason: format!("not valid TOML: {}", e.message()),
            })?;
            merge(&mut value, layer);
        }
        for ov in overrides {
            apply_override(&mut value, ov).map_err(|(key, reason)| MachineDataError {
                file: "--md".into(),
                key,
                reason,
            })?;
        }
        let origin = if overrides.is_empty() {
            origin
        } else {
            format!("{origin} with --md")
        };
        Self::from_value(value, &origin)
    }

    /// Parses machine data from TOML text laid over the built-in defaults.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, MachineDataError> {
        let mut value = builtin_value();
        let layer: toml::Value = toml::from_str(text).map_err(|e| MachineDataError {
            file: origin.into(),
            key: String::new(),
            reason: format!("not valid TOML: {}", e.message()),
        })?;
        merge(&mut value, layer);
        Self::from_value(value, origin)
    }

    fn from_value(value: toml::Value, origin: &str) -> Result<Self, MachineDataError> {
        let md: MachineData =
            serde_path_to_error::deserialize(value).map_err(|e| MachineDataError {
                file: origin.into(),
                key: e.path().to_string(),
                reason: e.inner().message().to_string(),
            })?;
        md.validate().map_err(|(key, reason)| MachineDataError {
            file: origin.into(),
            key,
            reason,
        })?;
        Ok(md)
    }

    /// Every value within its range, section by section (docs/machine-data.md): the first
    /// one that is not, as (key, reason).
    fn validate(&self) -> Result<(), (String, String)> {
        self.validate_hmi()?;
        self.validate_program()?;
        self.validate_trc()?;
        whole("ipo.cycle_us", self.ipo.cycle_us, 125, 100_000)?;
        self.validate_plc()?;
        let sim = &self.simulate;
        range(
            "simulate.max_machine_time",
            sim.max_machine_time,
            0.001,
            1e7,
        )?;
        range("simulate.max_rest_time", sim.max_rest_time, 0.001, 1e6)?;
        range("spindle.max_speed", self.spindle.max_speed, 1.0, 1e6)?;
        self.validate_ipo()?;
        self.validate_axes()
    }

    fn validate_hmi(&self) -> Result<(), (String, String)> {
        for (key, v) in [
            ("hmi.max_radius", self.hmi.max_radius),
            ("hmi.max_wear", self.hmi.max_wear),
            ("hmi.max_work_offset", self.hmi.max_work_offset),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= crate::tools::MAX_OFFSET_MM) {
                return Err((
                    key.into(),
                    format!(
                        "{v}: expected above 0 and at most {} mm",
                        crate::tools::MAX_OFFSET_MM
                    ),
                ));
            }
        }
        if self.hmi.port == 0 {
            return Err(("hmi.port".into(), "0: expected a TCP port (1–65535)".into()));
        }
        Ok(())
    }

    fn validate_program(&self) -> Result<(), (String, String)> {
        let p = &self.program;
        range(
            "program.least_input_increment_mm",
            p.least_input_increment_mm,
            1e-6,
            1.0,
        )?;
        range(
            "program.least_input_increment_inch",
            p.least_input_increment_inch,
            1e-7,
            0.1,
        )?;
        range(
            "program.arc_endpoint_tolerance",
            p.arc_endpoint_tolerance,
            0.0,
            1.0,
        )?;
        range("program.peck_retract", p.peck_retract, 0.0, 100.0)?;
        range("program.peck_clearance", p.peck_clearance, 0.0, 100.0)?;
        if p.max_loop_iterations == 0 {
            return Err((
                "program.max_loop_iterations".into(),
                "must be at least 1".into(),
            ));
        }
        whole("program.r_parameters", p.r_parameters, 0, 100_000)
    }

    fn validate_trc(&self) -> Result<(), (String, String)> {
        let t = &self.trc;
        range("trc.suppression_distance", t.suppression_distance, 0.0, 1.0)?;
        whole(
            "trc.max_blocks_outside_plane",
            t.max_blocks_outside_plane,
            1,
            8,
        )?;
        range("trc.feed_adaption_rmin", t.feed_adaption_rmin, 0.0, 1000.0)?;
        whole(
            "trc.bottleneck_window",
            t.bottleneck_window,
            0,
            crate::prep::MAX_WINDOW as u32,
        )
    }

    fn validate_plc(&self) -> Result<(), (String, String)> {
        let plc = &self.plc;
        whole("plc.watchdog_cycles", plc.watchdog_cycles, 2, 10_000)?;
        // The discrete position loop x += T·kv·(s − x) needs kv·T well below 1.
        let kv_max = 0.5e6 / f64::from(self.ipo.cycle_us);
        range("plc.kv", plc.kv, 0.1, kv_max)?;
        whole("plc.dead_time_cycles", plc.dead_time_cycles, 0, 100)?;
        whole("plc.tool_change_ms", plc.tool_change_ms, 0, 600_000)?;
        range(
            "plc.spindle_acceleration",
            plc.spindle_acceleration,
            1.0,
            1e6,
        )?;
        Ok(())
    }

    fn validate_ipo(&self) -> Result<(), (String, String)> {
        whole("ipo.lookahead", self.ipo.lookahead, 1, 128)?;
        for w in &self.ipo.wait_for_ack {
            let b = w.as_bytes();
            if b.len() < 2
                || !matches!(b[0].to_ascii_uppercase(), b'M' | b'H' | b'S' | b'T')
                || w[1..].parse::<f64>().map_or(true, |x| !x.is_finite())
            {
                return Err((
                    "ipo.wait_for_ack".into(),
                    format!(
                        "{w:?} is not an auxiliary function: an address M, H, S or T and a number"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The axes (axes.rs), and the initial plane's two axes.
    fn validate_axes(&self) -> Result<(), (String, String)> {
        self.axes.validate()?;
        let dialect = crate::dialect::Dialect::get(self.dialect);
        for (i, _) in self.axes.configured() {
            let letter = AXIS_NAMES[i];
            if dialect.address_taken(letter as u8) {
                return Err((
                    format!("axes.{letter}"),
                    format!(
                        "the {} dialect uses the address {letter} for another word",
                        self.dialect.as_str()
                    ),
                ));
            }
        }
        let plane_axes = match self.program.initial_plane {
            PlaneName::Xy => [0, 1],
            PlaneName::Zx => [2, 0],
            PlaneName::Yz => [1, 2],
        };
        for a in plane_axes {
            if self.axes.get(a).is_none() {
                return Err((
                    "program.initial_plane".into(),
                    format!(
                        "the plane needs axis {}, which is not configured",
                        ["X", "Y", "Z"][a]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Whether axis `axis` (an index into [`AXIS_NAMES`]) exists on this machine.
    pub fn has_axis(&self, axis: usize) -> bool {
        self.axes.get(axis).is_some()
    }
}

/// `v` within `lo ..= hi`, or (key, reason).
fn range(key: &str, v: f64, lo: f64, hi: f64) -> Result<(), (String, String)> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err((
            key.into(),
            format!("{v} is outside the allowed range {lo} ..= {hi}"),
        ))
    }
}

/// A whole number `v` within `lo ..= hi`, or (key, reason).
fn whole(key: &str, v: u32, lo: u32, hi: u32) -> Result<(), (String, String)> {
    if (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err((
            key.into(),
            format!("{v} is outside the allowed range {lo} ..= {hi}"),
        ))
    }
}

/// Lays `layer` over `base`. Tables merge key by key, except `axes`, which a file replaces
/// whole (a lathe file lists X and Z and must not inherit the milling machine's Y).
fn merge(base: &mut toml::Value, layer: toml::Value) {
    match (base, layer) {
        (toml::Value::Table(b), toml::Value::Table(l)) => {
            for (k, v) in l {
                match b.get_mut(&k) {
                    Some(existing) if k != "axes" => merge(existing, v),
                    _ => {
                        b.insert(k, v);
                    }
                }
            }
        }
        (b, l) => *b = l,
    }
}

/// `KEY=VALUE` with a dotted key (`trc.max_blocks_outside_plane=1`, `axes.X.max_jerk=1e5`).
/// The value is read as TOML (number, boolean, array) or else taken as a string.
fn apply_override(value: &mut toml::Value, text: &str) -> Result<(), (String, String)> {
    let (key, raw) = text
        .split_once('=')
        .ok_or_else(|| (text.to_string(), "expected KEY=VALUE".to_string()))?;
    let key = key.trim();
    let raw = raw.trim();
    if key.is_empty() {
        return Err((key.into(), "empty key".into()));
    }
    let parsed: toml::Value = toml::from_str::<toml::Table>(&format!("v = {raw}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(raw.to_string()));
    let mut cur = value;
    let parts: Vec<&str> = key.split('.').collect();
    for (i, part) in parts.iter().enumerate() {
        let table = cur
            .as_table_mut()
            .ok_or_else(|| (key.to_string(), format!("`{part}` is not inside a table")))?;
        if i + 1 == parts.len() {
            table.insert(part.to_string(), parsed);
            return Ok(());
        }
        cur = table
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_defaults_are_valid() {
        let md = MachineData::default();
        assert_eq!(md.dialect, DialectName::Siemens840C);
        assert_eq!(md.trc.max_blocks_outside_plane, 3);
        assert!(md.trc.suppression_distance <= 0.01);
    }

    #[test]
    fn ipo_keys_are_checked() {
        let md = MachineData::default();
        assert_eq!(md.ipo.lookahead, 64);
        assert!(md.ipo.waits_for(b'M', 6.0) && md.ipo.waits_for(b'M', 3.0));
        assert!(!md.ipo.waits_for(b'M', 5.0) && !md.ipo.waits_for(b'H', 6.0));
        let e = MachineData::load(None, &["ipo.lookahead=0".into()]).unwrap_err();
        assert_eq!(e.key, "ipo.lookahead");
        let e = MachineData::load(None, &["ipo.wait_for_ack=[\"X6\"]".into()]).unwrap_err();
        assert_eq!(e.key, "ipo.wait_for_ack");
        assert!(e.reason.contains("\"X6\""), "{}", e.reason);
        let md = MachineData::load(None, &["ipo.wait_for_ack=[\"M8\", \"H2\"]".into()]).unwrap();
        assert!(md.ipo.waits_for(b'H', 2.0) && !md.ipo.waits_for(b'M', 6.0));
    }

    #[test]
    fn unknown_key_names_file_and_key() {
        let e = MachineData::from_toml_str("[trc]\nfoo = 1\n", "m.toml").unwrap_err();
        assert_eq!(e.file, "m.toml");
        assert!(e.key.starts_with("trc"), "{e}");
        assert!(e.reason.contains("unknown field"), "{e}");
    }

    #[test]
    fn out_of_range_value_rejected() {
        let e = MachineData::from_toml_str("[trc]\nmax_blocks_outside_plane = 0\n", "m.toml")
            .unwrap_err();
        assert_eq!(e.key, "trc.max_blocks_outside_plane");
        let e = MachineData::load(None, &["program.arc_endpoint_tolerance=-1".into()]).unwrap_err();
        assert_eq!(e.key, "program.arc_endpoint_tolerance");
    }

    #[test]
    fn override_sets_value_and_dialect() {
        let md = MachineData::load(
            None,
            &[
                "dialect=isg".into(),
                "trc.max_blocks_outside_plane=1".into(),
            ],
        )
        .unwrap();
        assert_eq!(md.dialect, DialectName::Isg);
        assert_eq!(md.trc.max_blocks_outside_plane, 1);
        let e = MachineData::load(None, &["dialect=heidenhain".into()]).unwrap_err();
        assert_eq!(e.key, "dialect");
    }
}
