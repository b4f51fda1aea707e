//! The editor's own Open / Save As dialog, drawn with egui as a modal.
//!
//! Drape does not call the desktop's native file chooser: that needs a desktop
//! portal or a toolkit which a bare X server (Xvfb in CI) does not have, and a
//! native window cannot be driven by egui's headless tests. This dialog works
//! wherever the editor's window does, and every widget carries a stable label
//! ("Up", "Folder", "File name", "All files", "Open"/"Save", "Cancel",
//! "Replace", "Don't Replace") for tests that find widgets by label.
//!
//! The filesystem side — listing a folder, sorting, filtering by extension,
//! turning what the user typed into a path — lives in plain functions
//! ([`list_dir`], [`resolve_folder`], [`resolve_name`],
//! [`with_extension_if_missing`]) so it is tested without a GUI.

use std::cmp::Ordering;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use eframe::egui::{
    self, Align, Button, Id, Key, Layout, Modal, Modifiers, RichText, ScrollArea, TextEdit, TextStyle, text::CCursor,
    text_edit::TextEditState, text_selection::CCursorRange, vec2,
};

use super::prompt::{ModalKeys, is_top_modal, take_modal_keys};
use crate::atomic_file::io_reason;

/// What the dialog is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileDialogMode {
    /// Pick an existing file.
    Open,
    /// Choose a file name to save to ("Save As"); an existing file needs confirmation.
    Save,
}

/// How the user left the dialog.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FileDialogOutcome {
    /// An absolute path: an existing file for [`FileDialogMode::Open`]; for
    /// [`FileDialogMode::Save`] a path in an existing folder ending in the
    /// dialog's extension, which the user agreed to replace if it exists.
    Picked(PathBuf),
    Cancelled,
}

/// One row of a folder listing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DirEntry {
    /// The file name, lossily converted to text for display.
    pub name: String,
    pub path: PathBuf,
    /// A folder, or a symlink to one.
    pub is_dir: bool,
}

/// What a typed file name means, see [`resolve_name`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ResolvedName {
    /// The name is an existing folder: the dialog goes there.
    Folder(PathBuf),
    /// A file to open or save; `exists` is whether something is already there.
    File { path: PathBuf, exists: bool },
}

/// Lists `dir`: folders first, then files, each group sorted by name ignoring
/// case (ties broken by the exact name so the order is stable). Entries whose
/// name starts with `.` are left out. With `extension` (without the dot) only
/// files ending in it, in any case, are listed; `None` lists every file.
/// Entries that vanish or cannot be inspected while listing are skipped; only
/// failing to read the folder itself is an error.
pub fn list_dir(dir: &Path, extension: Option<&str>) -> io::Result<Vec<DirEntry>> {
    let mut entries = Vec::new();
    for entry in fs::read_dir(dir)? {
        let Ok(entry) = entry else { continue };
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            continue;
        }
        let path = entry.path();
        // `metadata` follows symlinks, so a link to a folder lists as a folder;
        // a dangling link lists as a file.
        let is_dir = match entry.file_type() {
            Ok(kind) if kind.is_symlink() => fs::metadata(&path).is_ok_and(|m| m.is_dir()),
            Ok(kind) => kind.is_dir(),
            Err(_) => continue,
        };
        if !is_dir && extension.is_some_and(|ext| !has_extension(&name, ext)) {
            continue;
        }
        entries.push(DirEntry { name, path, is_dir });
    }
    entries.sort_by(compare_entries);
    Ok(entries)
}

/// Folders before files, then by name ignoring case, then by exact name.
fn compare_entries(a: &DirEntry, b: &DirEntry) -> Ordering {
    b.is_dir.cmp(&a.is_dir).then_with(|| a.name.to_lowercase().cmp(&b.name.to_lowercase())).then(a.name.cmp(&b.name))
}

/// Whether `name` ends in `.extension`, ignoring case (`Tent.RON` is a `ron` file).
pub fn has_extension(name: &str, extension: &str) -> bool {
    Path::new(name).extension().is_some_and(|ext| ext.to_string_lossy().eq_ignore_ascii_case(extension))
}

/// `name` with `.extension` appended unless it already ends in it (any case):
/// `tent` → `tent.ron`, `tent.v2` → `tent.v2.ron`, `tent.` → `tent.ron`,
/// `tent.RON` unchanged. An empty extension leaves the name as it is.
pub fn with_extension_if_missing(name: &str, extension: &str) -> String {
    if extension.is_empty() || has_extension(name, extension) {
        return name.to_owned();
    }
    format!("{}.{extension}", name.strip_suffix('.').unwrap_or(name))
}

/// `~` or `~/…` at the start of typed text means the home folder.
fn expand_home(typed: &str) -> PathBuf {
    let home = || std::env::var_os("HOME").filter(|h| !h.is_empty()).map(PathBuf::from);
    if typed == "~" {
        if let Some(home) = home() {
            return home;
        }
    } else if let Some(rest) = typed.strip_prefix("~/")
        && let Some(home) = home()
    {
        return home.join(rest);
    }
    PathBuf::from(typed)
}

