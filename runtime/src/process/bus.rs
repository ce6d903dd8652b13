//! The IPO thread's ports: the [`Bus`] over iceoryx2. Every call returns at once: publishers
//! overwrite a slow subscriber's oldest sample, requests go out without waiting, and
//! answers are polled.

use crate::os;
use nc_kernel::cycle::{AuxOut, Bus, ChannelAlarm, PlcInput, Status};
use nc_kernel::ipo::{ChannelState, Setpoint};
use softnc_protocol::iceoryx2::node::Node;
use softnc_protocol::iceoryx2::pending_response::PendingResponse;
use softnc_protocol::iceoryx2::port::client::Client;
use softnc_protocol::iceoryx2::port::notifier::Notifier;
use softnc_protocol::iceoryx2::port::publisher::Publisher;
use softnc_protocol::iceoryx2::prelude::ipc;
use softnc_protocol::{
    newest, spindle_mode, state, AuxAck, AuxRequest, AuxWordMsg, Instance, IpcError, KernelStatus,
    PlcSignals, SetpointMsg, Sub, AUX_WORDS,
};

type Pending = PendingResponse<ipc::Service, AuxRequest, (), AuxAck, ()>;

pub struct IceBus {
    // Ports before the node: they are dropped first.
    setpoints: Publisher<ipc::Service, SetpointMsg, ()>,
    wake: Notifier<ipc::Service>,
    aux: Client<ipc::Service, AuxRequest, (), AuxAck, ()>,
    pending: heapless::Vec<(u64, Pending), 32>,
    signals: Sub<PlcSignals>,
    status: Publisher<ipc::Service, KernelStatus, ()>,
    _node: Node<ipc::Service>,
    seq: u64,
    status_seq: u64,
    /// The end of the running cycle, ns (the setpoint's deadline), set by the IPO loop.
    pub deadline_ns: u64,
    /// Periods the IPO loop skipped so far (runtime/clock.rs), for the status.
    pub skipped: u64,
    /// The tool table's version, for the status (set by the control thread's commands).
    pub tools_version: u32,
    pub work_offsets_version: u32,
    cycle_ns: u64,
    axes: crate::WireAxes,
    /// Sends that failed (no memory to loan, a peer gone while sending).
    pub send_errors: u64,
}

pub fn state_code(s: ChannelState) -> u8 {
    match s {
        ChannelState::Reset => state::RESET,
        ChannelState::Active => state::ACTIVE,
        ChannelState::Stopped => state::STOPPED,
        ChannelState::End => state::END,
    }
}

impl IceBus {
    pub fn open(
        instance: &Instance,
        cycle_ns: u64,
        axes: crate::WireAxes,
    ) -> Result<Self, IpcError> {
        let node = instance.node("nc-kernel")?;
        let err = |what: &str, e: &dyn std::fmt::Debug| {
            IpcError(format!(
                "{}: cannot create the {what}: {e:?}",
                instance.name()
            ))
        };
        let setpoints = instance
            .setpoints(&node)?
            .publisher_builder()
            .create()
            .map_err(|e| err("setpoint publisher", &e))?;
        let wake = instance
            .setpoint_event(&node)?
            .notifier_builder()
            .create()
            .map_err(|e| err("setpoint notifier", &e))?;
        let aux = instance
            .aux(&node)?
            .client_builder()
            .create()
            .map_err(|e| err("aux client", &e))?;
        let signals = instance
            .plc_signals(&node)?
            .subscriber_builder()
            .create()
            .map_err(|e| err("PLC signal subscriber", &e))?;
        let status = instance
            .status(&node)?
            .publisher_builder()
            .create()
            .map_err(|e| err("status publisher", &e))?;
        // Opened so that every service of the instance exists whoever starts first.
        instance.actual_values(&node)?;
        Ok(IceBus {
            setpoints,
            wake,
            aux,
            pending: heapless::Vec::new(),
            signals,
            status,
            _node: node,
            seq: 0,
            status_seq: 0,
            deadline_ns: 0,
            skipped: 0,
            tools_version: 1,
            work_offsets_version: 1,
            cycle_ns,
            axes,
            send_errors: 0,
        })
    }
}

impl Bus for IceBus {
    fn plc(&mut self) -> Option<PlcInput> {
        newest(&self.signals).map(|s| PlcInput {
            feed_hold: s.feed_hold != 0,
            read_in_disable: s.read_in_disable != 0,
            drives_ready: s.drives_ready != 0,
            emergency_stop: s.emergency_stop != 0,
            alarm: ChannelAlarm::new(s.alarm),
            spindle_rpm: if s.spindle_rpm[0].is_finite() {
                s.spindle_rpm[0]
            } else {
                0.0
            },
        })
    }

