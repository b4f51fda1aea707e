//! Render time per frame at 1280×720 on whatever adapter `GpuContext::headless`
//! finds (Mesa's lavapipe or llvmpipe here; `WGPU_BACKEND=gl|vulkan` picks).
//! "draw" waits for the GPU to finish the frame; "to image" also reads the
//! picture back to the CPU, as `drape render` does.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use drape::animate::evaluate;
use drape::render::camera::bounds;
use drape::render::readback::read_texture;
use drape::render::{FrameInput, GpuContext, OffscreenTarget, OrbitCamera, Overlay, RenderOptions, Renderer};
use drape::scene::{Cloth, Key, Pin, RelaxSettings, Scene};

const SIZE_PX: (u32, u32) = (1280, 720);

/// An n × n cloth held by its four corners, sagging.
fn scene(n: u32) -> Scene {
    let pin = |i, j, x, z| Pin::at((i, j), (x, 1.5, z));
    let last = n - 1;
    Scene {
        name: format!("{n}x{n}"),
        cloth: Cloth::new((2.0, 2.0), (n, n)),
        keys: vec![Key {
            frame: 0,
            pins: vec![
                pin(0, 0, -0.8, -0.8),
                pin(last, 0, 0.8, -0.8),
                pin(0, last, -0.8, 0.8),
                pin(last, last, 0.8, 0.8),
            ],
            elasticity: 1.1,
            stiffness: 0.2,
            relax: RelaxSettings::default(),
            ease: Default::default(),
            inbetween_relax: 0,
            thickness: drape::scene::DEFAULT_THICKNESS_M,
            friction: drape::scene::DEFAULT_FRICTION,
            placement: None,
        }],
        ..Scene::default()
    }
}

fn render(c: &mut Criterion) {
    let context = GpuContext::headless().unwrap_or_else(|error| panic!("{error}"));
    eprintln!("rendering on {}", context.describe());
    let (device, queue) = (&context.device, &context.queue);
    let mut group = c.benchmark_group("render");
    group.sample_size(20).warm_up_time(Duration::from_secs(2)).measurement_time(Duration::from_secs(8));
    for n in [64u32, 256] {
        let mesh = evaluate(&scene(n), 0.0);
        let (lo, hi) = bounds(&mesh.positions).unwrap();
        let camera = OrbitCamera::framing(lo, hi, SIZE_PX.0 as f32 / SIZE_PX.1 as f32);
        let options = RenderOptions { wireframe: false, ..RenderOptions::default() };
        let overlay = Overlay::default();
        let input =
            FrameInput { mesh: &mesh, camera: &camera, options: &options, ghosts: &[], overlay: &overlay, solids: &[] };
        let mut renderer = Renderer::new(device, queue);
        let target = OffscreenTarget::new(device, SIZE_PX);
        group.bench_function(format!("{n}x{n} at 1280x720 draw"), |b| {
            b.iter(|| {
                renderer.render(device, queue, &target, input);
                device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
            })
        });
        let bare = RenderOptions { ground: None, ..options.clone() };
        let bare_input = FrameInput { options: &bare, ..input };
        group.bench_function(format!("{n}x{n} at 1280x720 draw, no ground"), |b| {
            b.iter(|| {
                renderer.render(device, queue, &target, bare_input);
                device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
            })
        });
        group.bench_function(format!("{n}x{n} at 1280x720 to image"), |b| {
            b.iter(|| {
                renderer.render(device, queue, &target, input);
                read_texture(device, queue, target.resolved()).unwrap()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, render);
criterion_main!(benches);
