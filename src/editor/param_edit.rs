//! Editing an animatable parameter at a frame, as the layer panel does: a
//! constant stays constant until keyed; a keyed parameter gets a key where it
//! is edited (auto-key), and the key toggle adds or removes the key at the
//! playhead.

use crate::animate::track::sample;
use crate::scene::{Collider, Ease, Layer, Param, ParamKey, ParamValue, Scene};

/// The index of the key at `frame`, if the parameter is keyed there.
pub fn key_at(param: &Param, frame: i32) -> Option<usize> {
    match param {
        Param::Constant(_) => None,
        Param::Keys(keys) => keys.iter().position(|k| k.frame == frame),
    }
}

/// Sets the value at `frame`: a constant changes everywhere; a keyed
/// parameter changes its key at `frame`, or gains one there.
pub fn set_at(param: &mut Param, frame: i32, value: f64) {
    match param {
        Param::Constant(v) => *v = value,
        Param::Keys(keys) => match keys.iter_mut().find(|k| k.frame == frame) {
            Some(key) => key.value = value,
            None => insert(keys, ParamKey { frame, value, ease: Ease::default() }),
        },
    }
}

/// Sets the value at `frame` as [`set_at`] does, except that with `auto_key`
/// a constant becomes keyed: one key at `frame` holding `value`.
pub fn set_at_keying(param: &mut Param, frame: i32, value: f64, auto_key: bool) {
    match param {
        Param::Constant(_) if auto_key => *param = Param::Keys(vec![ParamKey { frame, value, ease: Ease::default() }]),
        _ => set_at(param, frame, value),
    }
}

/// Adds a key at `frame` holding the current value there, or removes the key
/// at `frame`; removing the last key leaves a constant of its value.
pub fn toggle_key(param: &mut Param, frame: i32) {
    let value = sample(param, f64::from(frame));
    match param {
        Param::Constant(v) => *param = Param::Keys(vec![ParamKey { frame, value: *v, ease: Ease::default() }]),
        Param::Keys(keys) => match keys.iter().position(|k| k.frame == frame) {
            Some(at) => {
                let removed = keys.remove(at);
                if keys.is_empty() {
                    *param = Param::Constant(removed.value);
                }
            }
            None => insert(keys, ParamKey { frame, value, ease: Ease::default() }),
        },
    }
}

fn insert(keys: &mut Vec<ParamKey>, key: ParamKey) {
    let at = keys.partition_point(|k| k.frame < key.frame);
    keys.insert(at, key);
}

/// The animatable parameters of a layer with their units, in panel order:
/// its schema's numbers ([`Layer::params`]).
pub fn param_names(layer: &Layer) -> Vec<(&'static str, &'static str)> {
    layer
        .params()
        .iter()
        .filter(|spec| matches!(spec.value, ParamValue::Number(_)))
        .map(|spec| (spec.name, spec.unit()))
        .collect()
}

/// The parameter `name` of `layer` (a name from [`param_names`]); `None`
/// for any other name.
pub fn param_mut<'a>(layer: &'a mut Layer, name: &str) -> Option<&'a mut Param> {
    layer.param_mut(name)
}

