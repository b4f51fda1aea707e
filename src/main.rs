//! The `drape` command line: check scenes and export their rest shapes.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Result, anyhow, bail};
use clap::{Parser, Subcommand, ValueEnum};
use drape::export::{write_atomically, write_obj};
use drape::mesh::Mesh;
use drape::scene::{self, Key, Layer, Scene};
use drape::shape::RestShape;
use drape::shape::relax::mean_structural_error;

#[derive(Parser)]
#[command(name = "drape", version, about = "Cloth animation with fake dynamics: pins, catenaries, relaxation.")]
#[command(arg_required_else_help = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Validate a scene and print a short summary; exit code 1 with the error otherwise.
    Check {
        /// The scene file (.ron).
        scene: PathBuf,
    },
    /// Write the cloth of the key in effect at a frame as a Wavefront OBJ.
    Export {
        /// The scene file (.ron).
        scene: PathBuf,
        /// Output file (.obj).
        #[arg(short, long)]
        output: PathBuf,
        /// Frame whose key is exported (the last key at or before it; the first key before that).
        #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
        frame: i32,
        /// Output format; by default it follows the output's extension.
        #[arg(long, value_enum)]
        format: Option<Format>,
        /// Modelling stage: before relaxation (approx) or after it (relaxed).
        #[arg(long, value_enum, default_value_t = Stage::Relaxed)]
        stage: Stage,
    },
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum Format {
    Obj,
}

#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
enum Stage {
    /// The surface approximated from the catenary network.
    Approx,
    /// The rest shape after relaxation.
    Relaxed,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Check { scene } => check(&scene),
        Command::Export { scene, output, frame, format, stage } => export(&scene, &output, frame, format, stage),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // Each error already names its file and cause in one line.
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}

fn check(path: &Path) -> Result<()> {
    let scene = scene::load(path)?;
    let cloth = &scene.cloth;
    let name = if scene.name.is_empty() { "(unnamed)" } else { &scene.name };
    println!("{}: {name} — valid", path.display());
    println!(
        "  cloth     {} × {} m, grid {} × {} ({} points, spacing {:.4} × {:.4} m)",
        cloth.width_m(),
        cloth.height_m(),
        cloth.cols(),
        cloth.rows(),
        cloth.cols() * cloth.rows(),
        cloth.spacing_u_m(),
        cloth.spacing_v_m()
    );
    let tl = &scene.timeline;
    println!(
        "  timeline  frames {}..{} at {} fps ({:.2} s)",
        tl.start,
        tl.end,
        tl.fps,
        (tl.end - tl.start) as f64 / tl.fps
    );
    println!("  keys      {}", scene.keys.len());
    for key in &scene.keys {
        let shape = RestShape::build(cloth, key);
        let error =
            mean_structural_error(&shape.relaxed, cloth.cols(), cloth.rows(), shape.rest_u_m(), shape.rest_v_m());
        let report = shape.relax_report;
        println!(
            "    frame {:>5}: {} pin{}, elasticity {}, stiffness {}, ease {:?}; relaxed in {} sweep{} ({}), mean edge error {:.2}%",
            key.frame,
            key.pins.len(),
            if key.pins.len() == 1 { "" } else { "s" },
            key.elasticity,
            key.stiffness,
            key.ease,
            report.iterations,
            if report.iterations == 1 { "" } else { "s" },
            if report.converged {
                "converged".to_string()
            } else {
                format!("stopped at the cap, last move {:.1e}", report.last_move)
            },
            error * 100.0
        );
        for warning in stretched_pin_warnings(&scene, key) {
            println!("      warning: {warning}");
        }
    }
    println!("  layers    {}", scene.layers.len());
    for layer in &scene.layers {
        let (kind, name, enabled) = (layer.kind(), layer.name(), layer.enabled());
        println!("    {kind} \"{name}\"{}", if enabled { "" } else { " (disabled)" });
    }
    Ok(())
}

/// Pins further apart in space than the cloth between them can reach: the
/// cloth is held taut (straight) there.
fn stretched_pin_warnings(scene: &Scene, key: &Key) -> Vec<String> {
    let cloth = &scene.cloth;
    let mut warnings = Vec::new();
    for (a, pa) in key.pins.iter().enumerate() {
        for pb in &key.pins[a + 1..] {
            let (ua, va) = cloth.material_uv(pa.grid.0 as usize, pa.grid.1 as usize);
            let (ub, vb) = cloth.material_uv(pb.grid.0 as usize, pb.grid.1 as usize);
            let reach = ((ua - ub).powi(2) + (va - vb).powi(2)).sqrt() * key.elasticity;
            let apart =
                ((pa.pos.0 - pb.pos.0).powi(2) + (pa.pos.1 - pb.pos.1).powi(2) + (pa.pos.2 - pb.pos.2).powi(2)).sqrt();
            if apart > reach * (1.0 + 1e-9) {
                warnings.push(format!(
                    "pins {:?} and {:?} are {apart:.3} m apart but the cloth between them reaches only {reach:.3} m: it is pulled taut",
                    pa.grid, pb.grid
                ));
            }
        }
    }
    warnings
}

/// The key in effect at `frame`: the last one at or before it, else the first.
fn key_at(scene: &Scene, frame: i32) -> &Key {
    scene.keys.iter().rev().find(|k| k.frame <= frame).unwrap_or(&scene.keys[0])
}

fn export(path: &Path, output: &Path, frame: i32, format: Option<Format>, stage: Stage) -> Result<()> {
    let scene = scene::load(path)?;
    let format = match format {
        Some(f) => f,
        None => match output.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("obj") => Format::Obj,
            Some(other) => bail!(
                "cannot tell the format from the extension .{other} of {}: use .obj or --format obj",
                output.display()
            ),
            None => bail!("{} has no extension: name it .obj or pass --format obj", output.display()),
        },
    };
    let key = key_at(&scene, frame);
    let shape = RestShape::build(&scene.cloth, key);
    let positions = if stage == Stage::Approx { &shape.approximated } else { &shape.relaxed };
    let mesh = Mesh::from_grid(scene.cloth.cols(), scene.cloth.rows(), positions);
    match format {
        Format::Obj => write_atomically(output, |w| write_obj(&mesh, &scene.name, w))
            .map_err(|e| anyhow!("cannot write {}: {e}", output.display()))?,
    }
    println!(
        "wrote {} ({} vertices, {} triangles; key at frame {}, {:?} stage)",
        output.display(),
        mesh.vertex_count(),
        mesh.triangle_count(),
        key.frame,
        stage
    );
    Ok(())
}
