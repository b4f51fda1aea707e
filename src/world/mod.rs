//! The world around the cloth (the name DESIGN.md gives it): what the cloth
//! meets and follows, apart from the scene file that describes it.
//!
//! - Colliders as geometry at one moment, with the distance and the outward
//!   direction from any point to their surface: pure math on numbers
//!   already sampled at a frame (`animate::colliders_at` samples a scene's
//!   colliders). Shape and animate use it to keep the cloth outside, render
//!   to draw it.
//! - [`rig`]: the referenced glTF characters and props, their nodes and
//!   skinned meshes posed at any time (what the cloth is pinned to, follows
//!   and, as a solid, keeps out of).

mod carry;
mod collider_shape;
mod edge_lift;
mod far_field;
mod mesh_sides;
mod mesh_solid;
mod outline;
mod path_around;
mod push_out;
mod ray;
pub mod rig;
mod surface_point;
mod tessellate;

pub use carry::carried_with;
pub use collider_shape::{ColliderShape, MESH_EXACT_WITHIN_M};
pub use edge_lift::{EDGE_SHARES, edge_place_lift, edge_surely_clear};
pub use mesh_solid::{MAX_MESH_TRIANGLES, MeshSolid, MeshSolidError};
pub use path_around::{Polyline, path_around};
pub use push_out::{Obstacle, Reach, push_out, push_out_along, slide_along};
pub use ray::ray_hit;
pub use surface_point::SurfacePoint;
pub use tessellate::TriangleMesh;
