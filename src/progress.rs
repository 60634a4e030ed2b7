//! Progress of a long run on standard error: the simulated time against the horizon, and
//! events a second. Drawn only when standard error is a terminal, so logs and pipes get
//! nothing.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal as _;
use std::time::Instant;

/// The bar's steps: the horizon is cut into this many.
const STEPS: u64 = 1000;

/// A run's progress bar (hidden when standard error is not a terminal).
pub struct Progress {
    bar: ProgressBar,
    horizon: f64,
    events: u64,
    start: Instant,
}

impl Progress {
    /// A bar for a run to `horizon`, drawn on standard error if it is a terminal.
    pub fn new(horizon: f64) -> Progress {
        let target = if std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr_with_hz(4)
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(STEPS), target);
        bar.set_style(
            ProgressStyle::with_template("t {msg} {bar:30} {percent}% {elapsed} (eta {eta})")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Progress {
            bar,
            horizon,
            events: 0,
            start: Instant::now(),
        }
    }

    /// The run has reached simulated time `t`, with `events` more contact events.
    pub fn reached(&mut self, t: f64, events: usize) {
        if self.bar.is_hidden() {
            return;
        }
        self.events += events as u64;
        let share = if self.horizon > 0.0 {
            (t / self.horizon).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let rate = self.events as f64 / self.start.elapsed().as_secs_f64().max(1e-9);
        self.bar.set_message(format!(
            "{t:.6e} of {:.6e}, {rate:.3e} events/s",
            self.horizon
        ));
        self.bar.set_position((share * STEPS as f64) as u64);
    }

    /// The run is over: the bar goes.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
