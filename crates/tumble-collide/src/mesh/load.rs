//! Mesh file loaders: Wavefront OBJ (via `tobj`) and STL, ASCII or binary
//! (via `stl_io`). All groups/objects of a file are merged into one mesh;
//! faces with more than three corners are fan-triangulated by `tobj`.
//!
//! OBJ coordinates are read in double precision (`tobj`'s `use_f64`
//! feature): an OBJ file is text and may carry every digit of an f64, and
//! read through f32 a mesh's mass properties came out ~1e-8 relative off
//! the same mesh built in memory. STL stores f32 by format; its corners are
//! widened exactly.

use super::{MeshError, TriMesh};
use crate::math::DVec3;
use std::io::{BufReader, Cursor};
use std::path::{Path, PathBuf};

/// Why a mesh file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// File path.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// The file is empty.
    #[error("{path}: file is empty")]
    EmptyFile {
        /// File path.
        path: PathBuf,
    },
    /// The extension is neither `.obj` nor `.stl`.
    #[error("{path}: unknown mesh format (expected a .obj or .stl file)")]
    UnknownFormat {
        /// File path.
        path: PathBuf,
    },
    /// The parser rejected the file.
    #[error("{path}: not a valid {format} file: {message}")]
    Parse {
        /// File path.
        path: PathBuf,
        /// "OBJ" or "STL".
        format: &'static str,
        /// What the parser said.
        message: String,
    },
    /// The file parsed but its mesh is invalid.
    #[error("{path}: {source}")]
    Mesh {
        /// File path.
        path: PathBuf,
        /// What is wrong with the mesh.
        source: MeshError,
    },
}

/// Loads `.obj` or `.stl` (by extension, case-insensitive).
pub fn load_mesh(path: impl AsRef<Path>) -> Result<TriMesh, LoadError> {
    let path = path.as_ref();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("obj") => load_obj(path),
        Some("stl") => load_stl(path),
        _ => Err(LoadError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}

fn read_bytes(path: &Path) -> Result<Vec<u8>, LoadError> {
    let bytes = std::fs::read(path).map_err(|source| LoadError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(LoadError::EmptyFile {
            path: path.to_path_buf(),
        });
    }
    Ok(bytes)
}

/// Loads a Wavefront OBJ file (positions and faces; normals and texture
/// coordinates are ignored so that vertices shared by faces stay shared).
pub fn load_obj(path: impl AsRef<Path>) -> Result<TriMesh, LoadError> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    parse_obj(&bytes).map_err(|e| e.at(path))
}

/// Loads an STL file, ASCII or binary. Identical corner positions are merged
/// into shared vertices.
pub fn load_stl(path: impl AsRef<Path>) -> Result<TriMesh, LoadError> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    parse_stl(&bytes).map_err(|e| e.at(path))
}

/// Where in-memory input is said to come from in errors.
const MEMORY: &str = "<memory>";

/// Parses Wavefront OBJ text held in memory (as [`load_obj`] does a file);
/// errors name the source `<memory>`.
pub fn obj_from_bytes(bytes: &[u8]) -> Result<TriMesh, LoadError> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(LoadError::EmptyFile { path: MEMORY.into() });
    }
    parse_obj(bytes).map_err(|e| e.at(Path::new(MEMORY)))
}

/// Parses an STL file (ASCII or binary) held in memory (as [`load_stl`]
/// does a file); errors name the source `<memory>`.
pub fn stl_from_bytes(bytes: &[u8]) -> Result<TriMesh, LoadError> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(LoadError::EmptyFile { path: MEMORY.into() });
    }
    parse_stl(bytes).map_err(|e| e.at(Path::new(MEMORY)))
}

/// A loader error before the file name is attached.
#[derive(Debug)]
pub(crate) enum ParseFailure {
    Parse(&'static str, String),
    Mesh(MeshError),
}

impl ParseFailure {
    fn at(self, path: &Path) -> LoadError {
        match self {
            ParseFailure::Parse(format, message) => LoadError::Parse {
                path: path.to_path_buf(),
                format,
                message,
            },
            ParseFailure::Mesh(source) => LoadError::Mesh {
                path: path.to_path_buf(),
                source,
            },
        }
    }
}

/// Parses OBJ text from memory.
pub(crate) fn parse_obj(bytes: &[u8]) -> Result<TriMesh, ParseFailure> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = BufReader::new(Cursor::new(bytes));
    let (models, _materials) =
        tobj::load_obj_buf(&mut reader, &options, |_| Err(tobj::LoadError::OpenFileFailed))
            .map_err(|e| ParseFailure::Parse("OBJ", e.to_string()))?;
    let mut vertices = Vec::new();
    let mut triangles: Vec<[u64; 3]> = Vec::new();
    for model in &models {
        let base = vertices.len() as u64;
        let m = &model.mesh;
        vertices.extend(m.positions.chunks_exact(3).map(|p| DVec3::new(p[0], p[1], p[2])));
        triangles.extend(
            m.indices
                .chunks_exact(3)
                .map(|t| [base + t[0] as u64, base + t[1] as u64, base + t[2] as u64]),
        );
    }
    TriMesh::from_indices(vertices, &triangles).map_err(ParseFailure::Mesh)
}

