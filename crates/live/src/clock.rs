//! The source's clock between samples: the source time (s) of the last sample plus the wall time
//! since it arrived, times the speed of the source (1 for a machine; a replay or a test server
//! playing a campaign faster than real time runs `speed` times the wall clock). Holds and ramps
//! are timed on it, so a replay at 600 times real time holds and ramps 600 times faster too.

use std::time::Instant;

/// Source time from the wall clock.
#[derive(Clone, Copy, Debug)]
pub struct Clock {
    speed: f64,
    anchor: Option<(Instant, f64)>,
}

impl Clock {
    pub fn new(speed: f64) -> Clock {
        Clock { speed, anchor: None }
    }

    /// Source time `source_s` is now.
    pub fn anchor(&mut self, source_s: f64) {
        self.anchor = Some((Instant::now(), source_s));
    }

    /// The source time now; `None` before the first anchor.
    pub fn now(&self) -> Option<f64> {
        self.anchor.map(|(at, s)| s + at.elapsed().as_secs_f64() * self.speed)
    }

    /// Wall time (s) for a span of source time.
    pub fn wall(&self, source_span_s: f64) -> f64 {
        source_span_s / self.speed
    }
}
