//! A PLC and transport for `Cyclic` in the test's own thread, on a mock clock (the cycle
//! number): PLC signals set by the test, auxiliary functions acknowledged a set number of
//! cycles after their request, and every status recorded into vectors allocated up front,
//! so the allocation test can run it too.
#![allow(dead_code)] // each test file uses a different part

use nc_kernel::cycle::{
    AuxOut, Bus, ChannelAlarm, Control, Cyclic, PlcInput, Program, Refusal, Status,
};
use nc_kernel::handover::{prepare_all, Handover, Job, Report, QUEUE};
use nc_kernel::ipo::Input;
use nc_kernel::ipo::{Channel, ChannelState, Setpoint};
use nc_kernel::{AxisPos, MachineData, ToolTable};
use std::sync::Arc;

/// An auxiliary-function request as the PLC got it.
#[derive(Clone, Copy, Debug)]
pub struct Request {
    pub id: u64,
    pub cycle: u64,
    pub wait: bool,
    /// The first word: address letter and value.
    pub word: (u8, f64),
}

pub struct MockPlc {
    pub signals: PlcInput,
    /// Sends its signals (its sign of life) every cycle.
    pub alive: bool,
    /// Cycles from a request to its acknowledgement (`None`: never acknowledged).
    pub ack_after: Option<u64>,
    /// Takes no request (its queue is full).
    pub full: bool,
    pub status: Vec<Status>,
    pub requests: Vec<Request>,
    /// (due cycle, id) of acknowledgements still to send.
    due: Vec<(u64, u64)>,
    now: u64,
}

impl MockPlc {
    /// Room for `cycles` statuses, so that recording never allocates.
    pub fn new(cycles: usize) -> Self {
        MockPlc {
            signals: PlcInput {
                drives_ready: true,
                ..PlcInput::default()
            },
            alive: true,
            ack_after: Some(0),
            full: false,
            status: Vec::with_capacity(cycles),
            requests: Vec::with_capacity(256),
            due: Vec::with_capacity(256),
            now: 0,
        }
    }
}

impl Bus for MockPlc {
    fn plc(&mut self) -> Option<PlcInput> {
        self.alive.then_some(self.signals)
    }
    fn setpoint(&mut self, _sp: &Setpoint) {}
    fn aux(&mut self, out: &AuxOut<'_>) -> bool {
        if self.full || self.requests.len() == self.requests.capacity() {
            return false;
        }
        let w = out
            .aux
            .words
            .first()
            .map_or((0, 0.0), |w| (w.address, w.value));
        self.requests.push(Request {
            id: out.id,
            cycle: out.cycle,
            wait: out.wait,
            word: w,
        });
        if let Some(n) = self.ack_after {
            self.due.push((out.cycle + n, out.id));
        }
        true
    }
    fn acks(&mut self, f: &mut dyn FnMut(u64, Option<ChannelAlarm>)) {
        let now = self.now;
        self.due.retain(|&(at, id)| {
            if at < now {
                f(id, None);
                false
            } else {
                true
            }
        });
    }
    fn status(&mut self, st: &Status) {
        if self.status.len() < self.status.capacity() {
            self.status.push(*st);
        }
    }
}

/// `Cyclic` with its PLC on the mock clock.
pub struct Rig {
    pub cyclic: Box<Cyclic>,
    pub plc: MockPlc,
    pub k: u64,
}

impl Rig {
    pub fn new(md: &MachineData, cycles: usize) -> Rig {
        Rig {
            cyclic: Box::new(Cyclic::new(md, AxisPos::default())),
            plc: MockPlc::new(cycles),
            k: 0,
        }
    }

    pub fn step(&mut self) -> Status {
        self.plc.now = self.k;
        self.cyclic.cycle(self.k, &mut self.plc);
        self.k += 1;
        self.cyclic.status()
    }

    /// Cycles until `until` holds for a status (that one returned), at most `limit`.
    pub fn run_until(&mut self, limit: u64, until: impl Fn(&Status) -> bool) -> Status {
        for _ in 0..limit {
            let s = self.step();
            if until(&s) {
                return s;
            }
        }
        panic!(
            "not reached within {limit} cycles; last status {:?}",
            self.plc.status.last()
        );
    }

    pub fn ask(&mut self, c: Control) -> Result<(), Refusal> {
        self.cyclic.command(c)
    }

    /// Loads `text` where the axes stand and starts it (after a few cycles of PLC signals).
    pub fn load_and_start(&mut self, md: &MachineData, id: u32, text: &str) {
        for _ in 0..3 {
            self.step();
        }
        let at = self.cyclic.setpoint().axes();
        self.ask(Control::Load(program(md, id, text, Some(at))))
            .expect("load");
        self.ask(Control::Start).expect("NC start");
    }

    /// The recorded statuses from cycle `from` on.
    pub fn since(&self, from: u64) -> &[Status] {
        let i = self.plc.status.partition_point(|s| s.cycle < from);
        &self.plc.status[i..]
    }
}

/// A program prepared completely up front (at most `QUEUE` records) with its channel.
pub fn program(md: &MachineData, id: u32, text: &str, at: Option<AxisPos>) -> Box<Program> {
    let (p, inputs, reports) = fed(md, id, text, at);
    assert!(reports.is_empty(), "{reports:?}");
    assert!(inputs.len() <= QUEUE, "{} records", inputs.len());
    for i in inputs {
        if p.hand.queue.push(i).is_err() {
            unreachable!("the queue holds QUEUE records");
        }
    }
    p.hand
        .finished
        .store(true, std::sync::atomic::Ordering::Release);
    p
}

/// A program whose preparation the test plays: its channel and an empty hand-over, and the
/// records preparation would hand over (its alarm included) with its reports, for the test
/// to push when it likes.
pub fn fed(
    md: &MachineData,
    id: u32,
    text: &str,
    at: Option<AxisPos>,
) -> (Box<Program>, Vec<Input>, Vec<Report>) {
    let tools = ToolTable::builtin();
    let job = Job {
        name: "test.mpf",
        source: text,
        md,
        tools: &tools,
        at,
    };
    let (start, inputs, reports) = prepare_all(job);
    let program = Box::new(Program {
        id,
        channel: Box::new(Channel::new(md, start)),
        hand: Arc::new(Handover::default()),
        start,
    });
    (program, inputs, reports)
}

pub fn state(s: &Status) -> ChannelState {
    s.state.unwrap_or(ChannelState::Reset)
}
