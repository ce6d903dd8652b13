//! Co-simulation: the kernel stepped cycle by cycle from another program through a C ABI
//! (include/softnc_cosim.h, docs/interfaces.md "Co-simulation (C ABI)").
//!
//! A handle owns one [`Simulation`], the same one `softnc simulate` steps to the end: the
//! preparation thread, the channel, and the simulated operator and PLC around it. With
//! nothing fed in, every setpoint has the bits `softnc simulate` writes for the same program
//! and machine data; a caller may switch the simulated operator and PLC off and play them
//! itself (NC start and stop, override, read-in disable, aux acknowledgements, the spindle's
//! actual speed, emergency stop).
//!
//! Rules at the boundary: every pointer is checked for NULL; no panic crosses it (each
//! function runs under `catch_unwind` and reports an internal error instead); strings
//! handed out are copied into the caller's buffer, `snprintf`-style.

use nc_kernel::cycle::{alarm, Override};
use nc_kernel::ipo::{ChannelState, Event, Setpoint};
use nc_kernel::simulate::{Options, Simulation, Step};
use nc_kernel::{MachineData, ToolTable};
use std::cell::RefCell;
use std::ffi::{c_char, c_int, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// Axes a setpoint carries: X Y Z U V W A B C.
pub const AXES: usize = 9;

/// [`softnc_cosim_step`]'s answers.
pub const RUNNING: c_int = 0;
pub const ENDED: c_int = 1;
pub const STOPPED: c_int = 2;
pub const ERROR: c_int = -1;

/// The setpoint of the last cycle stepped: the numbers of a `softnc simulate` row.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftncCosimSetpoint {
    /// IPO cycle number (the CSV's `cycle`).
    pub cycle: u64,
    /// `cycle` × the IPO cycle, µs (the CSV's `time`, in seconds there).
    pub time_us: u64,
    /// X Y Z U V W A B C, mm or degrees; 0 for an axis the machine does not have.
    pub pos: [f64; AXES],
    /// The spindle's speed setpoint, rev/min, + clockwise (the CSV's `S1`).
    pub spindle: f64,
    /// Path speed, mm/min (the CSV's `v_path`: mm/s × 60).
    pub v_path: f64,
    /// Source line and column of the block (0: none yet).
    pub line: u32,
    pub col: u32,
    /// The block's number (`N10` → 10, digits 2) when it has one (digits 0: none).
    pub block_number: u32,
    pub block_digits: u8,
    /// 0 RESET, 1 ACTIVE, 2 STOPPED, 3 END.
    pub state: u8,
    /// Events of the cycle (their text: `softnc_cosim_events`).
    pub events: u8,
    pub _pad: u8,
}

/// Where the channel is, for a caller playing operator or PLC.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftncCosimStatus {
    /// The last cycle stepped.
    pub cycle: u64,
    /// Auxiliary functions output so far (with words).
    pub aux: u64,
    /// The feed override, fraction (1.0: 100 %).
    pub override_: f64,
    /// Line and column of the block the setpoint belongs to (0: none yet).
    pub line: u32,
    pub col: u32,
    /// The first alarm that stopped the channel (0: none), and its block.
    pub alarm: u32,
    pub alarm_line: u32,
    pub alarm_col: u32,
    /// Acknowledgements of auxiliary functions the path waits for.
    pub acks_due: u32,
    /// 0 RESET, 1 ACTIVE, 2 STOPPED, 3 END.
    pub state: u8,
    /// 1: waits for NC start (program stop, single block, alarm).
    pub waits_for_start: u8,
    pub single_block: u8,
    /// 1: the simulated operator gives NC start after a stop without alarm.
    pub operator_: u8,
    /// 1: the simulated PLC acknowledges aux functions and reports the spindle's speed.
    pub plc: u8,
    /// 1: the run ended or stopped with an alarm; further steps do nothing.
    pub over: u8,
    pub _pad: [u8; 2],
}

/// What does not change during a run.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoftncCosimInfo {
    /// The IPO cycle, µs.
    pub cycle_us: u32,
    /// Position columns of a `softnc simulate` row: X Y Z and the additional axes configured.
    pub columns: u8,
    /// Index into `pos` of each column.
    pub column: [u8; AXES],
    pub _pad: [u8; 2],
}

