//! Whether a step that has work for the world's threads runs on them or on
//! one thread, chosen from the measured times of recent steps of each kind.
//!
//! Why: on a shared machine (a 2-vCPU cloud VM, this project's CI) there
//! are spells of minutes in which every hand-over between cores is slow (a
//! value bounced between two spinning threads takes 0.5 us instead of
//! 0.05-0.14; docs/benchmarks.md, "Reading the ratios"), while one thread
//! runs at full speed: the pile of 1,000 then takes 4.2-5.0 ms a step on
//! two threads against 3.5-3.9 on one. Results never depend on where the work
//! is done (the same bits for any thread count), so the step is free to
//! run where it is fastest now.
//!
//! How: the median time of the last five steps on the side in use is kept,
//! per unit of the step's work (bodies, candidate pairs, contacts: a landing
//! pile's steps grow ten times dearer within a second); every so often two
//! steps run on the other side (a probe; the faster of the two counts, so
//! that neither a hiccup of the machine nor the first step's moving of the
//! bodies between the cores' caches decides) and the world moves there if
//! the probe was clearly faster. A probe that loses makes the wait for the
//! next one four times longer (to [`MAX_INTERVAL`] steps: the probes of a
//! machine where two threads are 1.7x faster than one cost about 0.5 % of
//! the time); a side whose median rises by 60 % above its lowest since the
//! last probe is probed against at the next step (from [`MIN_INTERVAL`]
//! steps after the last), so a spell is left within a few dozen steps of its
//! start, and within the longest wait of its end. Tried and not kept: a
//! smoothed mean judged by one-step probes (it moved to one thread on a
//! single step of 18 ms among steps of 2, a helper having lost its core for
//! a moment, and then lost every probe back, each paying for the caches),
//! and a trigger that compared with the other side's last probe (it missed
//! a spell that began after the pile had settled).

/// Steps before the first probe, and between probes after a switch.
pub const MIN_INTERVAL: u32 = 32;

/// How much longer the wait for the next probe grows after a probe lost.
pub const BACK_OFF: u32 = 4;

/// Longest wait between probes (steps).
pub const MAX_INTERVAL: u32 = 256;

/// Steps of a probe.
pub const PROBE_STEPS: u32 = 2;

/// A probe must be this much faster (as a fraction of the side in use)
/// for the world to switch: a step is a noisy sample.
pub const SWITCH_MARGIN: f64 = 0.1;

/// A rise of the side's median over its lowest since the last probe (as
/// a fraction) that calls for a probe at once (at least [`MIN_INTERVAL`]
/// steps after the last): a spell doubles the threads' time, while the
/// lowest of many medians of five noisy steps lies well below their usual
/// (with a third, a quiet pile was probed every few dozen steps; with a
/// half, steps 25 % noisy were probed twice as often as scheduled).
pub const JUMP: f64 = 0.6;

/// Steps of the side in use whose median is its time.
const RECENT: usize = 5;

/// The choice between the threads and one thread, and what it is based on.
#[derive(Debug, Clone)]
pub(crate) struct ThreadChoice {
    /// The side the steps use: `true` on the threads.
    threaded: bool,
    /// The last steps' times on the side in use (s), a ring of `filled`.
    recent: [f64; RECENT],
    filled: usize,
    at: usize,
    /// The lowest median of the side in use since the last probe (s).
    lowest: f64,
    /// Steps on the side in use since the last probe (or switch).
    since_probe: u32,
    /// Steps to wait before the next probe.
    interval: u32,
    /// Steps of the running probe still to run (0: no probe).
    probe_left: u32,
    /// The fastest step of the running probe (s).
    probe_best: f64,
}

impl Default for ThreadChoice {
    fn default() -> Self {
        ThreadChoice {
            threaded: true,
            recent: [0.0; RECENT],
            filled: 0,
            at: 0,
            lowest: f64::INFINITY,
            since_probe: 0,
            interval: MIN_INTERVAL,
            probe_left: 0,
            probe_best: f64::INFINITY,
        }
    }
}

