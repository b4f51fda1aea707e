//! `drape check`: validates scenes and prints what each holds (cloth,
//! keys and how each relaxed, segments, layers, colliders, references,
//! camera and plate), with warnings for pins set further apart than the
//! cloth reaches.

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow};
use drape::animate::Evaluator;
use drape::animate::blend::relaxed_inbetween;
use drape::scene::{
    self, Collider, ColliderNumber, Key, Layer, Measure, Param, ParamSpec, ParamValue, Scene, WaveAxis, escaped,
    readable_number, readable_vec3, shown_name,
};
use drape::shape::relax::mean_structural_error;

use crate::terminal_progress;

/// [`check`] for each scene in turn, a blank line between; a scene that is
/// not valid is reported and the rest are still checked. With one scene its
/// error is the command's error, as `check` words it.
pub fn check_all(paths: &[PathBuf]) -> Result<()> {
    if let [path] = paths {
        return check(path);
    }
    let mut failed = 0;
    for (index, path) in paths.iter().enumerate() {
        if index > 0 {
            say!("");
        }
        if let Err(error) = check(path) {
            // Each error already names its file and cause in one line.
            eprintln!("error: {error}");
            failed += 1;
        }
    }
    match failed {
        0 => Ok(()),
        _ => Err(anyhow!("{failed} of {} scenes are not valid (each error above)", paths.len())),
    }
}

fn check(path: &Path) -> Result<()> {
    let scene = scene::load(path)?;
    // The plate's headers are read before the keys are relaxed, which can take minutes.
    let plate = scene::check_plate(&scene, path)?;
    let cloth = &scene.cloth;
    let name = if scene.name.is_empty() { "(unnamed)".to_string() } else { shown_name(&scene.name) };
    say!("{}: {name} — valid", escaped(&path.display().to_string()));
    say!(
        "  cloth     {} × {} m, grid {} × {} ({} points, spacing {:.4} × {:.4} m)",
        readable_number(cloth.width_m()),
        readable_number(cloth.height_m()),
        cloth.cols(),
        cloth.rows(),
        cloth.cols() * cloth.rows(),
        cloth.spacing_u_m(),
        cloth.spacing_v_m()
    );
    if cloth.stretch_limit > 0.0 {
        say!(
            "  stretch   layers may lengthen an edge by at most {}% of its rest length",
            readable_number(cloth.stretch_limit * 100.0)
        );
    } else {
        say!("  stretch   no limit: layers may lengthen the cloth freely");
    }
    let tl = &scene.timeline;
    say!(
        "  timeline  frames {}..{} at {} fps ({:.2} s)",
        tl.start,
        tl.end,
        readable_number(tl.fps),
        (f64::from(tl.end) - f64::from(tl.start)) / tl.fps
    );
    say!("  keys      {}", scene.keys.len());
    let mut evaluator = Evaluator::new();
    let mut status = terminal_progress::StatusLine::on_stderr();
    terminal_progress::build_key_shapes(&mut evaluator, &scene, scene.keys.iter(), &mut status);
    let shapes: Vec<_> = scene.keys.iter().map(|key| evaluator.key_shape(&scene, key)).collect();
    for (index, (key, shape)) in scene.keys.iter().zip(&shapes).enumerate() {
        let rest = &shape.rest;
        let error = mean_structural_error(&rest.relaxed, cloth.cols(), cloth.rows(), rest.rest_u_m(), rest.rest_v_m());
        let report = rest.relax_report;
        let held = if key.pins.is_empty() {
            let start = key.placement_or_default();
            format!(
                "no pins (dropped from {} m, turned {}°)",
                readable_vec3(start.center),
                readable_vec3(start.rotation_deg)
            )
        } else {
            format!("{} pin{}", key.pins.len(), if key.pins.len() == 1 { "" } else { "s" })
        };
        say!(
            "    frame {:>5}: {held}, elasticity {}, stiffness {}, mean edge error {:.2}%; {}",
            key.frame,
            readable_number(key.elasticity),
            readable_number(key.stiffness),
            error * 100.0,
            shape.verdict(key.thickness)
        );
        // A shape that settled through itself says so in its verdict.
        let crossings = shape.self_crossings();
        if crossings > 0 && (!report.converged || !(key.thickness > 0.0)) {
            say!(
                "      warning: the rest shape passes through itself ({crossings} edge{} the cloth); {}",
                if crossings == 1 { " crosses" } else { "s cross" },
                drape::shape::contact::crossing_advice(key.thickness, report.converged)
            );
        }
        let (warnings, taut_pairs) = stretched_pin_warnings(&scene, key);
        for warning in &warnings {
            say!("      warning: {warning}");
        }
        if taut_pairs > warnings.len() {
            let more = taut_pairs - warnings.len();
            say!(
                "      warning: … and {more} more pair{} of pins pulled taut ({taut_pairs} in all)",
                if more == 1 { "" } else { "s" }
            );
        }
        if let Some(next) = scene.keys.get(index + 1) {
            if key.inbetween_relax > 0 {
                status.show_now(&format!(
                    "relaxing the in-between of frames {}..{} ({} sweeps)",
                    key.frame, next.frame, key.inbetween_relax
                ));
            }
            let summary = segment_summary(&scene, index, &shapes);
            status.clear();
            say!("      → frame {}: {summary}", next.frame);
        }
    }
    say!("  layers    {}", scene.layers.len());
    for (index, layer) in scene.layers.iter().enumerate() {
        say!(
            "    {}{}: {}",
            layer.label(index),
            if layer.enabled() { "" } else { " (disabled)" },
            layer_parameters(layer)
        );
    }
    if !scene.colliders.is_empty() {
        say!("  colliders {}", scene.colliders.len());
        for (index, collider) in scene.colliders.iter().enumerate() {
            say!(
                "    {}{}: {}",
                collider.label(index),
                if collider.enabled() { "" } else { " (disabled)" },
                collider_parameters(collider)
            );
        }
    }
    if !scene.references.is_empty() {
        say!("  references {}", scene.references.len());
        for (index, reference) in scene.references.iter().enumerate() {
            say!("    {}: {}", reference.label(index), reference_summary(reference, scene.timeline.fps));
        }
    }
    if let Some(camera) = &scene.camera {
        say!("  camera    {}", camera_summary(&scene, camera));
    }
    if let (Some(plate), Some(checked)) = (&scene.plate, &plate) {
        say!("  plate     {}", plate_summary(plate, checked, &scene.timeline));
    }
    if let Some(follow) = &scene.follow {
        say!(
            "  follows   node {:?} of reference {:?}: the keys are carried as it moves",
            follow.node,
            follow.reference
        );
    }
    Ok(())
}