/// Parses STL (ASCII or binary) from memory.
pub(crate) fn parse_stl(bytes: &[u8]) -> Result<TriMesh, ParseFailure> {
    let mut cursor = Cursor::new(bytes);
    let indexed = stl_io::read_stl(&mut cursor).map_err(|e| ParseFailure::Parse("STL", e.to_string()))?;
    let vertices = indexed
        .vertices
        .iter()
        .map(|v| DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64))
        .collect();
    let triangles: Vec<[usize; 3]> = indexed.faces.iter().map(|f| f.vertices).collect();
    TriMesh::from_indices(vertices, &triangles).map_err(ParseFailure::Mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TET_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

    #[test]
    fn obj_tetrahedron_is_closed() {
        let m = parse_obj(TET_OBJ.as_bytes()).unwrap();
        assert_eq!(m.triangles().len(), 4);
        m.check_solid().unwrap();
    }

    /// Writes `mesh` as OBJ text with every digit of its coordinates
    /// (Rust's shortest round-trip formatting).
    fn obj_text(mesh: &TriMesh) -> String {
        let mut text = String::new();
        for v in mesh.vertices() {
            text += &format!("v {:?} {:?} {:?}\n", v.x, v.y, v.z);
        }
        for t in mesh.triangles() {
            text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        text
    }

    #[test]
    fn obj_coordinates_keep_double_precision() {
        // A torus's vertices are irrational: through f32 each would move by
        // up to 3e-8 relative. Written with all digits and read back, the
        // mesh must be the same bits, and so must its mass properties.
        let mesh = crate::mesh::torus_mesh(1.0, 0.3, 24, 12).unwrap();
        let back = parse_obj(obj_text(&mesh).as_bytes()).unwrap();
        // (tobj numbers the vertices in the order the faces first use them.)
        let sorted = |m: &TriMesh| {
            let mut v: Vec<[f64; 3]> = m.vertices().iter().map(|p| p.to_array()).collect();
            v.sort_by(|a, b| a.partial_cmp(b).unwrap());
            v
        };
        assert_eq!(sorted(&back), sorted(&mesh));
        assert_eq!(back.signed_volume(), mesh.signed_volume());
        let third = 1.0 / 3.0;
        let one = parse_obj(format!("v {third:?} 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").as_bytes());
        // An open triangle is refused as a solid later, but the loader keeps it.
        assert_eq!(one.unwrap().vertices()[0].x, third);
    }

    #[test]
    fn obj_quads_are_triangulated() {
        let quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
        assert_eq!(parse_obj(quad.as_bytes()).unwrap().triangles().len(), 2);
    }

    #[test]
    fn obj_errors_are_typed() {
        assert!(matches!(
            parse_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
            Err(ParseFailure::Parse(..)) | Err(ParseFailure::Mesh(MeshError::IndexOutOfRange { .. }))
        ));
        assert!(parse_obj(b"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").is_err());
        assert!(parse_obj(b"hello world\n").is_err());
    }

    #[test]
    fn stl_round_trip_shares_vertices() {
        let mesh = crate::mesh::box_mesh(DVec3::new(1.0, 2.0, 0.5)).unwrap();
        let tris: Vec<stl_io::Triangle> = (0..mesh.triangles().len())
            .map(|t| {
                let c = mesh.triangle(t);
                let n = mesh.triangle_normal_scaled(t).normalize();
                stl_io::Triangle {
                    normal: stl_io::Normal::new([n.x as f32, n.y as f32, n.z as f32]),
                    vertices: c.map(|v| stl_io::Vertex::new([v.x as f32, v.y as f32, v.z as f32])),
                }
            })
            .collect();
        let mut buf = Vec::new();
        stl_io::write_stl(&mut buf, tris.iter()).unwrap();
        let back = parse_stl(&buf).unwrap();
        assert_eq!(back.vertices().len(), 8);
        back.check_solid().unwrap();
        assert!((back.signed_volume() - 8.0).abs() < 1e-5);
    }

    #[test]
    fn empty_and_unknown_files() {
        let dir = std::env::temp_dir().join(format!("tumble-load-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let empty = dir.join("empty.obj");
        std::fs::write(&empty, "  \n").unwrap();
        assert!(matches!(load_mesh(&empty), Err(LoadError::EmptyFile { .. })));
        assert!(matches!(
            load_mesh(dir.join("x.ply")),
            Err(LoadError::UnknownFormat { .. })
        ));
        assert!(matches!(
            load_mesh(dir.join("missing.stl")),
            Err(LoadError::Io { .. })
        ));
        std::fs::remove_dir_all(&dir).ok();
    }
}
