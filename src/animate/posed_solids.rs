//! The solids of colliding references at the poses asked for last: a frame
//! asks for the same pose several times (every key's rest shape at its own
//! frame, the frame itself, the viewport). Each rig's solid at rest is
//! built once and kept; every pose's solid is that one moved (its
//! bounding-volume hierarchy refitted, not rebuilt).

use std::sync::{Arc, Mutex, MutexGuard};

use super::references_at::{PosedReference, rest_solid};
use crate::world::MeshSolid;
use crate::world::rig::Rig;

/// How many posed solids a [`PosedSolids`] keeps.
pub const KEPT_SOLIDS: usize = 16;

/// How many rigs' solids at rest a [`PosedSolids`] keeps (a scene has a
/// few references; a file read again is another rig).
const KEPT_RESTS: usize = 8;

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

/// A rig and its solid at rest, if its meshes make one.
type RestSolid = (Arc<Rig>, Option<Arc<MeshSolid>>);

/// The last [`KEPT_SOLIDS`] posed solids built, least recently used out
/// first. Owned by an [`Evaluator`](super::Evaluator); shared by `&`, so
/// whoever holds the evaluator can ask for a key's obstacles without
/// changing it. Equal poses give the same solid, cached or built afresh.
#[derive(Default)]
pub struct PosedSolids {
    kept: Mutex<Vec<(SolidKey, Arc<MeshSolid>)>>,
    /// Each rig's solid at rest (None: its meshes make no solid).
    rests: Mutex<Vec<RestSolid>>,
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
        let rest = self.rest(posed.rig)?;
        let solid = Arc::new(posed.solid_from(&rest)?);
        let mut kept = self.kept();
        if kept.len() >= KEPT_SOLIDS {
            kept.remove(0);
        }
        kept.push((key, solid.clone()));
        Some(solid)
    }

    /// `rig`'s solid at rest, built on first use.
    fn rest(&self, rig: &Arc<Rig>) -> Option<Arc<MeshSolid>> {
        {
            let rests = lock(&self.rests);
            if let Some((_, rest)) = rests.iter().find(|(r, _)| Arc::ptr_eq(r, rig)) {
                return rest.clone();
            }
        }
        let rest = rest_solid(rig).map(Arc::new);
        let mut rests = lock(&self.rests);
        if rests.len() >= KEPT_RESTS {
            rests.remove(0);
        }
        rests.push((Arc::clone(rig), rest.clone()));
        rest
    }

    /// How many solids are kept.
    pub fn len(&self) -> usize {
        self.kept().len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn kept(&self) -> MutexGuard<'_, Vec<(SolidKey, Arc<MeshSolid>)>> {
        lock(&self.kept)
    }
}

/// A kept list; a panic while it was held left it whole (each change is
/// one push or remove), so a poisoned lock is taken as it is.
fn lock<T>(list: &Mutex<T>) -> MutexGuard<'_, T> {
    list.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
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
    fn a_posed_walker_measures_as_a_solid_built_at_that_pose() {
        let scene = cape();
        let solids = PosedSolids::new();
        for frame in [0.0, 7.0, 19.5] {
            let Some(posed) = reference_at(&scene, 0, frame) else { panic!("the walker was read") };
            let Some(moved) = solids.solid(&posed) else { panic!("the walker is a solid") };
            let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
            for (mesh, placed) in posed.rig.meshes().iter().zip(posed.meshes()) {
                let base = vertices.len() as u32;
                vertices.extend(placed.positions);
                triangles.extend(mesh.indices.chunks_exact(3).map(|t| [t[0] + base, t[1] + base, t[2] + base]));
            }
            let Ok(built) = MeshSolid::new(&vertices, &triangles) else { panic!("the walker is a solid") };
            let (lo, hi) = built.bounds();
            for i in 0..3000 {
                let t = f64::from(i) * 0.618_034;
                let share = glam::DVec3::new(t.sin(), (1.7 * t).cos(), (2.3 * t + 0.4).sin()) * 0.6 + 0.5;
                let p = lo + (hi - lo) * share;
                let (a, b) = (moved.surface_point(p), built.surface_point(p));
                assert!((a.distance - b.distance).abs() < 1e-9, "frame {frame}, {p}: {a:?} against {b:?}");
                for keep in [0.0, 0.004, 0.03] {
                    assert_eq!(moved.keeps_clear(p, keep), a.distance >= keep, "frame {frame}, {p}, {keep}");
                }
            }
        }
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
