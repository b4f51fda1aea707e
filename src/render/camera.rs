//! An orbit camera: a target point, a direction (yaw, pitch) and a distance.
//!
//! Pure math on glam, no GPU. Yaw turns about +Y (0° looks along −Z, from +Z
//! towards the target); pitch lifts the eye above the target's horizon. Pixel
//! coordinates have their origin at the top-left corner of the target, x right,
//! y down, as in images and egui.

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::scene::{MAX_VIEW_DISTANCE_M, MAX_VIEW_PITCH_DEG, MIN_VIEW_DISTANCE_M, View};

/// Pitch stays inside ±this many degrees, the limit of a saved view.
pub const MAX_PITCH_DEG: f32 = MAX_VIEW_PITCH_DEG as f32;
/// Dolly limits (metres), those of a saved view.
pub const MIN_DISTANCE_M: f32 = MIN_VIEW_DISTANCE_M as f32;
pub const MAX_DISTANCE_M: f32 = MAX_VIEW_DISTANCE_M as f32;
/// Degrees of orbit per pixel of mouse motion.
pub const ORBIT_DEG_PER_PX: f32 = 0.3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    pub target: Vec3,
    pub yaw_deg: f32,
    pub pitch_deg: f32,
    pub distance_m: f32,
    /// Vertical field of view.
    pub fov_y_deg: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        OrbitCamera {
            target: Vec3::new(0.0, 1.0, 0.0),
            yaw_deg: 25.0,
            pitch_deg: 18.0,
            distance_m: 4.0,
            fov_y_deg: 35.0,
        }
    }
}

