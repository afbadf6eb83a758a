//! `tumble collide`: the collision query API of `tumble_collide::query` on
//! two meshes (files or generator specs) at given poses: intersection,
//! triangle pairs, contacts, distance and tolerance, as text or one JSON
//! object.

use crate::mesh_spec::{parse_mesh_arg, GENERATOR_HELP};
use crate::CliError;
use clap::{Args, ValueEnum};
use serde_json::{json, Map, Value};
use tumble_collide::query::{self, CollideOptions, DistanceOptions, MeshShape, ReportMode};
use tumble_collide::{Contact, DQuat, DVec3, Pose};

/// What `--report` asks for.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ReportArg {
    /// Only whether the meshes intersect (stops at the first pair).
    Bool,
    /// Every intersecting triangle pair.
    Pairs,
    /// The pairs and the contacts (point, normal, depth, kind).
    Contacts,
}

/// Arguments of `tumble collide`.
#[derive(Args)]
pub struct CollideArgs {
    /// Mesh A: file (.obj, .stl) or generator spec (e.g. torus:R=1,r=0.3,n=50).
    #[arg(value_name = "A", long_help = format!("Mesh A: file (.obj, .stl) or generator spec: {GENERATOR_HELP}"))]
    a: String,
    /// Mesh B: file or generator spec.
    #[arg(value_name = "B")]
    b: String,
    /// Pose of A: "x y z qx qy qz qw" (m; unit quaternion), or "x y z". Default identity.
    #[arg(long, value_name = "POSE", allow_hyphen_values = true)]
    pose_a: Option<String>,
    /// Pose of B: "x y z qx qy qz qw" (m; unit quaternion), or "x y z". Default identity.
    #[arg(long, value_name = "POSE", allow_hyphen_values = true)]
    pose_b: Option<String>,
    /// Stop at the first intersecting triangle pair.
    #[arg(long)]
    first: bool,
    /// What to report.
    #[arg(long, value_enum, default_value = "pairs")]
    report: ReportArg,
    /// Largest gap (m) still reported as a contact with --report contacts. Default 0.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    margin: f64,
    /// Also compute the minimum distance and the closest points.
    #[arg(long)]
    distance: bool,
    /// Also answer whether the meshes come within this distance (m).
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    tolerance: Option<f64>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Parses "x y z qx qy qz qw" or "x y z" (spaces or commas) into a pose.
pub fn parse_pose(flag: &str, text: &str) -> Result<Pose, String> {
    let expected = "expected \"x y z qx qy qz qw\" (or \"x y z\")";
    let nums: Vec<f64> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("{flag}: {expected}, got '{text}' (not all numbers)"))?;
    let (p, q) = match nums.as_slice() {
        [x, y, z] => (DVec3::new(*x, *y, *z), DQuat::IDENTITY),
        [x, y, z, qx, qy, qz, qw] => (DVec3::new(*x, *y, *z), DQuat::from_xyzw(*qx, *qy, *qz, *qw)),
        _ => {
            return Err(format!(
                "{flag}: {expected}, got {} numbers in '{text}'",
                nums.len()
            ))
        }
    };
    Pose::new(p, q).map_err(|e| format!("{flag}: {e}"))
}

fn load(arg: &str) -> Result<MeshShape, CliError> {
    let mesh = parse_mesh_arg(arg).map_err(CliError::Input)?;
    MeshShape::new(mesh).map_err(|e| CliError::Input(format!("{arg}: {e}")))
}

fn v3(v: DVec3) -> Value {
    json!([v.x, v.y, v.z])
}

fn contact_json(c: &Contact) -> Value {
    json!({
        "point": v3(c.point),
        "normal": v3(c.normal),
        "depth": c.depth(),
        "kind": format!("{:?}", c.kind),
        "feature_a": c.feature_a,
        "feature_b": c.feature_b,
    })
}

