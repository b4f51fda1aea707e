//! placeholder replaced by the catenary implementation
use glam::DVec3;
#[derive(Clone, Debug)]
pub struct Catenary { start: DVec3, end: DVec3, length_m: f64 }
impl Catenary {
    pub fn new(start: DVec3, end: DVec3, length_m: f64) -> Catenary { Catenary { start, end, length_m } }
    pub fn start(&self) -> DVec3 { self.start }
    pub fn end(&self) -> DVec3 { self.end }
    pub fn length_m(&self) -> f64 { self.length_m }
    pub fn is_taut(&self) -> bool { false }
    pub fn point_at_arc_fraction(&self, s: f64) -> DVec3 { self.start.lerp(self.end, s) }
    pub fn point_at_horizontal_fraction(&self, f: f64) -> DVec3 { self.start.lerp(self.end, f) }
    pub fn lowest_point(&self) -> DVec3 { self.start }
}
