//! Work offsets (docs/work-offsets.md): the sets each dialect has, selected as its programs
//! select them, the table file read and written, bad files and edits refused. Expected
//! positions worked out by hand: absolute position = programmed value + the set's value.

use nc_kernel::{interpret, AlarmCode, Block, MachineData, ToolTable, WorkOffsets};

fn machine(md: &[&str], offsets: &str) -> MachineData {
    let md: Vec<String> = md.iter().map(|s| s.to_string()).collect();
    let mut md = MachineData::load(None, &md).expect("machine data");
    md.work_offsets = WorkOffsets::from_toml_str(offsets, "offsets.toml", &md).expect("offsets");
    md
}

fn run(md: &MachineData, src: &str) -> Result<Vec<Block>, nc_kernel::Alarm> {
    interpret("w.nc", src, md, &ToolTable::builtin())
}

fn end(b: &Block) -> [f64; 3] {
    b.motion.expect("a motion").end
}

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-9)
}

const FANUC: &[&str] = &["dialect=\"fanuc\""];

#[test]
fn fanuc_g54_to_g59_and_the_numbered_sets() {
    let md = machine(
        FANUC,
        "[G55]\nX = 10\n[G59]\nY = -7.5\n[\"G54.1 P1\"]\nX = 1\nZ = 2\n[\"G54.1 P48\"]\nZ = -300\n",
    );
    let b = run(
        &md,
        "G0 G90 X1 Y1 Z1\nG55 X1\nG59 X1 Y1\nG54.1 P1 X1 Y1 Z1\nG54.1 P48 Z0\nG54 X0 Y0 Z0\n",
    )
    .unwrap();
    assert!(
        close(end(&b[0]), [1.0, 1.0, 1.0]),
        "G54 at program start: zero here"
    );
    assert!(close(end(&b[1]), [11.0, 1.0, 1.0]), "G55 X+10");
    assert!(close(end(&b[2]), [1.0, -6.5, 1.0]), "G59 Y-7.5");
    assert!(close(end(&b[3]), [2.0, 1.0, 3.0]), "G54.1 P1 (1, 0, 2)");
    assert!(
        close(end(&b[4]), [2.0, 1.0, -300.0]),
        "G54.1 P48 Z-300; X Y stay"
    );
    assert!(close(end(&b[5]), [0.0, 0.0, 0.0]), "G54 is zero");
}

#[test]
fn a_new_set_acts_on_the_axes_written_next_in_absolute() {
    // G55 alone moves nothing; G91 X5 moves by 5 whatever the set; the next absolute Y
    // lands in G55.
    let md = machine(FANUC, "[G55]\nX = 100\nY = 200\n");
    let b = run(&md, "G0 X0 Y0\nG55\nG91 X5\nG90 Y1\n").unwrap();
    assert!(b[1].motion.is_none());
    assert!(close(end(&b[2]), [5.0, 0.0, 0.0]));
    assert!(close(end(&b[3]), [5.0, 201.0, 0.0]));
}

#[test]
fn g53_is_machine_coordinates_for_its_block_on_fanuc_and_808d() {
    let md = machine(FANUC, "[G54]\nX = 50\nZ = -100\n");
    let b = run(&md, "G54 G0 X0 Z0\nG53 X10 Z-5\nX1\n").unwrap();
    assert!(close(end(&b[0]), [50.0, 0.0, -100.0]));
    assert!(close(end(&b[1]), [10.0, 0.0, -5.0]));
    assert!(
        close(end(&b[2]), [51.0, 0.0, -5.0]),
        "G54 again after the G53 block"
    );
    // 808D (a lathe, X in diameter there only with DIAMON): G500 switches the set off.
    let md = machine(
        &["dialect=\"siemens-808d\"", "machine=\"turning\""],
        "[G54]\nX = 2\nZ = 30\n",
    );
    let b = run(&md, "G54 G0 X10 Z0\nG500 Z0\nG54 Z1\nG53 Z1\n").unwrap();
    assert!(close(end(&b[0]), [12.0, 0.0, 30.0]));
    assert!(close(end(&b[1]), [12.0, 0.0, 0.0]), "G500: no set");
    assert!(close(end(&b[2]), [12.0, 0.0, 31.0]));
    assert!(close(end(&b[3]), [12.0, 0.0, 1.0]));
}

