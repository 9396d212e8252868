//! Samples from timestamped readings (OPC UA data changes): every reading carries the time it was
//! taken (its source timestamp); the reading of an input at time t is its latest reading taken at
//! or before t (sample and hold). The sample at t is complete when every input has reported a
//! reading taken at t or later (readings of one input arrive in time order), so a sample is formed
//! as soon as the last input of that instant has arrived, and an input whose value did not change
//! (a server that only reports changes) is held. Readings older than the last formed sample are
//! dropped (a re-delivery after a reconnection).
//!
//! Units: s (source time), readings as the source gives them.

use std::collections::{BTreeSet, VecDeque};

/// Readings of each input waiting to form samples.
#[derive(Clone, Debug)]
pub struct Assembler {
    queues: Vec<VecDeque<(f64, f64)>>,
    /// Times of readings seen and not yet formed (ordered; f64 bits of non-negative times).
    pending: BTreeSet<u64>,
    /// The reading of each input at the last formed sample.
    held: Vec<Option<f64>>,
    last_formed: Option<f64>,
}

impl Assembler {
    pub fn new(inputs: usize) -> Assembler {
        Assembler { queues: vec![VecDeque::new(); inputs], pending: BTreeSet::new(), held: vec![None; inputs], last_formed: None }
    }

    /// A reading of input `k` taken at `time_s` (non-negative).
    pub fn push(&mut self, k: usize, time_s: f64, value: f64) {
        if self.last_formed.is_some_and(|t| time_s <= t) || time_s.is_nan() || time_s < 0.0 {
            return;
        }
        let q = &mut self.queues[k];
        if q.back().is_some_and(|(t, _)| *t >= time_s) {
            // out of order for this input: keep the latest only
            q.retain(|(t, _)| *t < time_s);
        }
        q.push_back((time_s, value));
        self.pending.insert(time_s.to_bits());
    }

    /// The next complete sample, `(time_s, readings)`.
    pub fn pop(&mut self) -> Option<(f64, Vec<f64>)> {
        let t = f64::from_bits(*self.pending.iter().next()?);
        // every input known up to t: it has a reading at t or later
        if self.queues.iter().any(|q| !q.back().is_some_and(|(tq, _)| *tq >= t)) {
            return None;
        }
        self.pending.remove(&t.to_bits());
        for (q, held) in self.queues.iter_mut().zip(self.held.iter_mut()) {
            while q.front().is_some_and(|(tq, _)| *tq <= t) {
                *held = q.pop_front().map(|(_, v)| v);
            }
        }
        self.last_formed = Some(t);
        let readings: Option<Vec<f64>> = self.held.iter().copied().collect();
        // an input with no reading at or before t cannot form this sample: wait for the next
        readings.map(|r| (t, r)).or_else(|| self.pop())
    }

    /// Forgets everything (after a new run or a restart).
    pub fn clear(&mut self) {
        let n = self.queues.len();
        *self = Assembler::new(n);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_form_when_every_input_has_reported() {
        let mut a = Assembler::new(2);
        a.push(0, 10.0, 20.0);
        assert_eq!(a.pop(), None);
        a.push(1, 10.0, 21.0);
        assert_eq!(a.pop(), Some((10.0, vec![20.0, 21.0])));
        // input 1 unchanged at 20 s (a server reporting changes only): held when it reports 30 s
        a.push(0, 20.0, 22.0);
        assert_eq!(a.pop(), None);
        a.push(1, 30.0, 23.0);
        a.push(0, 30.0, 24.0);
        assert_eq!(a.pop(), Some((20.0, vec![22.0, 21.0])));
        assert_eq!(a.pop(), Some((30.0, vec![24.0, 23.0])));
        // a re-delivery of an old reading is dropped
        a.push(0, 30.0, 99.0);
        assert_eq!(a.pop(), None);
    }
}
