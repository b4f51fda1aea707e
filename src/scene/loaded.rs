//! What a file the scene names holds once read: a mesh collider's solid, a
//! reference's rig. Kept beside the field that names the file, never written
//! to the scene file.

use std::fmt;
use std::sync::Arc;

use crate::world::MeshSolid;
use crate::world::rig::Rig;

/// A file's contents once read; empty until then. Clones share the contents.
/// Two are equal when both are empty, or both hold equal contents: the same
/// read (compared by address first, so a shown scene and its document compare
/// at no cost) or two reads of equal files.
pub struct Loaded<T>(pub Option<Arc<T>>);

/// A mesh collider's solid once read.
pub type LoadedMesh = Loaded<MeshSolid>;

/// A reference's rig once read.
pub type LoadedRig = Loaded<Rig>;

impl<T> Default for Loaded<T> {
    fn default() -> Self {
        Loaded(None)
    }
}

impl<T> Clone for Loaded<T> {
    fn clone(&self) -> Self {
        Loaded(self.0.clone())
    }
}

impl<T: PartialEq> PartialEq for Loaded<T> {
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b) || a == b,
            _ => false,
        }
    }
}

impl<T: fmt::Debug> fmt::Debug for Loaded<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            Some(contents) => contents.fmt(f),
            None => f.write_str("not read"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn solid(height: f64) -> Arc<MeshSolid> {
        let vertices = [DVec3::ZERO, DVec3::X, DVec3::new(0.0, height, 1.0), DVec3::Y];
        let triangles = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        let Ok(solid) = MeshSolid::new(&vertices, &triangles) else { panic!("a tetrahedron is a solid") };
        Arc::new(solid)
    }

    #[test]
    fn equal_when_both_are_unread_or_hold_equal_contents() {
        let (one, same, other) = (solid(1.0), solid(1.0), solid(2.0));
        assert!(!Arc::ptr_eq(&one, &same));
        assert_eq!(LoadedMesh::default(), Loaded(None));
        assert_eq!(Loaded(Some(one.clone())), Loaded(Some(one.clone())), "the same read");
        assert_eq!(Loaded(Some(one.clone())), Loaded(Some(same)), "two reads of equal files");
        assert_ne!(Loaded(Some(one.clone())), Loaded(Some(other)), "different contents");
        assert_ne!(Loaded(Some(one)), LoadedMesh::default(), "read against not read");
    }
}
