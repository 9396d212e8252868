//! OPC UA as a source and a sink, through the async-opcua client (OPC UA Part 4 services; no
//! protocol code of our own). One session per process, anonymous, security mode None:
//!
//! - source: one subscription (publishing interval = the period) with a monitored item per input
//!   node, sampling interval = the period, a queue of 1000 values and the data change trigger
//!   `StatusValueTimestamp`, so that every reading reaches the client with its source timestamp
//!   even when its value repeats; readings are assembled into samples by their source timestamps
//!   ([`crate::assemble`]); a reading with a bad status is reported and left out, so the sample
//!   waits (a lost sensor becomes a gap);
//! - sink: each step's offsets written to the output nodes (Double, mm unless the mapping says
//!   um), with the source timestamp of the sample they belong to;
//! - every node id is read once at the start: one that does not exist is refused (exit 2), naming
//!   it; a server that cannot be reached at the start ends the process (exit 3);
//! - a connection lost later (link.rs says how that is seen) is built again whole, with a
//!   backoff of 0.5 s doubling to 5 s, until it is back (reconnect.rs); the loss, the attempts
//!   (thinned to one line a minute) and the reconnection are logged.
//!
//! Times: source timestamps (100 ns ticks since 1601) as seconds since the Unix epoch.

use crate::assemble::Assembler;
use crate::engine::{Sample, Step};
use crate::source::{Event, Sink, Source};
use crate::{environment, input, LiveError};
use link::Link;
use opcua::client::{MonitoredItemMap, OnSubscriptionNotificationCore};
use opcua::types::{DataChangeNotification, DataValue, DateTime, NodeId, NotificationMessage, Variant};
use reconnect::{keep_up, Plan, Write};
use std::collections::VecDeque;
use std::str::FromStr;
use std::sync::mpsc;
use std::time::Duration;

mod link;
mod reconnect;

/// 100 ns ticks from 1601-01-01 to 1970-01-01.
const UNIX_EPOCH_TICKS: i64 = 116_444_736_000_000_000;

/// Seconds since the Unix epoch of an OPC UA time stamp.
pub fn unix_seconds(t: &DateTime) -> f64 {
    (t.ticks() - UNIX_EPOCH_TICKS) as f64 / 1e7
}

/// The OPC UA time stamp of seconds since the Unix epoch.
pub fn date_time(unix_s: f64) -> DateTime {
    DateTime::from(UNIX_EPOCH_TICKS + (unix_s * 1e7).round() as i64)
}

/// What to subscribe to and write.
#[derive(Clone, Debug, Default)]
pub struct Nodes {
    /// (input name, node id) per engine input; empty when OPC UA is only the sink.
    pub inputs: Vec<(String, String)>,
    /// The run node, if any.
    pub run: Option<String>,
    /// (offset index, node id, factor from um) per written axis.
    pub outputs: Vec<(usize, String, f64)>,
}

enum Incoming {
    Values(Vec<(u32, DataValue)>),
    Note(String),
    /// The connection cannot go on (the process ends, exit 3).
    Failed(String),
}

/// The connection: the source side.
pub struct OpcUaSource {
    incoming: mpsc::Receiver<Incoming>,
    assembler: Assembler,
    inputs: Vec<String>,
    runs: VecDeque<(f64, String)>,
    has_run: bool,
    pending: VecDeque<Event>,
}

/// The connection: the sink side.
pub struct OpcUaSink {
    writes: tokio::sync::mpsc::UnboundedSender<Write>,
    outputs: Vec<(usize, f64)>,
    /// The messages of a connection that is only a sink (no source reads them).
    incoming: Option<mpsc::Receiver<Incoming>>,
}

impl OpcUaSink {
    /// A sink that reports its connection's messages itself (its source side is not used).
    pub fn reporting(mut self, source: OpcUaSource) -> OpcUaSink {
        self.incoming = Some(source.incoming);
        self
    }
}

fn parse_node(id: &str, what: &str) -> Result<NodeId, LiveError> {
    NodeId::from_str(id).map_err(|_| input(format!("{what}: `{id}` is not an OPC UA node id (ns=2;s=Name, ns=2;i=1001, ...)")))
}

/// Forwards each notification message as one batch.
struct Forward(mpsc::Sender<Incoming>);

impl OnSubscriptionNotificationCore for Forward {
    fn on_subscription_notification(&mut self, notification: NotificationMessage, _items: MonitoredItemMap<'_>) {
        let mut batch = Vec::new();
        for obj in notification.notification_data.into_iter().flatten() {
            if let Some(change) = obj.into_inner_as::<DataChangeNotification>() {
                batch.extend(change.monitored_items.into_iter().flatten().map(|n| (n.client_handle, n.value)));
            }
        }
        if !batch.is_empty() {
            let _ = self.0.send(Incoming::Values(batch));
        }
    }
}

