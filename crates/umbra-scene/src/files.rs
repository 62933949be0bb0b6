//! Reading input files: regular files only, never more than a declared number of bytes.

use crate::error::{SceneError, SceneResult};
use std::io::Read;
use std::path::Path;

/// Reads `path` whole if it is a regular file (after following symlinks) of at most `limit`
/// bytes. A FIFO, a device such as `/dev/zero`, a directory or a socket is refused before it is
/// opened, so nothing blocks and nothing reads without end; a file that grows past `limit`
/// while it is read (or a `/proc` file, whose size reads as 0) is cut off and refused.
pub(crate) fn read_regular(path: &Path, limit: u64) -> SceneResult<Vec<u8>> {
    let io = |source| SceneError::Io { path: path.to_owned(), source };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(SceneError::NotAFile { path: path.to_owned(), kind: kind_of(&meta.file_type()) });
    }
    let too_large = |size: u64| SceneError::Limit { what: format!("file {}", path.display()), value: size, limit };
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path).map_err(io)?.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

fn kind_of(t: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_dir() {
        "a directory"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "something"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_directories_and_fifos_are_refused_before_reading() {
        for (path, kind) in [("/dev/zero", "character device"), ("/", "directory")] {
            let e = read_regular(Path::new(path), 1 << 20).unwrap_err();
            assert!(e.to_string().contains(kind), "{path}: {e}");
        }
        let dir = std::env::temp_dir().join(format!("umbra-fifo-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("scene.toml");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(made.success(), "mkfifo");
        let e = read_regular(&fifo, 1 << 20).unwrap_err();
        assert!(e.to_string().contains("FIFO"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn files_past_the_limit_are_refused_and_proc_files_are_cut_off() {
        let e = read_regular(Path::new("/proc/self/maps"), 16).unwrap_err();
        assert!(matches!(e, SceneError::Limit { limit: 16, .. }), "{e}");
        let file = std::env::temp_dir().join(format!("umbra-big-{}.toml", std::process::id()));
        std::fs::write(&file, b"name = \"0123456789\"").unwrap();
        let e = read_regular(&file, 4).unwrap_err();
        assert!(e.to_string().contains("beyond umbra's limit of 4"), "{e}");
        std::fs::remove_file(&file).unwrap();
    }
}
