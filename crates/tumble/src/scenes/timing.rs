//! Timing statistics of a benchmark run of a standard scene: median,
//! 10th / 90th percentile spread and mean of the step or query wall times,
//! the one definition behind `tumble bench` and the Rust peers (and the same
//! as `bench/peers/common.py::timing_stats`, so every engine's row is
//! summarised alike): the median of the middle two for an even count,
//! nearest-rank percentiles `int(q (n - 1) + 0.5)`.

use serde::Serialize;

/// Summary of samples in `unit` ("ms" or "us").
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TimingStats {
    /// Unit of the numbers below.
    pub unit: &'static str,
    /// Number of samples.
    pub count: usize,
    /// Median.
    pub median: f64,
    /// Arithmetic mean.
    pub mean: f64,
    /// 10th percentile (nearest rank).
    pub p10: f64,
    /// 90th percentile (nearest rank).
    pub p90: f64,
    /// Smallest sample.
    pub min: f64,
    /// Largest sample.
    pub max: f64,
}

impl TimingStats {
    /// Summarises `seconds` scaled by `scale` (1e3 for ms, 1e6 for us); `None` when empty.
    pub fn of(seconds: &[f64], unit: &'static str, scale: f64) -> Option<TimingStats> {
        if seconds.is_empty() {
            return None;
        }
        let mut s: Vec<f64> = seconds.iter().map(|x| x * scale).collect();
        s.sort_by(f64::total_cmp);
        let n = s.len();
        let median = if n % 2 == 1 {
            s[n / 2]
        } else {
            0.5 * (s[n / 2 - 1] + s[n / 2])
        };
        let pct = |q: f64| s[((q * (n - 1) as f64 + 0.5) as usize).min(n - 1)];
        Some(TimingStats {
            unit,
            count: n,
            median,
            mean: s.iter().sum::<f64>() / n as f64,
            p10: pct(0.1),
            p90: pct(0.9),
            min: s[0],
            max: s[n - 1],
        })
    }

    /// Milliseconds.
    pub fn ms(seconds: &[f64]) -> Option<TimingStats> {
        TimingStats::of(seconds, "ms", 1e3)
    }

    /// Microseconds.
    pub fn us(seconds: &[f64]) -> Option<TimingStats> {
        TimingStats::of(seconds, "us", 1e6)
    }

    /// Microsecond summaries of all samples and of those with `flag` set
    /// and clear (the tori queries: colliding and separated poses), as
    /// `{all, colliding, separated}`; an empty group is `null`.
    pub fn us_split(seconds: &[f64], flag: &[bool]) -> serde_json::Value {
        let pick = |want: bool| -> Vec<f64> {
            seconds
                .iter()
                .zip(flag)
                .filter(|(_, &c)| c == want)
                .map(|(t, _)| *t)
                .collect()
        };
        serde_json::json!({
            "all": TimingStats::us(seconds),
            "colliding": TimingStats::us(&pick(true)),
            "separated": TimingStats::us(&pick(false)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_percentiles_of_a_permuted_ramp() {
        // 1..=11 ms in scrambled order: median 6, p10 = rank 1 -> 2, p90 = rank 9 -> 10.
        let xs: Vec<f64> = [7, 1, 11, 3, 9, 5, 2, 10, 4, 8, 6]
            .iter()
            .map(|&k| k as f64 * 1e-3)
            .collect();
        let s = TimingStats::ms(&xs).unwrap();
        assert!((s.median - 6.0).abs() < 1e-9);
        assert!((s.mean - 6.0).abs() < 1e-9);
        assert!((s.p10 - 2.0).abs() < 1e-9 && (s.p90 - 10.0).abs() < 1e-9);
        assert_eq!((s.min, s.max), (1.0, 11.0));
        assert!(TimingStats::us(&[]).is_none());
        // An even count: the median is the mean of the middle two.
        assert_eq!(TimingStats::ms(&[4e-3, 1e-3, 3e-3, 2e-3]).unwrap().median, 2.5);
        let split = TimingStats::us_split(&[1e-6, 2e-6, 3e-6], &[true, false, true]);
        assert_eq!(split["colliding"]["median"], 2.0);
        assert_eq!(split["separated"]["count"], 1);
        assert!(TimingStats::us_split(&[1e-6], &[true])["separated"].is_null());
    }
}