impl ThreadChoice {
    /// Whether the next step (one with work for the threads) runs on them.
    pub fn next_threaded(&mut self) -> bool {
        if self.probe_left == 0 && self.since_probe >= self.interval {
            self.probe_left = PROBE_STEPS;
            self.probe_best = f64::INFINITY;
        }
        self.threaded != (self.probe_left > 0)
    }

    /// Records the time of the step [`ThreadChoice::next_threaded`] chose
    /// for (s) and how much work it had (any measure that grows with the
    /// step's cost: the steps of a landing pile grow ten times dearer within
    /// a second, and times compared across such a change, raw, chose one
    /// thread while the threads were faster).
    pub fn record(&mut self, seconds: f64, work: usize) {
        let seconds = seconds / work.max(1) as f64;
        if !seconds.is_finite() {
            return;
        }
        if self.probe_left > 0 {
            self.probe_best = self.probe_best.min(seconds);
            self.probe_left -= 1;
            if self.probe_left == 0 {
                self.decide();
            }
            return;
        }
        self.push(seconds);
        self.since_probe += 1;
        // Well slower than lately (by `JUMP`): the machine may have turned
        // slow for this side (or the scene dearer per unit of work); probe
        // the other side at the next step rather than at the end of a long
        // wait.
        if let Some(now) = self.median() {
            self.lowest = self.lowest.min(now);
            if now > self.lowest * (1.0 + JUMP) && (MIN_INTERVAL..self.interval).contains(&self.since_probe) {
                self.interval = self.since_probe;
            }
        }
    }

    /// After a probe: move to the probed side if it was clearly faster.
    fn decide(&mut self) {
        let probe = self.probe_best;
        let now = self.median();
        self.since_probe = 0;
        if now.is_none_or(|now| probe < now * (1.0 - SWITCH_MARGIN)) {
            self.threaded = !self.threaded;
            self.filled = 0;
            self.push(probe);
            self.lowest = probe;
            self.interval = MIN_INTERVAL;
        } else {
            self.lowest = now.unwrap_or(f64::INFINITY);
            self.interval = (self.interval * BACK_OFF).min(MAX_INTERVAL);
        }
    }

    fn push(&mut self, seconds: f64) {
        if self.filled == 0 {
            self.at = 0;
        }
        self.recent[self.at] = seconds;
        self.at = (self.at + 1) % RECENT;
        self.filled = (self.filled + 1).min(RECENT);
    }

    /// The median of the recent steps on the side in use.
    fn median(&self) -> Option<f64> {
        if self.filled == 0 {
            return None;
        }
        let mut times = self.recent;
        let times = &mut times[..self.filled];
        times.sort_unstable_by(f64::total_cmp);
        Some(times[self.filled / 2])
    }

    /// The side the steps use now: `true` on the threads.
    #[cfg(test)]
    fn threaded(&self) -> bool {
        self.threaded
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `steps` steps whose time in each mode is given by `time(step,
    /// threaded)`; returns how many ran on the threads.
    fn run(
        choice: &mut ThreadChoice,
        steps: std::ops::Range<usize>,
        mut time: impl FnMut(usize, bool) -> f64,
    ) -> usize {
        let mut threaded = 0;
        for step in steps {
            let on_threads = choice.next_threaded();
            threaded += usize::from(on_threads);
            choice.record(time(step, on_threads), 1);
        }
        threaded
    }

    #[test]
    fn threads_that_are_faster_keep_the_steps_and_probes_back_off() {
        let mut choice = ThreadChoice::default();
        // Two threads 1.7x faster than one.
        let on_threads = run(&mut choice, 0..2000, |_, t| if t { 2.0e-3 } else { 3.4e-3 });
        assert!(choice.threaded());
        // Probes of two steps at 32, 162, 420, then every MAX_INTERVAL + 2
        // steps: nine in 2,000 steps.
        assert_eq!(2000 - on_threads, 18);
    }

    #[test]
    fn a_noisy_quiet_machine_is_not_probed_more_often() {
        let mut choice = ThreadChoice::default();
        // Each step's time off by up to 25 % either way (a fixed sequence).
        let mut seed = 12345u64;
        let on_threads = run(&mut choice, 0..2000, |_, t| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = 0.75 + 0.5 * (seed >> 11) as f64 / (1u64 << 53) as f64;
            noise * if t { 2.0e-3 } else { 3.4e-3 }
        });
        // The nine scheduled probes, and at most two more.
        assert!(
            2000 - on_threads <= 22,
            "{} steps on one thread",
            2000 - on_threads
        );
    }

