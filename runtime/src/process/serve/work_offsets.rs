//! Work-offset edits from the HMI (docs/work-offsets.md): the same rules as tool offsets
//! (840C 11.8) — taken at once in reset, at the end and in NC stop (NC start then prepares
//! the rest again and repositions), refused while the program runs unless machine data
//! allows it (then from the next program start); checked, saved atomically, versioned.

use super::{bump, unsaved, Desk};
use nc_kernel::{MachineData, AXIS_NAMES};
use softnc_protocol::{state, Command, KernelStatus, Reply, WorkOffsetEntry, WorkOffsetsMsg};

impl Desk<'_> {
    /// The machine data a program is loaded or resumed with: the work offsets in force now.
    pub(super) fn program_md(&self) -> MachineData {
        let mut md = self.md.clone();
        md.work_offsets = self.work.clone();
        md.kept_variables = self.kept.values.clone();
        md
    }

    pub(super) fn set_work_offset(&mut self, c: &Command, last: &KernelStatus) -> Reply {
        let name = c.text();
        let running = last.state == state::ACTIVE;
        if running && !self.md.hmi.edit_while_active {
            return Reply::new(
                false,
                0,
                &format!(
                    "the program is running: work offset {name} can be changed in NC stop or reset only (840C 11.8); nothing changed"
                ),
            );
        }
        let wire = crate::WireAxes::new(self.md);
        let mut values = Vec::new();
        for (slot, v) in c.axis_values() {
            match wire.axis_of_slot(slot) {
                Some(axis) => values.push((axis, v)),
                None => {
                    return Reply::new(
                        false,
                        0,
                        &format!("{name}: axis slot {slot} is not configured; nothing changed"),
                    )
                }
            }
        }
        let before = self.work.clone();
        let limit = self.md.hmi.max_work_offset;
        if let Err(e) = self.work.edit(self.md, name, &values, limit) {
            return Reply::new(false, 0, &format!("{e}; nothing changed"));
        }
        let saved = self
            .work_path
            .as_ref()
            .map(|path| (path, self.work.save_atomic(path, self.md)));
        if let Some(refusal) = unsaved(saved) {
            self.work = before;
            return refusal;
        }
        let version = bump(&self.shared.work_offsets_version);
        if let Some(w) = &mut self.record {
            w.line(&crate::record::Line::WorkEdit {
                name: name.to_string(),
                values: values
                    .iter()
                    .map(|&(a, v)| (a, crate::record::F(v)))
                    .collect(),
            });
        }
        let when = if running {
            "acts from the next program start; the running program keeps the offsets it was loaded with"
        } else if last.state == state::STOPPED && last.program != 0 {
            self.changed_in_stop = true;
            "acts at NC start: the rest of the program is prepared again and the axes reposition onto it"
        } else {
            "acts at the next NC start (a loaded program is prepared again with it) or program load"
        };
        let saved = if self.work_path.is_some() {
            "saved"
        } else {
            "not saved: no work-offset file"
        };
        let what: Vec<String> = values
            .iter()
            .map(|(a, v)| format!("{}{v}", AXIS_NAMES[*a]))
            .collect();
        Reply::new(
            true,
            0,
            &format!(
                "{name} {}; work offsets version {version} ({saved}); {when}",
                what.join(" ")
            ),
        )
    }

    /// The table as HMIs get it: every set of the dialect, in its order.
    pub(super) fn work_offsets_msg(&self, version: u32) -> WorkOffsetsMsg {
        let wire = crate::WireAxes::new(self.md);
        let d = nc_kernel::dialect_of(self.md);
        let mut m = WorkOffsetsMsg {
            version,
            saved: self.work_path.is_some() as u8,
            axes: wire.list,
            ..Default::default()
        };
        let n = usize::from(d.work_offset_count()).min(softnc_protocol::WORK_OFFSET_ENTRIES);
        m.count = n as u32;
        for (i, e) in m.entries.iter_mut().enumerate().take(n) {
            let index = i as u8 + 1;
            let name = d.work_offset_name(index).unwrap_or_default();
            *e = WorkOffsetEntry::new(&name, wire.to_wire_all(self.work.get(index)));
        }
        m
    }
}
