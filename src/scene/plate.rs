//! The background plate (`plate` in the scene, DESIGN.md's names): a
//! picture, or a numbered sequence of them, seen behind the cloth through
//! the shot camera.

use serde::{Deserialize, Serialize};

use super::param::Param;

/// One image (`file` without `#`), or a sequence where the run of `#`s stands
/// for the zero-padded frame number: frame F shows file F + `frame_offset`.
/// PNG or JPEG, the path relative to the scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plate {
    pub file: String,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub frame_offset: i32,
    /// 0 (not seen) to 1 (opaque) over the background colour.
    #[serde(default = "default_opacity")]
    pub opacity: Param,
}

fn is_zero(v: &i32) -> bool {
    *v == 0
}

fn default_opacity() -> Param {
    Param::Constant(1.0)
}

/// Largest `frame_offset` either way: far past any timeline.
pub const MAX_PLATE_FRAME_OFFSET: i32 = 1_000_000;
/// Most `#`s a sequence's number may have.
pub const MAX_PLATE_DIGITS: usize = 9;

/// A plate's file name split round its run of `#`s.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlatePattern {
    /// Everything before the `#`s (the whole path for a single image).
    pub prefix: String,
    /// How many `#`s: the number's zero-padded width; 0 for a single image.
    pub digits: usize,
    pub suffix: String,
}

impl PlatePattern {
    /// Splits `file`; an error says why it is no plate file name (two runs
    /// of `#`s, too many of them, `#`s in a folder's name).
    pub fn parse(file: &str) -> Result<PlatePattern, String> {
        let Some(start) = file.find('#') else {
            return Ok(PlatePattern { prefix: file.to_owned(), digits: 0, suffix: String::new() });
        };
        let digits = file[start..].chars().take_while(|c| *c == '#').count();
        let (prefix, suffix) = (&file[..start], &file[start + digits..]);
        if suffix.contains('#') {
            return Err(format!("{file:?} has two runs of #: one run stands for the frame number"));
        }
        if suffix.contains(['/', '\\']) {
            return Err(format!("{file:?} numbers a folder: the #s belong in the file name"));
        }
        if digits > MAX_PLATE_DIGITS {
            return Err(format!("{file:?} has {digits} #s; at most {MAX_PLATE_DIGITS} digits are read"));
        }
        Ok(PlatePattern { prefix: prefix.to_owned(), digits, suffix: suffix.to_owned() })
    }

    pub fn is_sequence(&self) -> bool {
        self.digits > 0
    }

    /// The file name of number `n`: zero-padded to the width of the `#`s
    /// (longer numbers keep every digit; negative ones a leading `-`).
    pub fn file_name(&self, n: i64) -> String {
        if !self.is_sequence() {
            return self.prefix.clone();
        }
        let width = self.digits;
        let number = if n < 0 { format!("-{:0width$}", -n) } else { format!("{n:0width$}") };
        format!("{}{number}{}", self.prefix, self.suffix)
    }

    /// The number in `name` (a file name alone, without folders), when it is
    /// one of this sequence's: the prefix's file part, at least `digits`
    /// digits, the suffix.
    pub fn number_in(&self, name: &str) -> Option<i64> {
        let prefix_name = self.prefix.rsplit(['/', '\\']).next().unwrap_or_default();
        let middle = name.strip_prefix(prefix_name)?.strip_suffix(self.suffix.as_str())?;
        let digits = middle.strip_prefix('-').unwrap_or(middle);
        if digits.len() < self.digits || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        // A number wider than the padding has no leading zero (`0012` is not `###`'s 12).
        if digits.len() > self.digits && digits.starts_with('0') {
            return None;
        }
        middle.parse().ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_of_hashes_is_the_zero_padded_frame_number() {
        let pattern = PlatePattern::parse("plates/bg_####.png").unwrap();
        assert_eq!(pattern.file_name(7), "plates/bg_0007.png");
        assert_eq!(pattern.file_name(12345), "plates/bg_12345.png");
        assert_eq!(pattern.file_name(-3), "plates/bg_-0003.png");
        assert_eq!(pattern.number_in("bg_0007.png"), Some(7));
        assert_eq!(pattern.number_in("bg_12345.png"), Some(12345));
        assert_eq!(pattern.number_in("bg_-0003.png"), Some(-3));
        assert_eq!(pattern.number_in("bg_007.png"), None, "too narrow");
        assert_eq!(pattern.number_in("bg_00007.png"), None, "padded wider than the #s");
        assert_eq!(pattern.number_in("bg_0007.jpg"), None);
        assert_eq!(pattern.number_in("fg_0007.png"), None);
        assert_eq!(pattern.number_in("bg_00a7.png"), None);
    }

    #[test]
    fn a_name_without_hashes_is_one_image_and_bad_patterns_say_why() {
        let still = PlatePattern::parse("sky.jpg").unwrap();
        assert!(!still.is_sequence());
        assert_eq!(still.file_name(40), "sky.jpg");
        assert!(PlatePattern::parse("a_##_b_##.png").unwrap_err().contains("two runs"));
        assert!(PlatePattern::parse("shot_##/bg.png").unwrap_err().contains("folder"));
        assert!(PlatePattern::parse("bg_##########.png").unwrap_err().contains("at most 9"));
    }

    #[test]
    fn a_plate_needs_only_its_file() {
        let plate: Plate = ron::from_str("(file: \"bg.png\")").unwrap();
        assert_eq!((plate.frame_offset, plate.opacity), (0, Param::Constant(1.0)));
        assert!(ron::from_str::<Plate>("(file: \"bg.png\", opacty: 0.5)").is_err(), "a misspelt field is refused");
    }
}