/// Every frame at which some parameter of `layer` has a key, in order, once each.
pub fn key_frames(layer: &Layer) -> Vec<i32> {
    let mut frames = Vec::new();
    for spec in layer.params() {
        if let Some(Param::Keys(keys)) = spec.number(layer) {
            frames.extend(keys.iter().map(|k| k.frame));
        }
    }
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// The frames the keys at `from` may move to without reaching another key
/// frame of the layer: strictly between its neighbours in [`key_frames`].
/// `None` when no parameter is keyed at `from`.
pub fn retime_range(layer: &Layer, from: i32) -> Option<(i32, i32)> {
    range_between_neighbours(&key_frames(layer), from)
}

/// Strictly between the neighbours of `from` in the sorted `frames`; `None`
/// when `from` is not one of them.
fn range_between_neighbours(frames: &[i32], from: i32) -> Option<(i32, i32)> {
    let at = frames.iter().position(|f| *f == from)?;
    let low = if at > 0 { frames[at - 1].saturating_add(1) } else { i32::MIN };
    let high = frames.get(at + 1).map_or(i32::MAX, |f| f - 1);
    Some((low, high))
}

/// Moves every parameter key of `layer` at frame `from` to `to`, clamped into
/// [`retime_range`] so keys never pass or land on one another; returns the
/// frame they ended at (`from` when nothing is keyed there).
pub fn move_keys(layer: &mut Layer, from: i32, to: i32) -> i32 {
    let Some((low, high)) = retime_range(layer, from) else { return from };
    let to = to.clamp(low, high);
    for spec in layer.params() {
        if let Some(Param::Keys(keys)) = spec.number_mut(layer) {
            for key in keys.iter_mut().filter(|k| k.frame == from) {
                key.frame = to;
            }
        }
    }
    to
}

/// Every frame at which some number of `collider` (its own thickness
/// included) has a key, in order, once each.
pub fn collider_key_frames(collider: &Collider) -> Vec<i32> {
    let mut frames = Vec::new();
    let params = collider.numbers().into_iter().filter_map(|n| collider.param(n)).chain(collider.thickness());
    for param in params {
        if let Param::Keys(keys) = param {
            frames.extend(keys.iter().map(|k| k.frame));
        }
    }
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// Moves every key of `collider` at frame `from` to `to`, as [`move_keys`]
/// does for a layer; returns the frame they ended at.
pub fn move_collider_keys(collider: &mut Collider, from: i32, to: i32) -> i32 {
    let Some((low, high)) = range_between_neighbours(&collider_key_frames(collider), from) else { return from };
    let to = to.clamp(low, high);
    let retime = |param: Option<&mut Param>| {
        if let Some(Param::Keys(keys)) = param {
            keys.iter_mut().filter(|k| k.frame == from).for_each(|k| k.frame = to);
        }
    };
    for number in collider.numbers() {
        retime(collider.param_mut(number));
    }
    retime(collider.thickness_mut().as_mut());
    to
}

/// Whose parameter keys the timeline shows as dots (and retimes when one is
/// dragged): the selected collider's, else the selected layer's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keyed {
    Layer(usize),
    Collider(usize),
}

impl Keyed {
    /// The selected collider, else the selected layer, if `scene` has it.
    pub fn selected(scene: &Scene, layer: Option<usize>, collider: Option<usize>) -> Option<Keyed> {
        match (collider, layer) {
            (Some(c), _) if c < scene.colliders.len() => Some(Keyed::Collider(c)),
            (_, Some(l)) if l < scene.layers.len() => Some(Keyed::Layer(l)),
            _ => None,
        }
    }

    /// Its key frames in `scene`, in order, once each (none if it is gone).
    pub fn key_frames(self, scene: &Scene) -> Vec<i32> {
        match self {
            Keyed::Layer(i) => scene.layers.get(i).map_or_else(Vec::new, key_frames),
            Keyed::Collider(i) => scene.colliders.get(i).map_or_else(Vec::new, collider_key_frames),
        }
    }

    /// Moves its keys at `from` to `to` (see [`move_keys`]); returns where they landed.
    pub fn move_keys(self, scene: &mut Scene, from: i32, to: i32) -> i32 {
        match self {
            Keyed::Layer(i) => scene.layers.get_mut(i).map_or(from, |l| move_keys(l, from, to)),
            Keyed::Collider(i) => scene.colliders.get_mut(i).map_or(from, |c| move_collider_keys(c, from, to)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_collider_s_keys_are_listed_and_retimed_together_within_their_neighbours() {
        let mut ball: Collider = ron::from_str("Sphere((center: (0.0, 1.0, 0.0), radius: 0.3))").unwrap();
        if let Collider::Sphere(b) = &mut ball {
            b.center.1 = keys(&[(0, 1.0), (24, 0.5)]);
            b.radius = keys(&[(10, 0.3), (24, 0.4)]);
            b.thickness = Some(keys(&[(40, 0.01)]));
        }
        assert_eq!(collider_key_frames(&ball), [0, 10, 24, 40]);
        // The keys at 24 move together, stopping short of the next key frame (40).
        assert_eq!(move_collider_keys(&mut ball, 24, 60), 39);
        assert_eq!(collider_key_frames(&ball), [0, 10, 39, 40]);
        assert_eq!(move_collider_keys(&mut ball, 5, 7), 5, "nothing keyed at 5");
        let mut scene = crate::scene::parse(crate::editor::DEFAULT_SCENE, "magic_carpet.ron").unwrap();
        scene.colliders.push(ball);
        assert_eq!(Keyed::selected(&scene, Some(0), Some(0)), Some(Keyed::Collider(0)), "the collider first");
        assert_eq!(Keyed::selected(&scene, Some(0), Some(7)), Some(Keyed::Layer(0)), "a collider that is gone");
        assert_eq!(Keyed::Collider(0).move_keys(&mut scene, 39, 30), 30);
        assert_eq!(Keyed::Collider(0).key_frames(&scene), [0, 10, 30, 40]);
    }

    fn keys(pairs: &[(i32, f64)]) -> Param {
        Param::Keys(pairs.iter().map(|&(frame, value)| ParamKey { frame, value, ease: Ease::default() }).collect())
    }

    fn wave() -> Layer {
        crate::editor::panels::layers::new_layer("Wave")
    }

    fn frames(param: &Param) -> Vec<(i32, f64)> {
        match param {
            Param::Constant(v) => vec![(i32::MIN, *v)],
            Param::Keys(keys) => keys.iter().map(|k| (k.frame, k.value)).collect(),
        }
    }

    #[test]
    fn a_constant_changes_everywhere_until_keyed() {
        let mut p = Param::Constant(1.0);
        set_at(&mut p, 10, 2.0);
        assert_eq!(p, Param::Constant(2.0));
        toggle_key(&mut p, 10);
        assert_eq!(frames(&p), [(10, 2.0)]);
    }

    #[test]
    fn with_auto_key_a_constant_becomes_keyed_where_it_is_edited() {
        let mut p = Param::Constant(1.0);
        set_at_keying(&mut p, 10, 2.0, true);
        assert_eq!(frames(&p), [(10, 2.0)]);
        set_at_keying(&mut p, 30, 3.0, true);
        assert_eq!(frames(&p), [(10, 2.0), (30, 3.0)]);
        let mut q = Param::Constant(1.0);
        set_at_keying(&mut q, 10, 2.0, false);
        assert_eq!(q, Param::Constant(2.0));
    }

    #[test]
    fn editing_a_keyed_parameter_off_its_keys_adds_one_in_order() {
        let mut p = keys(&[(0, 0.0), (48, 1.0)]);
        set_at(&mut p, 24, 5.0);
        assert_eq!(frames(&p), [(0, 0.0), (24, 5.0), (48, 1.0)]);
        set_at(&mut p, 48, 2.0);
        assert_eq!(frames(&p), [(0, 0.0), (24, 5.0), (48, 2.0)]);
        assert_eq!(key_at(&p, 24), Some(1));
        assert_eq!(key_at(&p, 25), None);
    }

    #[test]
    fn the_key_toggle_keys_the_current_value_and_unkeys() {
        let mut p = keys(&[(0, 0.0), (40, 1.0)]);
        toggle_key(&mut p, 20);
        let value = frames(&p)[1].1;
        assert!(value > 0.0 && value < 1.0, "the eased value at frame 20: {value}");
        toggle_key(&mut p, 20);
        toggle_key(&mut p, 0);
        assert_eq!(frames(&p), [(40, 1.0)]);
        toggle_key(&mut p, 40);
        assert_eq!(p, Param::Constant(1.0), "the last key leaves its value");
    }

    #[test]
    fn every_listed_parameter_can_be_reached() {
        for kind in Layer::KINDS {
            let Some(mut layer) = Layer::with_start_values(kind) else { panic!("no {kind}") };
            let names = param_names(&layer);
            assert_eq!(names.first(), Some(&("weight", "")), "{kind}");
            for (name, _) in names {
                assert!(param_mut(&mut layer, name).is_some(), "{kind} {name}");
            }
            assert!(param_mut(&mut layer, "nonsense").is_none());
        }
        let Some(mut wave) = Layer::with_start_values("Wave") else { panic!("no Wave") };
        assert!(param_names(&wave).contains(&("direction_deg", "°")));
        assert!(param_mut(&mut wave, "axis").is_none(), "not an animatable number");
    }

    #[test]
    fn layer_keys_retime_together_and_never_pass_a_neighbour() {
        let mut layer = wave();
        if let Layer::Wave(w) = &mut layer {
            w.magnitude = keys(&[(0, 0.0), (10, 1.0), (30, 2.0)]);
            w.phase = keys(&[(10, 0.5), (20, 0.0)]);
        }
        assert_eq!(key_frames(&layer), vec![0, 10, 20, 30]);
        assert_eq!(retime_range(&layer, 10), Some((1, 19)));
        assert_eq!(retime_range(&layer, 0), Some((i32::MIN, 9)));
        assert_eq!(retime_range(&layer, 5), None);
        assert_eq!(move_keys(&mut layer, 10, 25), 19, "clamped before the key at 20");
        let Layer::Wave(w) = &layer else { unreachable!() };
        assert_eq!(frames(&w.magnitude), vec![(0, 0.0), (19, 1.0), (30, 2.0)]);
        assert_eq!(frames(&w.phase), vec![(19, 0.5), (20, 0.0)]);
        assert_eq!(move_keys(&mut layer, 5, 7), 5, "no key there: nothing moves");
        assert_eq!(move_keys(&mut layer, 30, i32::MAX), i32::MAX, "the last key may go anywhere later");
    }
}
