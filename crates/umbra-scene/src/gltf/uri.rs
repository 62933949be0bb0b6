//! Buffer URIs (glTF 2.0 §3.3.2): `data:` URIs decoded in memory, relative references
//! resolved inside the glTF file's folder and nowhere else.

use std::path::{Component, Path, PathBuf};

/// What a buffer URI refers to.
pub(crate) enum Target {
    /// Embedded bytes (`data:…;base64,…`).
    Data(Vec<u8>),
    /// A regular file inside the document's folder (canonical path).
    File(PathBuf),
}

/// Resolves `uri` for a document in `folder` (`None`: from memory, no files at all). The
/// `Err` is why the URI is refused; it never contains the contents of any file.
pub(crate) fn resolve(uri: &str, folder: Option<&Path>) -> Result<Target, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest.split_once(";base64,").ok_or("a data: URI must be base64 (`;base64,`)")?;
        return decode_base64(data).map(Target::Data);
    }
    if has_scheme(uri) {
        return Err("only data: URIs and relative references are read (no schemes such as file: or http:)".into());
    }
    let folder = folder.ok_or("a document read from memory may only embed its buffers (data: URIs or GLB)")?;
    let decoded = percent_encoding::percent_decode_str(uri)
        .decode_utf8()
        .map_err(|_| "its percent-encoding does not decode to UTF-8".to_string())?;
    let relative = Path::new(decoded.as_ref());
    if decoded.contains('\0') || relative.has_root() {
        return Err("absolute paths are not read: a buffer must lie in the glTF file's folder".into());
    }
    if relative.components().any(|c| c == Component::ParentDir) {
        return Err("`..` is not followed: a buffer must lie in the glTF file's folder".into());
    }
    let inside = |p: &Path| p.canonicalize().map_err(|e| format!("{}: {e}", p.display()));
    let (root, file) = (inside(folder)?, inside(&folder.join(relative))?);
    if !file.starts_with(&root) {
        return Err(format!(
            "it resolves (through a symbolic link) to {}, outside the glTF file's folder",
            file.display()
        ));
    }
    Ok(Target::File(file))
}

/// RFC 3986 §3.1: `scheme = ALPHA *( ALPHA / DIGIT / "+" / "-" / "." )` followed by `:`.
fn has_scheme(uri: &str) -> bool {
    let Some((scheme, _)) = uri.split_once(':') else { return false };
    let mut chars = scheme.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
}

/// Standard base64 (RFC 4648 §4), padding optional.
fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    let digit = |c: u8| -> Result<u32, String> {
        Ok(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return Err(format!("byte {c:#04x} is not base64")),
        } as u32)
    };
    let text = text.trim_end_matches('=').as_bytes();
    if text.len() % 4 == 1 {
        return Err("base64 data of impossible length".into());
    }
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 2);
    for group in text.chunks(4) {
        let mut n = 0u32;
        for (k, &c) in group.iter().enumerate() {
            n |= digit(c)? << (18 - 6 * k);
        }
        out.extend_from_slice(&n.to_be_bytes()[1..group.len()]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_every_padding() {
        for (text, bytes) in [("", &b""[..]), ("TQ==", b"M"), ("TWE=", b"Ma"), ("TWFu", b"Man"), ("TWFuTQ", b"ManM")] {
            assert_eq!(decode_base64(text).unwrap(), bytes, "{text}");
        }
        assert!(decode_base64("TW!u").is_err());
        assert!(decode_base64("T").is_err());
    }

    #[test]
    fn only_relative_references_inside_the_folder_are_followed() {
        let dir = std::env::temp_dir().join(format!("umbra-uri-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/a b.bin"), b"x").unwrap();
        let _ = std::os::unix::fs::symlink("/etc/passwd", dir.join("link.bin"));
        assert!(matches!(resolve("sub/a%20b.bin", Some(&dir)), Ok(Target::File(_))));
        for (uri, why) in [
            ("/etc/passwd", "absolute"),
            ("../../../../etc/passwd", "`..`"),
            ("..%2F..%2Fetc%2Fpasswd", "`..`"),
            ("sub/../../x", "`..`"),
            ("file:///etc/passwd", "schemes"),
            ("%2Fproc%2Fself%2Fenviron", "absolute"),
            ("link.bin", "outside"),
            ("missing.bin", "No such file"),
        ] {
            let Err(e) = resolve(uri, Some(&dir)) else { panic!("{uri} was followed") };
            assert!(e.contains(why), "{uri}: {e}");
        }
        assert!(resolve("sub/a%20b.bin", None).is_err(), "no folder: no files");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