/// Connects to `url`, checks every node, subscribes to the inputs; blocks until ready or refused.
/// The connection is then kept up (reconnect.rs); `give_up`: the longest time without it.
pub fn connect(url: &str, nodes: Nodes, period: Duration, give_up: Option<Duration>) -> Result<(OpcUaSource, OpcUaSink), LiveError> {
    let mut ids = Vec::new();
    for (name, id) in &nodes.inputs {
        ids.push((parse_node(id, &format!("input {name}"))?, format!("input {name}")));
    }
    if let Some(id) = &nodes.run {
        ids.push((parse_node(id, "the run node")?, "the run node".into()));
    }
    let outputs: Vec<NodeId> = nodes.outputs.iter().map(|(_, id, _)| parse_node(id, "an output node")).collect::<Result<_, _>>()?;
    for ((k, _, _), id) in nodes.outputs.iter().zip(&outputs) {
        ids.push((id.clone(), format!("the offset node of axis {k}")));
    }
    let (tx, rx) = mpsc::channel();
    let (ready_tx, ready_rx) = mpsc::channel::<Result<(), LiveError>>();
    let (write_tx, write_rx) = tokio::sync::mpsc::unbounded_channel();
    let subscribed = nodes.inputs.len() + usize::from(nodes.run.is_some());
    let plan = Plan { url: url.to_string(), ids, subscribed, outputs, period, give_up };
    std::thread::Builder::new()
        .name("opcua".into())
        .spawn(move || {
            let runtime = match tokio::runtime::Builder::new_current_thread().enable_all().build() {
                Ok(r) => r,
                Err(e) => {
                    let _ = ready_tx.send(Err(environment(format!("cannot start the OPC UA runtime: {e}"))));
                    return;
                }
            };
            runtime.block_on(async move {
                match Link::open(&plan, &tx, || None).await {
                    Ok(link) => {
                        let _ = ready_tx.send(Ok(()));
                        keep_up(plan, link, write_rx, tx).await;
                    }
                    Err(e) => {
                        let _ = ready_tx.send(Err(e));
                    }
                }
            });
        })
        .map_err(|e| environment(format!("cannot start the OPC UA thread: {e}")))?;
    ready_rx.recv().map_err(|_| environment("the OPC UA connection ended while starting"))??;
    let source = OpcUaSource {
        incoming: rx,
        assembler: Assembler::new(nodes.inputs.len()),
        inputs: nodes.inputs.iter().map(|(n, _)| n.clone()).collect(),
        runs: VecDeque::new(),
        has_run: nodes.run.is_some(),
        pending: VecDeque::new(),
    };
    let sink = OpcUaSink { writes: write_tx, outputs: nodes.outputs.iter().map(|(k, _, f)| (*k, *f)).collect(), incoming: None };
    Ok((source, sink))
}

impl OpcUaSource {
    fn take(&mut self, batch: Vec<(u32, DataValue)>) {
        let n = self.inputs.len();
        for (handle, v) in batch {
            let k = handle as usize - 1;
            let time = v.source_timestamp.as_ref().or(v.server_timestamp.as_ref()).map(unix_seconds);
            let (Some(time), true) = (time, v.status.is_none_or(|s| s.is_good())) else {
                let name = if k < n { self.inputs[k].as_str() } else { "run" };
                self.pending
                    .push_back(Event::Note(format!("{name}: reading with status {:?} and no usable time stamp left out", v.status)));
                continue;
            };
            match (k < n, &v.value) {
                (true, Some(value)) => match value.as_f64() {
                    Some(x) => self.assembler.push(k, time, x),
                    None => self.pending.push_back(Event::Note(format!("{}: the value {value:?} is not a number", self.inputs[k]))),
                },
                (false, Some(value)) => self.runs.push_back((time, variant_text(value))),
                _ => {}
            }
        }
        while let Some((t, readings)) = self.assembler.pop() {
            while self.runs.len() > 1 && self.runs[1].0 <= t {
                self.runs.pop_front();
            }
            let run = if self.has_run {
                Some(self.runs.front().filter(|(tr, _)| *tr <= t).map_or(String::new(), |(_, r)| r.clone()))
            } else {
                None
            };
            self.pending.push_back(Event::Sample(Sample { time_s: t, run, readings }));
        }
    }
}

fn variant_text(v: &Variant) -> String {
    match v {
        Variant::String(s) => s.to_string(),
        other => other.as_f64().map_or_else(|| format!("{other:?}"), |x| x.to_string()),
    }
}

impl Source for OpcUaSource {
    fn next(&mut self, timeout: Duration) -> Result<Option<Event>, LiveError> {
        if let Some(e) = self.pending.pop_front() {
            return Ok(Some(e));
        }
        match self.incoming.recv_timeout(timeout) {
            Ok(Incoming::Values(batch)) => self.take(batch),
            Ok(Incoming::Note(n)) => self.pending.push_back(Event::Note(n)),
            Ok(Incoming::Failed(why)) => return Err(environment(why)),
            Err(mpsc::RecvTimeoutError::Timeout) => return Ok(None),
            Err(mpsc::RecvTimeoutError::Disconnected) => return Err(environment("the OPC UA connection ended")),
        }
        Ok(self.pending.pop_front())
    }
}

impl Sink for OpcUaSink {
    fn write(&mut self, step: &Step) -> Result<(), LiveError> {
        if !step.write || self.outputs.is_empty() {
            return Ok(());
        }
        let values = self.outputs.iter().enumerate().map(|(i, (k, f))| (i, step.offsets_um[*k] * f)).collect();
        self.writes.send((step.time_s, values)).map_err(|_| environment("the OPC UA connection ended"))
    }

    fn notes(&mut self) -> Result<Vec<String>, LiveError> {
        let mut notes = Vec::new();
        while let Some(m) = self.incoming.as_ref().and_then(|r| r.try_recv().ok()) {
            match m {
                Incoming::Note(n) => notes.push(n),
                Incoming::Failed(why) => return Err(environment(why)),
                Incoming::Values(_) => {}
            }
        }
        Ok(notes)
    }
}
