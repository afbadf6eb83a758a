//! `tumble mass`: mass properties of a mesh file or generated solid.

use crate::mesh_spec::{parse_mesh_arg, GENERATOR_HELP};
use crate::CliError;
use clap::Args;
use serde::Serialize;
use tumble_collide::mass::{mesh_mass_properties, MassFallback, MassSpec};
use tumble_collide::DMat3;

/// Arguments of `tumble mass`.
#[derive(Args)]
pub struct MassArgs {
    /// Mesh file (.obj, .stl) or generator spec (e.g. torus:R=1,r=0.3,n=50).
    #[arg(value_name = "FILE", long_help = format!("Mesh file (.obj, .stl) or generator spec: {GENERATOR_HELP}"))]
    mesh: String,
    /// Uniform density (kg/m^3). Default 1 when neither --density nor --mass is given.
    #[arg(long, conflicts_with = "mass")]
    density: Option<f64>,
    /// Total mass (kg); the density follows from the volume.
    #[arg(long)]
    mass: Option<f64>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct MassReport {
    volume: f64,
    mass: f64,
    com: [f64; 3],
    /// Row-major 3x3 about the centre of mass.
    inertia: [[f64; 3]; 3],
    principal_moments: [f64; 3],
    /// Row-major 3x3 whose columns are the principal axes.
    principal_axes: [[f64; 3]; 3],
}

fn rows(m: &DMat3) -> [[f64; 3]; 3] {
    let r = m.transpose();
    [r.x_axis.to_array(), r.y_axis.to_array(), r.z_axis.to_array()]
}

/// Runs the verb.
pub fn run(args: &MassArgs) -> Result<(), CliError> {
    let mesh = parse_mesh_arg(&args.mesh).map_err(CliError::Input)?;
    let spec = match (args.density, args.mass) {
        (_, Some(m)) => MassSpec::Mass(m),
        (Some(d), None) => MassSpec::Density(d),
        (None, None) => MassSpec::Density(1.0),
    };
    let props = mesh_mass_properties(&mesh, spec, MassFallback::None)
        .map_err(|e| CliError::Input(format!("{}: {e}", args.mesh)))?;
    let frame = props.principal();
    let axes = DMat3::from_quat(frame.rotation);
    let report = MassReport {
        volume: mesh.signed_volume(),
        mass: props.mass,
        com: props.com.to_array(),
        inertia: rows(&props.inertia),
        principal_moments: frame.moments.to_array(),
        principal_axes: rows(&axes),
    };
    if args.json {
        let text = serde_json::to_string(&report).map_err(|e| CliError::Internal(e.to_string()))?;
        println!("{text}");
    } else {
        let v = |a: [f64; 3]| format!("{:>14.8} {:>14.8} {:>14.8}", a[0], a[1], a[2]);
        println!(
            "mesh:              {} ({} vertices, {} triangles)",
            args.mesh,
            mesh.vertices().len(),
            mesh.triangles().len()
        );
        println!("volume (m^3):      {:.10}", report.volume);
        println!("mass (kg):         {:.10}", report.mass);
        println!("centre of mass (m):{}", v(report.com));
        println!("inertia about COM (kg m^2):");
        for row in report.inertia {
            println!("                   {}", v(row));
        }
        println!("principal moments: {}", v(report.principal_moments));
        println!("principal axes (columns):");
        for row in report.principal_axes {
            println!("                   {}", v(row));
        }
    }
    Ok(())
}
