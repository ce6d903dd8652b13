//! plc-sim's [`Transport`] in the process: the instance's services over iceoryx2, the
//! monotonic clock, stderr and the CSV trace. The wire's numbers (flags as 0/1, alarm 0 for
//! none, sequence numbers) are made here.

use crate::plc::{Actual, Row, Signals, Transport};
use crate::trace;
use nc_kernel::cycle::ChannelAlarm;
use softnc_protocol::iceoryx2::active_request::ActiveRequest;
use softnc_protocol::iceoryx2::node::Node;
use softnc_protocol::iceoryx2::port::listener::Listener;
use softnc_protocol::iceoryx2::port::publisher::Publisher;
use softnc_protocol::iceoryx2::port::server::Server;
use softnc_protocol::iceoryx2::prelude::ipc;
use softnc_protocol::{ActualValues, AuxAck, AuxRequest, Instance, PlcSignals, SetpointMsg, Sub};
use std::time::Duration;

type Request = ActiveRequest<ipc::Service, AuxRequest, (), AuxAck, ()>;

pub struct Ice {
    // Ports before the node: they are dropped first.
    setpoints: Sub<SetpointMsg>,
    listener: Listener<ipc::Service>,
    server: Server<ipc::Service, AuxRequest, (), AuxAck, ()>,
    signals: Publisher<ipc::Service, PlcSignals, ()>,
    actuals: Publisher<ipc::Service, ActualValues, ()>,
    _node: Node<ipc::Service>,
    /// Requests taken, not yet answered, by ticket.
    requests: Vec<(u64, Request)>,
    next_ticket: u64,
    signal_seq: u64,
    actual_seq: u64,
    trace: Option<trace::Trace>,
}

impl Ice {
    /// Opens plc-sim's ports of `instance`, after removing what dead processes of it left;
    /// the trace, if any, goes to `trace`.
    pub fn open(instance: &Instance, trace: Option<trace::Trace>) -> Result<Ice, String> {
        let (cleaned, _) = instance.cleanup_dead_nodes();
        if cleaned > 0 {
            eprintln!(
                "plc-sim: removed what {cleaned} dead process(es) of instance '{}' left behind",
                instance.name()
            );
        }
        let node = instance.node("plc-sim").map_err(|e| e.to_string())?;
        let e = |w: &str, x: &dyn std::fmt::Debug| format!("cannot create the {w}: {x:?}");
        let s = |x: softnc_protocol::IpcError| x.to_string();
        let setpoints = instance.setpoints(&node).map_err(s)?;
        let setpoints = setpoints
            .subscriber_builder()
            .create()
            .map_err(|x| e("setpoint subscriber", &x))?;
        let listener = instance.setpoint_event(&node).map_err(s)?;
        let listener = listener
            .listener_builder()
            .create()
            .map_err(|x| e("setpoint listener", &x))?;
        let server = instance.aux(&node).map_err(s)?;
        let server = server
            .server_builder()
            .create()
            .map_err(|x| e("aux server", &x))?;
        let signals = instance.plc_signals(&node).map_err(s)?;
        let signals = signals
            .publisher_builder()
            .create()
            .map_err(|x| e("signal publisher", &x))?;
        let actuals = instance.actual_values(&node).map_err(s)?;
        let actuals = actuals
            .publisher_builder()
            .create()
            .map_err(|x| e("actual-value publisher", &x))?;
        // Opened so that the instance's services exist whoever starts first.
        instance.status(&node).map_err(s)?;
        instance.commands(&node).map_err(s)?;
        Ok(Ice {
            setpoints,
            listener,
            server,
            signals,
            actuals,
            _node: node,
            requests: Vec::new(),
            next_ticket: 1,
            signal_seq: 0,
            actual_seq: 0,
            trace,
        })
    }

    /// Ends the trace: what is buffered is written.
    pub fn finish(&mut self) -> Result<(), String> {
        self.trace.take().map_or(Ok(()), trace::Trace::finish)
    }
}

impl Transport for Ice {
    fn now_ns(&mut self) -> u64 {
        nc_runtime::os::now_ns()
    }

    fn wait(&mut self, timeout: Duration) -> bool {
        let mut event = false;
        let _ = self.listener.timed_wait(|_| event = true, timeout);
        event
    }

    fn setpoint(&mut self) -> Option<SetpointMsg> {
        match self.setpoints.receive() {
            Ok(Some(s)) => Some(*s.payload()),
            _ => None,
        }
    }

    fn request(&mut self) -> Option<(u64, AuxRequest)> {
        let req = match self.server.receive() {
            Ok(Some(r)) => r,
            _ => return None,
        };
        let r = *req.payload();
        let ticket = self.next_ticket;
        self.next_ticket += 1;
        self.requests.push((ticket, req));
        Some((ticket, r))
    }

    fn ack(&mut self, ticket: u64, id: u64) {
        if let Some(i) = self.requests.iter().position(|(t, _)| *t == ticket) {
            let (_, req) = self.requests.swap_remove(i);
            let _ = req.send_copy(AuxAck {
                id,
                alarm: 0,
                _pad: 0,
            });
        }
    }

    fn signals(&mut self, echo_cycle: u64, s: &Signals) {
        self.signal_seq += 1;
        let _ = self.signals.send_copy(PlcSignals {
            seq: self.signal_seq,
            echo_cycle,
            feed_hold: s.feed_hold as u8,
            read_in_disable: s.read_in_disable as u8,
            drives_ready: s.drives_ready as u8,
            emergency_stop: s.emergency_stop as u8,
            alarm: ChannelAlarm::wire(s.alarm),
            spindle_rpm: s.spindle_rpm,
        });
    }

    fn actuals(&mut self, a: &Actual) {
        self.actual_seq += 1;
        let _ = self.actuals.send_copy(ActualValues {
            seq: self.actual_seq,
            cycle: a.cycle,
            pos: a.pos,
            following_error: a.following_error,
            spindle_rpm: a.spindle_rpm,
            tool: a.tool,
            aux_acked: a.aux_acked,
            plc_alarm: ChannelAlarm::wire(a.alarm),
            _pad: 0,
        });
    }

    fn row(&mut self, r: &Row<'_>) {
        if let Some(t) = &mut self.trace {
            // A full disk or a disk far behind shows at the end, when the trace is finished.
            t.row(r);
        }
    }

    fn log(&mut self, line: &str) {
        eprintln!("plc-sim: {line}");
    }
}
