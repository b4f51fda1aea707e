//! Reading a file whole, but never more than a limit: a scene, a mesh, a
//! buffer — whatever the path turns out to be (`/dev/zero` included).

use std::fs;
use std::io::Read as _;
use std::path::Path;

use super::error::SceneError;

/// The bytes of the file at `path`, or [`SceneError::TooLarge`] as soon as it
/// holds more than `limit_bytes`.
pub fn read_capped(path: &Path, limit_bytes: u64) -> Result<Vec<u8>, SceneError> {
    let read_error = |source| SceneError::Read { path: path.to_owned(), source };
    let too_large = || SceneError::TooLarge { path: path.to_owned(), limit_bytes };
    let file = fs::File::open(path).map_err(read_error)?;
    // The size a regular file declares; devices and pipes declare none and are counted as read.
    let declared = file.metadata().map(|m| if m.is_file() { m.len() } else { 0 }).unwrap_or(0);
    if declared > limit_bytes {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(declared as usize);
    file.take(limit_bytes + 1).read_to_end(&mut bytes).map_err(read_error)?;
    if bytes.len() as u64 > limit_bytes {
        return Err(too_large());
    }
    Ok(bytes)
}
