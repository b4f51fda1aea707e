//! Edits the editor makes to a scene, as plain functions on the document's
//! types: pinning, unpinning, moving pins and colliders, changing the grid. The document
//! validates the result; these only keep the scene's own invariants (no grid
//! point pinned twice, pins following the cloth when its grid changes).

use crate::animate::track::sample;
use crate::scene::{Collider, Key, Measure, Pin, Placement, Scene};

use super::param_edit::set_at_keying;

/// Pins grid point `grid` of `key` at `pos` (metres); an existing pin there moves instead.
pub fn pin_point(key: &mut Key, grid: (u32, u32), pos: (f64, f64, f64)) {
    match key.pins.iter_mut().find(|p| p.grid == grid) {
        Some(pin) => pin.pos = pos,
        None => key.pins.push(Pin::at(grid, pos)),
    }
}

/// Removes the pins at these grid points (others stay in order).
///
/// Unpinning the last pin leaves a key that colliders hold up (validation
/// refuses it without any): without a placement of its own, the cloth then
/// drops, level, from a little above where its pins were.
pub fn unpin(key: &mut Key, grids: &[(u32, u32)]) {
    let before = key.pins.clone();
    key.pins.retain(|p| !grids.contains(&p.grid));
    if key.pins.is_empty() && key.placement.is_none() && !before.is_empty() {
        let count = before.len() as f64;
        let centre = before
            .iter()
            .fold((0.0, 0.0, 0.0), |c, p| (c.0 + p.pos.0 / count, c.1 + p.pos.1 / count, c.2 + p.pos.2 / count));
        let center = (centre.0, centre.1 + DROP_ABOVE_PINS_M, centre.2);
        key.placement = Some(Placement { center, rotation_deg: (0.0, 0.0, 0.0) });
    }
}

/// How far above its last pins an unpinned cloth starts its drop (m).
pub const DROP_ABOVE_PINS_M: f64 = 0.05;

/// `start` moved by `offset` (m) at `frame`: every position it has (a
/// centre, a capsule's ends, the ground's height by `offset.y`) takes its
/// value there plus the offset, keyed at `frame` if it is keyed (or with
/// `auto_key`), as typing the numbers would. Sizes and turns stay.
pub fn moved_collider(start: &Collider, offset: glam::DVec3, frame: i32, auto_key: bool) -> Collider {
    let mut moved = start.clone();
    for number in start.numbers().into_iter().filter(|n| n.field.measure == Measure::Position) {
        let (Some(from), Some(to)) = (start.param(number), moved.param_mut(number)) else { continue };
        let by = offset[number.component.unwrap_or(1)];
        set_at_keying(to, frame, sample(from, f64::from(frame)) + by, auto_key);
    }
    moved
}

/// Whether `key` pins grid point `grid`.
pub fn is_pinned(key: &Key, grid: (u32, u32)) -> bool {
    key.pins.iter().any(|p| p.grid == grid)
}

/// Moves the pin at `grid` to `pos`; nothing happens when that point is not pinned.
pub fn move_pin(key: &mut Key, grid: (u32, u32), pos: (f64, f64, f64)) {
    if let Some(pin) = key.pins.iter_mut().find(|p| p.grid == grid) {
        pin.pos = pos;
    }
}

/// Puts back pins of `key` as `pins` hold them (position and attachment),
/// matched by grid point: a drag's Esc. Pins not in `key` stay out.
pub fn restore_pins(key: &mut Key, pins: &[Pin]) {
    for pin in key.pins.iter_mut() {
        if let Some(start) = pins.iter().find(|p| p.grid == pin.grid) {
            *pin = start.clone();
        }
    }
}

/// Index on a side of `to` points at the same material position as index
/// `at` on a side of `from` points (both at least 2), rounded to nearest.
pub fn remap_index(at: u32, from: u32, to: u32) -> u32 {
    let (from, to) = (from.max(2), to.max(2));
    let scaled = (at.min(from - 1) as u64 * (to - 1) as u64 * 2 + (from - 1) as u64) / (2 * (from - 1) as u64);
    scaled as u32
}