/// `typed` resolved against `current`: absolute as typed (with `~` for the
/// home folder), else relative to `current`.
fn typed_path(current: &Path, typed: &str) -> PathBuf {
    current.join(expand_home(typed))
}

/// The folder the path bar's text names, relative to `current` unless
/// absolute, with `~` for the home folder; canonical (no `..`, symlinks
/// resolved). The error is the message the dialog shows.
pub fn resolve_folder(current: &Path, typed: &str) -> Result<PathBuf, String> {
    let typed = typed.trim();
    if typed.is_empty() {
        return Err("Type the path of a folder".to_owned());
    }
    let path = typed_path(current, typed);
    match fs::canonicalize(&path) {
        Ok(folder) if folder.is_dir() => Ok(folder),
        Ok(_) => Err(format!("{typed} is a file, not a folder")),
        Err(error) if error.kind() == io::ErrorKind::NotFound => Err(format!("No such folder: {typed}")),
        Err(error) => Err(format!("Cannot open {typed}: {}", io_reason(&error))),
    }
}

/// What the file name typed in folder `dir` means. The name may be absolute,
/// hold folders (`renders/tent`) or start with `~`. Leading and trailing
/// spaces are ignored.
///
/// - An existing folder → [`ResolvedName::Folder`] (the dialog opens it).
/// - Open: an existing file, tried as typed and then with `.extension`
///   appended (`tent` finds `tent.ron`); anything else is an error.
/// - Save: `.extension` is appended if missing; the folder it goes in must
///   exist; `exists` says whether the save would replace a file.
///
/// The error is the message the dialog shows.
pub fn resolve_name(mode: FileDialogMode, dir: &Path, typed: &str, extension: &str) -> Result<ResolvedName, String> {
    let typed = typed.trim();
    if typed.is_empty() {
        return Err(match mode {
            FileDialogMode::Open => "Choose a file to open".to_owned(),
            FileDialogMode::Save => "Type a name for the file".to_owned(),
        });
    }
    let path = typed_path(dir, typed);
    if path.is_dir() {
        return Ok(ResolvedName::Folder(fs::canonicalize(&path).unwrap_or(path)));
    }
    // `renders/` names a folder; as a file name it would silently become `renders/.ron`.
    if typed.ends_with(std::path::is_separator) {
        return Err(format!("No such folder: {typed}"));
    }
    match mode {
        FileDialogMode::Open => {
            let with_extension = path.with_file_name(with_extension_if_missing(&file_name_of(&path), extension));
            [path, with_extension]
                .into_iter()
                .find(|candidate| candidate.is_file())
                .map(|path| ResolvedName::File { path, exists: true })
                .ok_or_else(|| format!("No such file: {typed}"))
        }
        FileDialogMode::Save => {
            let path = path.with_file_name(with_extension_if_missing(&file_name_of(&path), extension));
            let folder = path.parent().unwrap_or(dir);
            if !folder.is_dir() {
                return Err(format!("No such folder: {}", folder.display()));
            }
            let exists = fs::symlink_metadata(&path).is_ok();
            if path.is_dir() {
                return Ok(ResolvedName::Folder(path));
            }
            Ok(ResolvedName::File { path, exists })
        }
    }
}

