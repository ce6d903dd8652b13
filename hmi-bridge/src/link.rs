//! The bridge's side of the control: one thread owns every iceoryx2 port (they stay in the
//! thread that made them). It keeps the newest kernel status, actual values, tool table and
//! work-offset table in a [`Snapshot`] for the HTTP workers, sends their commands to the kernel one at a time
//! (so edits from several clients are serialised here, and again in the kernel), and pushes
//! the snapshot to the Server-Sent-Events subscribers. The OPC UA server (softnc-opcua)
//! reads the kernel through the same link, under a node name of its own.

use crossbeam::channel::{Receiver, Sender, TrySendError};
use softnc_protocol::iceoryx2::prelude::ipc;
use softnc_protocol::{
    command, newest, ActualValues, Command, Instance, KernelStatus, Reply, ToolTableMsg,
    WorkOffsetsMsg,
};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The kernel counts as there while its status arrived within this time.
const ALIVE: Duration = Duration::from_millis(500);
/// How long a command may take to be answered.
const REPLY_WAIT: Duration = Duration::from_secs(5);
/// How often subscribers get the snapshot.
const PUSH_EVERY: Duration = Duration::from_millis(100);

/// What the bridge knows of the control.
#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    pub status: Option<KernelStatus>,
    pub status_age: Option<Duration>,
    pub actual: Option<ActualValues>,
    pub tools: Option<ToolTableMsg>,
    /// The kernel's work offsets (G54 …), every set of its dialect.
    pub work_offsets: Option<WorkOffsetsMsg>,
    /// The path of the program in `status.program`, as the kernel loaded it.
    pub program_path: Option<String>,
}

impl Snapshot {
    pub fn connected(&self) -> bool {
        self.status_age.is_some_and(|a| a < ALIVE)
    }
}

/// A command from an HTTP worker and where its answer goes.
pub struct Job {
    pub command: Command,
    pub answer: Sender<Result<Reply, String>>,
}

/// The HTTP side's handle on the link thread.
#[derive(Clone)]
pub struct Link {
    jobs: Sender<Job>,
    snapshot: Arc<Mutex<Snapshot>>,
    subscribers: Arc<Mutex<Vec<Sender<String>>>>,
}

impl Link {
    pub fn snapshot(&self) -> Snapshot {
        self.snapshot.lock().map(|s| s.clone()).unwrap_or_default()
    }

    /// Sends a command to the kernel and waits for the reply.
    pub fn ask(&self, command: Command) -> Result<Reply, String> {
        let (tx, rx) = crossbeam::channel::bounded(1);
        self.jobs
            .send(Job {
                command,
                answer: tx,
            })
            .map_err(|_| "the bridge's link to the kernel has ended".to_string())?;
        rx.recv_timeout(REPLY_WAIT + Duration::from_secs(1))
            .map_err(|_| "the kernel did not answer".to_string())?
    }

    /// A new subscriber: it gets the snapshot as JSON text every `PUSH_EVERY` while it keeps
    /// up (a full queue drops it).
    pub fn subscribe(&self) -> Receiver<String> {
        let (tx, rx) = crossbeam::channel::bounded(16);
        if let Ok(mut s) = self.subscribers.lock() {
            s.push(tx);
        }
        rx
    }
}

/// A link without a kernel, for tests of the HTTP side: `snapshot` is what it knows, and
/// every command asked of it arrives at the receiver (and is answered by whoever holds it,
/// or not at all).
#[cfg(test)]
pub fn fake(snapshot: Snapshot) -> (Link, Receiver<Job>) {
    let (jobs, rx) = crossbeam::channel::unbounded();
    let link = Link {
        jobs,
        snapshot: Arc::new(Mutex::new(snapshot)),
        subscribers: Arc::default(),
    };
    (link, rx)
}

/// Starts the link thread under the iceoryx2 node name `role` (the bridge's, or another
/// reader's such as the OPC UA server); returns when its ports are open (or why they could
/// not be). `to_json` renders the snapshot for the event-stream subscribers.
pub fn start(
    instance: Instance,
    role: &'static str,
    to_json: fn(&Snapshot) -> String,
    stop: Arc<AtomicBool>,
) -> Result<(Link, std::thread::JoinHandle<()>), String> {
    let (jobs_tx, jobs_rx) = crossbeam::channel::unbounded::<Job>();
    let snapshot = Arc::new(Mutex::new(Snapshot::default()));
    let subscribers: Arc<Mutex<Vec<Sender<String>>>> = Arc::default();
    let link = Link {
        jobs: jobs_tx,
        snapshot: snapshot.clone(),
        subscribers: subscribers.clone(),
    };
    let (ready_tx, ready_rx) = crossbeam::channel::bounded::<Result<(), String>>(1);
    let thread = std::thread::Builder::new()
        .name("link".into())
        .spawn(move || {
            if let Err(e) = serve(
                &instance,
                role,
                &jobs_rx,
                &snapshot,
                &subscribers,
                to_json,
                &stop,
                &ready_tx,
            ) {
                let _ = ready_tx.send(Err(e));
            }
        })
        .map_err(|e| format!("cannot start the link thread: {e}"))?;
    match ready_rx.recv() {
        Ok(Ok(())) => Ok((link, thread)),
        Ok(Err(e)) => {
            let _ = thread.join();
            Err(e)
        }
        Err(_) => {
            let _ = thread.join();
            Err("the link thread ended before it was ready".into())
        }
    }
}