/// The plate in a line: its files, which frames have their own, the
/// headers read and how it shows.
fn plate_summary(plate: &scene::Plate, checked: &scene::CheckedPlate, timeline: &scene::Timeline) -> String {
    let files = &checked.files;
    let mut parts = vec![format!("{:?}", plate.file)];
    if let Some((first, last)) = files.number_range() {
        parts.push(format!("{} files numbered {first}..{last}", scene::group_thousands(files.count() as u64)));
        if plate.frame_offset != 0 {
            parts.push(format!("frame F shows file F {:+}", plate.frame_offset));
        }
        let missing = files.missing(timeline.start, timeline.end);
        if !missing.is_empty() {
            parts.push(format!(
                "frame{} {} without a file show the nearest",
                if missing.len() == 1 { "" } else { "s" },
                scene::frame_list(&missing)
            ));
        }
        parts.push(format!(
            "the {} the timeline shows read (frame {}: {})",
            if checked.files_read == 1 { "file".to_owned() } else { format!("{} files", checked.files_read) },
            timeline.start,
            checked.first
        ));
    } else {
        parts.push(format!("one picture ({})", checked.first));
    }
    match &plate.opacity {
        Param::Constant(v) if *v >= 1.0 => {}
        Param::Constant(v) => parts.push(format!("opacity {}", readable_number(*v))),
        Param::Keys(_) => parts.push("animated opacity".to_owned()),
    }
    parts.join(", ")
}