impl OrbitCamera {
    /// The camera a scene saved; values are taken as validated (pitch within ±89°, distance > 0).
    pub fn from_view(view: &View) -> OrbitCamera {
        let (x, y, z) = view.target;
        OrbitCamera {
            target: Vec3::new(x as f32, y as f32, z as f32),
            yaw_deg: view.yaw_deg as f32,
            pitch_deg: (view.pitch_deg as f32).clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG),
            distance_m: (view.distance_m as f32).clamp(MIN_DISTANCE_M, MAX_DISTANCE_M),
            fov_y_deg: view.fov_y_deg as f32,
        }
    }

    /// The view to save in a scene so it reopens looking the same way (the
    /// camera only: no playhead, Follow off; the editor adds those).
    pub fn to_view(&self) -> View {
        let t = self.target.as_dvec3();
        View {
            target: (t.x, t.y, t.z),
            yaw_deg: self.yaw_deg as f64,
            pitch_deg: self.pitch_deg as f64,
            distance_m: self.distance_m as f64,
            fov_y_deg: self.fov_y_deg as f64,
            frame: None,
            follow: false,
            through_camera: false,
        }
    }

    /// The default three-quarter view of a box, framed: from the front-right,
    /// a little above, or from the side when the box is much deeper than wide
    /// (a cloth that travels along z), so the long side runs across the picture.
    pub fn framing(min: Vec3, max: Vec3, aspect: f32) -> OrbitCamera {
        let size = max - min;
        let yaw_deg = if size.z > 1.5 * size.x { 65.0 } else { 25.0 };
        let mut camera = OrbitCamera { yaw_deg, ..OrbitCamera::default() };
        camera.frame_bounds(min, max, aspect);
        camera
    }

    /// Unit vector from the target towards the eye.
    pub fn backward(&self) -> Vec3 {
        let (yaw, pitch) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        Vec3::new(pitch.cos() * yaw.sin(), pitch.sin(), pitch.cos() * yaw.cos())
    }

    pub fn eye(&self) -> Vec3 {
        self.target + self.backward() * self.distance_m
    }

    pub fn view_from_world(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye(), self.target, Vec3::Y)
    }

    /// Perspective with wgpu's 0..1 depth. Near and far planes scale with the
    /// distance so depth precision is the same at every zoom.
    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
        let near_m = (self.distance_m * 0.01).max(1e-4);
        let far_m = self.distance_m * 100.0 + 100.0;
        // WebGPU clip space is Direct3D's: depth 0..1, y up.
        glam::camera::rh::proj::directx::perspective(self.fov_y_deg.to_radians(), aspect, near_m, far_m)
    }

    pub fn clip_from_world(&self, size_px: (u32, u32)) -> Mat4 {
        self.clip_from_view(size_px.0 as f32 / size_px.1.max(1) as f32) * self.view_from_world()
    }

    /// Turns the camera about its target by a mouse motion in pixels: right drag
    /// swings the eye left round the target, up drag raises it. Pitch is clamped.
    /// A non-finite motion is ignored.
    pub fn orbit(&mut self, delta_px: Vec2) {
        if !delta_px.is_finite() {
            return;
        }
        self.yaw_deg = (self.yaw_deg - delta_px.x * ORBIT_DEG_PER_PX).rem_euclid(360.0);
        self.pitch_deg = (self.pitch_deg + delta_px.y * ORBIT_DEG_PER_PX).clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
    }

    /// Slides the target in the view plane so the point under the mouse follows it.
    /// A non-finite motion is ignored.
    pub fn pan(&mut self, delta_px: Vec2, viewport_height_px: f32) {
        if !delta_px.is_finite() {
            return;
        }
        let metres_per_px = self.metres_per_pixel(viewport_height_px);
        let backward = self.backward();
        let right = Vec3::Y.cross(backward).normalize_or(Vec3::X);
        let up = backward.cross(right);
        self.target += (-right * delta_px.x + up * delta_px.y) * metres_per_px;
    }

    /// Moves towards (positive steps) or away from the target by 10% per step, within the distance limits.
    /// A non-finite step count is ignored.
    pub fn dolly(&mut self, steps: f32) {
        if !steps.is_finite() {
            return;
        }
        let distance = self.distance_m * 0.9f32.powf(steps);
        self.distance_m = distance.clamp(MIN_DISTANCE_M, MAX_DISTANCE_M);
    }

    /// Size of one pixel at the target's depth.
    pub fn metres_per_pixel(&self, viewport_height_px: f32) -> f32 {
        2.0 * self.distance_m * (self.fov_y_deg.to_radians() * 0.5).tan() / viewport_height_px.max(1.0)
    }

    /// Aims at the centre of the box `min..max` from the current direction, at
    /// the nearest distance where all eight corners are in view with a 5%
    /// margin (a picture's framing). An empty or non-finite box leaves the
    /// camera unchanged.
    pub fn frame_bounds(&mut self, min: Vec3, max: Vec3, aspect: f32) {
        self.frame_bounds_filling(min, max, aspect, 0.95);
    }

    /// [`OrbitCamera::frame_bounds`] with the corners at most `fill` of the
    /// way from the view's centre to its edges: an editor's framing leaves
    /// room round the box for handles and for the cloth to move.
    pub fn frame_bounds_filling(&mut self, min: Vec3, max: Vec3, aspect: f32, fill: f32) {
        if !(min.is_finite() && max.is_finite()) || min.cmpgt(max).any() {
            return;
        }
        let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
        let fill = if fill.is_finite() && fill > 0.0 { fill.min(1.0) } else { 0.95 };
        let tan_y = (self.fov_y_deg.to_radians() * 0.5).tan() * fill;
        let tan_x = tan_y * aspect;
        let center = (min + max) * 0.5;
        let backward = self.backward();
        let right = Vec3::Y.cross(backward).normalize_or(Vec3::X);
        let up = backward.cross(right);
        // A corner at view offset (x, y, z) from the centre is in view from
        // distance d when |x| ≤ (d − z)·tan_x and |y| ≤ (d − z)·tan_y.
        let mut distance_m: f32 = 0.0;
        for k in 0..8 {
            let corner = Vec3::new(
                if k & 1 == 0 { min.x } else { max.x },
                if k & 2 == 0 { min.y } else { max.y },
                if k & 4 == 0 { min.z } else { max.z },
            ) - center;
            let (x, y, z) = (corner.dot(right), corner.dot(up), corner.dot(backward));
            distance_m = distance_m.max(z + x.abs() / tan_x).max(z + y.abs() / tan_y);
        }
        self.target = center;
        self.distance_m = distance_m.max(0.05).clamp(MIN_DISTANCE_M, MAX_DISTANCE_M);
    }

    /// Whether any corner or the centre of the box `min..max` is in view at
    /// `aspect` (width / height). An empty or non-finite box is not.
    pub fn sees_any(&self, min: Vec3, max: Vec3, aspect: f32) -> bool {
        if !(min.is_finite() && max.is_finite()) || min.cmpgt(max).any() {
            return false;
        }
        let corner = |k: u32| {
            Vec3::new(
                if k & 1 == 0 { min.x } else { max.x },
                if k & 2 == 0 { min.y } else { max.y },
                if k & 4 == 0 { min.z } else { max.z },
            )
        };
        self.sees_any_of(std::iter::once((min + max) * 0.5).chain((0..8).map(corner)), aspect)
    }

    /// Whether any of `points` is in view at `aspect` (width / height); a
    /// non-finite point is not.
    pub fn sees_any_of(&self, points: impl IntoIterator<Item = Vec3>, aspect: f32) -> bool {
        let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
        let clip_from_world = self.clip_from_view(aspect) * self.view_from_world();
        points.into_iter().any(|p| {
            let clip = clip_from_world * p.extend(1.0);
            p.is_finite() && clip.w > 1e-6 && clip.x.abs() <= clip.w && clip.y.abs() <= clip.w
        })
    }

    /// The pixel where `world` is drawn in a target of `size_px`, or `None`
    /// when the point is behind the eye.
    pub fn project(&self, world: Vec3, size_px: (u32, u32)) -> Option<Vec2> {
        let clip = self.clip_from_world(size_px) * world.extend(1.0);
        if clip.w <= 1e-6 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some(Vec2::new((ndc.x * 0.5 + 0.5) * size_px.0 as f32, (0.5 - ndc.y * 0.5) * size_px.1 as f32))
    }

    /// The ray through a pixel: (origin at the eye, unit direction).
    pub fn ray(&self, pixel: Vec2, size_px: (u32, u32)) -> (Vec3, Vec3) {
        let ndc =
            Vec2::new(pixel.x / size_px.0.max(1) as f32 * 2.0 - 1.0, 1.0 - pixel.y / size_px.1.max(1) as f32 * 2.0);
        let world_from_clip = self.clip_from_world(size_px).inverse();
        let far = world_from_clip * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        let eye = self.eye();
        let direction = (far.truncate() / far.w - eye).normalize_or(-self.backward());
        (eye, direction)
    }
}

