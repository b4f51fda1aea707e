//! The part of the timeline the track shows: the whole range, or a zoomed
//! window into it that Ctrl+wheel narrows about the mouse and the wheel or a
//! middle drag slides.

/// The fewest frames the track zooms in to.
pub const MIN_SPAN_FRAMES: f64 = 8.0;

/// A visible window `start..=end` (frames, fractional) inside the timeline.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimelineZoom {
    /// `None`: the whole timeline.
    window: Option<(f64, f64)>,
}

impl TimelineZoom {
    /// The frames shown for a timeline from `first` to `last`: the window,
    /// kept inside the range, or the whole range.
    pub fn shown(&self, first: i32, last: i32) -> (f64, f64) {
        let (first, last) = (f64::from(first), f64::from(last));
        match self.window {
            Some((start, end)) => fit((start, end), first, last),
            None => (first, last),
        }
    }

    /// Whether only part of the timeline is shown.
    pub fn is_zoomed(&self) -> bool {
        self.window.is_some()
    }

    /// Shows the whole timeline again.
    pub fn reset(&mut self) {
        self.window = None;
    }

    /// Zooms by `factor` (> 1 in) about `frame`, which keeps its place on the
    /// track; never narrower than [`MIN_SPAN_FRAMES`], never wider than the
    /// timeline. A non-finite or non-positive factor is ignored.
    pub fn zoom_about(&mut self, factor: f64, frame: f64, first: i32, last: i32) {
        if !(factor.is_finite() && factor > 0.0 && frame.is_finite()) {
            return;
        }
        let (start, end) = self.shown(first, last);
        let full = f64::from(last - first);
        let span = ((end - start) / factor).clamp(MIN_SPAN_FRAMES.min(full), full.max(MIN_SPAN_FRAMES));
        if span >= full {
            self.window = None;
            return;
        }
        // `frame` sits at the same fraction of the track before and after.
        let along = if end > start { (frame - start) / (end - start) } else { 0.5 };
        let new_start = frame - along * span;
        self.window = Some(fit((new_start, new_start + span), f64::from(first), f64::from(last)));
    }

    /// Slides the window by `frames` (positive: later), staying inside the timeline.
    pub fn pan(&mut self, frames: f64, first: i32, last: i32) {
        if !frames.is_finite() {
            return;
        }
        if let Some((start, end)) = self.window {
            self.window = Some(fit((start + frames, end + frames), f64::from(first), f64::from(last)));
        }
    }

    /// Slides a zoomed window just enough to show `frame` (the playhead while playing).
    pub fn keep_in_view(&mut self, frame: f64, first: i32, last: i32) {
        let Some((start, end)) = self.window else { return };
        if frame < start {
            self.pan(frame - start, first, last);
        } else if frame > end {
            self.pan(frame - end, first, last);
        }
    }
}

/// `window` moved (not resized, unless wider than the range) to lie inside `first..=last`.
fn fit((start, end): (f64, f64), first: f64, last: f64) -> (f64, f64) {
    let span = (end - start).min(last - first).max(0.0);
    let start = start.clamp(first, (last - span).max(first));
    (start, start + span)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zooming_keeps_the_frame_under_the_mouse_at_its_place() {
        let mut zoom = TimelineZoom::default();
        assert_eq!(zoom.shown(0, 120), (0.0, 120.0));
        zoom.zoom_about(2.0, 30.0, 0, 120);
        let (start, end) = zoom.shown(0, 120);
        assert!((end - start - 60.0).abs() < 1e-9);
        assert!(((30.0 - start) / (end - start) - 0.25).abs() < 1e-9, "{start}..{end}");
        zoom.zoom_about(3.0, 40.0, 0, 120);
        let (start2, end2) = zoom.shown(0, 120);
        let before = (40.0 - start) / (end - start);
        let after = (40.0 - start2) / (end2 - start2);
        assert!((before - after).abs() < 1e-9);
    }

    #[test]
    fn the_window_stays_inside_the_timeline_and_wide_enough() {
        let mut zoom = TimelineZoom::default();
        zoom.zoom_about(1000.0, 119.0, 0, 120);
        let (start, end) = zoom.shown(0, 120);
        assert_eq!(end - start, MIN_SPAN_FRAMES);
        assert!(end <= 120.0 && start >= 0.0);
        zoom.pan(-1000.0, 0, 120);
        assert_eq!(zoom.shown(0, 120), (0.0, MIN_SPAN_FRAMES));
        zoom.zoom_about(0.001, 10.0, 0, 120);
        assert!(!zoom.is_zoomed(), "zooming out past the range shows it all");
        zoom.zoom_about(f64::NAN, 10.0, 0, 120);
        zoom.zoom_about(-2.0, 10.0, 0, 120);
        assert!(!zoom.is_zoomed());
    }

    #[test]
    fn a_shrunk_timeline_pulls_the_window_in() {
        let mut zoom = TimelineZoom::default();
        zoom.zoom_about(4.0, 100.0, 0, 120);
        let (start, end) = zoom.shown(0, 50);
        assert!(start >= 0.0 && end <= 50.0 && end > start);
        assert_eq!(zoom.shown(0, 10), (0.0, 10.0));
    }

    #[test]
    fn the_playhead_is_kept_in_a_zoomed_window() {
        let mut zoom = TimelineZoom::default();
        zoom.keep_in_view(100.0, 0, 120);
        assert!(!zoom.is_zoomed());
        zoom.zoom_about(4.0, 10.0, 0, 120);
        zoom.keep_in_view(100.0, 0, 120);
        let (start, end) = zoom.shown(0, 120);
        assert!(start <= 100.0 && 100.0 <= end && (end - start - 30.0).abs() < 1e-9);
    }
}
