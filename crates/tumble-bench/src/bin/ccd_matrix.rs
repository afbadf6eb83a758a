//! `ccd-matrix`: the projectile matrix of issue 16 (`tumble::scenes::projectile_cases`:
//! box, sphere, capsule, convex hull and mesh projectiles at 10 to 1,000 m/s against box
//! and mesh slabs 1 mm to 10 cm thick, turned 0 to 60 degrees) run in tumble (continuous
//! collision on, its default) and in Rapier (rapier3d, f32, `ccd_enabled` on the
//! projectile) in one invocation, every flight judged by the same `tumble::scenes::Flight`:
//! passing through the slab's square, gaining kinetic energy, being held in place while
//! moving. Prints a Markdown table per engine and projectile, then the failing cases.
//!
//! Same settings for both: dt 1/60 s, no gravity, restitution 0, no sleeping, default
//! solver settings; the projectile has the same mass and principal inertia in both (a
//! Rapier mesh gets tumble's solid mass properties). Rapier's friction is its default
//! (0.5), tumble's too.
//!
//! Usage: `ccd-matrix [--json FILE]`

use rapier3d::prelude::*;
use serde_json::json;
use tumble::scenes::{
    fire_projectile, projectile_cases, Fault, Projectile, ProjectileCase, PROJECTILE_STEPS,
};
use tumble_bench::rapier_scenes::{self as rs, v};

/// One case in Rapier, judged like tumble's.
fn fire_in_rapier(case: &ProjectileCase) -> Result<(), (Fault, String)> {
    let setup = |e: String| (Fault::NotFinite, format!("setup: {e}"));
    // Tumble's body gives the mass properties both engines use.
    let (tumble_world, ids) = case.scene(true).build().map_err(|e| setup(e.to_string()))?;
    let body = tumble_world.body(ids[1]).map_err(|e| setup(e.to_string()))?;
    let (mass, inertia) = (body.mass(), body.principal_inertia());
    let mut w = rs::world();
    w.gravity = Vector::ZERO;
    let turn = case.turn().to_scaled_axis().to_array();
    w.insert(
        RigidBodyBuilder::fixed().rotation(v(turn)),
        rs::collider(&case.slab_shape())
            .map_err(setup)?
            .friction(rs::FRICTION)
            .restitution(0.0),
    );
    let projectile = rs::collider(&case.projectile.shape())
        .map_err(setup)?
        .friction(rs::FRICTION)
        .restitution(0.0)
        .mass_properties(MassProperties::new(
            Vector::ZERO,
            mass as f32,
            v(inertia.to_array()),
        ));
    let handle = w
        .insert(
            RigidBodyBuilder::dynamic()
                .translation(v(case.start().to_array()))
                .linvel(v(case.velocity().to_array()))
                .ccd_enabled(true)
                .can_sleep(false),
            projectile,
        )
        .0;
    let mut flight = case.flight(0.5 * mass * case.speed * case.speed);
    for _ in 0..PROJECTILE_STEPS {
        w.step();
        let b = &w.bodies[handle];
        let t = b.translation();
        let position = tumble::collide::DVec3::new(t.x as f64, t.y as f64, t.z as f64);
        flight.observe(position, b.kinetic_energy() as f64, b.linvel().length() as f64)?;
    }
    Ok(())
}

#[derive(Default, Clone, Copy)]
struct Tally {
    cases: usize,
    through: usize,
    energy: usize,
    held: usize,
    other: usize,
}

impl Tally {
    fn add(&mut self, r: &Result<(), (Fault, String)>) {
        self.cases += 1;
        match r {
            Ok(()) => {}
            Err((Fault::PassedThrough, _)) => self.through += 1,
            Err((Fault::GainedEnergy, _)) => self.energy += 1,
            Err((Fault::Held, _)) => self.held += 1,
            Err((Fault::NotFinite, _)) => self.other += 1,
        }
    }
    fn held_all(&self) -> usize {
        self.cases - self.through - self.energy - self.held - self.other
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let json_out = args
        .iter()
        .position(|a| a == "--json")
        .and_then(|i| args.get(i + 1))
        .cloned();
    let cases = projectile_cases();
    let engines = ["tumble", "rapier3d (ccd)"];
    let mut tallies = vec![[Tally::default(); 5]; 2];
    let mut failures: Vec<(usize, String)> = Vec::new();
    let mut records = Vec::new();
    for case in &cases {
        let k = Projectile::ALL
            .iter()
            .position(|p| *p == case.projectile)
            .expect("known");
        let results = [fire_projectile(case, true), fire_in_rapier(case)];
        for (e, r) in results.iter().enumerate() {
            tallies[e][k].add(r);
            if let Err((_, why)) = r {
                failures.push((e, format!("{}: {why}", case.label())));
            }
        }
        records.push(json!({
            "case": case.label(),
            "tumble": results[0].as_ref().err().map(|(_, w)| w.clone()),
            "rapier3d": results[1].as_ref().err().map(|(_, w)| w.clone()),
        }));
    }
    println!("| engine | projectile | cases | no fault | passed through | gained energy | held in place or not finite |");
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for (e, engine) in engines.iter().enumerate() {
        for (k, p) in Projectile::ALL.iter().enumerate() {
            let t = tallies[e][k];
            println!(
                "| {engine} | {} | {} | {} | {} | {} | {} |",
                p.name(),
                t.cases,
                t.held_all(),
                t.through,
                t.energy,
                t.held + t.other
            );
        }
    }
    for (e, engine) in engines.iter().enumerate() {
        let n = failures.iter().filter(|(f, _)| *f == e).count();
        println!("\n{engine}: {n} of {} cases fail", cases.len());
        for (_, why) in failures.iter().filter(|(f, _)| *f == e) {
            println!("- {why}");
        }
    }
    if let Some(path) = json_out {
        let doc = json!({ "cases": records });
        if let Err(e) = std::fs::write(&path, serde_json::to_string_pretty(&doc).expect("json")) {
            eprintln!("ccd-matrix: {path}: {e}");
            std::process::exit(1);
        }
    }
}