    fn setpoint(&mut self, sp: &Setpoint) {
        self.seq += 1;
        let msg = SetpointMsg {
            seq: self.seq,
            cycle: sp.cycle,
            sent_ns: os::now_ns(),
            deadline_ns: self.deadline_ns,
            cycle_us: (self.cycle_ns / 1000) as u32,
            line: sp.source.map_or(0, |s| s.line),
            pos: self.axes.to_wire(&sp.axes()),
            v_path: sp.v_path,
            state: state_code(sp.state),
            axes: self.axes.list.count,
            spindles: 1,
            spindle_mode: [spindle_mode_code(sp.spindle_dir), spindle_mode::STOP],
            _pad: [0; 3],
            spindle: [sp.spindle, 0.0],
        };
        let sent = match self.setpoints.loan_uninit() {
            Ok(s) => s.write_payload(msg).send().is_ok(),
            Err(_) => false,
        };
        if !sent || self.wake.notify().is_err() {
            self.send_errors += 1;
        }
    }

    fn aux(&mut self, out: &AuxOut<'_>) -> bool {
        if self.pending.is_full() {
            return false;
        }
        let mut words = [AuxWordMsg::default(); AUX_WORDS];
        let mut count = 0;
        for (w, slot) in out.aux.words.iter().zip(words.iter_mut()) {
            *slot = AuxWordMsg {
                address: w.address.to_ascii_uppercase(),
                _pad: [0; 7],
                value: w.value,
            };
            count += 1;
        }
        let req = AuxRequest {
            id: out.id,
            cycle: out.cycle,
            line: out.aux.source.line,
            count,
            words,
            wait: out.wait as u8,
            _pad: [0; 7],
        };
        match self.aux.send_copy(req) {
            Ok(p) => self.pending.push((out.id, p)).is_ok(),
            Err(_) => false,
        }
    }

    fn acks(&mut self, f: &mut dyn FnMut(u64, Option<ChannelAlarm>)) {
        let mut i = 0;
        while i < self.pending.len() {
            let answered = match self.pending[i].1.receive() {
                Ok(Some(r)) => Some(ChannelAlarm::new(r.payload().alarm)),
                _ => None,
            };
            if let Some(alarm) = answered {
                f(self.pending[i].0, alarm);
                // Order among the pending ones does not matter; swap_remove keeps it cheap.
                drop(self.pending.swap_remove(i));
            } else {
                i += 1;
            }
        }
    }

    fn status(&mut self, st: &Status) {
        self.status_seq += 1;
        let msg = KernelStatus {
            seq: self.status_seq,
            cycle: st.cycle,
            program: st.program,
            line: st.line,
            pos: self.axes.to_wire(&st.axes()),
            axes: self.axes.list,
            v_path: st.v_path,
            override_: st.override_,
            alarm: ChannelAlarm::wire(st.alarm),
            aux_sent: st.aux_sent,
            aux_acked: st.aux_acked,
            tools_version: self.tools_version,
            work_offsets_version: self.work_offsets_version,
            plc_cycle: st.plc_cycle,
            state: st.state.map_or(state::RESET, state_code),
            single_block: st.single_block as u8,
            plc_alive: st.plc_alive as u8,
            role: st.progress.map_or(0, |p| p.role.code()),
            skipped: self.skipped.min(u64::from(u32::MAX)) as u32,
            block_seq: st.progress.map_or(0, |p| p.source.seq),
            piece: st.progress.map_or(0, |p| p.nth),
            along: st.progress.map_or(0.0, |p| p.along),
            work_offset: st.tech.work_offset.into(),
            tool: st.tech.tool,
            edge: st.tech.d,
            spindle: [st.spindle, 0.0],
        };
        if self.status.send_copy(msg).is_err() {
            self.send_errors += 1;
        }
    }
}

/// The wire's code for what the spindle is told to do.
fn spindle_mode_code(d: nc_kernel::SpindleDir) -> u8 {
    match d {
        nc_kernel::SpindleDir::Stop => spindle_mode::STOP,
        nc_kernel::SpindleDir::Clockwise | nc_kernel::SpindleDir::CounterClockwise => {
            spindle_mode::TURN
        }
        nc_kernel::SpindleDir::Orient => spindle_mode::ORIENT,
    }
}
