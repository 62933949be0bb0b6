//! Accessors (glTF 2.0 §3.6.2), validated before a byte is read: the index exists, the type
//! and componentType are the ones umbra reads for the semantic, `count × stride` lies inside
//! the bufferView and the bufferView inside its buffer, sparse indices are in range.

use super::buffers::Buffers;
use super::source::Source;
use crate::error::{SceneError, SceneResult};
use crate::limits::{MAX_INDICES, MAX_VERTICES};
use glam::Vec3;
use gltf::json::accessor::{ComponentType, Type};
use gltf::json::validation::Checked;
use gltf::json::Root;

/// Reads accessors of one document.
pub(crate) struct Reader<'a> {
    pub root: &'a Root,
    pub buffers: &'a Buffers,
    pub src: &'a Source,
}

/// The layout of one accessor's elements, checked.
struct Layout {
    component: ComponentType,
    count: usize,
}

fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

fn component_name(c: ComponentType) -> &'static str {
    match c {
        ComponentType::I8 => "BYTE",
        ComponentType::U8 => "UNSIGNED_BYTE",
        ComponentType::I16 => "SHORT",
        ComponentType::U16 => "UNSIGNED_SHORT",
        ComponentType::U32 => "UNSIGNED_INT",
        ComponentType::F32 => "FLOAT",
    }
}

