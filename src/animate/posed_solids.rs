//! The solids of colliding references at the poses asked for last: a frame
//! asks for the same pose several times (every key's rest shape at its own
//! frame, the frame itself, the viewport), and building a solid (its
//! bounding-volume hierarchy) is the costly part of posing one.

use std::sync::{Arc, Mutex, MutexGuard};

use super::references_at::PosedReference;
use crate::world::MeshSolid;
use crate::world::rig::Rig;

/// How many posed solids a [`PosedSolids`] keeps.
pub const KEPT_SOLIDS: usize = 16;

/// What a posed solid is made from: the rig (held, so that the entry names
/// this very rig: another read of the file is another rig, even if equal),
/// the clips and their time, the placement, all bit for bit.
struct SolidKey {
    rig: Arc<Rig>,
    clips: Vec<usize>,
    t_bits: u64,
    placement_bits: [u64; 16],
}

impl SolidKey {
    fn of(posed: &PosedReference<'_>) -> SolidKey {
        SolidKey {
            rig: Arc::clone(posed.rig),
            clips: posed.clips.clone(),
            t_bits: posed.t_secs.to_bits(),
            placement_bits: posed.scene_from_file.to_cols_array().map(f64::to_bits),
        }
    }

    fn is(&self, other: &SolidKey) -> bool {
        Arc::ptr_eq(&self.rig, &other.rig)
            && self.clips == other.clips
            && self.t_bits == other.t_bits
            && self.placement_bits == other.placement_bits
    }
}

/// The last [`KEPT_SOLIDS`] posed solids built, least recently used out
/// first. Owned by an [`Evaluator`](super::Evaluator); shared by `&`, so
/// whoever holds the evaluator can ask for a key's obstacles without
/// changing it. Equal poses give the same solid, cached or built afresh.
#[derive(Default)]
pub struct PosedSolids {
    kept: Mutex<Vec<(SolidKey, Arc<MeshSolid>)>>,
}

impl PosedSolids {
    pub fn new() -> PosedSolids {
        PosedSolids::default()
    }

    /// All meshes of `posed` as one solid in scene coordinates, from the
    /// kept ones if this pose was built lately; None when they hold no
    /// triangle with area.
    pub fn solid(&self, posed: &PosedReference<'_>) -> Option<Arc<MeshSolid>> {
        let key = SolidKey::of(posed);
        {
            let mut kept = self.kept();
            if let Some(at) = kept.iter().position(|(k, _)| k.is(&key)) {
                let entry = kept.remove(at);
                let solid = entry.1.clone();
                kept.push(entry);
                return Some(solid);
            }
        }
        // Built outside the lock: another thread asking meanwhile builds its own.
        let solid = Arc::new(posed.build_solid()?);
        let mut kept = self.kept();
        if kept.len() >= KEPT_SOLIDS {
            kept.remove(0);
        }
        kept.push((key, solid.clone()));
        Some(solid)
    }

    /// How many solids are kept.
    pub fn len(&self) -> usize {
        self.kept().len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The kept solids; a panic while they were held left them whole (each
    /// change is one push or remove), so a poisoned lock is taken as it is.
    fn kept(&self) -> MutexGuard<'_, Vec<(SolidKey, Arc<MeshSolid>)>> {
        self.kept.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

impl std::fmt::Debug for PosedSolids {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PosedSolids({} kept)", self.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animate::references_at::reference_at;

    fn cape() -> crate::scene::Scene {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cape.ron");
        let Ok(scene) = crate::scene::load(&path) else { panic!("the bundled cape loads") };
        scene
    }

    #[test]
    fn a_pose_asked_again_is_the_solid_built_for_it_and_equals_one_built_afresh() {
        let scene = cape();
        let solids = PosedSolids::new();
        let Some(posed) = reference_at(&scene, 0, 12.0) else { panic!("the walker was read") };
        let Some(first) = solids.solid(&posed) else { panic!("the walker is a solid") };
        let Some(again) = solids.solid(&posed) else { panic!("the walker is a solid") };
        assert!(Arc::ptr_eq(&first, &again), "kept, not built again");
        assert_eq!(solids.len(), 1);
        let Some(afresh) = posed.build_solid() else { panic!("the walker is a solid") };
        assert_eq!(*first, afresh, "the same triangles as a solid built afresh");
        // Another evaluator's solids are its own.
        let other = PosedSolids::new();
        let Some(elsewhere) = other.solid(&posed) else { panic!("the walker is a solid") };
        assert!(!Arc::ptr_eq(&first, &elsewhere) && *first == *elsewhere);
    }

    #[test]
    fn only_the_latest_poses_are_kept() {
        let scene = cape();
        let solids = PosedSolids::new();
        let frames = (0..=KEPT_SOLIDS as u32).map(|f| f64::from(f) * 0.5);
        let built: Vec<Arc<MeshSolid>> = frames
            .map(|frame| {
                let Some(posed) = reference_at(&scene, 0, frame) else { panic!("the walker was read") };
                let Some(solid) = solids.solid(&posed) else { panic!("the walker is a solid") };
                solid
            })
            .collect();
        assert_eq!(solids.len(), KEPT_SOLIDS);
        // The first pose went out; the last is still there.
        let Some(first) = reference_at(&scene, 0, 0.0) else { panic!("the walker was read") };
        let Some(last) = reference_at(&scene, 0, KEPT_SOLIDS as f64 * 0.5) else { panic!("the walker was read") };
        assert!(solids.solid(&last).is_some_and(|s| Arc::ptr_eq(&s, &built[KEPT_SOLIDS])));
        assert!(solids.solid(&first).is_some_and(|s| !Arc::ptr_eq(&s, &built[0])));
    }
}