/// Runs the verb.
pub fn run(args: &CollideArgs) -> Result<(), CliError> {
    let pose_of = |flag: &str, text: &Option<String>| match text {
        None => Ok(Pose::IDENTITY),
        Some(t) => parse_pose(flag, t).map_err(CliError::Input),
    };
    let pose_a = pose_of("--pose-a", &args.pose_a)?;
    let pose_b = pose_of("--pose-b", &args.pose_b)?;
    let a = load(&args.a)?;
    let b = load(&args.b)?;
    let input = |e: query::QueryError| CliError::Input(e.to_string());
    let options = CollideOptions {
        stop_at_first: args.first,
        report: match args.report {
            ReportArg::Bool => ReportMode::Boolean,
            ReportArg::Pairs => ReportMode::TrianglePairs,
            ReportArg::Contacts => ReportMode::Contacts,
        },
        contact_margin: args.margin,
    };
    let report = query::collide(&a, &pose_a, &b, &pose_b, &options).map_err(input)?;
    let dist = if args.distance {
        Some(query::distance(&a, &pose_a, &b, &pose_b, &DistanceOptions::default()).map_err(input)?)
    } else {
        None
    };
    let within = match args.tolerance {
        Some(t) => Some((
            t,
            query::within_tolerance(&a, &pose_a, &b, &pose_b, t).map_err(input)?,
        )),
        None => None,
    };
    if args.json {
        let mut out = Map::new();
        out.insert("intersect".into(), json!(report.intersect));
        if args.report != ReportArg::Bool {
            let pairs: Vec<[u32; 2]> = report.pairs.iter().map(|&(i, j)| [i, j]).collect();
            out.insert("pairs".into(), json!(pairs));
        }
        if args.report == ReportArg::Contacts {
            out.insert(
                "contacts".into(),
                Value::Array(report.contacts.iter().map(contact_json).collect()),
            );
        }
        if let Some(d) = &dist {
            out.insert(
                "distance".into(),
                json!({"distance": d.distance, "point_a": v3(d.point_a), "point_b": v3(d.point_b),
                       "tri_a": d.tri_a, "tri_b": d.tri_b}),
            );
        }
        if let Some((t, w)) = within {
            out.insert("within_tolerance".into(), json!({"tolerance": t, "within": w}));
        }
        out.insert("stats".into(), json!(report.stats));
        println!("{}", Value::Object(out));
        return Ok(());
    }
    let pose_text = |p: &Pose| {
        let (x, q) = (p.position, p.rotation);
        format!("({} {} {} | {} {} {} {})", x.x, x.y, x.z, q.x, q.y, q.z, q.w)
    };
    for (name, arg, m, p) in [("A", &args.a, &a, &pose_a), ("B", &args.b, &b, &pose_b)] {
        println!(
            "{name}: {arg} ({} triangles) at {}",
            m.mesh().triangles().len(),
            pose_text(p)
        );
    }
    println!("intersect: {}", if report.intersect { "yes" } else { "no" });
    if args.report != ReportArg::Bool {
        let shown: Vec<String> = report
            .pairs
            .iter()
            .take(10)
            .map(|(i, j)| format!("({i}, {j})"))
            .collect();
        let more = if report.pairs.len() > 10 { " ..." } else { "" };
        println!("triangle pairs: {} {}{more}", report.pairs.len(), shown.join(" "));
    }
    if args.report == ReportArg::Contacts {
        println!("contacts: {}", report.contacts.len());
        for c in report.contacts.iter().take(20) {
            println!(
                "  {:?} at ({:.6} {:.6} {:.6}), normal ({:.6} {:.6} {:.6}), depth {:.6} m",
                c.kind,
                c.point.x,
                c.point.y,
                c.point.z,
                c.normal.x,
                c.normal.y,
                c.normal.z,
                c.depth()
            );
        }
    }
    if let Some(d) = &dist {
        println!(
            "distance: {} m between ({} {} {}) on A triangle {} and ({} {} {}) on B triangle {}",
            d.distance,
            d.point_a.x,
            d.point_a.y,
            d.point_a.z,
            d.tri_a,
            d.point_b.x,
            d.point_b.y,
            d.point_b.z,
            d.tri_b
        );
    }
    if let Some((t, w)) = within {
        println!("within {t} m: {}", if w { "yes" } else { "no" });
    }
    println!(
        "work: {} box tests, {} triangle tests{}",
        report.stats.bv_tests,
        report.stats.triangle_tests,
        if report.stats.stopped_early {
            " (stopped at the first pair)"
        } else {
            ""
        }
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poses_parse_or_explain() {
        let p = parse_pose("--pose-a", "1 2 3").unwrap();
        assert_eq!(p.position, DVec3::new(1.0, 2.0, 3.0));
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let p = parse_pose("--pose-a", &format!("0,0,-1, 0 0 {s} {s}")).unwrap();
        assert!((p.transform_vector(DVec3::X) - DVec3::Y).length() < 1e-12);
        assert!(parse_pose("--pose-b", "1 2")
            .unwrap_err()
            .contains("got 2 numbers"));
        assert!(parse_pose("--pose-b", "1 2 x")
            .unwrap_err()
            .contains("not all numbers"));
        assert!(parse_pose("--pose-b", "0 0 0 1 1 1 1")
            .unwrap_err()
            .contains("unit quaternion"));
        assert!(parse_pose("--pose-b", "nan 0 0").unwrap_err().contains("finite"));
    }
}
