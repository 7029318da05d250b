//! Named data arrays attached to points or cells.

use glam::DVec2;

/// The values of a [`DataArray`], in one of the element types VTK knows.
#[derive(Clone, Debug, PartialEq)]
pub enum ArrayData {
    /// `Float64` values.
    F64(Vec<f64>),
    /// `Int32` values.
    I32(Vec<i32>),
    /// `Int64` values.
    I64(Vec<i64>),
    /// `UInt8` values (flags, material ids).
    U8(Vec<u8>),
}

impl ArrayData {
    /// Number of scalar values (tuples × components).
    pub fn len(&self) -> usize {
        match self {
            ArrayData::F64(v) => v.len(),
            ArrayData::I32(v) => v.len(),
            ArrayData::I64(v) => v.len(),
            ArrayData::U8(v) => v.len(),
        }
    }

    /// True if there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The VTK XML `type` attribute for this element type.
    pub fn vtk_type(&self) -> &'static str {
        match self {
            ArrayData::F64(_) => "Float64",
            ArrayData::I32(_) => "Int32",
            ArrayData::I64(_) => "Int64",
            ArrayData::U8(_) => "UInt8",
        }
    }

    /// Appends the values as little-endian bytes.
    pub(crate) fn extend_le_bytes(&self, out: &mut Vec<u8>) {
        match self {
            ArrayData::F64(v) => extend_f64(out, v),
            ArrayData::I32(v) => extend_le(out, v, |x| x.to_le_bytes()),
            ArrayData::I64(v) => extend_i64(out, v),
            ArrayData::U8(v) => out.extend_from_slice(v),
        }
    }

    /// Size in bytes once encoded.
    pub(crate) fn byte_len(&self) -> usize {
        match self {
            ArrayData::F64(v) => v.len() * 8,
            ArrayData::I32(v) => v.len() * 4,
            ArrayData::I64(v) => v.len() * 8,
            ArrayData::U8(v) => v.len(),
        }
    }
}

pub(crate) fn extend_f64(out: &mut Vec<u8>, v: &[f64]) {
    extend_le(out, v, |x| x.to_le_bytes());
}

pub(crate) fn extend_i64(out: &mut Vec<u8>, v: &[i64]) {
    extend_le(out, v, |x| x.to_le_bytes());
}

/// Grows `out` once and converts into the new tail in fixed-size chunks:
/// the compiler turns this into a straight copy on little-endian targets,
/// which per-element `extend_from_slice` (a capacity check per value) does
/// not become. This is the hot loop of writing million-point frames.
fn extend_le<T: Copy, const N: usize>(out: &mut Vec<u8>, v: &[T], f: impl Fn(T) -> [u8; N]) {
    let start = out.len();
    out.resize(start + v.len() * N, 0);
    for (dst, &x) in out[start..].chunks_exact_mut(N).zip(v) {
        dst.copy_from_slice(&f(x));
    }
}

/// A named field with `components` values per point (or per cell), stored
/// tuple by tuple (`x0 y0 z0 x1 y1 z1 ...` for a vector).
#[derive(Clone, Debug, PartialEq)]
pub struct DataArray {
    /// Name shown in ParaView.
    pub name: String,
    /// Values per tuple: 1 for scalars, 3 for vectors.
    pub components: usize,
    /// The values, `components` × number of tuples.
    pub data: ArrayData,
}

impl DataArray {
    /// A scalar `Float64` field.
    pub fn scalar_f64(name: &str, v: Vec<f64>) -> Self {
        Self::new(name, 1, ArrayData::F64(v))
    }

    /// A 2-D vector field, written with three components (z = 0) because
    /// ParaView only treats 3-component arrays as vectors (glyphs, arrows).
    pub fn vector2_f64(name: &str, v: &[DVec2]) -> Self {
        let mut flat = Vec::with_capacity(v.len() * 3);
        for p in v {
            flat.extend_from_slice(&[p.x, p.y, 0.0]);
        }
        Self::new(name, 3, ArrayData::F64(flat))
    }

    /// A 3-D vector field from `x0 y0 z0 x1 y1 z1 ...`; the length must be a
    /// multiple of three (checked when the file is written).
    pub fn vector3_f64(name: &str, v: Vec<f64>) -> Self {
        Self::new(name, 3, ArrayData::F64(v))
    }

    /// A scalar `Int32` field.
    pub fn scalar_i32(name: &str, v: Vec<i32>) -> Self {
        Self::new(name, 1, ArrayData::I32(v))
    }

    /// A scalar `Int64` field (ids that may exceed `i32`).
    pub fn scalar_i64(name: &str, v: Vec<i64>) -> Self {
        Self::new(name, 1, ArrayData::I64(v))
    }

    /// A scalar `UInt8` field (flags, small categories).
    pub fn scalar_u8(name: &str, v: Vec<u8>) -> Self {
        Self::new(name, 1, ArrayData::U8(v))
    }

    /// An array with an arbitrary number of components per tuple.
    pub fn new(name: &str, components: usize, data: ArrayData) -> Self {
        Self {
            name: name.to_string(),
            components,
            data,
        }
    }

    /// Number of tuples, or `None` if the value count is not a whole
    /// number of tuples.
    pub fn tuples(&self) -> Option<usize> {
        if self.components == 0 {
            return None;
        }
        let n = self.data.len();
        n.is_multiple_of(self.components)
            .then_some(n / self.components)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vector2_pads_z() {
        let a = DataArray::vector2_f64("v", &[DVec2::new(1.0, 2.0), DVec2::new(3.0, 4.0)]);
        assert_eq!(a.components, 3);
        assert_eq!(a.data, ArrayData::F64(vec![1.0, 2.0, 0.0, 3.0, 4.0, 0.0]));
        assert_eq!(a.tuples(), Some(2));
    }

    #[test]
    fn tuples_rejects_ragged_and_zero_components() {
        assert_eq!(DataArray::vector3_f64("v", vec![1.0; 4]).tuples(), None);
        assert_eq!(DataArray::new("z", 0, ArrayData::U8(vec![])).tuples(), None);
        assert_eq!(DataArray::scalar_i64("id", vec![1, 2]).tuples(), Some(2));
    }

    #[test]
    fn encodes_little_endian() {
        let mut out = Vec::new();
        ArrayData::I32(vec![1, -1]).extend_le_bytes(&mut out);
        assert_eq!(out, [1, 0, 0, 0, 0xff, 0xff, 0xff, 0xff]);
        out.clear();
        ArrayData::F64(vec![1.0]).extend_le_bytes(&mut out);
        assert_eq!(out, 1.0f64.to_le_bytes());
        assert_eq!(ArrayData::F64(vec![1.0]).byte_len(), 8);
        assert_eq!(ArrayData::U8(vec![7, 8]).vtk_type(), "UInt8");
    }
}
