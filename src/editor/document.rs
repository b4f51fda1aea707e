//! The open scene with its file, its saved state and its undo history.
//!
//! Undo snapshots the whole scene (a few kilobytes): simple and exact. Every
//! edit goes through [`Document::edit`], which validates it and rolls back an
//! edit that would make the scene invalid. Edits made while a gesture is open
//! (a drag, a slider held down) become one undo step when it ends.

use std::path::{Path, PathBuf};

use crate::scene::Scene;

/// Undo steps kept; the oldest go first.
pub const UNDO_LIMIT: usize = 200;

#[derive(Clone, Debug)]
struct Step {
    label: String,
    scene: Scene,
}

/// An edit the scene's rules reject, e.g. a pin outside a smaller grid.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct EditRejected(pub String);

pub struct Document {
    scene: Scene,
    path: Option<PathBuf>,
    /// The scene as last loaded or saved: the document is dirty when it differs
    /// (`None`: nothing on disk holds this work).
    saved: Option<Scene>,
    undo: Vec<Step>,
    redo: Vec<Step>,
    /// An open gesture: its label and the scene before it began.
    gesture: Option<Step>,
}

impl Document {
    /// A document showing `scene`, clean, with no history. `path` is where it
    /// was loaded from (`None` for a new, untitled scene).
    pub fn new(scene: Scene, path: Option<PathBuf>) -> Document {
        Document { saved: Some(scene.clone()), scene, path, undo: Vec::new(), redo: Vec::new(), gesture: None }
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// Where file dialogs start: the folder of the scene's file when it
    /// exists, else the working directory (".", failing that).
    pub fn folder(&self) -> PathBuf {
        self.path()
            .and_then(Path::parent)
            .filter(|dir| dir.is_dir())
            .map(Path::to_path_buf)
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_else(|| PathBuf::from("."))
    }

    /// How the scene names the file at `path` (a mesh, a reference):
    /// relative to the scene's folder once it has been saved, else absolute
    /// (a Save As then makes it relative).
    pub fn name_for_file(&self, path: &Path) -> String {
        match self.path().and_then(Path::parent).and_then(|folder| std::path::absolute(folder).ok()) {
            Some(folder) => crate::scene::relative_path(&folder, path).display().to_string(),
            None => path.display().to_string(),
        }
    }

    /// Whether the scene differs from the file (an undo back to the saved state is clean again).
    pub fn is_dirty(&self) -> bool {
        self.saved.as_ref() != Some(&self.scene)
    }

    /// The file name for titles and prompts: `tent.ron`, or `untitled`.
    pub fn display_name(&self) -> String {
        match self.path.as_deref().and_then(Path::file_name) {
            Some(name) => name.to_string_lossy().into_owned(),
            None => "untitled".to_owned(),
        }
    }

    /// Applies `change` to the scene. An edit that leaves the scene invalid is
    /// undone and its first problem returned. Outside a gesture the edit is an
    /// undo step of its own; inside one, the gesture's end makes it one.
    pub fn edit(&mut self, label: &str, change: impl FnOnce(&mut Scene)) -> Result<(), EditRejected> {
        let mut edited = self.scene.clone();
        change(&mut edited);
        if edited == self.scene {
            return Ok(());
        }
        if let Err(issues) = edited.validate() {
            let first = issues.first().map(|i| i.to_string()).unwrap_or_default();
            return Err(EditRejected(first));
        }
        let before = std::mem::replace(&mut self.scene, edited);
        match &self.gesture {
            Some(_) => {}
            None => self.push_undo(Step { label: label.to_owned(), scene: before }),
        }
        Ok(())
    }

    /// Opens a gesture: the edits until [`Document::end_gesture`] make one undo
    /// step named `label`. Does nothing if one is open already.
    pub fn begin_gesture(&mut self, label: &str) {
        if self.gesture.is_none() {
            self.gesture = Some(Step { label: label.to_owned(), scene: self.scene.clone() });
        }
    }

    pub fn in_gesture(&self) -> bool {
        self.gesture.is_some()
    }

    /// Closes the open gesture, recording one undo step if it changed anything.
    pub fn end_gesture(&mut self) {
        if let Some(before) = self.gesture.take()
            && before.scene != self.scene
        {
            self.push_undo(before);
        }
    }

    fn push_undo(&mut self, step: Step) {
        self.undo.push(step);
        if self.undo.len() > UNDO_LIMIT {
            self.undo.remove(0);
        }
        self.redo.clear();
    }

    /// What Edit ▸ Undo would undo, e.g. `Move pin`.
    pub fn undo_label(&self) -> Option<&str> {
        self.undo.last().map(|s| s.label.as_str())
    }

    pub fn redo_label(&self) -> Option<&str> {
        self.redo.last().map(|s| s.label.as_str())
    }

    /// How many undo steps lead back to `scene` (0 when it is the scene now);
    /// `None` when the undo history does not hold it.
    pub fn undo_steps_to(&self, scene: &Scene) -> Option<usize> {
        if self.scene == *scene {
            return Some(0);
        }
        self.undo.iter().rev().position(|step| step.scene == *scene).map(|at| at + 1)
    }

    /// How many redos bring the document to `scene`: `None` when it is not
    /// ahead on the redo stack.
    pub fn redo_steps_to(&self, scene: &Scene) -> Option<usize> {
        self.redo.iter().rev().position(|step| step.scene == *scene).map(|at| at + 1)
    }

    /// Steps back one edit; false when there is nothing to undo.
    pub fn undo(&mut self) -> bool {
        self.end_gesture();
        let Some(step) = self.undo.pop() else { return false };
        let current = std::mem::replace(&mut self.scene, step.scene);
        self.redo.push(Step { label: step.label, scene: current });
        true
    }

    pub fn redo(&mut self) -> bool {
        self.end_gesture();
        let Some(step) = self.redo.pop() else { return false };
        let current = std::mem::replace(&mut self.scene, step.scene);
        self.undo.push(Step { label: step.label, scene: current });
        true
    }

    /// Records that the scene is now on disk at `path` (Save / Save As).
    pub fn mark_saved(&mut self, path: PathBuf) {
        self.saved = Some(self.scene.clone());
        self.path = Some(path);
    }

    /// Marks the scene as differing from its file although it may not (work
    /// restored from a recovery file has to be saved to be kept).
    pub fn mark_unsaved(&mut self) {
        self.saved = None;
    }

    /// Updates the scene's saved camera without an undo step or making the
    /// document dirty by itself (the view is not part of the work).
    pub fn set_view_quietly(&mut self, view: Option<crate::scene::View>) {
        self.scene.view = view.clone();
        if let Some(saved) = &mut self.saved {
            saved.view = view;
        }
    }

    /// Renames the mesh and reference files for a scene file moving from the folder `from`
    /// to `to` (a Save As elsewhere), so they name the same files; no undo
    /// step (an undo after it brings back names relative to the old folder).
    pub fn move_files_quietly(&mut self, from: &Path, to: &Path) {
        crate::scene::move_referenced_files(&mut self.scene, from, to);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc() -> Document {
        let scene = crate::scene::parse(crate::editor::DEFAULT_SCENE, "magic_carpet.ron").unwrap();
        Document::new(scene, Some(PathBuf::from("/tmp/carpet.ron")))
    }

    #[test]
    fn an_edit_is_one_step_and_undo_redo_walk_it_back_and_forth() {
        let mut d = doc();
        let original = d.scene().clone();
        assert!(!d.is_dirty());
        d.edit("Elasticity", |s| s.keys[0].elasticity = 1.4).unwrap();
        assert!(d.is_dirty());
        assert_eq!(d.undo_label(), Some("Elasticity"));
        let edited = d.scene().clone();
        assert!(d.undo());
        assert_eq!(*d.scene(), original);
        assert!(!d.is_dirty(), "back at the saved state");
        assert!(d.redo());
        assert_eq!(*d.scene(), edited);
        assert!(!d.redo(), "nothing more to redo");
    }

    #[test]
    fn a_gesture_is_one_undo_step_however_many_edits() {
        let mut d = doc();
        let original = d.scene().clone();
        d.begin_gesture("Move pin");
        for step in 1..=30 {
            d.edit("Move pin", |s| s.keys[0].pins[0].pos.1 += 0.01 * step as f64).unwrap();
        }
        d.end_gesture();
        assert_eq!(d.undo_label(), Some("Move pin"));
        assert!(d.undo());
        assert_eq!(*d.scene(), original);
        assert!(d.undo_label().is_none());
    }

    #[test]
    fn an_invalid_edit_is_rejected_and_changes_nothing() {
        let mut d = doc();
        let original = d.scene().clone();
        let error = d.edit("Elasticity", |s| s.keys[0].elasticity = f64::NAN).unwrap_err();
        assert!(error.0.contains("elasticity"), "{error}");
        assert_eq!(*d.scene(), original);
        assert!(d.undo_label().is_none());
    }

    #[test]
    fn restored_work_is_unsaved_until_saved() {
        let mut d = doc();
        d.mark_unsaved();
        assert!(d.is_dirty());
        d.mark_saved(PathBuf::from("/tmp/restored.ron"));
        assert!(!d.is_dirty());
    }

    #[test]
    fn a_new_edit_clears_redo_and_saving_makes_clean() {
        let mut d = doc();
        d.edit("Stiffness", |s| s.keys[0].stiffness = 0.5).unwrap();
        d.undo();
        d.edit("Stiffness", |s| s.keys[0].stiffness = 0.7).unwrap();
        assert!(d.redo_label().is_none());
        d.mark_saved(PathBuf::from("/tmp/other.ron"));
        assert!(!d.is_dirty());
        assert_eq!(d.display_name(), "other.ron");
        d.undo();
        assert!(d.is_dirty(), "undoing past a save differs from the file");
    }

    #[test]
    fn history_is_bounded() {
        let mut d = doc();
        for step in 0..UNDO_LIMIT + 20 {
            d.edit("Stiffness", |s| s.keys[0].stiffness = step as f64 / 1000.0).unwrap();
        }
        let mut undone = 0;
        while d.undo() {
            undone += 1;
        }
        assert_eq!(undone, UNDO_LIMIT);
    }
}