/// Axis-aligned bounds of a point set; `None` for an empty set or any non-finite point.
pub fn bounds(points: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for p in points {
        if !p.is_finite() {
            return None;
        }
        min = min.min(*p);
        max = max.max(*p);
    }
    (!points.is_empty()).then_some((min, max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_round_trip() {
        let camera = OrbitCamera {
            target: Vec3::new(0.5, 1.25, -2.0),
            yaw_deg: 200.0,
            pitch_deg: -30.0,
            distance_m: 7.5,
            fov_y_deg: 50.0,
        };
        assert_eq!(OrbitCamera::from_view(&camera.to_view()), camera);
    }

    #[test]
    fn a_box_is_seen_once_framed_and_not_from_far_beside_it() {
        let (min, max) = (Vec3::new(4.0, 0.0, -1.0), Vec3::new(6.0, 1.0, 1.0));
        let mut camera = OrbitCamera::default();
        assert!(!camera.sees_any(min, max, 1.5), "the default camera looks at the origin");
        let angles = (camera.yaw_deg, camera.pitch_deg);
        camera.frame_bounds(min, max, 1.5);
        assert_eq!((camera.yaw_deg, camera.pitch_deg), angles, "framing keeps the orbit angles");
        assert!(camera.sees_any(min, max, 1.5));
        let aside = Vec3::Y.cross(camera.backward()).normalize() * 50.0;
        assert!(!camera.sees_any(min + aside, max + aside, 1.5));
        assert!(!camera.sees_any(max, min, 1.5), "an empty box");
        assert!(!camera.sees_any(min, Vec3::splat(f32::NAN), 1.5));
    }

    #[test]
    fn the_target_projects_to_the_centre() {
        let camera = OrbitCamera::default();
        let p = camera.project(camera.target, (640, 480)).unwrap();
        assert!((p - Vec2::new(320.0, 240.0)).length() < 1e-3, "{p}");
    }

    #[test]
    fn up_is_up_and_right_is_right_on_screen() {
        let camera = OrbitCamera { yaw_deg: 0.0, pitch_deg: 0.0, ..OrbitCamera::default() };
        let centre = camera.project(camera.target, (100, 100)).unwrap();
        let above = camera.project(camera.target + Vec3::Y * 0.1, (100, 100)).unwrap();
        let right = camera.project(camera.target + Vec3::X * 0.1, (100, 100)).unwrap();
        assert!(above.y < centre.y);
        assert!(right.x > centre.x);
    }

    #[test]
    fn points_behind_the_eye_do_not_project() {
        let camera = OrbitCamera::default();
        let behind = camera.eye() + camera.backward();
        assert_eq!(camera.project(behind, (100, 100)), None);
    }

    #[test]
    fn a_pixel_ray_passes_through_the_projected_point() {
        let camera = OrbitCamera { yaw_deg: 40.0, pitch_deg: 30.0, ..OrbitCamera::default() };
        let point = Vec3::new(0.3, 0.8, -0.2);
        let pixel = camera.project(point, (800, 600)).unwrap();
        let (origin, direction) = camera.ray(pixel, (800, 600));
        let to_point = point - origin;
        let miss = (to_point - direction * to_point.dot(direction)).length();
        assert!(miss < 1e-4, "{miss}");
    }

    #[test]
    fn pitch_is_clamped_and_yaw_wraps() {
        let mut camera = OrbitCamera::default();
        camera.orbit(Vec2::new(1e6, 1e6));
        assert_eq!(camera.pitch_deg, MAX_PITCH_DEG);
        assert!((0.0..360.0).contains(&camera.yaw_deg));
        let before = camera;
        camera.orbit(Vec2::new(f32::NAN, 0.0));
        camera.pan(Vec2::new(0.0, f32::INFINITY), 100.0);
        camera.dolly(f32::NAN);
        assert_eq!(camera, before);
    }

    #[test]
    fn dolly_stays_within_limits() {
        let mut camera = OrbitCamera::default();
        camera.dolly(1e4);
        assert_eq!(camera.distance_m, MIN_DISTANCE_M);
        camera.dolly(-1e4);
        assert_eq!(camera.distance_m, MAX_DISTANCE_M);
    }

    #[test]
    fn pan_moves_the_target_by_the_pixels_dragged() {
        let mut camera = OrbitCamera::default();
        let size = (800, 600);
        let start = camera.target;
        camera.pan(Vec2::new(100.0, 0.0), 600.0);
        // The old target is now 100 px right of the centre.
        let p = camera.project(start, size).unwrap();
        assert!((p.x - 500.0).abs() < 0.5 && (p.y - 300.0).abs() < 0.5, "{p}");
    }

    #[test]
    fn framing_puts_every_corner_on_screen() {
        let mut camera = OrbitCamera::default();
        let (min, max) = (Vec3::new(-3.0, 0.0, -1.0), Vec3::new(2.0, 4.0, 1.0));
        camera.frame_bounds(min, max, 16.0 / 9.0);
        for i in 0..8 {
            let corner = Vec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            );
            let p = camera.project(corner, (1280, 720)).unwrap();
            assert!((0.0..=1280.0).contains(&p.x) && (0.0..=720.0).contains(&p.y), "{corner} at {p}");
        }
    }

    #[test]
    fn framing_ignores_empty_or_infinite_bounds() {
        let mut camera = OrbitCamera::default();
        let before = camera;
        camera.frame_bounds(Vec3::ONE, Vec3::ZERO, 1.0);
        camera.frame_bounds(Vec3::ZERO, Vec3::splat(f32::INFINITY), 1.0);
        assert_eq!(camera, before);
        assert_eq!(bounds(&[]), None);
        assert_eq!(bounds(&[Vec3::new(f32::NAN, 0.0, 0.0)]), None);
    }
}
