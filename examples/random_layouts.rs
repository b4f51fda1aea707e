//! How many random pin layouts settle at the default relaxation settings.
//!
//! `cargo run --release --example random_layouts [COUNT] [SEED] [--stiffness S]
//! [--sides MIN..MAX]` builds the rest shape of COUNT (default 80) random,
//! reachable layouts and prints the ones that do not settle within the
//! default sweep cap, then a summary. `--stiffness` gives every layout that
//! stiffness instead of a random one; `--sides` draws the grid's sides from
//! MIN..=MAX points instead of 9..=65; `--each` prints every layout with its
//! time, whether it was relaxed again keeping its folds apart, and how many
//! edges cross the cloth. Every valid scene up to 256² should settle at
//! the default settings; a property test
//! in `tests/rest_shapes.rs` asserts it for soft cloth (stiffness 0), and this
//! measures the rest (BENCHMARKS.md has the figures).
//!
//! A layout: a cloth of 9–65 points a side, square cells 1–4 cm apart;
//! 1–8 pins at distinct grid points, each where the flat cloth would be but
//! squeezed towards the middle to 50–90 % of its material distance, on a
//! level plane or one tilted along x by up to 0.8; stiffness 0–1,
//! elasticity 1–1.3. A fixed xorshift generator, so a seed is a layout list.

use std::collections::HashSet;
use std::time::Instant;

use drape::scene::{Cloth, DEFAULT_FRICTION, DEFAULT_THICKNESS_M, Ease, Key, Pin, RelaxSettings};
use drape::shape::RestShape;
use drape::shape::contact::count_crossings;

/// xorshift64: the same layouts on every machine.
struct Xorshift(u64);

impl Xorshift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn below(&mut self, n: u32) -> u32 {
        (self.next() % u64::from(n)) as u32
    }
}

struct Layout {
    cloth: Cloth,
    key: Key,
    tilt: f64,
}

/// What the command line changes about the drawn layouts.
struct Options {
    stiffness: Option<f64>,
    sides: (u32, u32),
}

fn layout(rng: &mut Xorshift, options: &Options) -> Layout {
    let (min, max) = options.sides;
    let (cols, rows) = (min + rng.below(max - min + 1), min + rng.below(max - min + 1));
    let spacing_m = 0.01 + 0.03 * rng.unit();
    let size_m = (spacing_m * f64::from(cols - 1), spacing_m * f64::from(rows - 1));
    let count = 1 + rng.below(8) as usize;
    let squeeze = 0.5 + 0.4 * rng.unit();
    let tilt = if rng.below(2) == 0 { 0.0 } else { 0.8 * rng.unit() };
    let stiffness = options.stiffness.unwrap_or(rng.unit());
    let elasticity = 1.0 + 0.3 * rng.unit();
    let mut taken = HashSet::new();
    let mut pins = Vec::new();
    while pins.len() < count {
        let at = (rng.below(cols), rng.below(rows));
        if !taken.insert(at) {
            continue;
        }
        let x = (f64::from(at.0) * spacing_m - size_m.0 / 2.0) * squeeze;
        let z = (f64::from(at.1) * spacing_m - size_m.1 / 2.0) * squeeze;
        pins.push(Pin::at(at, (x, 1.5 + tilt * x, z)));
    }
    let key = Key {
        frame: 0,
        pins,
        elasticity,
        stiffness,
        relax: RelaxSettings::default(),
        ease: Ease::EaseInOut,
        inbetween_relax: 0,
        thickness: DEFAULT_THICKNESS_M,
        friction: DEFAULT_FRICTION,
        placement: None,
    };
    Layout { cloth: Cloth::new(size_m, (cols, rows)), key, tilt }
}

fn main() {
    let mut options = Options { stiffness: None, sides: (9, 65) };
    let mut each = false;
    let mut numbers = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--stiffness" => {
                let Some(stiffness) =
                    args.next().and_then(|a| a.parse::<f64>().ok()).filter(|s| (0.0..=1.0).contains(s))
                else {
                    eprintln!("--stiffness wants a number from 0 to 1");
                    std::process::exit(2);
                };
                options.stiffness = Some(stiffness);
            }
            "--each" => each = true,
            "--sides" => {
                let range = args.next().unwrap_or_default();
                let Some((Ok(min), Ok(max))) = range.split_once("..").map(|(a, b)| (a.parse(), b.parse())) else {
                    eprintln!("--sides wants MIN..MAX, e.g. 129..256");
                    std::process::exit(2);
                };
                if !(2 <= min && min <= max) {
                    eprintln!("--sides wants 2 ≤ MIN ≤ MAX");
                    std::process::exit(2);
                }
                options.sides = (min, max);
            }
            _ => numbers.push(arg),
        }
    }
    let count: usize = numbers.first().and_then(|a| a.parse().ok()).unwrap_or(80);
    let seed: u64 = numbers.get(1).and_then(|a| a.parse().ok()).unwrap_or(0x9e37_79b9_7f4a_7c15);
    let mut rng = Xorshift(seed.max(1));
    let started = Instant::now();
    let mut unsettled = Vec::new();
    for case in 0..count {
        let Layout { cloth, key, tilt } = layout(&mut rng, &options);
        let built = Instant::now();
        let shape = RestShape::build(&cloth, &key);
        let report = shape.relax_report;
        if each {
            let (cols, rows) = cloth.grid;
            let crossings = count_crossings(&shape.relaxed, cols as usize, rows as usize);
            println!(
                "case {case}: {cols} × {rows}, {} pins, stiffness {:.2}: {:.2} s, {}, {crossings} crossing edges",
                key.pins.len(),
                key.stiffness,
                built.elapsed().as_secs_f64(),
                if shape.kept_apart { "kept apart" } else { "relaxed once" },
            );
        }
        if !report.converged {
            let (cols, rows) = cloth.grid;
            println!(
                "case {case}: {cols} × {rows}, {} pins, stiffness {:.2}, elasticity {:.2}, tilt {tilt:.2}: {}",
                key.pins.len(),
                key.stiffness,
                key.elasticity,
                report.verdict()
            );
            unsettled.push(case);
        }
    }
    println!(
        "{} of {count} layouts did not settle at the default settings ({:.1} s): {unsettled:?}",
        unsettled.len(),
        started.elapsed().as_secs_f64()
    );
}