impl Reader<'_> {
    /// A `VEC3` `FLOAT` accessor (`POSITION`, `NORMAL`) as vectors; `semantic` is the JSON
    /// path that refers to it, for messages.
    pub fn vec3(&self, index: usize, semantic: &str) -> SceneResult<Vec<Vec3>> {
        let layout = self.layout(index, semantic, Type::Vec3, &[ComponentType::F32], MAX_VERTICES)?;
        let mut values = vec![Vec3::ZERO; layout.count];
        self.fill(index, semantic, &layout, 12, &mut values, |b| {
            let f = |k: usize| f32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]);
            Vec3::new(f(0), f(4), f(8))
        })?;
        Ok(values)
    }

    /// A `SCALAR` unsigned accessor (`indices`) as `u32`s.
    pub fn indices(&self, index: usize, semantic: &str) -> SceneResult<Vec<u32>> {
        let allowed = [ComponentType::U8, ComponentType::U16, ComponentType::U32];
        let layout = self.layout(index, semantic, Type::Scalar, &allowed, MAX_INDICES)?;
        let mut values = vec![0u32; layout.count];
        let size = component_size(layout.component);
        self.fill(index, semantic, &layout, size, &mut values, |b| unsigned(b, size))?;
        Ok(values)
    }

    fn error(&self, index: usize, semantic: &str, why: impl Into<String>) -> SceneError {
        self.src.error(format!("accessors[{index}] ({semantic})"), why)
    }

    fn layout(
        &self,
        index: usize,
        semantic: &str,
        ty: Type,
        allowed: &[ComponentType],
        max: usize,
    ) -> SceneResult<Layout> {
        let Some(a) = self.root.accessors.get(index) else {
            let n = self.root.accessors.len();
            return Err(self
                .src
                .error(format!("{semantic} accessor"), format!("accessor {index} does not exist (the file has {n})")));
        };
        let component = match a.component_type {
            Checked::Valid(c) if allowed.contains(&c.0) => c.0,
            Checked::Valid(c) => {
                let want: Vec<_> = allowed.iter().map(|&c| component_name(c)).collect();
                let why = format!("componentType {}; umbra reads it as {}", component_name(c.0), want.join(" or "));
                return Err(self.error(index, semantic, why));
            }
            Checked::Invalid => return Err(self.error(index, semantic, "componentType is not a glTF component type")),
        };
        if a.type_ != Checked::Valid(ty) {
            return Err(self.error(index, semantic, format!("type is not {ty:?}, which umbra reads here")));
        }
        if a.normalized {
            return Err(self.error(index, semantic, "normalized integers are not read for this semantic"));
        }
        let count = a.count.0;
        if count > max as u64 {
            let what = format!("glTF {}: accessors[{index}] ({semantic}) count", self.src.path.display());
            return Err(SceneError::Limit { what, value: count, limit: max as u64 });
        }
        Ok(Layout { component, count: count as usize })
    }

    /// Fills `out` (already `count` default elements) from the accessor's bufferView, then
    /// applies its sparse substitution.
    fn fill<T>(
        &self,
        index: usize,
        semantic: &str,
        layout: &Layout,
        elem: usize,
        out: &mut [T],
        decode: impl Fn(&[u8]) -> T,
    ) -> SceneResult<()> {
        let a = &self.root.accessors[index];
        let at = |why: String| self.error(index, semantic, why);
        if let Some(view) = a.buffer_view {
            let offset = a.byte_offset.map_or(0, |o| o.0);
            let (bytes, stride) =
                self.view(view.value(), offset, layout.count, elem, component_size(layout.component)).map_err(at)?;
            for (k, value) in out.iter_mut().enumerate() {
                *value = decode(&bytes[k * stride..k * stride + elem]);
            }
        } else if a.sparse.is_none() {
            return Err(at("has neither a bufferView nor sparse values".into()));
        }
        let Some(sparse) = &a.sparse else { return Ok(()) };
        let n = sparse.count.0;
        if n == 0 || n > layout.count as u64 {
            return Err(at(format!("sparse.count {n} must be in 1..={}", layout.count)));
        }
        let n = n as usize;
        let isize = match sparse.indices.component_type {
            Checked::Valid(c) if c.0 != ComponentType::I8 && c.0 != ComponentType::I16 && c.0 != ComponentType::F32 => {
                component_size(c.0)
            }
            _ => return Err(at("sparse.indices.componentType must be UNSIGNED_BYTE, _SHORT or _INT".into())),
        };
        let iview = sparse.indices.buffer_view.value();
        let (ibytes, istride) = self
            .view(iview, sparse.indices.byte_offset.0, n, isize, isize)
            .map_err(|e| at(format!("sparse.indices: {e}")))?;
        let vview = sparse.values.buffer_view.value();
        let (vbytes, vstride) = self
            .view(vview, sparse.values.byte_offset.0, n, elem, component_size(layout.component))
            .map_err(|e| at(format!("sparse.values: {e}")))?;
        let mut previous = None;
        for k in 0..n {
            let target = unsigned(&ibytes[k * istride..], isize) as usize;
            if target >= layout.count || previous.is_some_and(|p| target <= p) {
                return Err(at(format!(
                    "sparse index {k} is {target}: indices must increase and stay below count {}",
                    layout.count
                )));
            }
            previous = Some(target);
            out[target] = decode(&vbytes[k * vstride..k * vstride + elem]);
        }
        Ok(())
    }

    /// The bytes `count` elements of `elem` bytes occupy in bufferView `view` from `offset`,
    /// with the stride between them; every bound checked (§3.6.2.4).
    fn view(
        &self,
        view: usize,
        offset: u64,
        count: usize,
        elem: usize,
        align: usize,
    ) -> Result<(&[u8], usize), String> {
        let v = self.root.buffer_views.get(view).ok_or_else(|| {
            format!("bufferView {view} does not exist (the file has {})", self.root.buffer_views.len())
        })?;
        let buffer = v.buffer.value();
        let data =
            self.buffers.get(buffer).ok_or_else(|| format!("bufferViews[{view}] refers to missing buffer {buffer}"))?;
        let start = v.byte_offset.map_or(0, |o| o.0);
        let length = v.byte_length.0;
        let end = start.checked_add(length).filter(|&e| e <= data.len() as u64).ok_or_else(|| {
            format!(
                "bufferViews[{view}] spans bytes {start}..{start}+{length}, beyond buffer {buffer}'s {} bytes",
                data.len()
            )
        })?;
        let stride = match v.byte_stride {
            None => elem,
            Some(s) if s.0 >= elem && s.0 <= 252 && s.0 % align == 0 => s.0,
            Some(s) => {
                return Err(format!("bufferViews[{view}].byteStride {} is invalid for {elem}-byte elements (must be {elem}..=252 and a multiple of {align})", s.0))
            }
        };
        let span = match count {
            0 => 0,
            n => {
                ((n - 1) as u64).checked_mul(stride as u64).and_then(|s| s.checked_add(elem as u64)).unwrap_or(u64::MAX)
            }
        };
        if offset.checked_add(span).is_none_or(|e| e > length) {
            return Err(format!(
                "{count} elements of {elem} bytes (stride {stride}) from byte {offset} need {span} bytes; bufferViews[{view}] has {length}"
            ));
        }
        // Both below the buffer's length now: no overflow.
        if (start + offset) % align as u64 != 0 {
            return Err(format!("byte offset {} is not a multiple of the component size {align}", start + offset));
        }
        let from = (start + offset) as usize;
        Ok((&data[from..(end as usize).min(from + span as usize)], stride))
    }
}

/// A little-endian unsigned integer of `size` (1, 2 or 4) bytes.
fn unsigned(b: &[u8], size: usize) -> u32 {
    match size {
        1 => b[0] as u32,
        2 => u16::from_le_bytes([b[0], b[1]]) as u32,
        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}