#[test]
fn isg_g53_switches_the_set_off_modally() {
    // TF5200: G53 deselects the zero offset (modal), G54…G59 select one.
    let md = machine(&["dialect=\"isg\""], "[G58]\nY = 4\n");
    let b = run(&md, "G58 G0 X0 Y0\nG53 Y0\nY1\n").unwrap();
    assert!(close(end(&b[0]), [0.0, 4.0, 0.0]));
    assert!(close(end(&b[1]), [0.0, 0.0, 0.0]));
    assert!(close(end(&b[2]), [0.0, 1.0, 0.0]), "still without offset");
}

#[test]
fn arcs_and_the_840c_pole_take_the_offset() {
    // An arc's centre is relative to its start: only the end point moves with the set.
    let md = machine(FANUC, "[G54]\nX = 100\nY = 100\n");
    let b = run(&md, "G54 G0 X0 Y0\nG2 X10 Y0 I5 J0 F100\n").unwrap();
    let m = b[1].motion.unwrap();
    assert!(close(m.end, [110.0, 100.0, 0.0]) && close(m.center, [105.0, 100.0, 0.0]));
    // 840C G54…G57 (four sets): the pole given in G54 lies in G54.
    let md = machine(&[], "[G57]\nX = 20\n");
    let b = run(&md, "G57 G0 X0 Y0\nG10 X0 Y0 A0 U10\n").unwrap();
    assert!(
        close(end(&b[1]), [30.0, 0.0, 0.0]),
        "pole (20, 0), radius 10 at 0°"
    );
}

#[test]
fn a_rotary_axis_takes_its_set_value_too() {
    // The 5-axis mill: C is a modulo table axis, A a tilting axis. G54 C = 90, A = -10:
    // C0 goes to 90°, A0 to -10°.
    // The default machine has no C: a file that names it is refused with the key.
    let e = WorkOffsets::from_toml_str("[G54]\nC = 90\n", "o.toml", &MachineData::default())
        .unwrap_err();
    assert_eq!(e.key, "G54.C");
    assert!(e.reason.contains("not configured"), "{e}");
    let md5 = MachineData::load(Some(std::path::Path::new("config/fanuc-5axis.toml")), &[])
        .expect("5-axis machine data");
    let mut md = md5.clone();
    md.work_offsets =
        WorkOffsets::from_toml_str("[G54]\nC = 90\nA = -10\n", "o.toml", &md5).unwrap();
    let b = run(&md, "G54 G0 C0\nA0\n").unwrap();
    let c = |b: &Block| b.axes.map(|a| a.to);
    let to = c(&b[0]).expect("C moves");
    assert!((to[5] - 90.0).abs() < 1e-9, "{to:?}");
    let to = c(&b[1]).expect("A moves");
    assert!((to[3] + 10.0).abs() < 1e-9, "{to:?}");
}

#[test]
fn bad_selections_are_alarms_with_their_place() {
    let md = machine(FANUC, "");
    let a = run(&md, "G54.1 X1\n").unwrap_err();
    assert_eq!(
        (a.code, a.line, a.col),
        (AlarmCode::MissingValue, 1, 1),
        "{a}"
    );
    let a = run(&md, "G54.1 P49 X1\n").unwrap_err();
    assert_eq!((a.code, a.col), (AlarmCode::BadNumber, 7), "{a}");
    assert!(a.message.contains("P1 … P48"), "{a}");
    let a = run(&md, "G54.2 X1\n").unwrap_err();
    assert_eq!(a.code, AlarmCode::UnknownGCode, "{a}");
    assert!(a.message.contains("G54.2"), "{a}");
    // The 840C has four settable sets: G58 is its programmable offset, not one of them.
    let a = run(&machine(&[], ""), "G58 X1\n").unwrap_err();
    assert_eq!(a.code, AlarmCode::NotSupported, "{a}");
}