/// One co-simulation: what a handle points to. Rust callers may use it directly.
pub struct Cosim {
    sim: Simulation,
    override_: f64,
    single_block: bool,
    /// The first alarm: number, line, column.
    alarm: Option<(u32, u32, u32)>,
    last: Step,
    text: String,
}

impl Cosim {
    /// Loads the machine data (`None`: the built-in machine), the tool table (`None`: the
    /// built-in one) and the program with the subprogram files beside it, as `softnc
    /// simulate` does, and starts its preparation.
    pub fn new(
        machine: Option<&Path>,
        program: &Path,
        tools: Option<&Path>,
    ) -> Result<Cosim, String> {
        let mut md = MachineData::load(machine, &[]).map_err(|e| e.to_string())?;
        let tools = match tools {
            Some(p) => ToolTable::load(p).map_err(|e| e.to_string())?,
            None => ToolTable::builtin(),
        };
        let name = program.display().to_string();
        let bytes = std::fs::read(program).map_err(|e| format!("{name}: {e}"))?;
        md.programs = std::sync::Arc::new(nc_runtime::program_library(
            program,
            &md.program.search_path,
        )?);
        let source = String::from_utf8(bytes)
            .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned());
        let opts = Options::default();
        let sim = Simulation::new(&name, &source, &md, &tools, &opts)
            .map_err(|e| format!("starting block preparation: {e}"))?;
        Ok(Cosim {
            sim,
            override_: opts.override_,
            single_block: opts.single_block,
            alarm: None,
            last: Step::Running,
            text: String::new(),
        })
    }

    /// One IPO cycle.
    pub fn step(&mut self) -> Step {
        self.last = self.sim.step();
        if self.alarm.is_none() {
            self.alarm = self.sim.setpoint().events.iter().find_map(|e| match e {
                Event::Alarm { code, source } => Some((*code, source.line, source.col)),
                _ => None,
            });
        }
        self.last
    }

    pub fn simulation(&mut self) -> &mut Simulation {
        &mut self.sim
    }

    /// The last setpoint as the C struct.
    pub fn setpoint(&self) -> SoftncCosimSetpoint {
        let sp: &Setpoint = self.sim.setpoint();
        let mut pos = [0.0; AXES];
        pos[..3].copy_from_slice(&sp.pos);
        pos[3..].copy_from_slice(&sp.add);
        let src = sp.source.unwrap_or_default();
        let number = sp.source.and_then(|s| s.number);
        SoftncCosimSetpoint {
            cycle: sp.cycle,
            time_us: sp.cycle * u64::from(self.info().cycle_us),
            pos,
            spindle: sp.spindle,
            v_path: sp.v_path * 60.0,
            line: src.line,
            col: src.col,
            block_number: number.map_or(0, |n| n.value),
            block_digits: number.map_or(0, |n| n.digits.get()),
            state: state_number(sp.state),
            events: sp.events.len() as u8,
            _pad: 0,
        }
    }

    pub fn status(&self) -> SoftncCosimStatus {
        let sp = self.setpoint();
        let (alarm, alarm_line, alarm_col) = self.alarm.unwrap_or_default();
        let ch = self.sim.channel_ref();
        SoftncCosimStatus {
            cycle: sp.cycle,
            aux: self.sim.summary.aux,
            override_: self.override_,
            line: sp.line,
            col: sp.col,
            alarm,
            alarm_line,
            alarm_col,
            acks_due: ch.acks_due(),
            state: sp.state,
            waits_for_start: u8::from(ch.waits_for_start()),
            single_block: u8::from(self.single_block),
            operator_: u8::from(self.sim.operator),
            plc: u8::from(self.sim.plc),
            over: u8::from(self.last != Step::Running),
            _pad: [0; 2],
        }
    }

    pub fn info(&self) -> SoftncCosimInfo {
        let extra = self.sim.extra_axes();
        let mut column = [0u8; AXES];
        for (i, c) in (0..3).chain(extra.iter().copied()).enumerate().take(AXES) {
            column[i] = c as u8;
        }
        SoftncCosimInfo {
            cycle_us: self.sim.cycle_us(),
            columns: (3 + extra.len()).min(AXES) as u8,
            column,
            _pad: [0; 2],
        }
    }

    /// Feed override, fraction: above 0, at most 1.2.
    pub fn set_override(&mut self, fraction: f64) -> bool {
        let Some(o) = Override::from_fraction(fraction) else {
            return false;
        };
        self.override_ = o.fraction();
        self.sim.channel().set_override(self.override_);
        true
    }

    pub fn set_single_block(&mut self, on: bool) {
        self.single_block = on;
        self.sim.channel().set_single_block(on);
    }

    /// Emergency stop: the path brakes on its contour, the channel stops with alarm 3000.
    pub fn emergency_stop(&mut self) {
        self.sim.channel().fault();
        if self.alarm.is_none() {
            let sp = self.setpoint();
            self.alarm = Some((alarm::EMERGENCY_STOP.number(), sp.line, sp.col));
        }
    }
}