fn file_name_of(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

/// A modal Open / Save As dialog. Create it when the user asks for it, call
/// [`FileDialog::show`] every frame until it returns an outcome, then drop it.
pub struct FileDialog {
    mode: FileDialogMode,
    title: String,
    /// Without the dot; empty means no filter and nothing appended.
    extension: String,
    id: Id,
    /// The folder listed (absolute).
    dir: PathBuf,
    /// The path bar's text; differs from `dir` while the user edits it.
    dir_text: String,
    /// Why the path bar's text could not be opened, shown under it.
    dir_error: Option<String>,
    entries: Vec<DirEntry>,
    /// Why the folder could not be listed, shown in place of the listing.
    list_error: Option<String>,
    /// List every file, not only those with the extension.
    all_files: bool,
    selected: Option<usize>,
    /// The selection was the last thing the user chose (a click or an arrow
    /// key, not typing a name): Enter then opens a selected folder.
    selection_active: bool,
    /// Scroll the listing to the selection on the next frame (arrow keys).
    scroll_to_selected: bool,
    /// The listing's scroll offset and visible height in the last frame, in points.
    listing_view: (f32, f32),
    file_name: String,
    /// Why the typed name cannot be opened or saved, shown under it.
    name_error: Option<String>,
    /// A save that would replace this existing file, awaiting "Replace".
    confirm_replace: Option<PathBuf>,
    /// Focus the file name field on the first frame.
    first_frame: bool,
}

/// What the user asked for during one frame, applied after drawing.
enum Action {
    NavigateTyped,
    Up,
    Refresh,
    Select(usize),
    /// Arrow keys: move the selection by this many rows.
    MoveSelection(isize),
    Activate(usize),
    Confirm,
    Replace,
    KeepExisting,
    Cancel,
}

const DIALOG_WIDTH: f32 = 560.0;
const MIN_DIALOG_WIDTH: f32 = 320.0;
const LISTING_HEIGHT: f32 = 280.0;
/// The dialog's height besides the listing, for fitting it in small windows.
const DIALOG_HEIGHT_WITHOUT_LISTING: f32 = 200.0;

impl FileDialog {
    /// A dialog listing `start_dir` (made absolute; a folder that cannot be
    /// read shows its error in the dialog). `file_name` pre-fills the name
    /// field, e.g. the scene's current name for Save As. `extension` (without
    /// the dot, e.g. `"ron"`) filters the listing and is appended to saved
    /// names that lack it.
    pub fn new(mode: FileDialogMode, title: &str, start_dir: &Path, file_name: &str, extension: &str) -> FileDialog {
        let extension = extension.trim_start_matches('.').to_owned();
        let mut dialog = FileDialog {
            mode,
            title: title.to_owned(),
            id: Id::unique(("drape file dialog", mode == FileDialogMode::Save)),
            extension,
            dir: PathBuf::new(),
            dir_text: String::new(),
            dir_error: None,
            entries: Vec::new(),
            list_error: None,
            all_files: false,
            selected: None,
            selection_active: false,
            scroll_to_selected: false,
            listing_view: (0.0, LISTING_HEIGHT),
            file_name: file_name.to_owned(),
            name_error: None,
            confirm_replace: None,
            first_frame: true,
        };
        let start = fs::canonicalize(start_dir)
            .or_else(|_| std::path::absolute(start_dir))
            .unwrap_or_else(|_| start_dir.to_owned());
        dialog.navigate(start);
        dialog
    }

    pub fn mode(&self) -> FileDialogMode {
        self.mode
    }

    /// The folder being listed.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The listing as shown.
    pub fn entries(&self) -> &[DirEntry] {
        &self.entries
    }

    /// Draws the dialog as a modal over the editor; returns `Some` once the
    /// user picked a file or cancelled (then stop calling it). Enter confirms
    /// (or opens the folder typed in the path bar), Escape cancels, or backs
    /// out of a "Replace?" question.
    pub fn show(&mut self, ctx: &egui::Context) -> Option<FileDialogOutcome> {
        let ModalKeys { enter, escape } = take_modal_keys(ctx, self.id, &[self.path_bar_id(), self.file_name_id()]);
        let path_bar_focused = ctx.memory(|m| m.has_focus(self.path_bar_id()));
        let mut action = match (enter, escape, self.confirm_replace.is_some()) {
            (_, true, true) => Some(Action::KeepExisting),
            (_, true, false) => Some(Action::Cancel),
            (true, _, true) => Some(Action::Replace),
            (true, _, false) if path_bar_focused => Some(Action::NavigateTyped),
            (true, _, false) => Some(Action::Confirm),
            _ => self.take_list_keys(ctx),
        };
        Modal::new(self.id).show(ctx, |ui| {
            // Narrower in a small window, so the buttons stay on screen.
            ui.set_width(DIALOG_WIDTH.min(ctx.content_rect().width() - 40.0).max(MIN_DIALOG_WIDTH));
            ui.heading(&self.title);
            ui.add_space(4.0);
            self.path_bar(ui, &mut action);
            self.listing(ui, &mut action);
            self.name_row(ui);
            ui.add_space(4.0);
            self.buttons(ui, &mut action);
        });
        self.first_frame = false;
        let action = action?;
        // The frame is drawn already: show the new state without waiting for input.
        ctx.request_repaint();
        self.apply(action)
    }

    fn path_bar_id(&self) -> Id {
        self.id.with("folder")
    }

    fn file_name_id(&self) -> Id {
        self.id.with("file name")
    }

    /// Up/Down move through the listing and Alt+Up goes to the enclosing
    /// folder, while no text field is being typed in (there they move the cursor).
    fn take_list_keys(&self, ctx: &egui::Context) -> Option<Action> {
        if self.confirm_replace.is_some() || ctx.egui_wants_keyboard_input() || !is_top_modal(ctx, self.id) {
            return None;
        }
        ctx.input_mut(|i| {
            // Alt+Up first: a plain Up would also match it.
            if i.consume_key(Modifiers::ALT, Key::ArrowUp) {
                return Some(Action::Up);
            }
            // Key repeat or a fast typist can put several presses in one frame.
            let up = i.count_and_consume_key(Modifiers::NONE, Key::ArrowUp) as isize;
            let down = i.count_and_consume_key(Modifiers::NONE, Key::ArrowDown) as isize;
            (up != down).then_some(Action::MoveSelection(down - up))
        })
    }

    fn path_bar(&mut self, ui: &mut egui::Ui, action: &mut Option<Action>) {
        ui.horizontal(|ui| {
            let up = ui.add_enabled(self.dir.parent().is_some(), Button::new("Up"));
            if up.on_hover_text("Go to the enclosing folder").clicked() {
                *action = Some(Action::Up);
            }
            let label = ui.label("Folder");
            // Room for the Refresh button on the right.
            let width = (ui.available_width() - 70.0).max(100.0);
            let id = self.path_bar_id();
            let edit = TextEdit::singleline(&mut self.dir_text).id(id).desired_width(width);
            let response = ui.add(edit).labelled_by(label.id);
            if response.changed() {
                self.dir_error = None;
            }
            if ui.button("Refresh").on_hover_text("List the folder again").clicked() {
                *action = Some(Action::Refresh);
            }
        });
        if let Some(error) = &self.dir_error {
            ui.colored_label(ui.visuals().error_fg_color, error);
        }
    }

    fn listing(&mut self, ui: &mut egui::Ui, action: &mut Option<Action>) {
        let height = LISTING_HEIGHT.min(ui.ctx().content_rect().height() - DIALOG_HEIGHT_WITHOUT_LISTING).max(80.0);
        let frame = egui::Frame::group(ui.style()).inner_margin(4.0);
        frame.show(ui, |ui| {
            // One scroll position per folder: a new folder starts at the top.
            let area = ScrollArea::vertical()
                .id_salt(self.id.with("listing").with(&self.dir))
                .auto_shrink([false, false])
                .max_height(height);
            let message = match &self.list_error {
                Some(error) => Some(RichText::new(error).color(ui.visuals().error_fg_color)),
                None if self.entries.is_empty() => Some(
                    RichText::new(if self.all_files || self.extension.is_empty() {
                        "This folder is empty".to_owned()
                    } else {
                        format!("No folders or .{} files here", self.extension)
                    })
                    .italics()
                    .color(ui.visuals().weak_text_color()),
                ),
                None => None,
            };
            if let Some(message) = message {
                area.show(ui, |ui| ui.label(message));
                return;
            }
            self.entry_rows(ui, area, action);
        });
    }

    /// The entries as one selectable row each. Only the rows in view are
    /// laid out, so a folder of thousands of files stays responsive.
    fn entry_rows(&mut self, ui: &mut egui::Ui, mut area: ScrollArea, action: &mut Option<Action>) {
        // Every row gets this height, which `show_rows` relies on.
        let row_height = ui
            .spacing()
            .interact_size
            .y
            .max(ui.text_style_height(&TextStyle::Button) + 2.0 * ui.spacing().button_padding.y);
        if let Some(index) = self.selected
            && std::mem::take(&mut self.scroll_to_selected)
        {
            // Scroll just enough to bring the selected row into view.
            let (offset, view_height) = self.listing_view;
            let top = index as f32 * (row_height + ui.spacing().item_spacing.y);
            let offset = offset.min(top).max(top + row_height - view_height);
            area = area.vertical_scroll_offset(offset);
        }
        let output = area.show_rows(ui, row_height, self.entries.len(), |ui, rows| {
            ui.with_layout(Layout::top_down_justified(Align::LEFT), |ui| {
                for index in rows {
                    let entry = &self.entries[index];
                    // A trailing slash marks folders in any font.
                    let text = if entry.is_dir { format!("{}/", entry.name) } else { entry.name.clone() };
                    let button = Button::selectable(self.selected == Some(index), text).min_size(vec2(0.0, row_height));
                    let response = ui.add(button);
                    if response.double_clicked() {
                        *action = Some(Action::Activate(index));
                    } else if response.clicked() {
                        *action = Some(Action::Select(index));
                    }
                }
            });
        });
        self.listing_view = (output.state.clamped_offset().y, output.inner_rect.height());
    }

    fn name_row(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let label = ui.label("File name");
            let width = (ui.available_width() - 90.0).max(100.0);
            let id = self.file_name_id();
            let output = TextEdit::singleline(&mut self.file_name).id(id).desired_width(width).show(ui);
            let response = output.response.response.labelled_by(label.id);
            if response.changed() {
                self.name_error = None;
                self.confirm_replace = None;
                self.selection_active = false;
            }
            if self.first_frame {
                response.request_focus();
                self.select_stem(ui.ctx());
            }
            let filter = if self.extension.is_empty() {
                "Show every file".to_owned()
            } else {
                format!("Show every file, not only .{} files", self.extension)
            };
            if ui.checkbox(&mut self.all_files, "All files").on_hover_text(filter).changed() {
                self.relist();
            }
        });
        if let Some(error) = &self.name_error {
            ui.colored_label(ui.visuals().error_fg_color, error);
        }
    }

    /// Selects the name without its extension, so typing replaces the name
    /// and keeps `.ron`, as desktop save dialogs do.
    fn select_stem(&self, ctx: &egui::Context) {
        let id = self.file_name_id();
        let stem_chars = match self.file_name.rfind('.') {
            Some(dot) if dot > 0 => self.file_name[..dot].chars().count(),
            _ => self.file_name.chars().count(),
        };
        let mut state = TextEditState::load(ctx, id).unwrap_or_default();
        state.cursor.set_char_range(Some(CCursorRange::two(CCursor::new(0), CCursor::new(stem_chars))));
        state.store(ctx, id);
    }

    fn buttons(&mut self, ui: &mut egui::Ui, action: &mut Option<Action>) {
        ui.with_layout(Layout::right_to_left(Align::Center), |ui| {
            if let Some(path) = &self.confirm_replace {
                if ui.button("Replace").clicked() {
                    *action = Some(Action::Replace);
                }
                if ui.button("Don't Replace").clicked() {
                    *action = Some(Action::KeepExisting);
                }
                let name = path.file_name().map(|n| n.to_string_lossy()).unwrap_or_default();
                ui.label(RichText::new(format!("{name} already exists. Replace it?")).strong());
                return;
            }
            let confirm = match self.mode {
                FileDialogMode::Open => "Open",
                FileDialogMode::Save => "Save",
            };
            if ui.button(confirm).clicked() {
                *action = Some(Action::Confirm);
            }
            if ui.button("Cancel").clicked() {
                *action = Some(Action::Cancel);
            }
        });
    }

    fn apply(&mut self, action: Action) -> Option<FileDialogOutcome> {
        match action {
            Action::Cancel => return Some(FileDialogOutcome::Cancelled),
            Action::NavigateTyped => match resolve_folder(&self.dir, &self.dir_text) {
                Ok(dir) => self.navigate(dir),
                Err(error) => self.dir_error = Some(error),
            },
            Action::Up => {
                if let Some(parent) = self.dir.parent() {
                    self.navigate(parent.to_owned());
                }
            }
            Action::Refresh => self.relist(),
            Action::Select(index) => self.select(index),
            Action::MoveSelection(step) => {
                let last = self.entries.len().checked_sub(1)?;
                let index = match self.selected {
                    Some(current) => current.saturating_add_signed(step).min(last),
                    None if step < 0 => last,
                    None => 0,
                };
                self.select(index);
                self.scroll_to_selected = true;
            }
            Action::Activate(index) => {
                let entry = self.entries[index].clone();
                if entry.is_dir {
                    self.navigate(entry.path);
                } else {
                    self.file_name = entry.name;
                    return self.confirm();
                }
            }
            Action::Confirm => return self.confirm(),
            Action::Replace => return self.confirm_replace.take().map(FileDialogOutcome::Picked),
            Action::KeepExisting => self.confirm_replace = None,
        }
        None
    }

    /// Selects a listed entry; a file's name goes into the name field.
    fn select(&mut self, index: usize) {
        self.selected = Some(index);
        self.selection_active = true;
        let entry = &self.entries[index];
        if !entry.is_dir {
            self.file_name = entry.name.clone();
            self.name_error = None;
        }
    }

    /// The Open/Save button, Enter, or a double click on a file.
    fn confirm(&mut self) -> Option<FileDialogOutcome> {
        // A folder just selected in the listing, or selected with no name
        // typed, is opened, as in desktop file choosers.
        if let Some(entry) = self.selected.map(|i| &self.entries[i])
            && entry.is_dir
            && (self.selection_active || self.file_name.trim().is_empty())
        {
            self.navigate(entry.path.clone());
            return None;
        }
        match resolve_name(self.mode, &self.dir, &self.file_name, &self.extension) {
            Ok(ResolvedName::Folder(dir)) => {
                self.navigate(dir);
                self.file_name.clear();
                None
            }
            Ok(ResolvedName::File { path, exists: true }) if self.mode == FileDialogMode::Save => {
                self.confirm_replace = Some(path);
                None
            }
            Ok(ResolvedName::File { path, .. }) => Some(FileDialogOutcome::Picked(path)),
            Err(error) => {
                self.name_error = Some(error);
                None
            }
        }
    }

    fn navigate(&mut self, dir: PathBuf) {
        self.dir_text = dir.display().to_string();
        self.dir = dir;
        self.dir_error = None;
        self.relist();
    }

    fn relist(&mut self) {
        self.selected = None;
        self.selection_active = false;
        let filter = (!self.all_files && !self.extension.is_empty()).then_some(self.extension.as_str());
        match list_dir(&self.dir, filter) {
            Ok(entries) => {
                self.entries = entries;
                self.list_error = None;
            }
            Err(error) => {
                self.entries.clear();
                self.list_error = Some(format!("Cannot list {}: {}", self.dir.display(), io_reason(&error)));
            }
        }
    }
}

