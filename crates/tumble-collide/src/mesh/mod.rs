//! Triangle meshes: the validated [`TriMesh`] type, its topology checks,
//! generators for the standard solids and loaders for OBJ and STL files
//! (thesis 6.2, `BodyCreatorUtil`).

mod generators;
mod load;
pub mod topology;
mod trimesh;

pub use generators::{
    bowl_mesh, box_mesh, capsule_mesh, cone_mesh, cylinder_mesh, grid_mesh, half_pipe_mesh, icosphere_mesh,
    revolved_mesh, torus_mesh, uv_sphere_mesh, GeneratorError, MAX_GENERATED_TRIANGLES,
};
pub use load::{load_mesh, load_obj, load_stl, obj_from_bytes, stl_from_bytes, LoadError};
pub use topology::{EdgeReport, Topology};
pub use trimesh::{MeshError, TriMesh};