/// Changes the cloth's grid to `grid` (cols, rows), moving every key's pins to
/// the grid points at the same place on the material. Pins that land on the
/// same point merge (the first one is kept), so a coarser grid never holds a
/// point twice.
pub fn set_grid(scene: &mut Scene, grid: (u32, u32)) {
    let old = scene.cloth.grid;
    scene.cloth.grid = grid;
    for key in &mut scene.keys {
        let mut remapped: Vec<Pin> = Vec::with_capacity(key.pins.len());
        for pin in &key.pins {
            let at = (remap_index(pin.grid.0, old.0, grid.0), remap_index(pin.grid.1, old.1, grid.1));
            if !remapped.iter().any(|p| p.grid == at) {
                remapped.push(Pin { grid: at, ..pin.clone() });
            }
        }
        key.pins = remapped;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Cloth;

    fn scene() -> Scene {
        crate::scene::parse(crate::editor::DEFAULT_SCENE, "magic_carpet.ron").unwrap()
    }

    #[test]
    fn a_moved_collider_keeps_its_size_and_keys_what_was_keyed() {
        use crate::scene::{Param, ParamKey};
        let mut capsule: Collider =
            ron::from_str("Capsule((a: (0.0, 1.0, 0.0), b: (1.0, 1.0, 0.0), radius: 0.1))").unwrap();
        if let Collider::Capsule(c) = &mut capsule {
            c.a.1 = Param::Keys(vec![ParamKey { frame: 0, value: 1.0, ease: Default::default() }]);
        }
        let moved = moved_collider(&capsule, glam::DVec3::new(0.5, -0.25, 0.0), 10, false);
        let Collider::Capsule(m) = &moved else { panic!("{moved:?}") };
        assert_eq!(m.a.0, Param::Constant(0.5));
        assert_eq!(m.b.0, Param::Constant(1.5));
        assert_eq!(m.b.1, Param::Constant(0.75));
        let Param::Keys(keys) = &m.a.1 else { panic!("{:?}", m.a.1) };
        assert_eq!(keys.iter().map(|k| (k.frame, k.value)).collect::<Vec<_>>(), [(0, 1.0), (10, 0.75)]);
        assert_eq!(m.radius, Param::Constant(0.1), "sizes stay");
        // With auto-key a constant becomes a key at the frame; the ground moves by the height.
        let ground: Collider = ron::from_str("Ground((height: 0.0))").unwrap();
        let Collider::Ground(g) = moved_collider(&ground, glam::DVec3::new(3.0, 0.2, 3.0), 4, true) else { panic!() };
        assert_eq!(g.height, Param::Keys(vec![ParamKey { frame: 4, value: 0.2, ease: Default::default() }]));
    }

    #[test]
    fn unpinning_the_last_pins_drops_the_cloth_from_above_where_they_were() {
        let pin = |grid, pos| Pin::at(grid, pos);
        let mut key = scene().keys[0].clone();
        key.pins = vec![pin((0, 0), (-0.4, 1.0, 0.2)), pin((4, 0), (0.6, 1.2, 0.0))];
        unpin(&mut key, &[(0, 0)]);
        assert_eq!(key.placement, None, "a pin is left");
        unpin(&mut key, &[(4, 0)]);
        assert_eq!(key.placement.map(|p| p.center), Some((0.6, 1.25, 0.0)));
        // A placement of its own is kept.
        let own = Placement { center: (1.0, 2.0, 3.0), rotation_deg: (0.0, 45.0, 0.0) };
        key.pins = vec![pin((0, 0), (0.0, 0.0, 0.0))];
        key.placement = Some(own);
        unpin(&mut key, &[(0, 0)]);
        assert_eq!(key.placement, Some(own));
    }

    #[test]
    fn corners_and_middles_map_to_corners_and_middles() {
        assert_eq!(remap_index(0, 33, 9), 0);
        assert_eq!(remap_index(32, 33, 9), 8);
        assert_eq!(remap_index(16, 33, 9), 4);
        assert_eq!(remap_index(4, 9, 33), 16);
        assert_eq!(remap_index(8, 9, 65), 64);
        // Out-of-range input clamps to the last point instead of overflowing.
        assert_eq!(remap_index(u32::MAX, 9, 5), 4);
    }

    #[test]
    fn changing_the_grid_keeps_pins_at_their_place_on_the_material() {
        let mut s = scene();
        let old = s.cloth.grid;
        let corners: Vec<_> = s.keys[0].pins.iter().map(|p| (p.grid, p.pos)).collect();
        set_grid(&mut s, (17, 9));
        for ((grid, pos), pin) in corners.iter().zip(&s.keys[0].pins) {
            assert_eq!(pin.pos, *pos);
            assert_eq!(pin.grid.0, remap_index(grid.0, old.0, 17));
            assert_eq!(pin.grid.1, remap_index(grid.1, old.1, 9));
        }
        assert!(s.validate().is_ok());
    }

    #[test]
    fn pins_that_meet_on_a_coarse_grid_merge() {
        let mut s = scene();
        s.cloth = Cloth::new((1.0, 1.0), (9, 9));
        s.keys.truncate(1);
        s.keys[0].pins =
            vec![Pin::at((0, 0), (0.0, 1.0, 0.0)), Pin::at((1, 0), (0.1, 1.0, 0.0)), Pin::at((8, 0), (1.0, 1.0, 0.0))];
        set_grid(&mut s, (2, 2));
        let grids: Vec<_> = s.keys[0].pins.iter().map(|p| p.grid).collect();
        assert_eq!(grids, [(0, 0), (1, 0)]);
        assert_eq!(s.keys[0].pins[0].pos, (0.0, 1.0, 0.0), "the first pin wins");
    }

    #[test]
    fn pinning_twice_moves_and_unpinning_removes() {
        let mut key = scene().keys[0].clone();
        let count = key.pins.len();
        pin_point(&mut key, (3, 3), (0.0, 2.0, 0.0));
        assert!(is_pinned(&key, (3, 3)));
        pin_point(&mut key, (3, 3), (0.0, 2.5, 0.0));
        assert_eq!(key.pins.len(), count + 1);
        assert_eq!(key.pins.last().unwrap().pos, (0.0, 2.5, 0.0));
        move_pin(&mut key, (3, 3), (1.0, 1.0, 1.0));
        assert_eq!(key.pins.last().unwrap().pos, (1.0, 1.0, 1.0));
        unpin(&mut key, &[(3, 3)]);
        assert_eq!(key.pins.len(), count);
        assert!(!is_pinned(&key, (3, 3)));
    }
}
