//! The two containers of glTF 2.0: a JSON document, or a binary `.glb` (§4.4: a 12-byte
//! header, a JSON chunk, an optional BIN chunk), parsed with every length checked against the
//! bytes actually present.

use super::source::Source;
use crate::error::SceneResult;
use gltf::json::Root;

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// A parsed document and its GLB binary chunk, if any.
pub(crate) struct Document<'a> {
    /// The JSON, deserialised but not yet validated (umbra checks what it reads itself).
    pub root: Root,
    /// The BIN chunk of a `.glb`.
    pub bin: Option<&'a [u8]>,
}

/// Parses `.glb` bytes or JSON text.
pub(crate) fn parse<'a>(bytes: &'a [u8], src: &Source) -> SceneResult<Document<'a>> {
    let (json, bin) = if bytes.starts_with(GLB_MAGIC) { glb_chunks(bytes, src)? } else { (bytes, None) };
    let root = Root::from_slice(json).map_err(|e| src.error("JSON", format!("not a glTF 2.0 document: {e}")))?;
    check_asset(&root, src)?;
    Ok(Document { root, bin })
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

fn glb_chunks<'a>(bytes: &'a [u8], src: &Source) -> SceneResult<(&'a [u8], Option<&'a [u8]>)> {
    let bad = |why: String| src.error("GLB", why);
    let (Some(version), Some(length)) = (u32_at(bytes, 4), u32_at(bytes, 8)) else {
        return Err(bad(format!("a {}-byte file cannot hold the 12-byte GLB header", bytes.len())));
    };
    if version != 2 {
        return Err(bad(format!("GLB version {version}; umbra reads glTF 2.0 (version 2)")));
    }
    if length as usize > bytes.len() {
        return Err(bad(format!("the header declares {length} bytes but the file has {} (truncated)", bytes.len())));
    }
    let body = &bytes[..length as usize];
    let mut chunks = Vec::new();
    let mut at = 12usize;
    while at < body.len() {
        let (Some(len), Some(kind)) = (u32_at(body, at), u32_at(body, at + 4)) else {
            return Err(bad(format!("chunk {} header at byte {at} is cut off", chunks.len())));
        };
        let data = body.get(at + 8..).and_then(|rest| rest.get(..len as usize)).ok_or_else(|| {
            bad(format!(
                "chunk {} declares {len} bytes at byte {at}; only {} remain",
                chunks.len(),
                body.len() - at - 8
            ))
        })?;
        chunks.push((kind, data));
        at += 8 + len as usize;
    }
    match chunks.as_slice() {
        [(CHUNK_JSON, json)] => Ok((json, None)),
        [(CHUNK_JSON, json), (CHUNK_BIN, bin), ..] => Ok((json, Some(bin))),
        [(CHUNK_JSON, json), ..] => Ok((json, None)),
        _ => Err(bad("the first chunk must be JSON (0x4E4F534A)".into())),
    }
}

/// Extensions that may be required without changing the geometry umbra reads.
fn ignorable(extension: &str) -> bool {
    extension == "KHR_lights_punctual"
        || ["KHR_materials_", "KHR_texture_", "EXT_texture_"].iter().any(|p| extension.starts_with(p))
}

fn check_asset(root: &Root, src: &Source) -> SceneResult<()> {
    if !root.asset.version.starts_with("2.") {
        return Err(src.error("asset.version", format!("{:?}; umbra reads glTF 2.x", root.asset.version)));
    }
    if let Some(e) = root.extensions_required.iter().find(|e| !ignorable(e)) {
        return Err(src.error("extensionsRequired", format!("{e} is required but umbra does not implement it")));
    }
    Ok(())
}
