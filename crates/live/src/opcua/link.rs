//! One OPC UA connection (OPC UA Part 4 services through async-opcua's client, no protocol code
//! of our own): a new client, an anonymous session with security mode None, every node read once
//! (one that does not exist is refused, naming it), one subscription with a monitored item per
//! input node; and a watch of the session's event loop that reports the first sign that the
//! connection is gone:
//!
//! - the transport closed (`ConnectionLost`: the server stopped, the socket was reset) or the
//!   event loop ended;
//! - a keep-alive (a Read of `Server_ServerStatus_State` every [`KEEP_ALIVE`]) refused with a
//!   status that means the session or the channel is gone, or [`FAILED_KEEP_ALIVES`] in a row
//!   failed (a server that keeps the socket open and no longer answers);
//! - a Publish refused because the session or the subscription is gone (a session closed by the
//!   server), or no Publish response for [`silence_limit`] after the first one (the server sends
//!   a keep-alive message at the latest every 30 publishing intervals, the count requested).
//!
//! The client's own reconnection is off (retry limit 0): a lost connection is given up whole and
//! a new one built (reconnect.rs), which is the same whatever the server did (restarted
//! with new sessions, or the same one back after a network fault).

use super::reconnect::Plan;
use super::{Forward, Incoming};
use crate::{environment, input, LiveError};
use futures::{Stream, StreamExt};
use opcua::client::{ClientBuilder, IdentityToken, Session, SessionActivity, SessionPollResult, SubscriptionActivity};
use opcua::types::{
    DataChangeFilter, DataChangeTrigger, EndpointDescription, ExtensionObject, MessageSecurityMode, MonitoredItemCreateRequest,
    MonitoringMode, MonitoringParameters, NodeId, ReadValueId, StatusCode, TimestampsToReturn, UserTokenPolicy,
};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};
use tokio::sync::oneshot;

/// The longest one connection attempt may wait for each of: the TCP connection, GetEndpoints,
/// the session.
pub const ATTEMPT: Duration = Duration::from_secs(20);
/// The timeout of every service request (Read, Write, CreateSubscription, ...).
const REQUEST_TIMEOUT: Duration = Duration::from_secs(10);
/// The interval of the session keep-alive reads.
pub const KEEP_ALIVE: Duration = Duration::from_secs(5);
/// Keep-alives failed in a row that end a connection.
pub const FAILED_KEEP_ALIVES: u32 = 3;
/// The keep-alive count requested for the subscription (publishing intervals without data after
/// which the server sends an empty Publish response).
const SUBSCRIPTION_KEEP_ALIVE: u32 = 30;

/// How long the subscription may stay silent before the connection is given up: three of the
/// server's keep-alive intervals (30 publishing intervals, at least the client's 100 ms minimum),
/// and never less than 20 s.
pub fn silence_limit(period: Duration) -> Duration {
    let publishing = period.max(Duration::from_millis(100));
    (publishing * SUBSCRIPTION_KEEP_ALIVE * 3).max(Duration::from_secs(20))
}

/// An open connection: its session and the watch of its event loop.
pub struct Link {
    pub session: Arc<Session>,
    /// Receives, once, why the connection is gone.
    pub lost: oneshot::Receiver<String>,
    watch: tokio::task::JoinHandle<()>,
}

/// Whether a status says that the session or its channel is gone (a request on it cannot succeed).
pub fn session_gone(code: StatusCode) -> bool {
    matches!(
        code,
        StatusCode::BadSessionClosed
            | StatusCode::BadSessionIdInvalid
            | StatusCode::BadSessionNotActivated
            | StatusCode::BadShutdown
            | StatusCode::BadServerHalted
            | StatusCode::BadServerNotConnected
            | StatusCode::BadNotConnected
            | StatusCode::BadConnectionClosed
            | StatusCode::BadSecureChannelClosed
            | StatusCode::BadSecureChannelIdInvalid
            | StatusCode::BadTcpSecureChannelUnknown
            | StatusCode::BadDisconnect
            | StatusCode::BadCommunicationError
            | StatusCode::BadNoCommunication
            | StatusCode::BadEndOfStream
            | StatusCode::BadInvalidState
    )
}

impl Link {
    /// Connects to the plan's server, checks every node, subscribes to the inputs (readings to
    /// `tx`); `announce`: a message sent to `tx` before the subscription's first readings.
    pub async fn open(plan: &Plan, tx: &mpsc::Sender<Incoming>, announce: impl FnOnce() -> Option<String>) -> Result<Link, LiveError> {
        let (url, ids, subscribed, period) = (plan.url.as_str(), &plan.ids, plan.subscribed, plan.period);
        let link = Link::connect(url, subscribed > 0, period).await?;
        let ready = link.check_and_subscribe(url, ids, subscribed, period, tx, announce).await;
        match ready {
            Ok(()) => Ok(link),
            Err(e) => {
                link.close().await;
                Err(e)
            }
        }
    }