/// The shot camera in a line: where it is and looks (a keyed position or
/// target by where it is at the timeline's start and end), its lens, its
/// picture; or the reference's camera it follows ([`reference_camera_summary`]).
fn camera_summary(scene: &scene::Scene, camera: &scene::ShotCamera) -> String {
    let (width, height) = camera.image_size;
    if let Some(from) = &camera.from_reference {
        return reference_camera_summary(scene, camera, from);
    }
    let (start, end) = (scene.timeline.start, scene.timeline.end);
    let vector = |vec3: &scene::ParamVec3| match vec3 {
        (Param::Constant(x), Param::Constant(y), Param::Constant(z)) => readable_vec3((*x, *y, *z)),
        _ => {
            let at =
                |frame: i32| -> (f64, f64, f64) { drape::animate::track::sample_vec3(vec3, f64::from(frame)).into() };
            format!("{} → {}", readable_vec3(at(start)), readable_vec3(at(end)))
        }
    };
    let keyed = |(x, y, z): &scene::ParamVec3| [x, y, z].iter().any(|p| matches!(p, Param::Keys(_)));
    let moves = if keyed(&camera.position) || keyed(&camera.target) {
        format!(" over frames {start}–{end}")
    } else {
        String::new()
    };
    let lens = match (&camera.focal_length_mm, &camera.sensor_width_mm) {
        (Param::Constant(f), Param::Constant(w)) => {
            format!(
                "{} mm on a {} mm sensor ({:.1}° across)",
                readable_number(*f),
                readable_number(*w),
                scene::horizontal_fov_deg(*f, *w)
            )
        }
        _ => "an animated lens".to_owned(),
    };
    format!("from {} at {}{moves}, {lens}, {width} × {height} px", vector(&camera.position), vector(&camera.target))
}

/// A shot camera that follows a reference's glTF camera: `ShotCam of
/// reference "layout", yfov 28.6° (33.8 mm on a 36 mm sensor, 48.6° across),
/// 1280 × 720 px, level`, the lens at the timeline's start, and how far the
/// camera rolls over the timeline, which the picture leaves out.
fn reference_camera_summary(scene: &scene::Scene, camera: &scene::ShotCamera, from: &scene::ReferenceCamera) -> String {
    use drape::world::rig::Projection;
    let (width, height) = camera.image_size;
    let source = format!("{} of reference {:?}", from.camera, from.reference);
    let found = scene.references.iter().find(|r| r.name == from.reference);
    let Some(rig_camera) = found.and_then(|r| r.rig.0.as_deref()?.camera_named(&from.camera).cloned()) else {
        return format!("{source} (not read), {width} × {height} px");
    };
    let Projection::Perspective { yfov_rad, aspect_ratio, .. } = rig_camera.projection else {
        return format!("{source}, orthographic (not usable), {width} × {height} px");
    };
    let start = f64::from(scene.timeline.start);
    let look = drape::picture::shot_look_at(scene, camera, start);
    let lens = format!(
        "yfov {:.1}° ({} mm on a {} mm sensor, {:.1}° across)",
        yfov_rad.to_degrees(),
        readable_number((look.focal_length_mm * 100.0).round() / 100.0),
        readable_number(look.sensor_width_mm),
        scene::horizontal_fov_deg(look.focal_length_mm, look.sensor_width_mm)
    );
    let picture_aspect = f64::from(width.max(1)) / f64::from(height.max(1));
    let aspect = match aspect_ratio {
        Some(file) if (file - picture_aspect).abs() > 1e-3 => format!(
            " (the file's aspect ratio {} differs: its vertical field of view is kept)",
            readable_number((file * 1000.0).round() / 1000.0)
        ),
        _ => String::new(),
    };
    // Every frame of the timeline, or a thousand spread over it.
    let (first, last) = (scene.timeline.start, scene.timeline.end.max(scene.timeline.start));
    let step = ((i64::from(last) - i64::from(first)) / 1000).max(1) as usize;
    let most_roll = (first..=last)
        .step_by(step)
        .map(|frame| drape::picture::shot_look_at(scene, camera, f64::from(frame)).roll_deg.abs())
        .fold(0.0, f64::max);
    let roll = if most_roll < 0.05 {
        "level".to_owned()
    } else {
        format!("rolls up to {most_roll:.1}°, shown level (Drape's camera cannot roll)")
    };
    format!("{source}, {lens}, {width} × {height} px{aspect}, {roll}")
}

