//! Self-contact: where the cloth passes through itself.

mod broad_phase;
mod closest;
mod crossings;
mod geometry;
mod one_to_one;

pub(crate) use broad_phase::{BoxGrid, CellHasher};
pub use closest::segment_triangle_closest;
pub use crossings::count_crossings;

/// What to do about a rest shape that passes through itself, for `drape
/// check` and the Cloth panel: a key with a thickness keeps its folds apart
/// once its drape settles (the relaxation's self-contact), so what is left
/// has a cause the animator can act on.
pub fn crossing_advice(thickness_m: f64, settled: bool) -> &'static str {
    if !(thickness_m > 0.0) {
        "its Thickness is 0: raise it to keep the folds apart"
    } else if !settled {
        "it has not settled; once it does, its folds are kept apart"
    } else {
        "Drape could not keep these folds apart (a fall onto colliders, an approximation that starts folded through \
         itself, or folds too crowded to all keep the thickness): pins that gather the cloth less fold it less"
    }
}
