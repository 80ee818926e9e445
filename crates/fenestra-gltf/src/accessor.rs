//! Accessors read into plain arrays: float or (KHR_mesh_quantization) integer components,
//! normalised or not, interleaved views, sparse substitutions, every offset checked against
//! the buffer it reads.

use crate::error::GltfError;
use crate::source::Source;
use gltf::accessor::{DataType, Dimensions};

/// The most elements an accessor without a buffer view may have (2^28: a billion-triangle
/// mesh's worth).
const MAX_ZERO_ELEMENTS: usize = 1 << 28;

/// The JSON pointer of accessor `a`.
fn at(a: &gltf::Accessor) -> String {
    format!("/accessors/{}", a.index())
}

/// Reads accessor `a` as `N` floats per element (normalised integers mapped as the
/// specification says, other integers converted).
pub fn floats<const N: usize>(
    src: &Source,
    a: &gltf::Accessor,
) -> Result<Vec<[f32; N]>, GltfError> {
    if a.dimensions().multiplicity() != N {
        return Err(GltfError::at(
            &src.path,
            at(a),
            format!("has type {:?}, expected {N} components", a.dimensions()),
        ));
    }
    let decode = component(a.data_type(), a.normalized());
    let size = a.data_type().size();
    read(src, a, [0.0; N], |bytes| {
        std::array::from_fn(|k| decode(&bytes[k * size..]))
    })
}

/// Reads an index accessor (unsigned byte, short or int scalars).
pub fn indices(src: &Source, a: &gltf::Accessor) -> Result<Vec<u32>, GltfError> {
    if a.dimensions() != Dimensions::Scalar {
        return Err(GltfError::at(&src.path, at(a), "indices must be scalars"));
    }
    let ty = a.data_type();
    if !matches!(ty, DataType::U8 | DataType::U16 | DataType::U32) {
        return Err(GltfError::at(
            &src.path,
            at(a),
            format!("indices of type {ty:?} (unsigned integers expected)"),
        ));
    }
    read(src, a, 0, |bytes| unsigned(ty, bytes))
}

/// An unsigned integer component of type `ty` at the start of `b`.
fn unsigned(ty: DataType, b: &[u8]) -> u32 {
    match ty {
        DataType::U8 => b[0] as u32,
        DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as u32,
        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}

/// How one component of type `ty` becomes a float.
fn component(ty: DataType, normalized: bool) -> fn(&[u8]) -> f32 {
    match (ty, normalized) {
        (DataType::F32, _) => |b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        (DataType::I8, true) => |b| (b[0] as i8 as f32 / 127.0).max(-1.0),
        (DataType::U8, true) => |b| b[0] as f32 / 255.0,
        (DataType::I16, true) => |b| (i16::from_le_bytes([b[0], b[1]]) as f32 / 32767.0).max(-1.0),
        (DataType::U16, true) => |b| u16::from_le_bytes([b[0], b[1]]) as f32 / 65535.0,
        (DataType::I8, false) => |b| b[0] as i8 as f32,
        (DataType::U8, false) => |b| b[0] as f32,
        (DataType::I16, false) => |b| i16::from_le_bytes([b[0], b[1]]) as f32,
        (DataType::U16, false) => |b| u16::from_le_bytes([b[0], b[1]]) as f32,
        (DataType::U32, _) => |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
    }
}

/// The bytes of buffer view `view`, checked against its buffer.
fn view_bytes<'s>(src: &'s Source, view: &gltf::buffer::View) -> Result<&'s [u8], GltfError> {
    let buffer = &src.buffers[view.buffer().index()];
    let (start, len) = (view.offset(), view.length());
    buffer.get(start..start.saturating_add(len)).ok_or_else(|| {
        GltfError::at(
            &src.path,
            format!("/bufferViews/{}", view.index()),
            format!(
                "bytes {start}..{} lie beyond its buffer's {} bytes",
                start.saturating_add(len),
                buffer.len()
            ),
        )
    })
}

/// `count` elements of `size` bytes, `stride` apart from `offset` in `bytes`, checked.
fn elements(
    bytes: &[u8],
    (offset, stride, size, count): (usize, usize, usize, usize),
) -> Option<impl Iterator<Item = &[u8]>> {
    let end = match count {
        0 => offset,
        n => offset
            .checked_add(stride.checked_mul(n - 1)?)?
            .checked_add(size)?,
    };
    (end <= bytes.len()).then(|| (0..count).map(move |i| &bytes[offset + i * stride..][..size]))
}

/// Reads every element of `a` with `decode` (`zero` where it has no buffer view), sparse
/// substitutions applied.
fn read<T: Copy>(
    src: &Source,
    a: &gltf::Accessor,
    zero: T,
    decode: impl Fn(&[u8]) -> T,
) -> Result<Vec<T>, GltfError> {
    let size = a.size();
    let out_of_range = || {
        GltfError::at(
            &src.path,
            at(a),
            format!(
                "{} elements of {size} bytes from offset {} do not fit in their buffer view",
                a.count(),
                a.offset()
            ),
        )
    };
    let mut out = match a.view() {
        // No view: zeros, which sparse values may replace (a count beyond any real mesh is
        // refused before it is allocated).
        None if a.count() > MAX_ZERO_ELEMENTS => {
            return Err(GltfError::at(
                &src.path,
                at(a),
                format!("{} elements without a buffer view", a.count()),
            ));
        }
        None => vec![zero; a.count()],
        Some(view) => {
            let bytes = view_bytes(src, &view)?;
            let stride = view.stride().unwrap_or(size);
            if stride < size {
                // Elements would overlap: each read partly from the next (wrong geometry).
                return Err(GltfError::at(
                    &src.path,
                    format!("/bufferViews/{}", view.index()),
                    format!(
                        "byteStride {stride} is smaller than its accessor's {size}-byte elements"
                    ),
                ));
            }
            elements(bytes, (a.offset(), stride, size, a.count()))
                .ok_or_else(out_of_range)?
                .map(&decode)
                .collect()
        }
    };
    if let Some(sparse) = a.sparse() {
        let idx = sparse.indices();
        let ity = match idx.index_type() {
            gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let n = sparse.count();
        let idx_bytes = view_bytes(src, &idx.view())?;
        let val_bytes = view_bytes(src, &sparse.values().view())?;
        let indices = elements(idx_bytes, (idx.offset(), ity.size(), ity.size(), n));
        let values = elements(val_bytes, (sparse.values().offset(), size, size, n));
        let (Some(indices), Some(values)) = (indices, values) else {
            return Err(GltfError::at(
                &src.path,
                format!("{}/sparse", at(a)),
                "does not fit in its buffer views",
            ));
        };
        for (i, v) in indices.zip(values) {
            let i = unsigned(ity, i) as usize;
            *out.get_mut(i).ok_or_else(|| {
                GltfError::at(
                    &src.path,
                    format!("{}/sparse", at(a)),
                    format!("index {i} out of range"),
                )
            })? = decode(v);
        }
    }
    Ok(out)
}