/// What a reference holds and how it plays: `walker.glb: 10 072 vertices,
/// 19 joints; "Walk" 0–1 s (24 frames) from frame 0, repeated`.
fn reference_summary(reference: &scene::Reference, fps: f64) -> String {
    let file = escaped(&reference.file);
    let mut parts = vec![file.to_string()];
    let Some(rig) = reference.rig.0.as_deref() else { return parts.remove(0) };
    let joints: usize = rig.skins().iter().map(|s| s.joints.len()).sum();
    let vertices = rig.vertex_count();
    parts[0] = format!(
        "{file}: {} vertices, {} nodes, {joints} joints",
        scene::group_thousands(vertices as u64),
        rig.nodes().len()
    );
    match reference.clip_frames(fps) {
        Some(clip) => {
            let (first, last) = clip.secs;
            parts.push(format!(
                "animation {:?} {}–{} s ({} frames at speed {}) from frame {}{}",
                clip.name,
                readable_number(first),
                readable_number(last),
                readable_number(((clip.frames.1 - clip.frames.0) * 100.0).round() / 100.0),
                readable_number(reference.speed),
                reference.start_frame,
                if reference.repeat { ", repeated" } else { "" }
            ));
        }
        None => parts.push("no animation".to_owned()),
    }
    if !reference.visible {
        parts.push("hidden".to_owned());
    }
    if reference.collider {
        let thickness = reference.thickness.as_ref().map_or("the key's".to_owned(), |t| describe_param(t, "m"));
        parts.push(format!("a collider (thickness {thickness})"));
    }
    parts.join("; ")
}

/// Every number of `collider` in file order, `name value`; a vector whose
/// components are all constant reads as one `(x, y, z)`.
fn collider_parameters(collider: &Collider) -> String {
    let mut parts = Vec::new();
    for field in collider.fields() {
        let unit = match field.measure {
            Measure::Position | Measure::Length => "m",
            Measure::Angle => "°",
            Measure::Scale => "",
        };
        let number = |component| ColliderNumber { field: *field, component };
        if field.vector {
            let params: Vec<&Param> = (0..3).filter_map(|c| collider.param(number(Some(c)))).collect();
            let constants: Vec<f64> =
                params.iter().filter_map(|p| if let Param::Constant(v) = p { Some(*v) } else { None }).collect();
            if let [x, y, z] = constants[..] {
                let spaced = if unit == "°" { "°" } else { " m" };
                parts.push(format!("{} {}{spaced}", field.name, readable_vec3((x, y, z))));
            } else {
                for (c, param) in params.into_iter().enumerate() {
                    parts.push(format!("{} {}", number(Some(c)).label(), describe_param(param, unit)));
                }
            }
        } else if let Some(param) = collider.param(number(None)) {
            parts.push(format!("{} {}", field.name, describe_param(param, unit)));
        }
    }
    if let Collider::Mesh(mesh) = collider {
        let triangles =
            mesh.solid.0.as_ref().map_or_else(String::new, |s| format!(", {} triangles", s.triangle_count()));
        parts.insert(0, format!("file {:?}{triangles}", mesh.file));
    }
    match collider.thickness() {
        Some(thickness) => parts.push(format!("thickness {}", describe_param(thickness, "m"))),
        None => parts.push("thickness the key's".to_string()),
    }
    parts.join(", ")
}

/// The easing of a segment and how much straight blending shortens the cloth
/// halfway through it, with and without the in-between relaxation.
fn segment_summary(scene: &Scene, from: usize, shapes: &[std::sync::Arc<drape::animate::KeyShape>]) -> String {
    let cloth = &scene.cloth;
    let (key_a, key_b) = (&scene.keys[from], &scene.keys[from + 1]);
    let (a, b) = (&shapes[from], &shapes[from + 1]);
    let elasticity = 0.5 * (key_a.elasticity + key_b.elasticity);
    let (rest_u, rest_v) = (cloth.spacing_u_m() * elasticity, cloth.spacing_v_m() * elasticity);
    let halfway: Vec<glam::DVec3> = a.rest.relaxed.iter().zip(&b.rest.relaxed).map(|(p, q)| (*p + *q) * 0.5).collect();
    let plain = mean_structural_error(&halfway, cloth.cols(), cloth.rows(), rest_u, rest_v);
    let mut text = format!("ease {:?}; halfway blend mean edge error {:.2}%", key_a.ease, plain * 100.0);
    if key_a.inbetween_relax > 0 {
        let mut relaxed = Vec::new();
        relaxed_inbetween(key_a, key_b, a, b, (0.5, None), key_a.inbetween_relax, &mut relaxed);
        let relaxed: Vec<glam::DVec3> = relaxed.iter().map(|p| p.as_dvec3()).collect();
        let error = mean_structural_error(&relaxed, cloth.cols(), cloth.rows(), rest_u, rest_v);
        text += &format!(", {:.2}% after {} in-between sweeps", error * 100.0, key_a.inbetween_relax);
    }
    text
}

