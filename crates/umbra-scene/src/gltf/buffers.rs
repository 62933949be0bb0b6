//! The bytes of the buffers a document's meshes use, each checked against its declared
//! `byteLength` and never read past it (glTF 2.0 §3.6.1).

use super::container::Document;
use super::source::Source;
use super::uri::{self, Target};
use crate::error::{SceneError, SceneResult};
use crate::limits::MAX_FILE_BYTES;

/// Loaded buffers, by index; `None` for buffers no mesh reads (never opened).
pub(crate) struct Buffers(Vec<Option<Vec<u8>>>);

impl Buffers {
    /// Loads every buffer in `needed` (indices already checked against `buffers`).
    pub fn load(doc: &Document, needed: &[bool], src: &Source) -> SceneResult<Self> {
        let mut out = Vec::with_capacity(needed.len());
        let mut total = 0u64;
        for (i, (buffer, &need)) in doc.root.buffers.iter().zip(needed).enumerate() {
            if !need {
                out.push(None);
                continue;
            }
            let at = format!("buffers[{i}]");
            let declared = buffer.byte_length.0;
            total = total.saturating_add(declared);
            if total > MAX_FILE_BYTES {
                let what = format!("glTF {}: the buffers' total byteLength", src.path.display());
                return Err(SceneError::Limit { what, value: total, limit: MAX_FILE_BYTES });
            }
            let mut bytes = match &buffer.uri {
                None if i == 0 => doc
                    .bin
                    .map(<[u8]>::to_vec)
                    .ok_or_else(|| src.error(&at, "has no uri and the file has no GLB binary chunk to stand for it"))?,
                None => return Err(src.error(&at, "has no uri; only buffer 0 of a .glb may omit it")),
                Some(u) => read_uri(u, &at, src)?,
            };
            if (bytes.len() as u64) < declared {
                return Err(src.error(&at, format!("byteLength is {declared} but its data has {} bytes", bytes.len())));
            }
            bytes.truncate(declared as usize);
            out.push(Some(bytes));
        }
        Ok(Self(out))
    }

    /// The bytes of buffer `index` (loaded by [`Buffers::load`]).
    pub fn get(&self, index: usize) -> Option<&[u8]> {
        self.0.get(index)?.as_deref()
    }
}

fn read_uri(u: &str, at: &str, src: &Source) -> SceneResult<Vec<u8>> {
    let refused = |why: String| {
        let uri = if u.len() > 80 { format!("{}…", u.chars().take(77).collect::<String>()) } else { u.to_owned() };
        SceneError::GltfUri { path: src.path.clone(), at: at.to_owned(), uri, why }
    };
    match uri::resolve(u, src.folder.as_deref()).map_err(refused)? {
        Target::Data(bytes) => Ok(bytes),
        Target::File(file) => crate::files::read_regular(&file, MAX_FILE_BYTES),
    }
}