    /// A session on `url`, its event loop watched.
    async fn connect(url: &str, subscribing: bool, period: Duration) -> Result<Link, LiveError> {
        let mut client = ClientBuilder::new()
            .application_name("trueaxis live")
            .application_uri("urn:trueaxis:live")
            .product_uri("urn:trueaxis")
            .pki_dir(std::env::temp_dir().join("trueaxis-live-pki"))
            .create_sample_keypair(false)
            .trust_server_certs(true)
            // one attempt: a lost connection is rebuilt whole by `reconnect`
            .session_retry_limit(0)
            .recreate_subscriptions(false)
            .request_timeout(REQUEST_TIMEOUT)
            .keep_alive_interval(KEEP_ALIVE)
            .max_failed_keep_alive_count(0)
            .client()
            .map_err(|e| environment(format!("OPC UA client: {}", e.join("; "))))?;
        reachable(url).await?;
        let endpoint: EndpointDescription = (url, "None", MessageSecurityMode::None, UserTokenPolicy::anonymous()).into();
        let (session, event_loop) = tokio::time::timeout(ATTEMPT, client.connect_to_matching_endpoint(endpoint, IdentityToken::Anonymous))
            .await
            .map_err(|_| environment(format!("{url}: no answer to GetEndpoints within {} s", ATTEMPT.as_secs())))?
            .map_err(|e| environment(format!("{url}: cannot connect to the OPC UA server: {e}")))?;
        let (lost_tx, mut lost) = oneshot::channel();
        let silence = subscribing.then(|| silence_limit(period));
        let watch = tokio::spawn(watch(event_loop.enter(), silence, lost_tx));
        let started: Result<(), String> = tokio::select! {
            c = tokio::time::timeout(ATTEMPT, session.wait_for_connection()) => match c {
                Ok(true) => Ok(()),
                _ => Err(format!("no OPC UA session within {} s", ATTEMPT.as_secs())),
            },
            why = &mut lost => Err(format!("no OPC UA session: {}", why.unwrap_or_else(|_| "the session ended".into()))),
        };
        let link = Link { session, lost, watch };
        match started {
            Ok(()) => Ok(link),
            Err(why) => {
                link.close().await;
                Err(environment(format!("{url}: {why}")))
            }
        }
    }

    /// Every node read once; the subscription.
    async fn check_and_subscribe(
        &self,
        url: &str,
        ids: &[(NodeId, String)],
        subscribed: usize,
        period: Duration,
        tx: &mpsc::Sender<Incoming>,
        announce: impl FnOnce() -> Option<String>,
    ) -> Result<(), LiveError> {
        let reads: Vec<ReadValueId> = ids.iter().map(|(id, _)| ReadValueId::from(id.clone())).collect();
        let values =
            self.session.read(&reads, TimestampsToReturn::Neither, 0.0).await.map_err(|e| environment(format!("{url}: read: {e}")))?;
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
        if let Some(message) = announce() {
            let _ = tx.send(Incoming::Note(message));
        }
        if subscribed > 0 {
            subscribe(&self.session, url, &ids[..subscribed], period, tx.clone()).await?;
        }
        Ok(())
    }

    /// Ends the connection: a session still connected is closed (its subscription deleted on the
    /// server), at most 1 s; the event loop is dropped.
    pub async fn close(self) {
        self.session.disable_reconnects();
        if !self.watch.is_finished() {
            let _ = tokio::time::timeout(Duration::from_secs(1), self.session.disconnect()).await;
        }
        self.watch.abort();
    }
}

/// Polls the session's event loop; sends the first reason the connection is gone and returns
/// (which drops the event loop and its socket).
async fn watch(
    stream: impl Stream<Item = Result<SessionPollResult, StatusCode>>,
    silence: Option<Duration>,
    lost: oneshot::Sender<String>,
) {
    futures::pin_mut!(stream);
    let mut health = Health { failed_keep_alives: 0, last_publish: None };
    let mut tick = tokio::time::interval(Duration::from_secs(1));
    let why = loop {
        tokio::select! {
            event = stream.next() => {
                if let Some(why) = health.judge(event) {
                    break why;
                }
            }
            _ = tick.tick(), if silence.is_some() => {
                let limit = silence.unwrap_or(Duration::MAX);
                if health.last_publish.is_some_and(|t| t.elapsed() > limit) {
                    break format!("no Publish response from the server in {} s", limit.as_secs());
                }
            }
        }
    };
    let _ = lost.send(why);
}

/// What the event loop has said so far.
struct Health {
    failed_keep_alives: u32,
    /// Set by the first Publish response: the silence watch starts then.
    last_publish: Option<Instant>,
}

