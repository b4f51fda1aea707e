//! The animation phase (paper §3.2–3.3), pure math: easing, animated
//! parameters, pin-distance falloff, key blending and the layer stack,
//! joined by [`evaluate()`].
//!
//! - [`ease`]: the interpolation curves of segments and parameter keys.
//! - [`track`]: the value of an animated parameter at a frame.
//! - [`falloff`]: a = (d_cp/d_max)^falloff in material space.
//! - [`cache`]: rest shapes cached per key by content.
//! - [`blend`]: in-betweens: which keys surround a frame, and their blend.
//! - [`layer`]: the one interface every layer implements ([`layer::ApplyLayer`]).
//! - [`sway`], [`wave`], [`gusts`], [`follow_through`]: the layers, whose parameters
//!   are listed once in `scene/layers.rs`.
//! - [`stretch_limit`]: after the layers, no edge longer than the cloth allows.
//! - [`colliders_at`], [`keep_out`]: the colliders at a frame, and every point kept outside them.
//! - [`detours`]: in-betweens that go round the colliders that never move instead of through them.
//! - [`posed_solids`]: the colliding references' solids at the poses asked for last.
//! - [`follow`]: the cloth carried by a node of a reference.
//! - [`attachments`]: pins bound to a reference, exactly on it at every frame.
//! - [`references_at`]: each referenced glTF file posed at a frame, placed in the scene.
//! - [`noise`]: the seeded value noise behind the gusts; [`wave_tables`]: the sines behind the wave.
//! - [`evaluate`](mod@evaluate): scene + time → mesh.

pub mod attachments;
pub mod blend;
pub mod cache;
pub mod colliders_at;
pub mod detours;
pub mod ease;
pub mod evaluate;
pub mod falloff;
pub mod follow;
pub mod follow_through;
pub mod gusts;
pub mod keep_out;
pub mod keep_side;
pub mod layer;
pub mod noise;
pub mod posed_solids;
pub mod references_at;
pub mod stretch_limit;
pub mod sway;
pub mod track;
pub mod wave;
pub mod wave_tables;

pub use cache::{KeyShape, RestShapeCache, ShapeId, key_obstacles, key_obstacles_among};
pub use evaluate::{EvaluateOptions, Evaluator, Stage, evaluate, frame_time_secs};