#[test]
fn the_table_file_round_trips_and_bad_files_name_the_key() {
    let md = machine(FANUC, "");
    let t = WorkOffsets::from_toml_str(
        "[G54]\nX = -12.5\nz = 3\n[\"g54.1 p7\"]\nY = 1e-3\n",
        "o.toml",
        &md,
    )
    .unwrap();
    let text = t.to_toml(&md);
    assert!(
        text.contains("[G54]") && text.contains("[\"G54.1 P7\"]"),
        "{text}"
    );
    assert_eq!(
        WorkOffsets::from_toml_str(&text, "again.toml", &md).unwrap(),
        t
    );
    for (file, key, why) in [
        ("[G60]\nX = 1\n", "G60", "not a work offset"),
        ("[\"G54.1 P49\"]\nX = 1\n", "G54.1 P49", "not a work offset"),
        ("[G54]\nQ = 1\n", "G54.Q", "not configured"),
        ("[G54]\nXY = 1\n", "G54.XY", "not an axis letter"),
        ("[G54]\nX = \"a\"\n", "G54.X", "expected a number"),
        ("[G54]\nX = 2e6\n", "G54.X", "beyond"),
        ("[G54]\nX = nan\n", "G54.X", "not a number"),
        ("G54 = 1\n", "G54", "expected a table"),
        ("[G54\n", "", ""),
    ] {
        let e = WorkOffsets::from_toml_str(file, "bad.toml", &md).unwrap_err();
        assert_eq!(e.key, key, "{file:?}: {e}");
        assert!(e.reason.contains(why), "{file:?}: {e}");
        assert!(e.to_string().starts_with("bad.toml"), "{e}");
    }
}

