//! Workpiece coordinates: where the program's zero lies. It is the work offset set in
//! force — from the table, or from the program's own copy once it writes the table (Fanuc
//! G10) — plus the program's shifts: Fanuc G92 (coordinate system setting: the position
//! now gets the values written) and G52 (local coordinate system, added to every set).
//! Both shifts start at zero with the program.

use super::interpreter::Interpreter;
use crate::machine_data::AXES;
use crate::tools::ToolTable;
use crate::work_offsets::WorkOffsets;

/// The program's changes to the zero and to the tables it reads.
#[derive(Clone, Debug, Default)]
pub struct Coordinates {
    /// The work offset table once the program wrote it.
    table: Option<Box<WorkOffsets>>,
    /// The tool offsets once the program wrote them.
    tools: Option<Box<ToolTable>>,
    /// G92 and G52, per axis (mm, degrees).
    pub g92: [f64; AXES],
    pub g52: [f64; AXES],
    /// Mirror, scaling and rotation (frame.rs).
    pub frame: super::frame::Frame,
    /// Fanuc G16: polar coordinates in force, with the radius and angle written last (in
    /// program units and degrees; a word left out keeps its value).
    pub polar: Option<(f64, f64)>,
}

impl Interpreter<'_> {
    /// The zero of set `set` in machine coordinates: the table's value and the shifts.
    #[inline(always)]
    pub(super) fn zero(&self, set: u8) -> [f64; AXES] {
        let t = self.work_offset_table().get(set);
        let c = &self.coords;
        std::array::from_fn(|i| t[i] + c.g92[i] + c.g52[i])
    }

    /// The work offset table the program reads.
    #[inline(always)]
    pub(super) fn work_offset_table(&self) -> &WorkOffsets {
        self.coords
            .table
            .as_deref()
            .unwrap_or(&self.md.work_offsets)
    }

    /// The work offset table, to write (copied from the machine's at the first write).
    pub(super) fn work_offset_table_mut(&mut self) -> &mut WorkOffsets {
        let md = self.md;
        self.coords
            .table
            .get_or_insert_with(|| Box::new(md.work_offsets.clone()))
    }

    /// The tool offsets the program reads.
    #[inline(always)]
    pub(super) fn tool_table(&self) -> &ToolTable {
        self.coords.tools.as_deref().unwrap_or(self.tools)
    }

    /// The tool offsets, to write.
    pub(super) fn tool_table_mut(&mut self) -> &mut ToolTable {
        let tools = self.tools;
        self.coords
            .tools
            .get_or_insert_with(|| Box::new(tools.clone()))
    }
}
