//! The OPC UA connection kept up for the life of the process: offsets written as the run loop
//! sends them; after any loss of the connection (link.rs: the server stopped or
//! restarted, the socket reset, the session closed by the server, the event loop ended, a write
//! refused because the session is gone) the connection is given up whole and a new one built (a
//! new client, session, node check and subscription with a monitored item per mapped node),
//! attempt after attempt with a bounded exponential backoff: the waits before attempts are
//! 0.5, 1, 2, 4 s, then 5 s for ever (or until `--give-up-after`).
//!
//! Log lines, not a flood: the loss once; each failed attempt while the wait grows (4 lines
//! in the first 7.5 s), then one line a minute (every 12th attempt at 5 s) while the server stays
//! away; `reconnected` once. While disconnected no offset can be written: the latest one the
//! run loop sent (held, ramped, zero) is kept and written first on the new connection, so the
//! controller gets the engine's present offsets whatever it kept across the loss.

use super::link::{session_gone, Link};
use super::{date_time, Incoming};
use opcua::client::Session;
use opcua::types::{AttributeId, DataValue, NodeId, NumericRange, Variant, WriteValue};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use tokio::sync::mpsc::UnboundedReceiver;

/// The first wait before reconnecting.
pub const BACKOFF_FIRST: Duration = Duration::from_millis(500);
/// The longest wait between attempts.
pub const BACKOFF_MAX: Duration = Duration::from_secs(5);
/// At the longest wait, one failed attempt in this many is logged (one line a minute).
const LOG_EVERY: u32 = 12;

/// Offsets to write: (source time s, (output index, value in the node's unit) per axis).
pub type Write = (f64, Vec<(usize, f64)>);

/// The waits between attempts: doubling from [`BACKOFF_FIRST`] to [`BACKOFF_MAX`].
#[derive(Clone, Debug)]
pub struct Backoff {
    next: Duration,
    /// Attempts made.
    pub attempts: u32,
}

impl Default for Backoff {
    fn default() -> Self {
        Backoff { next: BACKOFF_FIRST, attempts: 0 }
    }
}

impl Backoff {
    /// The wait before the next attempt (counted).
    pub fn wait(&mut self) -> Duration {
        let w = self.next;
        self.next = (self.next * 2).min(BACKOFF_MAX);
        self.attempts += 1;
        w
    }

    /// Whether the failure of the attempt just made is worth a log line: every one while the
    /// wait grows and the first at the longest wait, then one in [`LOG_EVERY`].
    pub fn worth_logging(&self) -> bool {
        let growing = Self::steps_to_max();
        self.attempts <= growing + 1 || (self.attempts - growing - 1) % LOG_EVERY == 0
    }

    /// Attempts whose wait is shorter than the longest (4: 0.5, 1, 2, 4 s).
    fn steps_to_max() -> u32 {
        let (mut w, mut n) = (BACKOFF_FIRST, 0);
        while w < BACKOFF_MAX {
            w *= 2;
            n += 1;
        }
        n
    }
}

/// What the connection needs to be built again.
pub struct Plan {
    pub url: String,
    /// Every node checked (inputs first, then the run node and the outputs), with what it is.
    pub ids: Vec<(NodeId, String)>,
    /// How many of `ids` are subscribed to.
    pub subscribed: usize,
    pub outputs: Vec<NodeId>,
    pub period: Duration,
    /// Give up (the process ends, exit 3) after this long without a connection.
    pub give_up: Option<Duration>,
}

/// Runs the connection until the run loop goes away (its write channel closes) or the plan's
/// time without a connection is over.
pub async fn keep_up(plan: Plan, first: Link, mut writes: UnboundedReceiver<Write>, tx: mpsc::Sender<Incoming>) {
    let note = |message: String| {
        let _ = tx.send(Incoming::Note(message));
    };
    let mut link = first;
    let mut unsent: Option<Write> = None;
    loop {
        let Some(why) = serve(&mut link, &plan.outputs, &mut writes, &mut unsent, &note).await else { return };
        link.close().await;
        note(format!(
            "OPC UA connection lost ({why}): reconnecting, waiting {} s doubling to {} s between attempts",
            BACKOFF_FIRST.as_secs_f64(),
            BACKOFF_MAX.as_secs()
        ));
        let lost_at = Instant::now();
        match reconnect(&plan, &mut writes, &mut unsent, &tx, lost_at).await {
            Some(new) => link = new,
            None => return,
        }
    }
}