    #[test]
    fn a_hiccup_of_one_step_moves_nothing() {
        let mut choice = ThreadChoice::default();
        // A helper loses its core for a moment every 50 steps: 18 ms.
        let time = |step: usize, t: bool| match (t, step % 50 == 49) {
            (true, true) => 18.0e-3,
            (true, false) => 2.0e-3,
            (false, _) => 3.4e-3,
        };
        let on_threads = run(&mut choice, 0..2000, time);
        assert!(
            2000 - on_threads <= 20,
            "{} steps on one thread",
            2000 - on_threads
        );
    }

    #[test]
    fn a_slow_spell_moves_the_steps_to_one_thread_and_its_end_moves_them_back() {
        let mut choice = ThreadChoice::default();
        // Quiet: threads 2.1 ms, one thread 3.5 ms; from step 1000 to 3000
        // the threads take 4.7 ms. The first step on the threads after steps
        // on one thread moves the bodies between the caches: 4 ms.
        let mut last = true;
        let mut time = move |step: usize, threads: bool| {
            let first = threads && !last;
            last = threads;
            match (threads, (1000..3000).contains(&step)) {
                (true, true) => 4.7e-3,
                (true, false) if first => 4.0e-3,
                (true, false) => 2.1e-3,
                (false, _) => 3.5e-3,
            }
        };
        run(&mut choice, 0..1000, &mut time);
        assert!(choice.threaded());
        // Within a few steps of the spell's start, on one thread.
        run(&mut choice, 1000..1040, &mut time);
        assert!(!choice.threaded(), "still on the threads 40 steps into the spell");
        let threaded = run(&mut choice, 1040..3000, &mut time);
        // During the spell only probes run on the threads, fewer and fewer.
        assert!(threaded <= 20, "{threaded} steps on the threads during the spell");
        // After the spell, back on the threads within the longest wait,
        // though a probe's first step is slow.
        run(
            &mut choice,
            3000..3000 + (MAX_INTERVAL + PROBE_STEPS) as usize,
            &mut time,
        );
        assert!(choice.threaded());
    }

    #[test]
    fn a_spell_after_a_scene_grew_cheaper_is_seen() {
        let mut choice = ThreadChoice::default();
        // A landing pile: for 300 steps each unit of work costs three times
        // what it costs at rest (threads 1.7x faster throughout); the spell
        // begins at step 400, its last probes (at 32 and 162) taken while
        // the pile was landing and the next one due at 420.
        let time = |step: usize, threads: bool| {
            let landing = if step < 300 { 3.0 } else { 1.0 };
            let spell = (400..1400).contains(&step);
            landing
                * match (threads, spell) {
                    (true, true) => 4.7e-3,
                    (true, false) => 2.0e-3,
                    (false, _) => 3.4e-3,
                }
        };
        run(&mut choice, 0..400, time);
        assert!(choice.threaded());
        run(&mut choice, 400..440, time);
        assert!(!choice.threaded(), "still on the threads 40 steps into the spell");
    }

    #[test]
    fn a_probe_must_win_clearly_and_bad_times_are_ignored() {
        let mut choice = ThreadChoice::default();
        // One thread 5 % faster than two: within the margin, no switch.
        run(&mut choice, 0..500, |_, t| if t { 2.0e-3 } else { 1.9e-3 });
        assert!(choice.threaded());
        // A non-finite time changes nothing.
        let before = format!("{choice:?}");
        choice.record(f64::NAN, 1);
        assert_eq!(format!("{choice:?}"), before);
    }
}
