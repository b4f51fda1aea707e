//! Pins placed by the caller (in Blender, by bones): the scene gains a
//! reference whose rig has one node per such pin, keyed where the caller
//! says the pin is at each key's frame and now, and each pin is attached to
//! its node. The library's own attachment code then relaxes every key with
//! its pins there and carries the cloth so each pin sits on its target at
//! this exact time: no math of the module's own.

use std::sync::Arc;

use drape::scene::{Attachment, Loaded, NodeAttachment, Reference, Scene};
use drape::world::rig::{Channel, Clip, Interpolation, Property, Rig, RigNode, Trs};
use glam::DVec3;

/// The added reference's name; no scene file can name one so (a control character).
const REFERENCE_NAME: &str = "\u{1}caller's pins";

/// Where the caller puts one pin (Drape's Y-up metres).
#[derive(Clone, Debug, PartialEq)]
pub struct PinTarget {
    /// The pin's grid index (i, j), as the scene's keys name it.
    pub grid: (u32, u32),
    /// Where it is at the time evaluated.
    pub now: DVec3,
    /// Where it is at each key's frame, in key order; None leaves that key's pin as the file has it.
    pub at_keys: Vec<Option<DVec3>>,
}

/// Why the targets do not fit the scene.
pub fn check(scene: &Scene, targets: &[PinTarget]) -> Result<(), String> {
    for target in targets {
        let (i, j) = target.grid;
        if target.at_keys.len() != scene.keys.len() {
            return Err(format!(
                "pin ({i}, {j}) has {} key positions; the scene has {} keys (None where a key keeps its own)",
                target.at_keys.len(),
                scene.keys.len()
            ));
        }
        if !scene.keys.iter().any(|key| key.pins.iter().any(|pin| pin.grid == target.grid)) {
            return Err(format!("no key of the scene has a pin at grid ({i}, {j})"));
        }
        let finite = |p: &DVec3| p.is_finite();
        if !finite(&target.now) || !target.at_keys.iter().flatten().all(finite) {
            return Err(format!("pin ({i}, {j}) has a position that is not a finite number"));
        }
        if targets.iter().filter(|other| other.grid == target.grid).count() > 1 {
            return Err(format!("pin ({i}, {j}) is given twice"));
        }
    }
    Ok(())
}

/// `scene` with each target's pin attached to a node of an added reference
/// that is at `at_keys[k]` at key k's frame and at `now` at `t_secs`.
/// Targets must pass [`check`].
pub fn scene_with_targets(scene: &Scene, targets: &[PinTarget], t_secs: f64) -> Scene {
    let mut posed = scene.clone();
    if targets.is_empty() {
        return posed;
    }
    let fps = scene.timeline.fps;
    let mut nodes = Vec::with_capacity(targets.len());
    let mut channels = Vec::with_capacity(targets.len());
    for (index, target) in targets.iter().enumerate() {
        let (i, j) = target.grid;
        nodes.push(RigNode {
            name: format!("pin {i} {j}"),
            parent: None,
            rest: Trs { translation: target.now, ..Trs::IDENTITY },
            morph_weights: Vec::new(),
        });
        // The clip's clock is the scene's seconds (the reference starts at frame 0, speed 1).
        let mut samples: Vec<(f64, DVec3)> = scene
            .keys
            .iter()
            .zip(&target.at_keys)
            .filter_map(|(key, at)| at.map(|at| (f64::from(key.frame) / fps, at)))
            .collect();
        // At a key's own time the key's position stands, so its rest shape never changes with `now`.
        if !samples.iter().any(|(t, _)| *t == t_secs) {
            samples.push((t_secs, target.now));
        }
        samples.sort_by(|a, b| a.0.total_cmp(&b.0));
        channels.push(Channel {
            node: index,
            property: Property::Translation,
            interpolation: Interpolation::Linear,
            times_secs: samples.iter().map(|(t, _)| *t).collect(),
            values: samples.iter().flat_map(|(_, p)| p.to_array()).collect(),
            width: 3,
        });
    }
    let clip = Clip { name: "caller's pins".to_owned(), channels };
    let rig = Rig::new(nodes, Vec::new(), Vec::new(), vec![clip]).expect("pin nodes without parents form a rig");
    let mut reference: Reference =
        ron::from_str(r#"(file: "", visible: false, collider: false)"#).expect("a reference of defaults parses");
    reference.name = REFERENCE_NAME.to_owned();
    reference.rig = Loaded(Some(Arc::new(rig)));
    posed.references.push(reference);
    for (k, key) in posed.keys.iter_mut().enumerate() {
        for pin in &mut key.pins {
            let Some(target) = targets.iter().find(|t| t.grid == pin.grid) else { continue };
            let Some(at) = target.at_keys[k] else { continue };
            let (i, j) = target.grid;
            pin.pos = at.into();
            pin.attach = Some(Attachment::Node(NodeAttachment {
                reference: REFERENCE_NAME.to_owned(),
                node: format!("pin {i} {j}"),
                offset: (0.0, 0.0, 0.0),
            }));
        }
    }
    posed
}

#[cfg(test)]
mod tests {
    use super::*;
    use drape::animate::attachments::attachment_at;

    fn carpet() -> Scene {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/magic_carpet.ron");
        drape::scene::load(std::path::Path::new(path)).unwrap()
    }

    #[test]
    fn the_pins_node_is_at_each_keys_sample_and_at_now() {
        let scene = carpet();
        let keys = scene.keys.len();
        let at_keys: Vec<Option<DVec3>> = (0..keys).map(|k| Some(DVec3::new(k as f64, 1.0, 0.0))).collect();
        let target = PinTarget { grid: (0, 0), now: DVec3::new(9.0, 9.0, 9.0), at_keys };
        check(&scene, std::slice::from_ref(&target)).unwrap();
        let posed = scene_with_targets(&scene, &[target], 1.3);
        for (k, key) in posed.keys.iter().enumerate() {
            let pin = key.pins.iter().find(|p| p.grid == (0, 0)).unwrap();
            let at = attachment_at(&posed, pin.attach.as_ref().unwrap(), f64::from(key.frame)).unwrap();
            assert!((at - DVec3::new(k as f64, 1.0, 0.0)).length() < 1e-12, "key {k}: {at}");
        }
        let pin = &posed.keys[0].pins[0];
        let now = attachment_at(&posed, pin.attach.as_ref().unwrap(), 1.3 * scene.timeline.fps).unwrap();
        assert!((now - DVec3::splat(9.0)).length() < 1e-12, "{now}");
    }

    #[test]
    fn targets_that_do_not_fit_are_refused() {
        let scene = carpet();
        let keys = scene.keys.len();
        let fits = |grid, at_keys: usize| PinTarget { grid, now: DVec3::ZERO, at_keys: vec![None; at_keys] };
        assert!(check(&scene, &[fits((0, 0), keys - 1)]).unwrap_err().contains("key positions"));
        assert!(check(&scene, &[fits((3, 3), keys)]).unwrap_err().contains("no key"));
        assert!(check(&scene, &[fits((0, 0), keys), fits((0, 0), keys)]).unwrap_err().contains("twice"));
        let mut nan = fits((0, 0), keys);
        nan.now.x = f64::NAN;
        assert!(check(&scene, &[nan]).unwrap_err().contains("finite"));
    }
}
