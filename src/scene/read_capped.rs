//! The one way Drape reads a file someone else made (a scene, a mesh, a
//! buffer, a plate's header): only a regular file, never more bytes than a
//! limit, so no path (`/dev/zero`, a FIFO with no writer, a directory) can
//! hang a read or fill memory.

use std::fs;
use std::io::{self, Read as _};
use std::path::Path;

use super::error::SceneError;

/// The bytes of the regular file at `path`, or [`SceneError::TooLarge`] as
/// soon as it holds more than `limit_bytes`; anything but a regular file
/// (following symlinks) is refused before it is opened for reading.
pub fn read_capped(path: &Path, limit_bytes: u64) -> Result<Vec<u8>, SceneError> {
    let read_error = |source| SceneError::Read { path: path.to_owned(), source };
    let too_large = || SceneError::TooLarge { path: path.to_owned(), limit_bytes };
    let (file, declared) = open_regular(path).map_err(read_error)?;
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

/// The first `length_bytes` bytes of the regular file at `path` (a glTF
/// buffer its document declares that long), or an error when it is shorter
/// or not a regular file. Nothing past `length_bytes` is read.
pub fn read_prefix(path: &Path, length_bytes: u64) -> Result<Vec<u8>, SceneError> {
    let read_error = |source| SceneError::Read { path: path.to_owned(), source };
    let (file, declared) = open_regular(path).map_err(read_error)?;
    let short = || {
        read_error(io::Error::new(
            io::ErrorKind::UnexpectedEof,
            format!("it holds {declared} bytes, fewer than the {length_bytes} declared"),
        ))
    };
    if declared < length_bytes {
        return Err(short());
    }
    let mut bytes = Vec::with_capacity(length_bytes as usize);
    file.take(length_bytes).read_to_end(&mut bytes).map_err(read_error)?;
    if (bytes.len() as u64) < length_bytes {
        return Err(short());
    }
    Ok(bytes)
}

/// The file at `path` opened for reading with the size it declares, or an
/// error saying what it is when it is not a regular file. The kind is checked
/// before opening (opening a FIFO waits for a writer) and again on the open
/// file, which is opened non-blocking in case the path changed in between.
pub(super) fn open_regular(path: &Path) -> io::Result<(fs::File, u64)> {
    refuse_unless_regular(&fs::metadata(path)?)?;
    let mut options = fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, libc::O_NONBLOCK);
    let file = options.open(path)?;
    let metadata = file.metadata()?;
    refuse_unless_regular(&metadata)?;
    Ok((file, metadata.len()))
}

fn refuse_unless_regular(metadata: &fs::Metadata) -> io::Result<()> {
    if metadata.is_file() {
        return Ok(());
    }
    let what = file_kind(metadata);
    Err(io::Error::other(format!("it is {what}, not a regular file")))
}

/// What a path that is not a regular file is, in a user's words.
fn file_kind(metadata: &fs::Metadata) -> &'static str {
    if metadata.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        let kind = metadata.file_type();
        if kind.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    "not a file"
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(result: Result<Vec<u8>, SceneError>) -> String {
        match result {
            Ok(bytes) => format!("read {} bytes", bytes.len()),
            Err(error) => error.to_string(),
        }
    }

    #[test]
    fn only_regular_files_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.ron");
        fs::write(&file, "12345").unwrap();
        assert_eq!(message(read_capped(&file, 5)), "read 5 bytes");
        assert!(message(read_capped(&file, 4)).contains("too large"));
        assert!(message(read_capped(dir.path(), 100)).ends_with("it is a folder, not a regular file"));
        assert!(message(read_capped(Path::new("/dev/zero"), 100)).ends_with("it is a device, not a regular file"));
        assert!(message(read_capped(Path::new("/dev/null"), 100)).ends_with("it is a device, not a regular file"));
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_with_no_writer_is_refused_at_once() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe.glb");
        let c_path = std::ffi::CString::new(fifo.as_os_str().as_encoded_bytes()).unwrap();
        // SAFETY: `c_path` is a NUL-terminated path that lives across the call.
        assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0);
        assert!(message(read_capped(&fifo, 100)).ends_with("it is a named pipe (FIFO), not a regular file"));
        assert!(message(read_prefix(&fifo, 100)).ends_with("it is a named pipe (FIFO), not a regular file"));
    }

    #[test]
    fn a_prefix_reads_exactly_what_is_declared() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.bin");
        fs::write(&file, [1u8, 2, 3, 4, 5]).unwrap();
        assert_eq!(read_prefix(&file, 3).unwrap(), vec![1, 2, 3]);
        assert_eq!(read_prefix(&file, 5).unwrap().len(), 5);
        assert!(message(read_prefix(&file, 6)).contains("fewer than the 6 declared"));
        assert!(message(read_prefix(Path::new("/dev/zero"), 6)).ends_with("it is a device, not a regular file"));
    }
}
