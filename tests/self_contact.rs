//! The cloth keeps its thickness between its own layers: gathered curtains,
//! crossed pins and a cloth folded over itself relax without passing through
//! themselves, at every grid size and at the default stiffness.

use drape::animate::KeyShape;
use drape::scene::{Cloth, DEFAULT_FRICTION, DEFAULT_THICKNESS_M, Ease, Key, Pin, RelaxSettings};
use drape::shape::RestShape;
use drape::shape::contact::count_crossings;
use glam::DVec3;

const DEFAULT_STIFFNESS: f64 = 0.2;

fn build(n: u32, pins: Vec<Pin>, stiffness: f64, thickness: f64) -> RestShape {
    let cloth = Cloth::new((1.0, 1.0), (n, n));
    RestShape::build(&cloth, &key(pins, 1.0, stiffness, thickness))
}

/// A key at frame 0 with the default relaxation settings.
fn key(pins: Vec<Pin>, elasticity: f64, stiffness: f64, thickness: f64) -> Key {
    Key {
        frame: 0,
        pins,
        elasticity,
        stiffness,
        relax: RelaxSettings::default(),
        ease: Ease::EaseInOut,
        inbetween_relax: 0,
        thickness,
        friction: DEFAULT_FRICTION,
        placement: None,
    }
}

/// Two top corners `width_m` apart (negative: crossed over).
fn two_corners(n: u32, width_m: f64) -> Vec<Pin> {
    vec![Pin::at((0, 0), (-width_m / 2.0, 1.0, 0.0)), Pin::at((n - 1, 0), (width_m / 2.0, 1.0, 0.0))]
}

/// Five pins along the top, 5 cm apart: a pleated heading.
fn gathered_heading(n: u32) -> Vec<Pin> {
    let m = n - 1;
    (0..5).map(|k| Pin::at((k * m / 4, 0), (-0.1 + 0.05 * f64::from(k), 1.0, 0.0))).collect()
}

/// The cloth folded in half: its bottom corners brought up beside its top
/// corners, 2 cm in front of them.
fn folded_in_half(n: u32) -> Vec<Pin> {
    let m = n - 1;
    vec![
        Pin::at((0, 0), (-0.5, 1.0, 0.0)),
        Pin::at((m, 0), (0.5, 1.0, 0.0)),
        Pin::at((0, m), (-0.5, 1.0, 0.02)),
        Pin::at((m, m), (0.5, 1.0, 0.02)),
    ]
}

/// The smallest distance between two points more than two grid steps apart.
fn smallest_gap_m(p: &[DVec3], n: usize) -> f64 {
    let mut gap = f64::INFINITY;
    for a in 0..p.len() {
        for b in a + 1..p.len() {
            if (a % n).abs_diff(b % n) > 2 || (a / n).abs_diff(b / n) > 2 {
                gap = gap.min(p[a].distance(p[b]));
            }
        }
    }
    gap
}

/// Settled, no edge through the cloth, and layers apart: the floor gives a
/// little where folds are pressed together (the self-contact module doc), so
/// points of different layers keep at least half the thickness.
fn assert_keeps_its_thickness(label: &str, shape: &RestShape) {
    let n = shape.grid.cols;
    assert!(shape.relax_report.converged, "{label}: {}", shape.relax_report.verdict());
    assert_eq!(count_crossings(&shape.relaxed, n, shape.grid.rows), 0, "{label}: edges through the cloth");
    let gap = smallest_gap_m(&shape.relaxed, n);
    assert!(gap >= 0.5 * DEFAULT_THICKNESS_M, "{label}: layers {:.2} mm apart", gap * 1e3);
}

fn assert_at_every_size(label: &str, pins: impl Fn(u32) -> Vec<Pin>, sizes: &[u32]) {
    for &n in sizes {
        for stiffness in [DEFAULT_STIFFNESS, 0.0] {
            let shape = build(n, pins(n), stiffness, DEFAULT_THICKNESS_M);
            assert_keeps_its_thickness(&format!("{label}, {n}², stiffness {stiffness}"), &shape);
        }
    }
}

#[test]
fn a_curtain_gathered_to_a_tenth_of_its_width_folds_without_passing_through_itself() {
    assert_at_every_size("gathered to 10%", |n| two_corners(n, 0.1), &[17, 33, 65]);
}

#[test]
fn a_curtain_gathered_to_a_third_of_its_width_folds_without_passing_through_itself() {
    assert_at_every_size("gathered to 30%", |n| two_corners(n, 0.3), &[17, 33, 65]);
}

