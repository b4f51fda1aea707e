//! Editing an animatable parameter at a frame, as the layer panel does: a
//! constant stays constant until keyed; a keyed parameter gets a key where it
//! is edited (auto-key), and the key toggle adds or removes the key at the
//! playhead.

use crate::animate::track::sample;
use crate::scene::{Ease, Layer, Param, ParamKey, ParamValue};

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
    let frames = key_frames(layer);
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

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(pairs: &[(i32, f64)]) -> Param {
        Param::Keys(pairs.iter().map(|&(frame, value)| ParamKey { frame, value, ease: Ease::default() }).collect())
    }

    fn wave() -> Layer {
        crate::editor::layers_panel::new_layer("Wave")
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
