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
//!   it; a server that cannot be reached at the start ends the process (exit 3); a connection lost
//!   later is retried every 0.5 to 5 s by the client, the subscription recreated, and the loss and
//!   the reconnection are logged.
//!
//! Times: source timestamps (100 ns ticks since 1601) as seconds since the Unix epoch.

use crate::assemble::Assembler;
use crate::engine::{Sample, Step};
use crate::source::{Event, Sink, Source};
use crate::{environment, input, LiveError};
use futures::StreamExt;
use opcua::client::{
    ClientBuilder, IdentityToken, MonitoredItemMap, OnSubscriptionNotificationCore, Session, SessionConnectMode, SessionPollResult,
};
use opcua::types::{
    AttributeId, DataChangeFilter, DataChangeNotification, DataChangeTrigger, DataValue, DateTime, EndpointDescription, ExtensionObject,
    MessageSecurityMode, MonitoredItemCreateRequest, MonitoringMode, MonitoringParameters, NodeId, NotificationMessage, NumericRange,
    ReadValueId, StatusCode, TimestampsToReturn, UserTokenPolicy, Variant, WriteValue,
};
use std::collections::VecDeque;
use std::str::FromStr;
use std::sync::{mpsc, Arc};
use std::time::Duration;

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
    writes: tokio::sync::mpsc::UnboundedSender<(f64, Vec<(usize, f64)>)>,
    outputs: Vec<(usize, f64)>,
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
pub fn connect(url: &str, nodes: Nodes, period: Duration) -> Result<(OpcUaSource, OpcUaSink), LiveError> {
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
    let url = url.to_string();
    let subscribed = nodes.inputs.len() + usize::from(nodes.run.is_some());
    std::thread::spawn(move || {
        let runtime = match tokio::runtime::Builder::new_current_thread().enable_all().build() {
            Ok(r) => r,
            Err(e) => {
                let _ = ready_tx.send(Err(environment(format!("cannot start the OPC UA runtime: {e}"))));
                return;
            }
        };
        runtime.block_on(async move {
            match open(&url, &ids, subscribed, period, tx.clone()).await {
                Ok(session) => {
                    let _ = ready_tx.send(Ok(()));
                    write_loop(session, outputs, write_rx, tx).await;
                }
                Err(e) => {
                    let _ = ready_tx.send(Err(e));
                }
            }
        });
    });
    ready_rx.recv().map_err(|_| environment("the OPC UA connection ended while starting"))??;
    let source = OpcUaSource {
        incoming: rx,
        assembler: Assembler::new(nodes.inputs.len()),
        inputs: nodes.inputs.iter().map(|(n, _)| n.clone()).collect(),
        runs: VecDeque::new(),
        has_run: nodes.run.is_some(),
        pending: VecDeque::new(),
    };
    let sink = OpcUaSink { writes: write_tx, outputs: nodes.outputs.iter().map(|(k, _, f)| (*k, *f)).collect() };
    Ok((source, sink))
}

/// Session, node check, subscription.
async fn open(
    url: &str,
    ids: &[(NodeId, String)],
    subscribed: usize,
    period: Duration,
    tx: mpsc::Sender<Incoming>,
) -> Result<Arc<Session>, LiveError> {
    let pki = std::env::temp_dir().join("trueaxis-live-pki");
    let mut client = ClientBuilder::new()
        .application_name("trueaxis live")
        .application_uri("urn:trueaxis:live")
        .product_uri("urn:trueaxis")
        .pki_dir(pki)
        .create_sample_keypair(false)
        .trust_server_certs(true)
        .session_retry_limit(-1)
        .session_retry_initial(Duration::from_millis(500))
        .session_retry_max(Duration::from_secs(5))
        // subscriptions are made again by this module on a new session (a restarted server)
        .recreate_subscriptions(false)
        .client()
        .map_err(|e| environment(format!("OPC UA client: {}", e.join("; "))))?;
    reachable(url)?;
    let endpoint: EndpointDescription = (url, "None", MessageSecurityMode::None, UserTokenPolicy::anonymous()).into();
    let (session, event_loop) =
        tokio::time::timeout(Duration::from_secs(20), client.connect_to_matching_endpoint(endpoint, IdentityToken::Anonymous))
            .await
            .map_err(|_| environment(format!("{url}: no answer to GetEndpoints within 20 s")))?
            .map_err(|e| environment(format!("{url}: cannot connect to the OPC UA server: {e}")))?;
    let notes = tx.clone();
    let (new_session_tx, mut new_session) = tokio::sync::mpsc::unbounded_channel::<()>();
    tokio::spawn(async move {
        let stream = event_loop.enter();
        futures::pin_mut!(stream);
        let mut sessions = 0;
        while let Some(event) = stream.next().await {
            let note = match event {
                Ok(SessionPollResult::ConnectionLost(code)) => format!("OPC UA connection lost ({code})"),
                Ok(SessionPollResult::Reconnected(SessionConnectMode::NewSession(_))) => {
                    sessions += 1;
                    if sessions == 1 {
                        continue;
                    }
                    let _ = new_session_tx.send(());
                    "OPC UA session created again: subscribing again".to_string()
                }
                Ok(SessionPollResult::Reconnected(_)) => "OPC UA session reactivated".to_string(),
                Ok(_) => continue,
                Err(code) => format!("OPC UA session ended ({code})"),
            };
            let _ = notes.send(Incoming::Note(note));
        }
    });
    if !tokio::time::timeout(Duration::from_secs(20), session.wait_for_connection()).await.unwrap_or(false) {
        return Err(environment(format!("{url}: no OPC UA session within 20 s")));
    }
    let reads: Vec<ReadValueId> = ids.iter().map(|(id, _)| ReadValueId::from(id.clone())).collect();
    let values = session.read(&reads, TimestampsToReturn::Neither, 0.0).await.map_err(|e| environment(format!("{url}: read: {e}")))?;
    for ((id, what), v) in ids.iter().zip(&values) {
        if let Some(code) = v.status.filter(|s| s.is_bad()) {
            let why = if code == StatusCode::BadNodeIdUnknown {
                "does not exist on the server".to_string()
            } else {
                format!("cannot be read ({code})")
            };
            return Err(input(format!("{url}: node `{id}` ({what}) {why}")));
        }
    }
    if subscribed > 0 {
        subscribe(&session, url, &ids[..subscribed], period, tx.clone()).await?;
        let (session, url, ids, notes) = (session.clone(), url.to_string(), ids[..subscribed].to_vec(), tx);
        tokio::spawn(async move {
            while new_session.recv().await.is_some() {
                if let Err(e) = subscribe(&session, &url, &ids, period, notes.clone()).await {
                    let _ = notes.send(Incoming::Note(format!("warning: {e}")));
                }
            }
        });
    }
    Ok(session)
}

