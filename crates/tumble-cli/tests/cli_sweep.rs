//! `tumble sweep`: one run per combination of scene parameters into a
//! results table. Checked against physics (a ball's rebound rises e^2 of its
//! drop), against the same sweep uninterrupted (an interrupted and resumed
//! sweep gives the same table, byte for byte), and for located errors.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn tumble() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tumble"))
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tumble-sweep-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A ball dropped from 1 m (its lowest point) onto the ground, 2 s.
fn drop_scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/bounce.toml")
}

/// Rows of a CSV table as maps from column name to cell.
fn rows(csv: &str) -> Vec<std::collections::BTreeMap<String, String>> {
    let mut lines = csv.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

#[test]
fn a_restitution_sweep_bounces_to_e_squared_of_the_drop() {
    let dir = temp_dir("bounce");
    let scene = drop_scene();
    let out = dir.join("bounce.csv");
    let status = tumble()
        .arg("sweep")
        .arg(&scene)
        .args([
            "--param",
            "bodies[ball].restitution=0.3,0.5,0.7,0.9",
            "--param",
            "settings.substeps=4,8",
        ])
        .args(["--metric", "ball.rebound_z,time", "--quiet", "--out"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    assert!(!dir.join("bounce.csv.part").exists());
    let table = rows(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(table.len(), 8);
    for (k, row) in table.iter().enumerate() {
        assert_eq!(row["run"], k.to_string());
        assert_eq!(row["status"], "ok");
        let e: f64 = row["bodies[ball].restitution"].parse().unwrap();
        assert_eq!(e, [0.3, 0.5, 0.7, 0.9][k / 2], "first parameter varies slowest");
        assert_eq!(row["settings.substeps"], ["4", "8"][k % 2]);
        let rebound: f64 = row["ball.rebound_z"].parse::<f64>().unwrap() - 0.1;
        assert!(
            (rebound - e * e).abs() < 0.03 * e * e + 0.005,
            "e = {e}: rebound {rebound} m"
        );
        assert_eq!(row["steps"], "500");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_sweeps_are_refused_naming_the_path_and_the_file() {
    let dir = temp_dir("bad");
    let scene = drop_scene();
    let out = dir.join("x.csv");
    let check = |param: &str, metric: &str, expect: &[&str]| {
        let o = tumble()
            .arg("sweep")
            .arg(&scene)
            .args(["--param", param, "--metric", metric, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{param}");
        let err = String::from_utf8_lossy(&o.stderr);
        for e in expect {
            assert!(err.contains(e), "{param}: {err}");
        }
        assert!(!out.exists());
    };
    check(
        "bodies[rock].mass=1",
        "time",
        &["bounce.toml", "bodies[rock].mass", "no element named \"rock\""],
    );
    check("settings..dt=1", "time", &["settings..dt"]);
    check("settings.dt=0.01", "ball.colour", &["unknown metric"]);
    // A bad value fails its own row only.
    let o = tumble()
        .arg("sweep")
        .arg(&scene)
        .args(["--param", "bodies[ball].mass=1,-2", "--steps", "5", "-q", "--out"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(o.success());
    let table = rows(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(table[0]["status"], "ok");
    assert_eq!(table[1]["status"], "failed");
    assert!(table[1]["error"].contains("bodies[ball].mass=-2"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_interrupted_sweep_keeps_its_rows_and_resumes_to_the_same_table() {
    let dir = temp_dir("resume");
    let scene = drop_scene();
    // 40 runs of 100 s each (25,000 steps): long enough to interrupt.
    let values: Vec<String> = (0..40).map(|k| format!("{}", 0.5 + 0.01 * k as f64)).collect();
    let param = format!("bodies[ball].position[2]={}", values.join(","));
    let sweep = |out: &Path, extra: &[&str]| {
        let mut c = tumble();
        c.arg("sweep")
            .arg(&scene)
            .args([
                "--param",
                &param,
                "--duration",
                "100",
                "--threads",
                "2",
                "--metric",
                "ball.max_z,energy_drift",
                "-q",
            ])
            .args(extra)
            .arg("--out")
            .arg(out);
        c
    };
    let out = dir.join("r.csv");
    let part = dir.join("r.csv.part");
    let child = sweep(&out, &[])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while std::fs::read_to_string(&part).map_or(0, |t| t.lines().count()) < 3 {
        assert!(start.elapsed() < Duration::from_secs(120), "no rows finished");
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let partial = rows(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(partial.len(), 40);
    let finished = partial.iter().filter(|r| r["status"] == "ok").count();
    assert!((3..40).contains(&finished), "{finished} finished");
    assert!(partial
        .iter()
        .all(|r| r["status"] == "ok" || r["status"] == "cancelled"));
    assert!(part.exists(), "the journal stays for --resume");

    // The journal belongs to its sweep: resuming another one is refused.
    let other = tumble()
        .arg("sweep")
        .arg(&scene)
        .args([
            "--param",
            "bodies[ball].position[2]=0.7,0.9",
            "--duration",
            "100",
            "-q",
            "--resume",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(other.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&other.stderr).contains("another sweep"));

    assert!(sweep(&out, &["--resume"]).status().unwrap().success());
    assert!(!part.exists());
    let whole = dir.join("whole.csv");
    assert!(sweep(&whole, &[]).status().unwrap().success());
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        std::fs::read_to_string(&whole).unwrap()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn dominoes_fall_as_far_as_a_domino_reaches() {
    // A domino of height h and thickness t, falling about its front edge,
    // reaches a neighbour whose near face is within h: centres up to h + t
    // apart (1.7 m). Well inside, the whole row falls; beyond, only the
    // pushed domino and the first of the row (0.8 m from it) do.
    let dir = temp_dir("domino");
    let out = dir.join("row.csv");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/domino_row.toml");
    let status = tumble()
        .arg("sweep")
        .arg(scene)
        .args([
            "--param",
            "bodies[row{i}].grid.spacing[0]=0.5,1.0,1.9,2.2",
            "--metric",
            "toppled",
            "-q",
        ])
        .arg("--out")
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let fallen: Vec<String> = rows(&std::fs::read_to_string(&out).unwrap())
        .into_iter()
        .map(|r| r["toppled"].clone())
        .collect();
    assert_eq!(fallen, ["20", "20", "2", "2"]);
    let _ = std::fs::remove_dir_all(&dir);
}