/// Writes offsets until the connection is gone (`Some(why)`) or the run loop ends (`None`).
async fn serve(
    link: &mut Link,
    outputs: &[NodeId],
    writes: &mut UnboundedReceiver<Write>,
    unsent: &mut Option<Write>,
    note: &impl Fn(String),
) -> Option<String> {
    loop {
        let next = match unsent.take() {
            Some(w) => w,
            None => tokio::select! {
                why = &mut link.lost => return Some(why.unwrap_or_else(|_| "the session ended".into())),
                w = writes.recv() => w?,
            },
        };
        match write(&link.session, outputs, &next).await {
            Ok(None) => {}
            Ok(Some(refused)) => note(refused),
            Err(why) => {
                *unsent = Some(next);
                return Some(why);
            }
        }
    }
}

/// Attempts with the backoff until one succeeds: the new connection, announced (`reconnected`)
/// before the first readings of its subscription.
async fn reconnect(
    plan: &Plan,
    writes: &mut UnboundedReceiver<Write>,
    unsent: &mut Option<Write>,
    tx: &mpsc::Sender<Incoming>,
    lost_at: Instant,
) -> Option<Link> {
    let mut backoff = Backoff::default();
    loop {
        let deadline = tokio::time::Instant::now() + backoff.wait();
        // the wait: the offsets the run loop sends meanwhile, the latest kept
        loop {
            tokio::select! {
                _ = tokio::time::sleep_until(deadline) => break,
                w = writes.recv() => *unsent = Some(w?),
            }
        }
        let (attempts, again) = (backoff.attempts, if unsent.is_some() { ", writing the latest offsets again" } else { "" });
        let announce = || {
            Some(format!(
                "OPC UA reconnected to {} after {:.1} s ({attempts} attempt{}): subscribing again to {} nodes{again}",
                plan.url,
                lost_at.elapsed().as_secs_f64(),
                if attempts == 1 { "" } else { "s" },
                plan.subscribed
            ))
        };
        match Link::open(plan, tx, announce).await {
            Ok(link) => return Some(link),
            Err(e) => {
                let away = lost_at.elapsed();
                if plan.give_up.is_some_and(|g| away >= g) {
                    let message = format!("no OPC UA connection for {:.0} s (--give-up-after): {e}", away.as_secs_f64());
                    let _ = tx.send(Incoming::Failed(message));
                    return None;
                }
                if backoff.worth_logging() {
                    let later = if backoff.attempts > Backoff::steps_to_max() { " (logged once a minute)" } else { "" };
                    let _ = tx.send(Incoming::Note(format!(
                        "OPC UA reconnection attempt {} failed after {:.1} s: {}; trying again{later}",
                        backoff.attempts,
                        away.as_secs_f64(),
                        e
                    )));
                }
            }
        }
    }
}

/// Writes one step's offsets: `Ok(Some(note))` when the server refused a node, `Err(why)` when the
/// session is gone (the connection is then built again).
async fn write(session: &Session, outputs: &[NodeId], (time_s, values): &Write) -> Result<Option<String>, String> {
    let nodes: Vec<WriteValue> = values
        .iter()
        .map(|(i, v)| WriteValue {
            node_id: outputs[*i].clone(),
            attribute_id: AttributeId::Value as u32,
            index_range: NumericRange::None,
            value: DataValue { value: Some(Variant::Double(*v)), source_timestamp: Some(date_time(*time_s)), ..Default::default() },
        })
        .collect();
    match session.write(&nodes).await {
        Ok(codes) => {
            Ok(codes.iter().zip(&nodes).find(|(c, _)| c.is_bad()).map(|(c, n)| format!("OPC UA write of `{}` refused ({c})", n.node_id)))
        }
        Err(e) if session_gone(e.status()) || e.status() == opcua::types::StatusCode::BadTimeout => Err(format!("write failed: {e}")),
        Err(e) => Ok(Some(format!("OPC UA write failed: {e}"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_waits_double_from_half_a_second_to_5_s_and_the_log_thins_to_once_a_minute() {
        let mut b = Backoff::default();
        let mut waits = Vec::new();
        let mut logged = Vec::new();
        for _ in 0..40 {
            waits.push(b.wait().as_secs_f64());
            if b.worth_logging() {
                logged.push(b.attempts);
            }
        }
        assert_eq!(waits[..6], [0.5, 1.0, 2.0, 4.0, 5.0, 5.0]);
        assert!(waits[5..].iter().all(|w| *w == 5.0));
        // attempts 1-5 (the wait growing, then the first at 5 s), then every 12th: 60 s apart
        assert_eq!(logged, [1, 2, 3, 4, 5, 17, 29]);
        let at = |n: usize| waits[..n].iter().sum::<f64>();
        assert_eq!(at(17) - at(5), 60.0);
        assert_eq!(at(29) - at(17), 60.0);
    }
}