#[test]
fn an_edit_is_checked_whole_before_anything_changes() {
    let md = machine(FANUC, "[G55]\nX = 1\n");
    let mut t = md.work_offsets.clone();
    let before = t.clone();
    // X fine, Y beyond the limit: nothing changes.
    let e = t
        .edit(&md, "G55", &[(0, 5.0), (1, 20_000.0)], 10_000.0)
        .unwrap_err();
    assert!(e.contains("beyond") && e.contains("G55 Y"), "{e}");
    assert_eq!(t, before);
    for (name, values) in [
        ("G60", vec![(0, 1.0)]),
        ("G55", vec![]),
        ("G55", vec![(5, 1.0)]),
        ("G55", vec![(0, f64::INFINITY)]),
    ] {
        assert!(
            t.edit(&md, name, &values, 10_000.0).is_err(),
            "{name} {values:?}"
        );
        assert_eq!(t, before);
    }
    assert_eq!(t.edit(&md, "g55", &[(2, -4.25)], 10_000.0), Ok(2));
    assert_eq!(t.get(2)[..3], [1.0, 0.0, -4.25]);
    // Saved atomically: read back equal, no temporary file left.
    let dir = std::env::temp_dir().join(format!("softnc-wo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("offsets.toml");
    t.save_atomic(&path, &md).unwrap();
    assert_eq!(WorkOffsets::load(&path, &md).unwrap(), t);
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().collect();
    assert_eq!(left.len(), 1, "{left:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Fanuc memory C (tool offsets of config/tools.toml: offset number n holds H n's length and
/// D n's radius, each geometry + wear): G43 H adds the length along the tool axis, G44
/// subtracts it, G49 and H0 take it off; D gives only the radius.
#[test]
fn fanuc_g43_g44_g49_take_the_h_register_with_its_wear() {
    let md = machine(FANUC, "");
    let mut tools = ToolTable::builtin();
    // Offset 2: length 80 geometry, wear -0.25: H2 = 79.75.
    tools
        .offset
        .iter_mut()
        .find(|o| o.d == 2 && o.t.is_none())
        .unwrap()
        .length_wear = -0.25;
    let b = interpret(
        "h.nc",
        "G0 Z50 D1\nG43 H2 Z10\nZ5\nG44 Z5\nH0 Z5\nG43 Z5\nG49 Z5\nG18 G43 H2 Y1\n",
        &md,
        &tools,
    )
    .unwrap();
    let l: Vec<(f64, u32)> = b.iter().map(|b| (b.modal.length, b.modal.h)).collect();
    assert_eq!(l[0], (0.0, 0), "D1 gives no length on a Fanuc");
    assert_eq!(b[0].modal.radius, 10.0);
    assert_eq!(l[1], (79.75, 2));
    assert_eq!(l[2], (79.75, 2), "modal");
    assert_eq!(l[3], (-79.75, 2), "G44");
    assert_eq!(l[4], (0.0, 0), "H0");
    assert_eq!(l[5], (0.0, 0), "G43 with H0 active");
    assert_eq!(l[6], (0.0, 0), "G49");
    assert_eq!(l[7], (79.75, 2));
    // Through preparation: the length lies on the active plane's normal (G17 Z, G18 Y).
    let segs = nc_kernel::prepare(
        "h.nc",
        "G0 Z50\nG43 H2 Z10\nG49 Z10\nG18 G43 H2 Y1\nM30\n",
        &md,
        &tools,
    )
    .expect("prepared");
    let ends: Vec<[f64; 3]> = segs.iter().map(|s| s.to).collect();
    assert!(close(ends[0], [0.0, 0.0, 50.0]), "{ends:?}");
    assert!(close(ends[1], [0.0, 0.0, 89.75]), "{ends:?}");
    assert!(close(ends[2], [0.0, 0.0, 10.0]), "{ends:?}");
    assert!(close(ends[3], [0.0, 80.75, 10.0]), "{ends:?}");
}

#[test]
fn an_unknown_h_is_an_alarm_at_its_word() {
    let md = machine(FANUC, "");
    let a = run(&md, "G0 Z5\nG43 H99 Z1\n").unwrap_err();
    assert_eq!(
        (a.code, a.line, a.col),
        (AlarmCode::UnknownOffset, 2, 5),
        "{a}"
    );
    assert!(a.message.contains("H99"), "{a}");
    // Elsewhere H is an auxiliary function for the PLC, as before.
    let b = run(&machine(&[], ""), "G0 X1 H2\n").unwrap();
    assert!(b[0].words.iter().any(|w| w.address == b'H'));
}

/// The command line reads `--offsets`; a file that does not load stops it with exit status 2
/// and names the file and the key, before anything runs.
#[test]
fn the_command_line_takes_the_offsets_file_and_refuses_a_bad_one() {
    let dir = std::env::temp_dir().join(format!("softnc-wo-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let prog = dir.join("p.mpf");
    std::fs::write(&prog, "G54 G0 X10 Y0 Z0\nM30\n").unwrap();
    let good = dir.join("good.toml");
    std::fs::write(&good, "[G54]\nX = 5.5\n").unwrap();
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[G54]\nX = 5.5\nQ = 1\n").unwrap();
    let broken = dir.join("broken.toml");
    std::fs::write(&broken, "[G54\n").unwrap();
    let softnc = |offsets: &std::path::Path| {
        std::process::Command::new(env!("CARGO_BIN_EXE_softnc"))
            .args(["path", prog.to_str().unwrap(), "--offsets"])
            .arg(offsets)
            .output()
            .unwrap()
    };
    let out = softnc(&good);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let path = String::from_utf8_lossy(&out.stdout);
    assert!(path.contains("\"to\":[15.5,0.0,0.0]"), "{path}");
    for (file, key) in [(&bad, "key `G54.Q`"), (&broken, "broken.toml")] {
        let out = softnc(file);
        let said = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{said}");
        assert!(said.contains(key), "{said}");
        assert!(out.stdout.is_empty(), "nothing ran");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_fanuc_program_starts_in_g54() {
    // Fanuc: G54 is in force at power-on and reset (group 14's initial code); the other
    // controls start without a set.
    let md = machine(FANUC, "[G54]\nX = 100\n");
    let b = run(&md, "G1 X5 F100\n").unwrap();
    assert!(close(end(&b[0]), [105.0, 0.0, 0.0]));
    let md = machine(&[], "[G54]\nX = 100\n");
    let b = run(&md, "G1 X5 F100\n").unwrap();
    assert!(close(end(&b[0]), [5.0, 0.0, 0.0]));
}