/// Room kept beside a file's name for its Choose… button, points.
const CHOOSE_WIDTH: f32 = 100.0;

/// A panel's row for a file it names: `label`, the name (cut to the panel,
/// whole on hover; "none" when empty) and Choose… with `hint`; returns
/// whether Choose… was clicked (the caller opens its dialog).
pub fn file_row_ui(ui: &mut egui::Ui, label: &str, file: &str, hint: &str) -> bool {
    ui.horizontal(|ui| {
        ui.label(label);
        let shown = if file.is_empty() { "none" } else { file };
        // A fixed share of the panel, so a long path is cut instead of widening it.
        let width = (ui.available_width() - CHOOSE_WIDTH).max(40.0);
        let name = egui::Label::new(egui::RichText::new(shown).monospace()).truncate();
        ui.add_sized([width, 18.0], name).on_hover_text(file);
        ui.button("Choose…").on_hover_text(hint).clicked()
    })
    .inner
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::ui_driver::UiDriver;
    use egui::Event;

    /// A folder with a few scenes, other files, a hidden file and sub-folders.
    fn sample_dir() -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for name in ["b.ron", "A.ron", "c.RON", "notes.txt", ".hidden.ron", "tent.ron.bak"] {
            fs::write(dir.path().join(name), "").unwrap();
        }
        for name in ["zeta", "Alpha", ".git"] {
            fs::create_dir(dir.path().join(name)).unwrap();
        }
        dir
    }

    fn names(entries: &[DirEntry]) -> Vec<String> {
        entries.iter().map(|e| if e.is_dir { format!("{}/", e.name) } else { e.name.clone() }).collect()
    }

    fn canonical(dir: &tempfile::TempDir) -> PathBuf {
        fs::canonicalize(dir.path()).unwrap()
    }

    #[test]
    fn listing_puts_folders_first_sorts_ignoring_case_and_hides_dot_entries() {
        let dir = sample_dir();
        let filtered = list_dir(dir.path(), Some("ron")).unwrap();
        assert_eq!(names(&filtered), ["Alpha/", "zeta/", "A.ron", "b.ron", "c.RON"]);
        let all = list_dir(dir.path(), None).unwrap();
        assert_eq!(names(&all), ["Alpha/", "zeta/", "A.ron", "b.ron", "c.RON", "notes.txt", "tent.ron.bak"]);
        assert_eq!(all[0].path, dir.path().join("Alpha"));
    }

    #[test]
    fn listing_a_missing_folder_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let error = list_dir(&dir.path().join("gone"), None).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::NotFound);
    }

    #[cfg(unix)]
    #[test]
    fn listing_follows_symlinks_to_folders() {
        let dir = sample_dir();
        std::os::unix::fs::symlink(dir.path().join("zeta"), dir.path().join("link")).unwrap();
        std::os::unix::fs::symlink(dir.path().join("nowhere"), dir.path().join("dangling.ron")).unwrap();
        let entries = list_dir(dir.path(), Some("ron")).unwrap();
        assert_eq!(names(&entries), ["Alpha/", "link/", "zeta/", "A.ron", "b.ron", "c.RON", "dangling.ron"]);
    }

    #[test]
    fn the_extension_is_appended_only_when_missing() {
        assert_eq!(with_extension_if_missing("tent", "ron"), "tent.ron");
        assert_eq!(with_extension_if_missing("tent.ron", "ron"), "tent.ron");
        assert_eq!(with_extension_if_missing("tent.RON", "ron"), "tent.RON");
        assert_eq!(with_extension_if_missing("tent.v2", "ron"), "tent.v2.ron");
        assert_eq!(with_extension_if_missing("tent.", "ron"), "tent.ron");
        assert_eq!(with_extension_if_missing("tent", ""), "tent");
        assert!(has_extension("X.Ron", "ron"));
        assert!(!has_extension("ron", "ron"));
    }

    #[test]
    fn typed_folders_resolve_relative_absolute_and_with_errors() {
        let dir = sample_dir();
        let base = canonical(&dir);
        assert_eq!(resolve_folder(&base, "Alpha"), Ok(base.join("Alpha")));
        assert_eq!(resolve_folder(&base, " Alpha/../zeta "), Ok(base.join("zeta")));
        assert_eq!(resolve_folder(Path::new("/"), base.to_str().unwrap()), Ok(base.clone()));
        assert_eq!(resolve_folder(&base, "nope"), Err("No such folder: nope".to_owned()));
        assert_eq!(resolve_folder(&base, "b.ron"), Err("b.ron is a file, not a folder".to_owned()));
        assert_eq!(resolve_folder(&base, ""), Err("Type the path of a folder".to_owned()));
    }

    #[test]
    fn typed_names_resolve_for_save() {
        let dir = sample_dir();
        let base = canonical(&dir);
        let save = |typed| resolve_name(FileDialogMode::Save, &base, typed, "ron");
        assert_eq!(save("new"), Ok(ResolvedName::File { path: base.join("new.ron"), exists: false }));
        assert_eq!(save(" b "), Ok(ResolvedName::File { path: base.join("b.ron"), exists: true }));
        assert_eq!(save("Alpha/inner"), Ok(ResolvedName::File { path: base.join("Alpha/inner.ron"), exists: false }));
        assert_eq!(save("zeta"), Ok(ResolvedName::Folder(base.join("zeta"))));
        let elsewhere = base.join("Alpha/abs.ron");
        assert_eq!(
            save(elsewhere.to_str().unwrap()),
            Ok(ResolvedName::File { path: elsewhere.clone(), exists: false })
        );
        assert_eq!(save("missing/x"), Err(format!("No such folder: {}", base.join("missing").display())));
        assert_eq!(save("missing/"), Err("No such folder: missing/".to_owned()));
        assert_eq!(save("  "), Err("Type a name for the file".to_owned()));
    }

    #[test]
    fn typed_names_resolve_for_open() {
        let dir = sample_dir();
        let base = canonical(&dir);
        let open = |typed| resolve_name(FileDialogMode::Open, &base, typed, "ron");
        assert_eq!(open("b.ron"), Ok(ResolvedName::File { path: base.join("b.ron"), exists: true }));
        assert_eq!(open("b"), Ok(ResolvedName::File { path: base.join("b.ron"), exists: true }));
        assert_eq!(open("notes.txt"), Ok(ResolvedName::File { path: base.join("notes.txt"), exists: true }));
        assert_eq!(open("Alpha"), Ok(ResolvedName::Folder(base.join("Alpha"))));
        assert_eq!(open("d"), Err("No such file: d".to_owned()));
        assert_eq!(open(""), Err("Choose a file to open".to_owned()));
    }

    type Driver = UiDriver<FileDialog, FileDialogOutcome>;

    fn save_dialog(dir: &Path, name: &str) -> Driver {
        UiDriver::new(FileDialog::new(FileDialogMode::Save, "Save Scene As", dir, name, "ron"), FileDialog::show)
    }

    fn open_dialog(dir: &Path) -> Driver {
        UiDriver::new(FileDialog::new(FileDialogMode::Open, "Open Scene", dir, "", "ron"), FileDialog::show)
    }

    #[test]
    fn widgets_carry_stable_labels() {
        let dir = sample_dir();
        let driver = save_dialog(dir.path(), "untitled.ron");
        for label in ["Up", "Folder", "Refresh", "File name", "All files", "Save", "Cancel", "Alpha/", "b.ron"] {
            assert!(driver.exists(label), "{label} missing");
        }
        assert!(!driver.exists("notes.txt"));
        assert!(!driver.exists(".hidden.ron"));
        assert_eq!(driver.value_of("Folder"), Some(canonical(&dir).display().to_string()));
        assert_eq!(driver.value_of("File name").as_deref(), Some("untitled.ron"));
        assert!(open_dialog(dir.path()).exists("Open"));
    }

    #[test]
    fn typing_a_name_and_enter_saves_with_the_extension() {
        let dir = sample_dir();
        let mut driver = save_dialog(dir.path(), "untitled.ron");
        // The name field has focus with the stem selected: typing replaces it and keeps `.ron`.
        driver.type_text("tent");
        assert_eq!(driver.value_of("File name").as_deref(), Some("tent.ron"));
        assert_eq!(driver.press(Key::Enter), Some(FileDialogOutcome::Picked(canonical(&dir).join("tent.ron"))));
    }

    #[test]
    fn a_typed_name_without_extension_gets_it() {
        let dir = sample_dir();
        let mut driver = save_dialog(dir.path(), "");
        driver.type_text("curtain");
        assert_eq!(driver.click("Save"), Some(FileDialogOutcome::Picked(canonical(&dir).join("curtain.ron"))));
    }

    #[test]
    fn escape_cancels() {
        let dir = sample_dir();
        let mut driver = open_dialog(dir.path());
        assert_eq!(driver.press(Key::Escape), Some(FileDialogOutcome::Cancelled));
        let mut driver = save_dialog(dir.path(), "x.ron");
        assert_eq!(driver.click("Cancel"), Some(FileDialogOutcome::Cancelled));
    }

    #[test]
    fn enter_on_a_button_reached_with_tab_presses_that_button() {
        let dir = sample_dir();
        let mut driver = save_dialog(dir.path(), "new.ron");
        driver.focus("Cancel");
        assert_eq!(driver.press(Key::Enter), Some(FileDialogOutcome::Cancelled));
    }

    #[test]
    fn saving_over_an_existing_file_asks_first() {
        let dir = sample_dir();
        let mut driver = save_dialog(dir.path(), "b.ron");
        assert_eq!(driver.click("Save"), None);
        assert!(driver.shows("b.ron already exists. Replace it?"));
        // Escape backs out of the question, not out of the dialog.
        assert_eq!(driver.press(Key::Escape), None);
        assert!(!driver.exists("Replace"));
        // Enter asks again.
        assert_eq!(driver.press(Key::Enter), None);
        assert_eq!(driver.click("Don't Replace"), None);
        assert!(driver.exists("Save"));
        driver.click("Save");
        assert_eq!(driver.click("Replace"), Some(FileDialogOutcome::Picked(canonical(&dir).join("b.ron"))));
    }

    #[test]
    fn opening_a_missing_name_shows_an_error() {
        let dir = sample_dir();
        let mut driver = open_dialog(dir.path());
        driver.type_text("nothing");
        assert_eq!(driver.press(Key::Enter), None);
        assert!(driver.shows("No such file: nothing"));
        // Editing the name clears the message.
        driver.type_text("x");
        assert!(!driver.shows("No such file"));
    }

    #[test]
    fn clicking_selects_and_double_clicking_opens() {
        let dir = sample_dir();
        let mut driver = open_dialog(dir.path());
        assert_eq!(driver.click("b.ron"), None);
        assert_eq!(driver.value_of("File name").as_deref(), Some("b.ron"));
        fs::write(dir.path().join("Alpha/inner.ron"), "").unwrap();
        assert_eq!(driver.double_click("Alpha/"), None);
        assert_eq!(driver.state.dir(), canonical(&dir).join("Alpha"));
        assert!(driver.exists("inner.ron"));
        assert_eq!(
            driver.double_click("inner.ron"),
            Some(FileDialogOutcome::Picked(canonical(&dir).join("Alpha/inner.ron")))
        );
    }

    #[test]
    fn enter_opens_a_folder_selected_in_the_listing() {
        let dir = sample_dir();
        let mut driver = save_dialog(dir.path(), "scene.ron");
        driver.click("zeta/");
        assert_eq!(driver.value_of("File name").as_deref(), Some("scene.ron"), "a folder leaves the name alone");
        assert_eq!(driver.press(Key::Enter), None);
        assert_eq!(driver.state.dir(), canonical(&dir).join("zeta"));
        assert_eq!(driver.press(Key::Enter), Some(FileDialogOutcome::Picked(canonical(&dir).join("zeta/scene.ron"))));
    }

    #[test]
    fn arrow_keys_move_through_the_listing_and_alt_up_goes_up() {
        let dir = sample_dir();
        let mut driver = open_dialog(dir.path());
        driver.click("Alpha/");
        // The name field no longer has focus: arrows move the selection.
        driver.press(Key::ArrowDown);
        driver.press(Key::ArrowDown);
        assert_eq!(driver.value_of("File name").as_deref(), Some("A.ron"));
        for _ in 0..10 {
            driver.press(Key::ArrowDown);
        }
        assert_eq!(driver.value_of("File name").as_deref(), Some("c.RON"), "stops at the last entry");
        driver.press(Key::ArrowUp);
        assert_eq!(driver.value_of("File name").as_deref(), Some("b.ron"));
        driver.click("zeta/");
        driver.press(Key::Enter);
        assert_eq!(driver.state.dir(), canonical(&dir).join("zeta"));
        driver.press_with(Modifiers::ALT, Key::ArrowUp);
        assert_eq!(driver.state.dir(), canonical(&dir));
    }

    #[test]
    fn only_rows_in_view_are_drawn_and_arrows_scroll_to_the_selection() {
        let dir = tempfile::tempdir().unwrap();
        for i in 0..200 {
            fs::write(dir.path().join(format!("s{i:03}.ron")), "").unwrap();
        }
        let mut driver = open_dialog(dir.path());
        assert!(driver.exists("s000.ron"));
        assert!(!driver.exists("s150.ron"), "rows far out of view are not laid out");
        driver.click("s001.ron");
        for _ in 0..20 {
            driver.press(Key::ArrowDown);
        }
        // Presses that arrive in one frame all count.
        let down = |pressed| Event::Key {
            key: Key::ArrowDown,
            physical_key: None,
            pressed,
            repeat: false,
            modifiers: Modifiers::NONE,
        };
        driver.frame((0..10).flat_map(|_| [down(true), down(false)]).collect());
        assert_eq!(driver.value_of("File name").as_deref(), Some("s031.ron"));
        assert!(driver.exists("s031.ron"), "the selection scrolled into view");
        assert!(!driver.exists("s000.ron"));
        driver.press(Key::ArrowUp);
        assert!(driver.exists("s030.ron"));
    }

    #[test]
    fn the_path_bar_navigates_on_enter_and_reports_bad_folders() {
        let dir = sample_dir();
        let mut driver = open_dialog(dir.path());
        driver.focus("Folder");
        // Select everything in the path bar and type over it.
        driver.press_with(Modifiers::COMMAND, Key::A);
        driver.type_text("/no/such/folder");
        assert_eq!(driver.press(Key::Enter), None);
        assert!(driver.shows("No such folder: /no/such/folder"));
        assert_eq!(driver.state.dir(), canonical(&dir), "still listing the old folder");

        driver.press_with(Modifiers::COMMAND, Key::A);
        driver.type_text(&canonical(&dir).join("zeta").display().to_string());
        assert_eq!(driver.press(Key::Enter), None);
        assert_eq!(driver.state.dir(), canonical(&dir).join("zeta"));
        assert!(!driver.shows("No such folder"));
        driver.click("Up");
        assert_eq!(driver.state.dir(), canonical(&dir));
    }

    #[test]
    fn the_all_files_toggle_lists_every_file() {
        let dir = sample_dir();
        let mut driver = open_dialog(dir.path());
        assert!(!driver.exists("notes.txt"));
        driver.click("All files");
        driver.frame(Vec::new());
        assert!(driver.exists("notes.txt"));
    }

    #[test]
    fn a_missing_start_folder_shows_an_error_instead_of_panicking() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("gone");
        let mut driver = open_dialog(&missing);
        assert!(driver.shows("Cannot list"), "the listing explains the problem");
        driver.click("Up");
        assert_eq!(driver.state.dir(), canonical(&dir));
        assert!(!driver.shows("Cannot list"));
    }

    #[cfg(unix)]
    #[test]
    fn an_unreadable_folder_shows_an_error() {
        use std::os::unix::fs::PermissionsExt;
        let dir = sample_dir();
        let locked = dir.path().join("locked");
        fs::create_dir(&locked).unwrap();
        fs::set_permissions(&locked, fs::Permissions::from_mode(0o000)).unwrap();
        // Root reads any folder, so only check the message when the lock holds.
        if fs::read_dir(&locked).is_err() {
            let mut driver = open_dialog(dir.path());
            driver.double_click("locked/");
            assert!(driver.shows("Cannot list"));
            assert!(driver.shows("Permission denied"));
        }
        fs::set_permissions(&locked, fs::Permissions::from_mode(0o755)).unwrap();
    }
}
