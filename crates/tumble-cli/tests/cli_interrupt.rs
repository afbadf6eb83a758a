//! Long runs lose nothing: `tumble run` stopped by Ctrl-C writes its outputs
//! for the steps done (exit status 130), a killed run leaves its streamed
//! trajectory chunks readable, and a run resumed from a checkpoint equals an
//! uninterrupted one bit for bit. Each assertion compares against an
//! uninterrupted run of the same scene, row for row, as text.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn tumble() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tumble"))
}

fn chain_scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/chain.toml")
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tumble-interrupt-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A long run of the chain, writing `x.glb` and `x.csv` in `dir`.
fn start_long_run(dir: &Path) -> Child {
    tumble()
        .current_dir(dir)
        .args(["run"])
        .arg(chain_scene())
        .args([
            "--duration",
            "600",
            "--out",
            "x.glb",
            "--trajectory",
            "x.csv",
            "--threads",
            "1",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Waits until the streamed trajectory holds more than its header.
fn wait_for_rows(part: &Path) {
    let start = Instant::now();
    loop {
        let lines = std::fs::read_to_string(part).map_or(0, |t| t.lines().count());
        if lines > 100 {
            return;
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "{} never got rows",
            part.display()
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn signal(child: &Child, name: &str) {
    let ok = Command::new("kill")
        .args([name, &child.id().to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill {name} failed");
}

/// The CSV of an uninterrupted run of `steps` steps.
fn uninterrupted_csv(dir: &Path, steps: usize) -> String {
    let out = dir.join(format!("ref{steps}.csv"));
    let status = tumble()
        .args(["run"])
        .arg(chain_scene())
        .args(["--steps", &steps.to_string(), "--quiet", "--trajectory"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    std::fs::read_to_string(out).unwrap()
}

/// Distinct frame times of a trajectory table (without its header).
fn frame_count(csv: &str) -> usize {
    let mut times: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    times.dedup();
    times.len()
}

#[test]
fn ctrl_c_writes_the_steps_done_and_exits_130() {
    let dir = temp_dir("sigint");
    let child = start_long_run(&dir);
    wait_for_rows(&dir.join("x.csv.part"));
    signal(&child, "-INT");
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "stderr: {stderr}");
    assert!(stderr.contains("interrupted at step"), "stderr: {stderr}");
    assert!(
        !dir.join("x.csv.part").exists(),
        "the partial file is removed once x.csv is written"
    );
    let glb = std::fs::read(dir.join("x.glb")).unwrap();
    assert_eq!(&glb[..4], b"glTF");
    let csv = std::fs::read_to_string(dir.join("x.csv")).unwrap();
    let frames = frame_count(&csv);
    assert!(frames > 2, "{frames} frames");
    // The interrupted run's trajectory is the first K steps of a run of K steps.
    assert_eq!(csv, uninterrupted_csv(&dir, frames - 1));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_killed_run_leaves_whole_rows_of_its_trajectory() {
    let dir = temp_dir("sigkill");
    let mut child = start_long_run(&dir);
    let part = dir.join("x.csv.part");
    wait_for_rows(&part);
    signal(&child, "-KILL");
    child.wait().unwrap();
    assert!(!dir.join("x.csv").exists());
    let text = std::fs::read_to_string(&part).unwrap();
    assert!(text.ends_with('\n'), "the streamed file ends with a whole row");
    // Whole frames: every body of each frame (21 links), rows as in an
    // uninterrupted run's table.
    let rows = text.lines().count() - 1;
    assert_eq!(rows % 21, 0, "{rows} rows are not whole frames");
    let frames = rows / 21;
    assert_eq!(text, uninterrupted_csv(&dir, frames - 1));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_resumed_run_equals_an_uninterrupted_one_bit_for_bit() {
    let dir = temp_dir("resume");
    let snapshot = dir.join("c.snapshot");
    let first = tumble()
        .args(["run"])
        .arg(chain_scene())
        .args([
            "--steps",
            "60",
            "--checkpoint-every",
            "30",
            "--quiet",
            "--checkpoint",
        ])
        .arg(&snapshot)
        .status()
        .unwrap();
    assert!(first.success());
    let resumed_csv = dir.join("b.csv");
    let second = tumble()
        .args(["run"])
        .arg(chain_scene())
        .args(["--steps", "100", "--resume"])
        .arg(&snapshot)
        .arg("--trajectory")
        .arg(&resumed_csv)
        .output()
        .unwrap();
    assert!(
        second.status.success(),
        "{}",
        String::from_utf8_lossy(&second.stderr)
    );
    assert!(String::from_utf8_lossy(&second.stdout).contains("resumed at step 60"));
    let resumed = std::fs::read_to_string(&resumed_csv).unwrap();
    let full = uninterrupted_csv(&dir, 100);
    // Frames 60..=100 of the full run, header apart.
    let tail: Vec<&str> = full.lines().skip(1 + 60 * 21).collect();
    let resumed_rows: Vec<&str> = resumed.lines().skip(1).collect();
    assert_eq!(resumed_rows.len(), 41 * 21);
    assert_eq!(resumed_rows, tail);

    // A snapshot at or after the run's end, or of another scene, is refused.
    let late = tumble()
        .args(["run"])
        .arg(chain_scene())
        .args(["--steps", "50", "--resume"])
        .arg(&snapshot)
        .output()
        .unwrap();
    assert_eq!(late.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&late.stderr).contains("nothing to resume"));
    let other = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/domino.toml");
    let wrong = tumble()
        .args(["run"])
        .arg(other)
        .args(["--resume"])
        .arg(&snapshot)
        .output()
        .unwrap();
    assert_eq!(wrong.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&wrong.stderr).contains("not a snapshot of"));
    let _ = std::fs::remove_dir_all(&dir);
}