#[test]
fn a_heading_gathered_by_five_pins_folds_without_passing_through_itself() {
    assert_at_every_size("five pins", gathered_heading, &[17, 33, 65]);
}

#[test]
fn a_curtain_with_crossed_pins_twists_without_passing_through_itself() {
    assert_at_every_size("crossed", |n| two_corners(n, -0.8), &[17, 33, 65]);
}

#[test]
fn a_cloth_folded_in_half_hangs_in_two_layers_that_never_cross() {
    assert_at_every_size("folded in half", folded_in_half, &[17, 33]);
}

#[test]
fn without_thickness_a_gathered_curtain_passes_through_itself() {
    // What the thickness prevents: the same curtain with none.
    let shape = build(17, two_corners(17, 0.1), DEFAULT_STIFFNESS, 0.0);
    assert!(count_crossings(&shape.relaxed, 17, 17) > 0);
}

#[test]
fn a_drape_that_does_not_reach_itself_is_the_same_with_or_without_thickness() {
    // Contact only runs where the drape without it passes through itself, so
    // the bundled curtain and a tent are bit for bit the same either way.
    let tent = vec![
        Pin::at((0, 0), (-0.5, 1.0, -0.5)),
        Pin::at((16, 0), (0.5, 1.0, -0.5)),
        Pin::at((0, 16), (-0.5, 1.0, 0.5)),
        Pin::at((16, 16), (0.5, 1.0, 0.5)),
        Pin::at((8, 8), (0.0, 1.4, 0.0)),
    ];
    for pins in [two_corners(17, 0.8), tent] {
        let with = build(17, pins.clone(), DEFAULT_STIFFNESS, DEFAULT_THICKNESS_M);
        let without = build(17, pins, DEFAULT_STIFFNESS, 0.0);
        assert_eq!(with.relaxed, without.relaxed);
    }
}

/// The first tutorial's third step: a curtain pinned at four corners whose
/// bottom-left corner is typed up to table height and forward. Its drape
/// without contact passes through itself, and the relaxation keeping its
/// folds apart cannot part them: contact pushes against the constraints
/// sweep after sweep. No sweep may then move or ask to move a point
/// further than the cloth is wide (the pushes once outgrew the sweeps and
/// ran the cloth off by kilometres, each sweep listing every pair on the
/// grid, for over ten minutes). The shape it keeps passes through itself,
/// so it is not settled, and its verdict says so.
#[test]
fn folds_that_cannot_be_kept_apart_never_run_the_cloth_away_and_are_not_settled() {
    let cloth = Cloth::new((1.0, 1.0), (33, 33));
    let pins = vec![
        Pin::at((0, 0), (-0.5, 1.5, 0.0)),
        Pin::at((32, 0), (0.5, 1.5, 0.0)),
        Pin::at((0, 32), (-0.5, 1.0, 0.5)),
        Pin::at((32, 32), (0.4994271231268916, 0.45001577848317753, 1.7077784640244735e-6)),
    ];
    let key = key(pins, 1.05, DEFAULT_STIFFNESS, DEFAULT_THICKNESS_M);
    let mut largest_m = 0.0f64;
    let mut sweeps = 0u32;
    let built = KeyShape::build_with(&cloth, &key, &[], &mut |progress| {
        sweeps += 1;
        largest_m = largest_m.max(progress.last_move_m);
        // A runaway stops here rather than sweeping on at a second a sweep.
        if largest_m < 1.0 { std::ops::ControlFlow::Continue(()) } else { std::ops::ControlFlow::Break(()) }
    });
    assert!(largest_m < 1.0, "a sweep moved the cloth {largest_m:.3} m (after {sweeps} sweeps)");
    let Ok(shape) = built else { panic!("the build stopped without being asked to") };
    assert!(shape.rest.relaxed.iter().all(|p| p.is_finite() && p.distance(DVec3::new(0.0, 1.0, 0.0)) < 1.5));
    let crossings = shape.self_crossings();
    assert!(crossings > 0, "the folds cross");
    assert!(shape.rest.relax_report.converged, "the drape without contact settles");
    assert!(!shape.settled(DEFAULT_THICKNESS_M));
    let verdict = shape.verdict(DEFAULT_THICKNESS_M);
    let expected = format!("NOT settled: passes through itself ({crossings} edges cross the cloth) after ");
    assert!(verdict.starts_with(&expected), "{verdict}");
    assert!(verdict.contains("pins that gather the cloth less fold it less"), "{verdict}");
    // Without a thickness to keep, passing through itself is what was asked for.
    assert!(shape.settled(0.0));
    assert_eq!(shape.verdict(0.0), shape.rest.relax_report.verdict());
}