type Client = softnc_protocol::iceoryx2::port::client::Client<ipc::Service, Command, (), Reply, ()>;

#[allow(clippy::too_many_arguments)]
fn serve(
    instance: &Instance,
    role: &str,
    jobs: &Receiver<Job>,
    snapshot: &Mutex<Snapshot>,
    subscribers: &Mutex<Vec<Sender<String>>>,
    to_json: fn(&Snapshot) -> String,
    stop: &AtomicBool,
    ready: &Sender<Result<(), String>>,
) -> Result<(), String> {
    let node = instance.node(role).map_err(|e| e.to_string())?;
    let e = |w: &str, x: &dyn std::fmt::Debug| format!("cannot create the {w}: {x:?}");
    let client: Client = instance
        .commands(&node)
        .map_err(|e| e.to_string())?
        .client_builder()
        .create()
        .map_err(|x| e("command client", &x))?;
    let status = instance
        .status(&node)
        .map_err(|e| e.to_string())?
        .subscriber_builder()
        .create()
        .map_err(|x| e("status subscriber", &x))?;
    let actuals = instance
        .actual_values(&node)
        .map_err(|e| e.to_string())?
        .subscriber_builder()
        .create()
        .map_err(|x| e("actual-value subscriber", &x))?;
    let tools = instance
        .tools(&node)
        .map_err(|e| e.to_string())?
        .subscriber_builder()
        .create()
        .map_err(|x| e("tool-table subscriber", &x))?;
    let work_offsets = instance
        .work_offsets(&node)
        .map_err(|e| e.to_string())?
        .subscriber_builder()
        .create()
        .map_err(|x| e("work-offset subscriber", &x))?;
    let _ = ready.send(Ok(()));

    let mut last_status: Option<Instant> = None;
    let mut known_program = 0u32;
    let mut last_push = Instant::now();
    let drain = |snap: &mut Snapshot, last_status: &mut Option<Instant>| {
        if let Some(s) = newest(&status) {
            snap.status = Some(s);
            *last_status = Some(Instant::now());
        }
        snap.actual = newest(&actuals).or(snap.actual);
        snap.tools = newest(&tools).or(snap.tools);
        snap.work_offsets = newest(&work_offsets).or(snap.work_offsets);
        snap.status_age = last_status.map(|t| t.elapsed());
    };
    while !stop.load(Ordering::Relaxed) {
        let mut snap = snapshot.lock().map(|s| s.clone()).unwrap_or_default();
        drain(&mut snap, &mut last_status);
        // The path of a newly loaded program (for its text and its plot).
        let program = snap.status.map_or(0, |s| s.program);
        if program != known_program && snap.connected() {
            let mut c = Command::new(command::PROGRAM_INFO);
            c.d = program;
            snap.program_path = match ask(&client, c) {
                Ok(r) if r.ok != 0 => Some(r.message().to_string()),
                _ => None,
            };
            known_program = program;
        }
        if let Ok(mut s) = snapshot.lock() {
            *s = snap.clone();
        }
        if let Ok(job) = jobs.try_recv() {
            let answer = if snap.connected() {
                ask(&client, job.command)
            } else {
                Err("the kernel is not running (no status from it)".to_string())
            };
            // What the kernel published before its reply (a new tool or work-offset table) is in the
            // snapshot before the asker hears back: reads after a write see it.
            drain(&mut snap, &mut last_status);
            if let Ok(mut s) = snapshot.lock() {
                *s = snap.clone();
            }
            let _ = job.answer.send(answer);
        }
        if last_push.elapsed() >= PUSH_EVERY {
            last_push = Instant::now();
            if let Ok(mut subs) = subscribers.lock() {
                if !subs.is_empty() {
                    let text = to_json(&snap);
                    subs.retain(|s| match s.try_send(text.clone()) {
                        Ok(()) => true,
                        Err(TrySendError::Full(_)) | Err(TrySendError::Disconnected(_)) => false,
                    });
                }
            }
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    Ok(())
}

/// One command, its reply awaited (the only request in flight: the link is serial). A
/// request that reached no server (the kernel is still starting its command service) is sent
/// again once it is there.
fn ask(client: &Client, c: Command) -> Result<Reply, String> {
    use softnc_protocol::iceoryx2::port::update_connections::UpdateConnections;
    let t = Instant::now();
    let pending = loop {
        let p = client
            .send_copy(c)
            .map_err(|e| format!("cannot send the command to the kernel: {e:?}"))?;
        if p.number_of_server_connections() > 0 {
            break p;
        }
        if t.elapsed() > REPLY_WAIT {
            return Err("the kernel's command service is not there".into());
        }
        std::thread::sleep(Duration::from_millis(20));
        let _ = client.update_connections();
    };
    while t.elapsed() < REPLY_WAIT {
        match pending.receive() {
            Ok(Some(r)) => return Ok(*r.payload()),
            Ok(None) => std::thread::sleep(Duration::from_millis(1)),
            Err(e) => return Err(format!("no reply from the kernel: {e:?}")),
        }
    }
    Err("the kernel did not answer in time".into())
}
