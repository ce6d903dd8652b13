//! The C ABI fed by hand: the caller as operator and PLC (NC start and stop, override,
//! emergency stop) and the boundary's rules (NULL pointers, bad values, errors to read).
//!
//! The program (built-in 840C milling machine): N10 rapid to X0 Y0 Z0, N20 X10 at F600
//! (10 mm/s: 1000 cycles of 1 ms at full speed, longer with the ramps), N30 M0 (program stop),
//! N40 X20, N50 M30. At the M0 stop the path stands at X10 exactly.

use softnc_cosim::*;
use std::ffi::{CStr, CString};
use std::ptr::null_mut;

const PROGRAM: &str = "N10 G0 G90 X0 Y0 Z0\nN20 G1 X10 F600\nN30 M0\nN40 X20\nN50 M30\n";

fn create() -> *mut Cosim {
    create_with(PROGRAM)
}

fn create_with(program: &str) -> *mut Cosim {
    let dir = std::env::temp_dir().join(format!("softnc-cosim-signals-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(format!("P{:?}.mpf", std::thread::current().id()).replace(['(', ')'], ""));
    std::fs::write(&p, program).unwrap();
    let path = CString::new(p.to_str().unwrap()).unwrap();
    // SAFETY: NUL-terminated strings or NULL.
    let h = unsafe { softnc_cosim_create(std::ptr::null(), path.as_ptr(), std::ptr::null()) };
    assert!(!h.is_null(), "{}", last_error());
    h
}

fn last_error() -> String {
    // SAFETY: the library's NUL-terminated string.
    unsafe { CStr::from_ptr(softnc_cosim_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn setpoint(h: *mut Cosim) -> SoftncCosimSetpoint {
    let mut sp = SoftncCosimSetpoint::default();
    // SAFETY: a live handle, a struct to fill.
    assert_eq!(unsafe { softnc_cosim_setpoint(h, &mut sp) }, 0);
    sp
}

fn status(h: *mut Cosim) -> SoftncCosimStatus {
    let mut st = SoftncCosimStatus::default();
    // SAFETY: as above.
    assert_eq!(unsafe { softnc_cosim_status(h, &mut st) }, 0);
    st
}

/// Steps until `done` holds (at most `max` cycles); the last step's answer.
fn step_until(h: *mut Cosim, max: u32, done: impl Fn(*mut Cosim) -> bool) -> i32 {
    for _ in 0..max {
        // SAFETY: a live handle.
        let r = unsafe { softnc_cosim_step(h) };
        if r != RUNNING || done(h) {
            return r;
        }
    }
    panic!("not done after {max} cycles: {:?}", status(h));
}

#[test]
fn the_caller_plays_operator_at_a_program_stop() {
    let h = create();
    // SAFETY (all calls below): a live handle.
    assert_eq!(unsafe { softnc_cosim_set_operator(h, 0) }, 0);
    let r = step_until(h, 20_000, |h| status(h).waits_for_start == 1);
    assert_eq!(r, RUNNING);
    let st = status(h);
    assert_eq!(st.state, 2, "STOPPED at M0");
    assert_eq!(st.operator_, 0);
    assert_eq!(setpoint(h).pos[0], 10.0);
    // Nobody presses NC start: the path stands.
    for _ in 0..500 {
        assert_eq!(unsafe { softnc_cosim_step(h) }, RUNNING);
    }
    assert_eq!(setpoint(h).pos[0], 10.0);
    assert_eq!(unsafe { softnc_cosim_nc_start(h) }, 0);
    let r = step_until(h, 20_000, |_| false);
    assert_eq!(r, ENDED);
    assert_eq!(setpoint(h).pos[0], 20.0);
    assert_eq!(status(h).over, 1);
    // After the end a step does nothing.
    assert_eq!(unsafe { softnc_cosim_step(h) }, STOPPED);
    unsafe { softnc_cosim_destroy(h) };
}

#[test]
fn nc_stop_brakes_and_holds_until_nc_start() {
    let h = create();
    unsafe { softnc_cosim_set_operator(h, 0) };
    step_until(h, 20_000, |h| setpoint(h).pos[0] > 2.0);
    assert_eq!(unsafe { softnc_cosim_nc_stop(h) }, 0);
    step_until(h, 20_000, |h| status(h).state == 2);
    let held = setpoint(h).pos[0];
    assert!(held > 2.0 && held < 10.0, "stopped on the way: X{held}");
    for _ in 0..200 {
        unsafe { softnc_cosim_step(h) };
    }
    assert_eq!(setpoint(h).pos[0], held);
    assert_eq!(setpoint(h).v_path, 0.0);
    unsafe { softnc_cosim_nc_start(h) };
    step_until(h, 20_000, |h| status(h).waits_for_start == 1);
    assert_eq!(setpoint(h).pos[0], 10.0, "on to the M0 stop");
    unsafe { softnc_cosim_destroy(h) };
}

#[test]
fn the_caller_plays_plc_acknowledging_m3() {
    // The built-in machine waits for the PLC's acknowledgement of M3 (ipo.wait_for_ack).
    let h = create_with("N10 G1 G90 X5 F600 M3 S1000\nN20 X10\nN30 M30\n");
    assert_eq!(unsafe { softnc_cosim_set_plc(h, 0) }, 0);
    for _ in 0..5000 {
        assert_eq!(unsafe { softnc_cosim_step(h) }, RUNNING);
    }
    let st = status(h);
    assert_eq!((st.acks_due, st.plc, st.aux), (1, 0, 1), "{st:?}");
    assert!(setpoint(h).pos[0] < 10.0, "waits for the acknowledgement");
    assert_eq!(unsafe { softnc_cosim_ack(h) }, 0);
    assert_eq!(unsafe { softnc_cosim_set_spindle_actual(h, 1000.0) }, 0);
    assert_eq!(
        unsafe { softnc_cosim_set_spindle_actual(h, f64::INFINITY) },
        ERROR
    );
    assert_eq!(step_until(h, 20_000, |_| false), ENDED);
    assert_eq!(setpoint(h).pos[0], 10.0);
    assert_eq!(status(h).acks_due, 0);
    unsafe { softnc_cosim_destroy(h) };
}

#[test]
fn emergency_stop_ends_the_run_with_alarm_3000() {
    let h = create();
    step_until(h, 20_000, |h| setpoint(h).pos[0] > 2.0);
    assert_eq!(unsafe { softnc_cosim_emergency_stop(h) }, 0);
    let r = step_until(h, 20_000, |_| false);
    assert_eq!(r, STOPPED);
    let st = status(h);
    assert_eq!((st.alarm, st.alarm_line), (3000, 2), "{st:?}");
    assert!(setpoint(h).pos[0] < 10.0);
    unsafe { softnc_cosim_destroy(h) };
}

#[test]
fn override_outside_its_range_is_refused() {
    let h = create();
    assert_eq!(unsafe { softnc_cosim_set_override(h, 0.0) }, ERROR);
    assert!(last_error().contains("override"), "{}", last_error());
    assert_eq!(unsafe { softnc_cosim_set_override(h, 1.5) }, ERROR);
    assert_eq!(unsafe { softnc_cosim_set_override(h, f64::NAN) }, ERROR);
    assert_eq!(unsafe { softnc_cosim_set_override(h, 0.5) }, 0);
    assert_eq!(status(h).override_, 0.5);
    unsafe { softnc_cosim_destroy(h) };
}

#[test]
fn null_pointers_are_errors_not_crashes() {
    // SAFETY: NULL is what is being checked.
    unsafe {
        assert_eq!(softnc_cosim_step(null_mut()), ERROR);
        assert!(last_error().contains("NULL"));
        assert_eq!(softnc_cosim_nc_start(null_mut()), ERROR);
        assert_eq!(softnc_cosim_setpoint(null_mut(), null_mut()), ERROR);
        assert_eq!(softnc_cosim_row(null_mut(), null_mut(), 0), -1);
        softnc_cosim_destroy(null_mut());
        let h = softnc_cosim_create(std::ptr::null(), std::ptr::null(), std::ptr::null());
        assert!(h.is_null());
        assert!(last_error().contains("program"), "{}", last_error());
        let h = create();
        assert_eq!(softnc_cosim_status(h, null_mut()), ERROR);
        // A buffer too short: cut, NUL-terminated, the whole length returned.
        let mut buf = [0x55 as std::ffi::c_char; 8];
        let n = softnc_cosim_header(h, buf.as_mut_ptr(), buf.len());
        assert_eq!(n, "cycle,time,X,Y,Z,S1,v_path,block,events".len() as isize);
        assert_eq!(CStr::from_ptr(buf.as_ptr()).to_str().unwrap(), "cycle,t");
        softnc_cosim_destroy(h);
    }
}

#[test]
fn bad_machine_data_is_an_error_to_read() {
    let md = CString::new("/nonexistent/machine.toml").unwrap();
    let prog = CString::new("/nonexistent/p.mpf").unwrap();
    // SAFETY: NUL-terminated strings.
    let h = unsafe { softnc_cosim_create(md.as_ptr(), prog.as_ptr(), std::ptr::null()) };
    assert!(h.is_null());
    assert!(last_error().contains("machine.toml"), "{}", last_error());
}
