//! Whether a step that has work for the world's threads runs on them or on
//! one thread, chosen from the measured times of recent steps of each kind.
//!
//! Why: on a shared machine (a 2-vCPU cloud VM, this project's CI) there
//! are spells of minutes in which every hand-over between cores is slow (a
//! value bounced between two spinning threads takes 0.5 us instead of
//! 0.05-0.14; docs/benchmarks.md, "Reading the ratios"), while one thread
//! runs at full speed: the pile of 1,000 then takes 4.3-4.8 ms a step on
//! two threads against 3.5 on one. Results never depend on where the work
//! is done (the same bits for any thread count), so the step is free to
//! run where it is fastest now.
//!
//! How: a smoothed time per step is kept for the mode in use; every so
//! often one step runs in the other mode (a probe) and the world moves to
//! it if it was clearly faster. A probe that loses doubles the wait for the
//! next one (to [`MAX_INTERVAL`] steps: a serial probe on a machine where
//! two threads are 1.7x faster costs 0.3 % of the time); a mode that gets
//! slower than the other's last probe is probed against at once, so a
//! spell is left within a few steps of its start and of its end.

/// Steps before the first probe, and between probes after a switch.
pub const MIN_INTERVAL: u32 = 8;

/// Longest wait between probes (steps).
pub const MAX_INTERVAL: u32 = 256;

/// A probe must be this much faster (as a fraction of the mode in use)
/// for the world to switch: a single step is a noisy sample, and a probe
/// on one thread runs with caches the threads left behind.
pub const SWITCH_MARGIN: f64 = 0.1;

/// Weight of the newest step in the smoothed time of the mode in use.
const SMOOTHING: f64 = 0.25;

/// The choice between the threads and one thread, and what it is based on.
#[derive(Debug, Clone)]
pub(crate) struct ThreadChoice {
    /// The mode the steps use: `true` on the threads.
    threaded: bool,
    /// Smoothed time of a step in the mode in use (s).
    current: Option<f64>,
    /// Time of the last probe of the other mode (s).
    other: Option<f64>,
    /// Steps since the last probe (or switch).
    since_probe: u32,
    /// Steps to wait before the next probe.
    interval: u32,
    /// The step being run is a probe.
    probing: bool,
}

impl Default for ThreadChoice {
    fn default() -> Self {
        ThreadChoice {
            threaded: true,
            current: None,
            other: None,
            since_probe: 0,
            interval: MIN_INTERVAL,
            probing: false,
        }
    }
}

impl ThreadChoice {
    /// Whether the next step (one with work for the threads) runs on them.
    pub fn next_threaded(&mut self) -> bool {
        self.probing = self.since_probe >= self.interval;
        self.threaded != self.probing
    }

    /// Records the time of the step [`ThreadChoice::next_threaded`] chose
    /// for (s).
    pub fn record(&mut self, seconds: f64) {
        if !seconds.is_finite() {
            return;
        }
        if self.probing {
            self.probing = false;
            self.since_probe = 0;
            let faster = self
                .current
                .is_none_or(|now| seconds < now * (1.0 - SWITCH_MARGIN));
            if faster {
                // The probe's mode becomes the one in use; the mode left
                // keeps its last smoothed time as the one to beat.
                self.threaded = !self.threaded;
                self.other = self.current;
                self.current = Some(seconds);
                self.interval = MIN_INTERVAL;
            } else {
                self.other = Some(seconds);
                self.interval = (self.interval * 2).min(MAX_INTERVAL);
            }
            return;
        }
        let now = match self.current {
            Some(t) => t + SMOOTHING * (seconds - t),
            None => seconds,
        };
        self.current = Some(now);
        self.since_probe += 1;
        // Slower now than the other mode was at its last probe: probe it
        // at the next step rather than at the end of a long wait.
        if self.other.is_some_and(|other| now > other) && self.since_probe < self.interval {
            self.interval = self.since_probe;
        }
    }

    /// The mode the steps use now: `true` on the threads.
    #[cfg(test)]
    fn threaded(&self) -> bool {
        self.threaded
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `steps` steps whose time in each mode is given by `time(step,
    /// threaded)`; returns how many ran on the threads and the mode at the end.
    fn run(
        choice: &mut ThreadChoice,
        steps: std::ops::Range<usize>,
        time: impl Fn(usize, bool) -> f64,
    ) -> usize {
        let mut threaded = 0;
        for step in steps {
            let on_threads = choice.next_threaded();
            threaded += usize::from(on_threads);
            choice.record(time(step, on_threads));
        }
        threaded
    }

    #[test]
    fn threads_that_are_faster_keep_the_steps_and_probes_back_off() {
        let mut choice = ThreadChoice::default();
        // Two threads 1.7x faster than one.
        let on_threads = run(&mut choice, 0..2000, |_, t| if t { 2.0e-3 } else { 3.4e-3 });
        assert!(choice.threaded());
        // Probes at 8, 16, 32, ... then every MAX_INTERVAL steps.
        let probes = 2000 - on_threads;
        assert!((5..=14).contains(&probes), "{probes} probes");
    }

    #[test]
    fn a_slow_spell_moves_the_steps_to_one_thread_and_its_end_moves_them_back() {
        let mut choice = ThreadChoice::default();
        // Quiet: threads 2.1 ms, one thread 3.5 ms; from step 1000 to 3000
        // the threads take 4.7 ms.
        let time = |step: usize, threads: bool| match (threads, (1000..3000).contains(&step)) {
            (true, true) => 4.7e-3,
            (true, false) => 2.1e-3,
            (false, _) => 3.5e-3,
        };
        run(&mut choice, 0..1000, time);
        assert!(choice.threaded());
        // Within a few steps of the spell's start, on one thread.
        run(&mut choice, 1000..1010, time);
        assert!(!choice.threaded(), "still on the threads 10 steps into the spell");
        let threaded = run(&mut choice, 1010..3000, time);
        // During the spell only probes run on the threads, fewer and fewer.
        assert!(threaded <= 14, "{threaded} steps on the threads during the spell");
        // After the spell, back on the threads within the longest wait.
        run(&mut choice, 3000..3000 + MAX_INTERVAL as usize + 1, time);
        assert!(choice.threaded());
    }

    #[test]
    fn a_probe_must_win_clearly_and_bad_times_are_ignored() {
        let mut choice = ThreadChoice::default();
        // One thread 5 % faster than two: within the margin, no switch.
        run(&mut choice, 0..500, |_, t| if t { 2.0e-3 } else { 1.9e-3 });
        assert!(choice.threaded());
        // A non-finite time changes nothing.
        let before = format!("{choice:?}");
        choice.next_threaded();
        choice.record(f64::NAN);
        choice.probing = false;
        assert_eq!(format!("{choice:?}"), before);
    }
}