/// A number with its unit: `0.2 m`, `65°`, `1` for a plain factor.
fn with_unit(number: f64, unit: &str) -> String {
    match unit {
        "" => readable_number(number),
        "°" => format!("{}°", readable_number(number)),
        unit => format!("{} {unit}", readable_number(number)),
    }
}

/// A parameter with its unit, as `0.2 m` or `0 → 0.05 m (frames 0..48, 2 keys)`.
fn describe_param(param: &Param, unit: &str) -> String {
    match param {
        Param::Constant(v) => with_unit(*v, unit),
        Param::Keys(keys) => match (keys.first(), keys.last()) {
            (Some(first), Some(last)) if keys.len() > 1 => format!(
                "{} → {} (frames {}..{}, {} keys)",
                readable_number(first.value),
                with_unit(last.value, unit),
                first.frame,
                last.frame,
                keys.len()
            ),
            (Some(only), _) => with_unit(only.value, unit),
            _ => "no keys".to_string(),
        },
    }
}

/// Every parameter of `layer` in file order, each as `name value`.
fn layer_parameters(layer: &Layer) -> String {
    let shown = |spec: &ParamSpec| -> Option<String> {
        Some(match spec.value {
            ParamValue::Number(number) => describe_param(number.access.get(layer)?, number.unit),
            ParamValue::Direction(direction) => readable_vec3(*direction.access.get(layer)?),
            ParamValue::Axis(axis) => match axis.access.get(layer)? {
                WaveAxis::Normal => "normal".to_string(),
                WaveAxis::Fixed(v) => readable_vec3(*v),
            },
            ParamValue::Count(count) => count.access.get(layer)?.to_string(),
        })
    };
    let parts: Vec<String> =
        layer.params().iter().filter_map(|spec| Some(format!("{} {}", spec.name, shown(spec)?))).collect();
    parts.join(", ")
}

/// Most "pulled taut" warnings `check` prints for one key; the other pairs
/// are counted in one line (4096 pins have over eight million pairs).
const MAX_TAUT_WARNINGS_PER_KEY: usize = 10;

/// Pins further apart in space than the cloth between them can reach: the
/// cloth is held taut (straight) there. The first
/// [`MAX_TAUT_WARNINGS_PER_KEY`] warnings, and how many pairs there are.
fn stretched_pin_warnings(scene: &Scene, key: &Key) -> (Vec<String>, usize) {
    let cloth = &scene.cloth;
    let mut warnings = Vec::new();
    let mut taut_pairs = 0;
    for (a, pa) in key.pins.iter().enumerate() {
        for pb in &key.pins[a + 1..] {
            let (ua, va) = cloth.material_uv(pa.grid.0 as usize, pa.grid.1 as usize);
            let (ub, vb) = cloth.material_uv(pb.grid.0 as usize, pb.grid.1 as usize);
            let reach = ((ua - ub).powi(2) + (va - vb).powi(2)).sqrt() * key.elasticity;
            let apart =
                ((pa.pos.0 - pb.pos.0).powi(2) + (pa.pos.1 - pb.pos.1).powi(2) + (pa.pos.2 - pb.pos.2).powi(2)).sqrt();
            if apart > reach * (1.0 + 1e-9) {
                taut_pairs += 1;
                if warnings.len() == MAX_TAUT_WARNINGS_PER_KEY {
                    continue;
                }
                warnings.push(format!(
                    "pins {:?} and {:?} are {apart:.3} m apart but the cloth between them reaches only {reach:.3} m: it is pulled taut",
                    pa.grid, pb.grid
                ));
            }
        }
    }
    (warnings, taut_pairs)
}
