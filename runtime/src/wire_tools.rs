//! The tool table on the wire (protocol's `ToolTableMsg`): what the kernel publishes of its
//! table, and the table a reader (the HMI's plot and edit checks) makes of it again. Both
//! directions live here so that every field, the cutting edge position included, goes
//! across and comes back the same.

use nc_kernel::{ToolOffset, ToolTable};
use softnc_protocol::{ToolEntry, ToolTableMsg, TOOL_ENTRIES};

/// `tools` as the kernel publishes it: table version `version`, `saved` to a tool file.
pub fn tool_table_msg(tools: &ToolTable, version: u32, saved: bool) -> ToolTableMsg {
    let mut m = ToolTableMsg {
        version,
        saved: u8::from(saved),
        ..Default::default()
    };
    let n = tools.offset.len().min(TOOL_ENTRIES);
    m.count = n as u32;
    m.truncated = u8::from(tools.offset.len() > n);
    for (e, o) in m.entries.iter_mut().zip(&tools.offset) {
        // A `--set Dn=R` override stands for radius R with wear 0.
        let (radius, radius_wear) = tools
            .radius_overrides
            .iter()
            .find(|(d, _)| *d == o.d)
            .map_or((o.radius, o.radius_wear), |(_, r)| (*r, 0.0));
        *e = ToolEntry {
            t: o.t.unwrap_or(0),
            d: o.d,
            radius,
            radius_wear,
            length: o.length,
            length_wear: o.length_wear,
            cutting_edge: o.edge.unwrap_or(0),
            ..Default::default()
        };
    }
    m
}

/// The table a [`ToolTableMsg`] carries, as preparation reads it. A cutting edge position
/// outside 1–9 (a peer's garbage) counts as none: the tip is then the nose centre.
pub fn tool_table(m: &ToolTableMsg) -> ToolTable {
    ToolTable {
        offset: m
            .entries()
            .iter()
            .map(|e| ToolOffset {
                t: (e.t != 0).then_some(e.t),
                d: e.d,
                radius: e.radius,
                radius_wear: e.radius_wear,
                length: e.length,
                length_wear: e.length_wear,
                edge: (1..=9).contains(&e.cutting_edge).then_some(e.cutting_edge),
            })
            .collect(),
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped table (mill offsets without, lathe tools with a cutting edge position)
    /// goes across and comes back whole.
    #[test]
    fn the_table_comes_back_with_its_cutting_edges() {
        let tools = ToolTable::builtin();
        let m = tool_table_msg(&tools, 3, true);
        assert_eq!((m.version, m.saved, m.truncated), (3, 1, 0));
        assert_eq!(m.count as usize, tools.offset.len());
        let back = tool_table(&m);
        assert_eq!(back.offset, tools.offset);
        let t2d1 = back.find(Some(2), 1).expect("T2 D1");
        assert_eq!((t2d1.radius, t2d1.edge), (1.2, Some(3)));
        assert_eq!(back.find(None, 1).map(|o| o.edge), Some(None));
    }

    #[test]
    fn an_override_is_published_as_the_radius_and_a_bad_position_read_as_none() {
        let mut tools = ToolTable::builtin();
        tools.apply_set("D1=6.5").unwrap();
        let mut m = tool_table_msg(&tools, 1, false);
        let d1 = m.entries().iter().find(|e| e.t == 0 && e.d == 1).unwrap();
        assert_eq!((d1.radius, d1.radius_wear, d1.cutting_edge), (6.5, 0.0, 0));
        m.entries[0].cutting_edge = 12;
        assert_eq!(tool_table(&m).offset[0].edge, None);
    }
}
