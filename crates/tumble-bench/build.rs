//! Records the rapier3d and parry3d versions that Cargo.lock resolved, so that the peers
//! report the version they actually ran (env PEER_RAPIER3D_VERSION, PEER_PARRY3D_VERSION).

use std::path::Path;

fn locked_version(lock: &str, name: &str) -> String {
    let needle = format!("name = \"{name}\"\nversion = \"");
    match lock.find(&needle) {
        Some(at) => {
            let rest = &lock[at + needle.len()..];
            rest.split('"').next().unwrap_or("unknown").to_string()
        }
        None => "unknown".to_string(),
    }
}

fn main() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default();
    let lock_path = Path::new(&manifest).join("../../Cargo.lock");
    println!("cargo:rerun-if-changed={}", lock_path.display());
    let lock = std::fs::read_to_string(&lock_path).unwrap_or_default();
    println!(
        "cargo:rustc-env=PEER_RAPIER3D_VERSION={}",
        locked_version(&lock, "rapier3d")
    );
    println!(
        "cargo:rustc-env=PEER_PARRY3D_VERSION={}",
        locked_version(&lock, "parry3d")
    );
}
