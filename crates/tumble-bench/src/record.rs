//! The JSON record each peer prints on one stdout line (same shape as bench/peers/common.py).

use serde::Serialize;
use serde_json::Value;

/// One peer result: engine, version, scene, settings, figures.
#[derive(Debug, Clone, Serialize)]
pub struct Record {
    /// Engine name (`rapier3d`, `parry3d`).
    pub engine: &'static str,
    /// Crate version resolved in Cargo.lock.
    pub version: &'static str,
    /// Scene name (`pyramid`, `pile1000`, `tori`).
    pub scene: String,
    /// `ok`, or what the engine cannot do.
    pub status: &'static str,
    /// Settings used (dt, iterations, ...).
    pub settings: Value,
    /// Measured figures (timings and quality numbers).
    pub figures: Value,
    /// Peak resident set size of the process in bytes (Linux VmHWM), if readable.
    pub peak_rss_bytes: Option<u64>,
}

impl Record {
    /// Prints the record as one JSON line. Non-finite numbers become `null` (serde_json),
    /// so the line always parses.
    pub fn emit(mut self) {
        self.peak_rss_bytes = peak_rss_bytes();
        match serde_json::to_string(&self) {
            Ok(s) => println!("{s}"),
            Err(e) => eprintln!("could not serialise the {} record: {e}", self.engine),
        }
    }
}

/// Peak resident set size (VmHWM of /proc/self/status) in bytes.
pub fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