fn state_number(s: ChannelState) -> u8 {
    match s {
        ChannelState::Reset => 0,
        ChannelState::Active => 1,
        ChannelState::Stopped => 2,
        ChannelState::End => 3,
    }
}

fn step_number(s: Step) -> c_int {
    match s {
        Step::Running => RUNNING,
        Step::Ended => ENDED,
        Step::Stopped => STOPPED,
    }
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_error(msg: &str) {
    let c = CString::new(msg.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

/// Runs `f` with no panic escaping: a panic is an internal error, answered with `fallback`.
fn guard<R>(fallback: R, f: impl FnOnce() -> R) -> R {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|_| {
        set_error("internal error in softnc-cosim (a panic; please report it)");
        fallback
    })
}

/// The handle's simulation, or an error for NULL.
///
/// # Safety
/// `h` is NULL or a handle from [`softnc_cosim_create`] not yet destroyed.
unsafe fn handle<'a>(h: *mut Cosim) -> Option<&'a mut Cosim> {
    // SAFETY: the caller passes a live handle or NULL (checked here).
    let c = unsafe { h.as_mut() };
    if c.is_none() {
        set_error("NULL handle");
    }
    c
}

/// A path argument: NULL is `None`; not UTF-8 is an error.
///
/// # Safety
/// `p` is NULL or a NUL-terminated string.
unsafe fn path_arg<'a>(p: *const c_char, what: &str) -> Result<Option<&'a Path>, String> {
    if p.is_null() {
        return Ok(None);
    }
    // SAFETY: the caller passes a NUL-terminated string.
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str()
        .map(|s| Some(Path::new(s)))
        .map_err(|_| format!("{what}: the path is not UTF-8"))
}

/// Copies `s` into `buf` (at most `cap - 1` bytes and a NUL); returns `s`'s length.
///
/// # Safety
/// `buf` is NULL (with any `cap`) or points to `cap` writable bytes.
unsafe fn copy_out(s: &str, buf: *mut c_char, cap: usize) -> usize {
    if !buf.is_null() && cap > 0 {
        let n = s.len().min(cap - 1);
        // SAFETY: `buf` has `cap` bytes; `n + 1 <= cap`.
        unsafe {
            std::ptr::copy_nonoverlapping(s.as_ptr(), buf.cast::<u8>(), n);
            *buf.add(n) = 0;
        }
    }
    s.len()
}

/// Creates a co-simulation. `machine`: machine data (TOML), NULL for the built-in machine;
/// `program`: the part program (required); `tools`: tool table (TOML), NULL for the
/// built-in one. Returns NULL on failure (`softnc_cosim_last_error` says why). The handle
/// is the caller's: free it with `softnc_cosim_destroy`.
///
/// # Safety
/// Each argument is NULL or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_create(
    machine: *const c_char,
    program: *const c_char,
    tools: *const c_char,
) -> *mut Cosim {
    guard(std::ptr::null_mut(), || {
        // SAFETY: the caller's strings (see above).
        let args = unsafe {
            (
                path_arg(machine, "machine data"),
                path_arg(program, "program"),
                path_arg(tools, "tools"),
            )
        };
        let made = match args {
            (Ok(m), Ok(Some(p)), Ok(t)) => Cosim::new(m, p, t),
            (_, Ok(None), _) => Err("program: NULL (a part program is required)".into()),
            (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => Err(e),
        };
        match made {
            Ok(c) => {
                set_error("");
                Box::into_raw(Box::new(c))
            }
            Err(e) => {
                set_error(&e);
                std::ptr::null_mut()
            }
        }
    })
}

/// Frees a handle (stops its preparation thread). NULL is ignored.
///
/// # Safety
/// `h` is NULL or a handle from [`softnc_cosim_create`], not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_destroy(h: *mut Cosim) {
    guard((), || {
        if !h.is_null() {
            // SAFETY: the handle came from `Box::into_raw` and is given back once.
            drop(unsafe { Box::from_raw(h) });
        }
    })
}

/// Why the last call on this thread failed ("" if it did not). The string is the library's,
/// valid until the next call of a `softnc_cosim_` function on this thread.
#[no_mangle]
pub extern "C" fn softnc_cosim_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// One IPO cycle: 0 running, 1 ended, 2 stopped with an alarm (and every later step after
/// 1 or 2), -1 error.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_step(h: *mut Cosim) -> c_int {
    guard(ERROR, || {
        // SAFETY: see above.
        unsafe { handle(h) }.map_or(ERROR, |c| step_number(c.step()))
    })
}

