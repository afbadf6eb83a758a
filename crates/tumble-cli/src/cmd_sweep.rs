//! `tumble sweep`: one run of a scene per combination of parameter values
//! (`tumble::sweep`), on every core, into a results table (.parquet, .csv or
//! .json). Finished runs go to `OUT.part` as they end; Ctrl-C stops the
//! sweep (the running runs are cancelled) and writes the table of what
//! finished, exit status 130; `--resume` runs only the runs not in
//! `OUT.part`. With `--ray ADDRESS` the same sweep is handed to the Python
//! package's Ray backend (`tumble.sweep(..., backend="ray")`).

use crate::{interrupt, CliError};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::Value;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Mutex;
use tumble::scene::params::value_from_text;
use tumble::scene::SceneDocument;
use tumble::sweep::{RunLength, RunStatus, Sweep};

/// Arguments of `tumble sweep`.
#[derive(Args)]
#[command(after_long_help = SWEEP_EXAMPLES)]
pub struct SweepArgs {
    /// Scene file (.toml or .json).
    #[arg(value_name = "SCENE")]
    scene: PathBuf,
    /// A parameter and its values: PATH=v1,v2,... where PATH names a value
    /// of the scene file (settings.dt, bodies[ball].restitution,
    /// bodies[0].position[2], materials.rubber.friction) and each value is
    /// JSON (0.5, [0, 0, 1], true) or text; or PATH=START:STOP:COUNT for
    /// COUNT evenly spaced numbers. Repeat for more parameters: one run per
    /// combination, the first parameter varying slowest.
    #[arg(long = "param", value_name = "PATH=V1,V2,...", required = true)]
    params: Vec<String>,
    /// Steps per run.
    #[arg(long, value_name = "N", conflicts_with = "duration")]
    steps: Option<u64>,
    /// Simulated time per run (s), in steps of each run's own dt. Default:
    /// the scene's steps or duration.
    #[arg(long, value_name = "S")]
    duration: Option<f64>,
    /// Metrics, each a column of the table (repeat or separate by commas).
    /// See the list below.
    #[arg(long = "metric", value_name = "NAME", value_delimiter = ',', default_values_t = ["max_penetration".to_string(), "energy_drift".to_string()])]
    metrics: Vec<String>,
    /// The results table: .parquet, .csv or .json.
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
    /// Also write each finished run's trajectory to DIR/run_00007.csv (run
    /// 7; the CSV of `tumble run --trajectory`), named in a `trajectory` column.
    #[arg(long, value_name = "DIR")]
    trajectories: Option<PathBuf>,
    /// Run only the runs not yet in OUT.part (from an interrupted sweep).
    #[arg(long)]
    resume: bool,
    /// Worker threads, one run each (0: every core).
    #[arg(long, value_name = "N", default_value_t = 0)]
    threads: u32,
    /// Run on the Ray cluster at ADDRESS ("auto", "ray://host:10001", or
    /// "local" for a cluster started here) through the Python package
    /// (pip install .[ray]); the table is the same, bit for bit.
    #[arg(long, value_name = "ADDRESS")]
    ray: Option<String>,
    /// No progress bar and no summary.
    #[arg(long, short)]
    quiet: bool,
}

const SWEEP_EXAMPLES: &str = "\
Examples:
  tumble sweep examples/scenes/first.toml --param materials.rubber.restitution=0.2,0.5,0.8 \\
      --metric ball.rebound_z --out bounce.csv
  tumble sweep examples/scenes/domino.toml --param settings.dt=0.004,0.008,0.016 \\
      --param settings.substeps=4,8 --duration 3 --out dt.parquet

Metrics: max_penetration (m), energy_start, energy_end, energy_drift
(kinetic + potential, J), kinetic_energy_end (J), max_joint_error (m), time (s),
toppled (dynamic bodies turned more than 45 degrees from their start), and per
body NAME.x, NAME.y, NAME.z (final centre of mass, m), NAME.max_z, NAME.min_z,
NAME.speed (final, m/s), NAME.rebound_z (highest z after the body first turned
from falling to rising, m).

The table has one row per run: run, one column per parameter, status (ok,
failed, cancelled), error, steps, then the metrics. A run that fails (a bad
value, a state that became non-finite) is a row with its error; the others go
on. A parameter path that the scene does not have stops the sweep before it
starts (exit status 2). Ctrl-C cancels the running runs and writes the table of
the finished ones (exit status 130); `--resume` then runs only the rest.";

