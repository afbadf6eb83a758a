//! Mesh arguments of the command line: a file path (`.obj`, `.stl`) or a
//! generator spec such as `torus:R=1,r=0.3,n=50` or `box:hx=1,hy=0.5,hz=0.25`.

use std::collections::BTreeMap;
use tumble_collide::mesh::{self, TriMesh};
use tumble_collide::DVec3;

/// Generators understood by [`parse_mesh_arg`], for `--help` texts.
pub const GENERATOR_HELP: &str = "box:hx=,hy=,hz= | sphere:r=,n= | icosphere:r=,sub= | \
cylinder:r=,h=,n= | capsule:r=,h=,n= | cone:r=,h=,n= | torus:R=,r=,n= (or nu=,nv=)";

/// Loads a mesh from a file path or builds it from a generator spec.
pub fn parse_mesh_arg(arg: &str) -> Result<TriMesh, String> {
    match arg.split_once(':') {
        Some((name, params)) if is_generator(name) => {
            generate(name, params).map_err(|e| format!("{arg}: {e}"))
        }
        _ => mesh::load_mesh(arg).map_err(|e| e.to_string()),
    }
}

fn is_generator(name: &str) -> bool {
    matches!(
        name,
        "box" | "sphere" | "icosphere" | "cylinder" | "capsule" | "cone" | "torus"
    )
}

struct Params<'a> {
    map: BTreeMap<&'a str, &'a str>,
}

impl<'a> Params<'a> {
    fn parse(text: &'a str, allowed: &[&str]) -> Result<Self, String> {
        let mut map = BTreeMap::new();
        for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (k, v) = item
                .split_once('=')
                .ok_or_else(|| format!("expected key=value, got '{item}'"))?;
            let k = k.trim();
            if !allowed.contains(&k) {
                return Err(format!(
                    "unknown parameter '{k}' (expected one of {})",
                    allowed.join(", ")
                ));
            }
            if map.insert(k, v.trim()).is_some() {
                return Err(format!("parameter '{k}' given twice"));
            }
        }
        Ok(Params { map })
    }

    /// The value of `key` parsed as a `T`, or `default` when it is absent; the
    /// error names the parameter and says what it must be (`what`).
    fn value_or<T: std::str::FromStr>(&self, key: &str, default: T, what: &str) -> Result<T, String> {
        match self.map.get(key) {
            None => Ok(default),
            Some(v) => v
                .parse::<T>()
                .map_err(|_| format!("parameter '{key}' must be {what}, got '{v}'")),
        }
    }

    fn f64_or(&self, key: &str, default: f64) -> Result<f64, String> {
        self.value_or(key, default, "a number")
    }

    fn usize_or(&self, key: &str, default: usize) -> Result<usize, String> {
        self.value_or(key, default, "a non-negative integer")
    }
}

fn generate(name: &str, params: &str) -> Result<TriMesh, String> {
    let e = |err: mesh::GeneratorError| err.to_string();
    match name {
        "box" => {
            let p = Params::parse(params, &["hx", "hy", "hz"])?;
            mesh::box_mesh(DVec3::new(
                p.f64_or("hx", 0.5)?,
                p.f64_or("hy", 0.5)?,
                p.f64_or("hz", 0.5)?,
            ))
            .map_err(e)
        }
        "sphere" => {
            let p = Params::parse(params, &["r", "n"])?;
            let n = p.usize_or("n", 32)?;
            mesh::uv_sphere_mesh(p.f64_or("r", 1.0)?, n, n / 2).map_err(e)
        }
        "icosphere" => {
            let p = Params::parse(params, &["r", "sub"])?;
            mesh::icosphere_mesh(p.f64_or("r", 1.0)?, p.usize_or("sub", 3)?).map_err(e)
        }
        "cylinder" => {
            let p = Params::parse(params, &["r", "h", "n"])?;
            mesh::cylinder_mesh(p.f64_or("r", 0.5)?, p.f64_or("h", 0.5)?, p.usize_or("n", 32)?).map_err(e)
        }
        "capsule" => {
            let p = Params::parse(params, &["r", "h", "n"])?;
            let n = p.usize_or("n", 32)?;
            mesh::capsule_mesh(p.f64_or("r", 0.5)?, p.f64_or("h", 0.5)?, n, (n / 4).max(1)).map_err(e)
        }
        "cone" => {
            let p = Params::parse(params, &["r", "h", "n"])?;
            mesh::cone_mesh(p.f64_or("r", 0.5)?, p.f64_or("h", 1.0)?, p.usize_or("n", 32)?).map_err(e)
        }
        "torus" => {
            let p = Params::parse(params, &["R", "r", "n", "nu", "nv"])?;
            let n = p.usize_or("n", 50)?;
            mesh::torus_mesh(
                p.f64_or("R", 1.0)?,
                p.f64_or("r", 0.3)?,
                p.usize_or("nu", n)?,
                p.usize_or("nv", n)?,
            )
            .map_err(e)
        }
        _ => Err(format!("unknown generator '{name}'")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generator_specs() {
        assert_eq!(
            parse_mesh_arg("torus:R=1,r=0.3,n=50").unwrap().triangles().len(),
            5000
        );
        assert_eq!(
            parse_mesh_arg("box:hx=1,hy=2,hz=3").unwrap().triangles().len(),
            12
        );
        assert!(parse_mesh_arg("torus:R=1,q=2")
            .unwrap_err()
            .contains("unknown parameter 'q'"));
        assert!(parse_mesh_arg("box:hx=-1").is_err());
        assert!(parse_mesh_arg("box:hx=abc")
            .unwrap_err()
            .contains("must be a number"));
        assert!(parse_mesh_arg("/no/such/file.obj").is_err());
    }
}