/// Runs `f` on the handle and writes its answer to `out`: 0, or -1 for a NULL pointer.
///
/// # Safety
/// `h` is NULL or a live handle; `out` is NULL or points to a `T`.
unsafe fn read<T>(h: *mut Cosim, out: *mut T, f: impl FnOnce(&Cosim) -> T) -> c_int {
    guard(ERROR, || {
        // SAFETY: see above.
        let Some(c) = (unsafe { handle(h) }) else {
            return ERROR;
        };
        if out.is_null() {
            set_error("NULL output pointer");
            return ERROR;
        }
        // SAFETY: `out` points to a `T` (checked not NULL).
        unsafe { out.write(f(c)) };
        0
    })
}

/// The last cycle's setpoint into `*out`: 0, or -1 for NULL.
///
/// # Safety
/// `h` is NULL or a live handle; `out` is NULL or points to the struct.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_setpoint(
    h: *mut Cosim,
    out: *mut SoftncCosimSetpoint,
) -> c_int {
    // SAFETY: see above.
    unsafe { read(h, out, Cosim::setpoint) }
}

/// The channel's status into `*out`: 0, or -1 for NULL.
///
/// # Safety
/// `h` is NULL or a live handle; `out` is NULL or points to the struct.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_status(h: *mut Cosim, out: *mut SoftncCosimStatus) -> c_int {
    // SAFETY: see above.
    unsafe { read(h, out, Cosim::status) }
}

/// The run's constants into `*out`: 0, or -1 for NULL.
///
/// # Safety
/// `h` is NULL or a live handle; `out` is NULL or points to the struct.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_info(h: *mut Cosim, out: *mut SoftncCosimInfo) -> c_int {
    // SAFETY: see above.
    unsafe { read(h, out, Cosim::info) }
}

/// Text the handle formats, `snprintf`-style: at most `cap - 1` bytes and a NUL into `buf`;
/// returns the text's whole length (compare with `cap` to see it was cut), or -1.
///
/// # Safety
/// `h` is NULL or a live handle; `buf` is NULL or has `cap` bytes.
unsafe fn text(
    h: *mut Cosim,
    buf: *mut c_char,
    cap: usize,
    f: impl FnOnce(&Cosim, &mut String),
) -> isize {
    guard(-1, || {
        // SAFETY: see above.
        let Some(c) = (unsafe { handle(h) }) else {
            return -1;
        };
        let mut s = std::mem::take(&mut c.text);
        s.clear();
        f(c, &mut s);
        // SAFETY: see above.
        let n = unsafe { copy_out(&s, buf, cap) };
        c.text = s;
        n as isize
    })
}

/// The CSV header `softnc simulate` writes (no newline).
///
/// # Safety
/// `h` is NULL or a live handle; `buf` is NULL or has `cap` bytes.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_header(h: *mut Cosim, buf: *mut c_char, cap: usize) -> isize {
    // SAFETY: see above.
    unsafe { text(h, buf, cap, |c, s| s.push_str(&c.sim.header())) }
}