/// Splits `v1,v2,...` at the commas outside brackets and quotes.
fn split_values(text: &str) -> Vec<String> {
    let (mut out, mut cur, mut depth, mut quoted) = (Vec::new(), String::new(), 0i32, false);
    for c in text.chars() {
        match c {
            '"' => quoted = !quoted,
            '[' | '{' if !quoted => depth += 1,
            ']' | '}' if !quoted => depth -= 1,
            ',' if depth == 0 && !quoted => {
                out.push(std::mem::take(&mut cur));
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    out.push(cur);
    out
}

/// `START:STOP:COUNT`: COUNT evenly spaced numbers, both ends included.
fn linspace(text: &str) -> Option<Result<Vec<Value>, String>> {
    let parts: Vec<&str> = text.split(':').collect();
    let [a, b, n] = parts.as_slice() else {
        return None;
    };
    let (a, b) = (a.trim().parse::<f64>().ok()?, b.trim().parse::<f64>().ok()?);
    let n = n.trim().parse::<usize>().ok()?;
    if !(a.is_finite() && b.is_finite()) || n < 2 {
        return Some(Err(format!(
            "{text:?}: START:STOP:COUNT needs finite ends and COUNT >= 2"
        )));
    }
    Some(Ok((0..n)
        .map(|k| Value::from(a + (b - a) * k as f64 / (n - 1) as f64))
        .collect()))
}

fn parse_param(text: &str) -> Result<(String, Vec<Value>), CliError> {
    let (path, values) = text
        .split_once('=')
        .ok_or_else(|| CliError::Input(format!("--param {text:?}: expected PATH=V1,V2,...")))?;
    if let Some(range) = linspace(values) {
        let values = range.map_err(|e| CliError::Input(format!("--param {path}: {e}")))?;
        return Ok((path.trim().to_string(), values));
    }
    let values: Vec<Value> = split_values(values)
        .iter()
        .filter(|v| !v.trim().is_empty())
        .map(|v| value_from_text(v))
        .collect();
    if values.is_empty() {
        return Err(CliError::Input(format!("--param {text:?}: no values after '='")));
    }
    Ok((path.trim().to_string(), values))
}

/// Hands the sweep to `tumble.sweep(..., backend="ray")` in Python.
fn run_on_ray(args: &SweepArgs, params: &[(String, Vec<Value>)], address: &str) -> Result<(), CliError> {
    let spec = serde_json::json!({
        "scene": args.scene,
        // A list of pairs, not an object: the order of the parameters is the
        // order of the runs.
        "params": params.iter().map(|(p, v)| serde_json::json!([p, v])).collect::<Vec<_>>(),
        "steps": args.steps,
        "duration": args.duration,
        "metrics": args.metrics,
        "out": args.out,
        "trajectories": args.trajectories,
        "resume": args.resume,
        "address": if address == "local" { Value::Null } else { Value::from(address) },
        "progress": !args.quiet,
    });
    let python = std::env::var("TUMBLE_PYTHON").unwrap_or_else(|_| "python3".into());
    let status = std::process::Command::new(&python)
        .args(["-m", "tumble._sweep_cli"])
        .arg(spec.to_string())
        .status()
        .map_err(|e| {
            CliError::Input(format!(
                "--ray: cannot start {python} ({e}); the Ray backend runs through the tumble Python \
                 package (pip install .[ray]); set TUMBLE_PYTHON to its interpreter"
            ))
        })?;
    match status.code() {
        Some(0) => Ok(()),
        Some(130) => Err(CliError::Interrupted("sweep interrupted".into())),
        Some(2) => Err(CliError::Input(
            "--ray: the Python sweep refused its input (message above)".into(),
        )),
        _ => Err(CliError::Internal(format!(
            "--ray: {python} -m tumble._sweep_cli failed ({status}); is the tumble package with Ray \
             installed there (pip install .[ray])?"
        ))),
    }
}

/// Runs the verb.
pub fn run(args: &SweepArgs) -> Result<(), CliError> {
    let params = args
        .params
        .iter()
        .map(|p| parse_param(p))
        .collect::<Result<Vec<_>, _>>()?;
    let ext = args
        .out
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if !["parquet", "csv", "json"].contains(&ext.as_str()) {
        return Err(CliError::Input(format!(
            "--out {}: give a .parquet, .csv or .json file",
            args.out.display()
        )));
    }
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError::Input(format!("{}: cannot create directory: {e}", dir.display())))?;
    }
    let length = match (args.steps, args.duration) {
        (Some(n), _) => RunLength::Steps(n),
        (None, Some(t)) => RunLength::Duration(t),
        (None, None) => RunLength::Scene,
    };
    let doc = SceneDocument::load(&args.scene).map_err(|e| CliError::Input(e.to_string()))?;
    let mut sweep =
        Sweep::new(doc, params.clone(), length, &args.metrics).map_err(|e| CliError::Input(e.to_string()))?;
    if let Some(dir) = &args.trajectories {
        sweep = sweep
            .with_trajectories(dir)
            .map_err(|e| CliError::Input(e.to_string()))?;
    }
    if let Some(address) = &args.ray {
        return run_on_ray(args, &params, address);
    }

    // The journal of finished runs beside the table, as a run's streamed trajectory.
    let part = crate::cmd_run::part_path(&args.out);
    let (journal, mut rows) = sweep
        .open_journal(&part, args.resume)
        .map_err(|e| CliError::Input(e.to_string()))?;
    let done: std::collections::BTreeSet<usize> = rows.iter().map(|r| r.index).collect();
    let pending: Vec<usize> = (0..sweep.len()).filter(|i| !done.contains(i)).collect();
    interrupt::install();
    let bar = if args.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(Some(sweep.len() as u64), ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("sweep {bar:40} {pos}/{len} runs, {elapsed} (eta {eta})")
                .expect("static template"),
        );
        bar.set_position(done.len() as u64);
        bar
    };
    let journal = Mutex::new(journal);
    let journal_error: Mutex<Option<String>> = Mutex::new(None);
    let new_rows = sweep.run(&pending, args.threads, interrupt::flag(), &|row| {
        let mut j = journal.lock().unwrap_or_else(|e| e.into_inner());
        if let Err(e) = j.append(std::slice::from_ref(row)) {
            *journal_error.lock().unwrap_or_else(|e| e.into_inner()) = Some(e.to_string());
        }
        bar.inc(1);
    });
    bar.finish_and_clear();
    if let Some(e) = journal_error.into_inner().unwrap_or_else(|e| e.into_inner()) {
        return Err(CliError::Input(e));
    }
    rows.extend(new_rows);
    let table = sweep.table(&rows);
    table
        .write(&args.out)
        .map_err(|e| CliError::Input(e.to_string()))?;
    let count = |s: fn(&RunStatus) -> bool| rows.iter().filter(|r| s(&r.status)).count();
    let (ok, failed, cancelled) = (
        count(|s| *s == RunStatus::Ok),
        count(|s| matches!(s, RunStatus::Failed(_))),
        count(|s| *s == RunStatus::Cancelled),
    );
    if cancelled == 0 {
        let _ = std::fs::remove_file(&part);
    }
    if !args.quiet {
        let resumed = if done.is_empty() {
            String::new()
        } else {
            format!(" ({} from an earlier run)", done.len())
        };
        println!(
            "{}: {} runs: {ok} ok, {failed} failed, {cancelled} cancelled{resumed}",
            args.scene.display(),
            sweep.len()
        );
        println!("wrote {}", args.out.display());
    }
    if cancelled > 0 {
        return Err(CliError::Interrupted(format!(
            "sweep interrupted: {cancelled} runs cancelled; `--resume` runs them (finished runs are in {})",
            part.display()
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_split_at_top_level_commas() {
        assert_eq!(split_values("0.1,0.2"), ["0.1", "0.2"]);
        assert_eq!(split_values("[0,0,1],[1,0,0]"), ["[0,0,1]", "[1,0,0]"]);
        assert_eq!(split_values("\"a,b\",c"), ["\"a,b\"", "c"]);
        let Ok((p, v)) = parse_param("bodies[ball].position=[0,0,1],[0,0,2]") else {
            panic!("a list of vectors parses")
        };
        assert_eq!(p, "bodies[ball].position");
        assert_eq!(
            v,
            vec![serde_json::json!([0, 0, 1]), serde_json::json!([0, 0, 2])]
        );
        assert!(parse_param("settings.dt").is_err());
        let Ok((_, v)) = parse_param("settings.dt=0.01:0.02:3") else {
            panic!("a range parses")
        };
        assert_eq!(
            v,
            vec![
                serde_json::json!(0.01),
                serde_json::json!(0.015),
                serde_json::json!(0.02)
            ]
        );
        assert!(parse_param("settings.dt=0.01:0.02:1").is_err());
        assert!(parse_param("settings.dt=").is_err());
    }
}