impl Health {
    /// Why the connection is gone, if this event says so.
    fn judge(&mut self, event: Option<Result<SessionPollResult, StatusCode>>) -> Option<String> {
        let event = match event {
            None => return Some("the session was closed".into()),
            Some(Err(code)) => return Some(format!("the session ended: {code}")),
            Some(Ok(event)) => event,
        };
        match event {
            SessionPollResult::ConnectionLost(code) => Some(format!("connection lost: {code}")),
            SessionPollResult::SessionActivity(SessionActivity::KeepAliveSucceeded) => {
                self.failed_keep_alives = 0;
                None
            }
            SessionPollResult::SessionActivity(SessionActivity::KeepAliveFailed(code)) => {
                self.failed_keep_alives += 1;
                (session_gone(code) || self.failed_keep_alives >= FAILED_KEEP_ALIVES)
                    .then(|| format!("keep-alive failed {} times in a row: {code}", self.failed_keep_alives))
            }
            SessionPollResult::Subscription(SubscriptionActivity::Publish) => {
                self.last_publish = Some(Instant::now());
                None
            }
            SessionPollResult::Subscription(SubscriptionActivity::FatalFailure(code)) => Some(format!("the subscription failed: {code}")),
            SessionPollResult::Subscription(SubscriptionActivity::PublishFailed(code))
                if session_gone(code) || code == StatusCode::BadNoSubscription || code == StatusCode::BadSubscriptionIdInvalid =>
            {
                Some(format!("Publish refused: {code}"))
            }
            _ => None,
        }
    }
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
        .create_subscription(period, 600, SUBSCRIPTION_KEEP_ALIVE, 0, 0, true, Forward(tx))
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

/// Refuses at once a server that does not accept TCP connections, naming the reason.
async fn reachable(url: &str) -> Result<(), LiveError> {
    let rest = url.trim_start_matches("opc.tcp://");
    let authority = rest.split('/').next().unwrap_or(rest);
    let with_port = if authority.rsplit_once(':').is_some_and(|(_, p)| p.parse::<u16>().is_ok()) {
        authority.to_string()
    } else {
        format!("{authority}:4840")
    };
    let why = match tokio::time::timeout(ATTEMPT, tokio::net::TcpStream::connect(&with_port)).await {
        Ok(Ok(_)) => return Ok(()),
        Ok(Err(e)) => e.to_string(),
        Err(_) => format!("no answer within {} s", ATTEMPT.as_secs()),
    };
    Err(environment(format!("{url}: the OPC UA server cannot be reached at {with_port} ({why})")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_silence_limit_is_three_server_keep_alives_and_at_least_20_s() {
        assert_eq!(silence_limit(Duration::from_secs(1)), Duration::from_secs(90));
        // 20 ms asks for 100 ms publishing (the client's minimum): 9 s, raised to 20 s
        assert_eq!(silence_limit(Duration::from_millis(20)), Duration::from_secs(20));
        assert_eq!(silence_limit(Duration::from_secs(10)), Duration::from_secs(900));
    }

    #[test]
    fn a_keep_alive_refused_for_a_closed_session_ends_the_connection_at_once() {
        let mut h = Health { failed_keep_alives: 0, last_publish: None };
        let keep_alive = |code| Some(Ok(SessionPollResult::SessionActivity(SessionActivity::KeepAliveFailed(code))));
        assert!(h.judge(keep_alive(StatusCode::BadSessionIdInvalid)).is_some());
        // a timeout is given FAILED_KEEP_ALIVES chances, and a success resets the count
        let mut h = Health { failed_keep_alives: 0, last_publish: None };
        assert!(h.judge(keep_alive(StatusCode::BadTimeout)).is_none());
        assert!(h.judge(keep_alive(StatusCode::BadTimeout)).is_none());
        assert!(h.judge(Some(Ok(SessionPollResult::SessionActivity(SessionActivity::KeepAliveSucceeded)))).is_none());
        assert!(h.judge(keep_alive(StatusCode::BadTimeout)).is_none());
        assert!(h.judge(keep_alive(StatusCode::BadTimeout)).is_none());
        assert!(h.judge(keep_alive(StatusCode::BadTimeout)).unwrap().contains("3 times in a row"));
        // the end of the event loop, a lost transport, a subscription the server no longer has
        assert!(h.judge(None).is_some());
        assert!(h.judge(Some(Ok(SessionPollResult::ConnectionLost(StatusCode::BadConnectionClosed)))).is_some());
        let publish = |code| Some(Ok(SessionPollResult::Subscription(SubscriptionActivity::PublishFailed(code))));
        assert!(h.judge(publish(StatusCode::BadNoSubscription)).is_some());
        assert!(h.judge(publish(StatusCode::BadTimeout)).is_none());
    }
}