/// One subscription with a monitored item per node (client handles 1, 2, ... in the order of `ids`).
async fn subscribe(
    session: &Session,
    url: &str,
    ids: &[(NodeId, String)],
    period: Duration,
    tx: mpsc::Sender<Incoming>,
) -> Result<(), LiveError> {
    let sub = session
        .create_subscription(period, 600, 30, 0, 0, true, Forward(tx))
        .await
        .map_err(|e| environment(format!("{url}: cannot create a subscription: {e}")))?;
    let filter = DataChangeFilter { trigger: DataChangeTrigger::StatusValueTimestamp, deadband_type: 0, deadband_value: 0.0 };
    let items: Vec<MonitoredItemCreateRequest> = ids
        .iter()
        .enumerate()
        .map(|(k, (id, _))| {
            MonitoredItemCreateRequest::new(
                ReadValueId::from(id.clone()),
                MonitoringMode::Reporting,
                MonitoringParameters {
                    client_handle: k as u32 + 1,
                    sampling_interval: period.as_secs_f64() * 1e3,
                    filter: ExtensionObject::from_message(filter.clone()),
                    queue_size: 1000,
                    discard_oldest: true,
                },
            )
        })
        .collect();
    let created = session
        .create_monitored_items(sub, TimestampsToReturn::Both, items)
        .await
        .map_err(|e| environment(format!("{url}: cannot create monitored items: {e}")))?;
    for ((id, what), c) in ids.iter().zip(&created) {
        if c.result.status_code.is_bad() {
            return Err(input(format!("{url}: node `{id}` ({what}) cannot be monitored ({})", c.result.status_code)));
        }
    }
    Ok(())
}

/// Refuses at once a server that does not accept TCP connections (the client would retry for ever).
fn reachable(url: &str) -> Result<(), LiveError> {
    use std::net::ToSocketAddrs;
    let rest = url.trim_start_matches("opc.tcp://");
    let authority = rest.split('/').next().unwrap_or(rest);
    let with_port = if authority.rsplit_once(':').is_some_and(|(_, p)| p.parse::<u16>().is_ok()) {
        authority.to_string()
    } else {
        format!("{authority}:4840")
    };
    let addresses: Vec<_> =
        with_port.to_socket_addrs().map_err(|e| environment(format!("{url}: cannot resolve `{with_port}`: {e}")))?.collect();
    let mut last = None;
    for a in &addresses {
        match std::net::TcpStream::connect_timeout(a, Duration::from_secs(5)) {
            Ok(_) => return Ok(()),
            Err(e) => last = Some(e),
        }
    }
    Err(environment(format!("{url}: the OPC UA server cannot be reached ({})", last.map_or("no address".into(), |e| e.to_string()))))
}

/// Writes offsets as they come; a failed write is logged, the next one tried.
async fn write_loop(
    session: Arc<Session>,
    outputs: Vec<NodeId>,
    mut writes: tokio::sync::mpsc::UnboundedReceiver<(f64, Vec<(usize, f64)>)>,
    notes: mpsc::Sender<Incoming>,
) {
    while let Some((time_s, values)) = writes.recv().await {
        let nodes: Vec<WriteValue> = values
            .iter()
            .map(|(i, v)| WriteValue {
                node_id: outputs[*i].clone(),
                attribute_id: AttributeId::Value as u32,
                index_range: NumericRange::None,
                value: DataValue { value: Some(Variant::Double(*v)), source_timestamp: Some(date_time(time_s)), ..Default::default() },
            })
            .collect();
        let why = match session.write(&nodes).await {
            Ok(codes) => {
                codes.iter().zip(&nodes).find(|(c, _)| c.is_bad()).map(|(c, n)| format!("OPC UA write of `{}` refused ({c})", n.node_id))
            }
            Err(e) => Some(format!("OPC UA write failed: {e}")),
        };
        if let Some(why) = why {
            let _ = notes.send(Incoming::Note(why));
        }
    }
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
}