/// The last setpoint's CSV row as `softnc simulate` writes it (no newline).
///
/// # Safety
/// `h` is NULL or a live handle; `buf` is NULL or has `cap` bytes.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_row(h: *mut Cosim, buf: *mut c_char, cap: usize) -> isize {
    // SAFETY: see above.
    unsafe {
        text(h, buf, cap, |c, s| {
            c.sim.row(s);
            s.pop();
        })
    }
}

/// The last setpoint's block column (`N10`, `L3` or empty).
///
/// # Safety
/// `h` is NULL or a live handle; `buf` is NULL or has `cap` bytes.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_block(h: *mut Cosim, buf: *mut c_char, cap: usize) -> isize {
    // SAFETY: see above.
    unsafe { text(h, buf, cap, |c, s| c.sim.block(s)) }
}

/// The last setpoint's events column (`aux M3 @S1;single-block`, …).
///
/// # Safety
/// `h` is NULL or a live handle; `buf` is NULL or has `cap` bytes.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_events(h: *mut Cosim, buf: *mut c_char, cap: usize) -> isize {
    // SAFETY: see above.
    unsafe { text(h, buf, cap, |c, s| c.sim.events(s)) }
}

/// Runs `f` on the handle: 0, or -1 for NULL or when `f` refuses.
///
/// # Safety
/// `h` is NULL or a live handle.
unsafe fn feed(h: *mut Cosim, f: impl FnOnce(&mut Cosim) -> Result<(), &'static str>) -> c_int {
    guard(ERROR, || {
        // SAFETY: see above.
        let Some(c) = (unsafe { handle(h) }) else {
            return ERROR;
        };
        match f(c) {
            Ok(()) => 0,
            Err(e) => {
                set_error(e);
                ERROR
            }
        }
    })
}

/// Feed override, a fraction above 0 and at most 1.2 (-1 outside, nothing changed).
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_set_override(h: *mut Cosim, fraction: f64) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            c.set_override(fraction)
                .then_some(())
                .ok_or("override: expected a fraction above 0 and at most 1.2")
        })
    }
}

/// Single-block mode on (non-zero) or off.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_set_single_block(h: *mut Cosim, on: c_int) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            c.set_single_block(on != 0);
            Ok(())
        })
    }
}

/// NC start: after an NC stop, a program stop or a single-block stop (not after an alarm).
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_nc_start(h: *mut Cosim) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            c.sim.channel().start();
            Ok(())
        })
    }
}

/// NC stop (feed hold): the path brakes on its contour and holds, STOPPED at rest.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_nc_stop(h: *mut Cosim) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            c.sim.channel().stop();
            Ok(())
        })
    }
}

/// Read-in disable (PLC) on or off: no further block starts while on.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_set_read_in_disable(h: *mut Cosim, on: c_int) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            c.sim.channel().set_read_in_disable(on != 0);
            Ok(())
        })
    }
}

/// Emergency stop: the path brakes on its contour and the channel stops with alarm 3000.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_emergency_stop(h: *mut Cosim) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            c.emergency_stop();
            Ok(())
        })
    }
}

/// The simulated operator (NC start after a stop without alarm) on or off; on at creation.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_set_operator(h: *mut Cosim, on: c_int) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            c.sim.operator = on != 0;
            Ok(())
        })
    }
}

/// The simulated PLC (aux acknowledgement one cycle after output, the spindle's actual speed
/// following its setpoint) on or off; on at creation. Off, the caller acknowledges with
/// `softnc_cosim_ack` and reports the speed with `softnc_cosim_set_spindle_actual`.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_set_plc(h: *mut Cosim, on: c_int) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            c.sim.plc = on != 0;
            Ok(())
        })
    }
}

/// The PLC acknowledges one auxiliary function the path waits for.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_ack(h: *mut Cosim) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            c.sim.channel().ack();
            Ok(())
        })
    }
}

/// The main spindle's actual speed, rev/min, signed as the setpoint.
///
/// # Safety
/// `h` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn softnc_cosim_set_spindle_actual(h: *mut Cosim, rpm: f64) -> c_int {
    // SAFETY: see above.
    unsafe {
        feed(h, |c| {
            if !rpm.is_finite() {
                return Err("spindle speed: not a finite number");
            }
            c.sim.channel().set_spindle_actual(rpm);
            Ok(())
        })
    }
}
