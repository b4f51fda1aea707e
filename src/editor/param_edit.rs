//! Editing an animatable parameter at a frame, as the layer panel does: a
//! constant stays constant until keyed; a keyed parameter gets a key where it
//! is edited (auto-key), and the key toggle adds or removes the key at the
//! playhead.

use crate::animate::track::sample;
use crate::scene::{Ease, Layer, Param, ParamKey};

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

/// The animatable parameters of a layer with their units, in panel order.
pub fn param_names(layer: &Layer) -> &'static [(&'static str, &'static str)] {
    match layer {
        Layer::Sway(_) => {
            &[("weight", ""), ("magnitude", "m"), ("speed", ""), ("frequency", "Hz"), ("phase", "rad"), ("falloff", "")]
        }
        Layer::Wave(_) => &[
            ("weight", ""),
            ("magnitude", "m"),
            ("frequency", "rad/m"),
            ("phase", "rad"),
            ("speed", "rad/s"),
            ("direction_deg", "°"),
            ("falloff", ""),
        ],
        Layer::Noise(_) => {
            &[("weight", ""), ("amplitude", "m"), ("scale", "m"), ("speed", "m/s"), ("turbulence", ""), ("falloff", "")]
        }
        Layer::FollowThrough(_) => &[("weight", ""), ("lag", "s"), ("falloff", "")],
    }
}

/// The parameter `name` of `layer` (a name from [`param_names`]).
pub fn param_mut<'a>(layer: &'a mut Layer, name: &str) -> Option<&'a mut Param> {
    Some(match (layer, name) {
        (Layer::Sway(l), "weight") => &mut l.weight,
        (Layer::Sway(l), "magnitude") => &mut l.magnitude,
        (Layer::Sway(l), "speed") => &mut l.speed,
        (Layer::Sway(l), "frequency") => &mut l.frequency,
        (Layer::Sway(l), "phase") => &mut l.phase,
        (Layer::Sway(l), "falloff") => &mut l.falloff,
        (Layer::Wave(l), "weight") => &mut l.weight,
        (Layer::Wave(l), "magnitude") => &mut l.magnitude,
        (Layer::Wave(l), "frequency") => &mut l.frequency,
        (Layer::Wave(l), "phase") => &mut l.phase,
        (Layer::Wave(l), "speed") => &mut l.speed,
        (Layer::Wave(l), "direction_deg") => &mut l.direction_deg,
        (Layer::Wave(l), "falloff") => &mut l.falloff,
        (Layer::Noise(l), "weight") => &mut l.weight,
        (Layer::Noise(l), "amplitude") => &mut l.amplitude,
        (Layer::Noise(l), "scale") => &mut l.scale,
        (Layer::Noise(l), "speed") => &mut l.speed,
        (Layer::Noise(l), "turbulence") => &mut l.turbulence,
        (Layer::Noise(l), "falloff") => &mut l.falloff,
        (Layer::FollowThrough(l), "weight") => &mut l.weight,
        (Layer::FollowThrough(l), "lag") => &mut l.lag,
        (Layer::FollowThrough(l), "falloff") => &mut l.falloff,
        _ => return None,
    })
}

/// Every frame at which some parameter of `layer` has a key, in order, once each.
pub fn key_frames(layer: &Layer) -> Vec<i32> {
    let mut layer = layer.clone();
    let mut frames = Vec::new();
    for (name, _) in param_names(&layer) {
        if let Some(Param::Keys(keys)) = param_mut(&mut layer, name) {
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
    for (name, _) in param_names(layer) {
        if let Some(Param::Keys(keys)) = param_mut(layer, name) {
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
    use crate::scene::{FollowThrough, Noise, Sway, Wave, WaveAxis};

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
        let one = || Param::Constant(1.0);
        let layers = [
            Layer::Sway(Sway {
                name: String::new(),
                enabled: true,
                weight: one(),
                magnitude: one(),
                direction: (1.0, 0.0, 0.0),
                speed: one(),
                frequency: one(),
                phase: one(),
                falloff: one(),
            }),
            Layer::Wave(Wave {
                name: String::new(),
                enabled: true,
                weight: one(),
                magnitude: one(),
                frequency: one(),
                phase: one(),
                speed: one(),
                direction_deg: one(),
                axis: WaveAxis::Normal,
                falloff: one(),
            }),
            Layer::Noise(Noise {
                name: String::new(),
                enabled: true,
                weight: one(),
                amplitude: one(),
                scale: one(),
                speed: one(),
                direction: (1.0, 0.0, 0.0),
                turbulence: one(),
                octaves: 2,
                seed: 0,
                falloff: one(),
            }),
            Layer::FollowThrough(FollowThrough {
                name: String::new(),
                enabled: true,
                weight: one(),
                lag: one(),
                falloff: one(),
            }),
        ];
        for mut layer in layers {
            for (name, _) in param_names(&layer) {
                assert!(param_mut(&mut layer, name).is_some(), "{} {name}", layer.kind());
            }
            assert!(param_mut(&mut layer, "nonsense").is_none());
        }
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
