//! Triangle-level narrow phase: the exact tests every mesh-mesh query ends in
//! once the OBBTrees have narrowed a body pair down to triangle pairs.
//!
//! - [`orient`]: orientation predicates (Shewchuk's adaptive exact signs,
//!   from the `robust` crate).
//! - [`tri_tri_overlap`](mod@tri_tri_overlap): closed triangle-triangle
//!   intersection (Guigue & Devillers 2003), coplanar and degenerate cases included.
//! - [`tri_box`]: triangle vs oriented box (Akenine-Moller 2001, 13 axes).
//! - [`tri_distance`]: closest points between points, segments and triangles
//!   (Ericson, Real-Time Collision Detection 5.1.5, 5.1.9).
//! - [`tri_contact`]: vertex/face, face/vertex and edge/edge contacts of a
//!   triangle pair within a margin, and push-out contacts for intersecting pairs
//!   (thesis 5.2, 7.1).
//! - `tri_vertex_edge`: vertex/edge, edge/vertex and vertex/vertex contacts of
//!   two meshes, from the features' owners (Voronoi regions of features).
//! - [`phong`]: a point against the smooth surface a triangle with corner
//!   normals stands for (Phong normals, Phong tessellation).
//! - `tri_measure`: a triangle's box and longest edge, shared by the tests above.
//! - [`merge`]: removal of the duplicates that shared vertices and edges produce.
//!
//! All functions take triangles as `[DVec3; 3]` in one common frame: the caller
//! transforms B into A's frame or both into the world frame.

#[cfg(test)]
mod exact_oracle;
pub mod merge;
pub mod orient;
pub mod phong;
pub mod tri_box;
pub mod tri_contact;
pub mod tri_distance;
mod tri_measure;
pub mod tri_tri_overlap;
mod tri_vertex_edge;

pub use merge::{merge_contacts, MergeError, MergeParams};
pub use orient::{orient2d, orient3d};
pub use phong::{phong_point, PhongPoint, OVER_TRIANGLE_TOLERANCE, PHONG_SHAPE_FACTOR};
pub use tri_box::tri_box_overlap;
pub use tri_contact::{triangle_contacts, TriContactError};
pub(crate) use tri_contact::{triangle_contacts_and_corners, triangle_contacts_owned, Copies, Owned, Side};
pub use tri_distance::{
    closest_point_on_triangle, closest_points_segments, triangle_distance, SegmentClosest, TriDistance,
};
pub use tri_tri_overlap::{segment_triangle_overlap, tri_tri_overlap};
