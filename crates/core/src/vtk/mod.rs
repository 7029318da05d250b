//! Our own VTK XML writer (`.vtp` poly data and its `.pvtp` index over pieces, `.vtu`
//! unstructured grids, `.vts` structured grids) with
//! raw appended binary data, and a reader for the same files.
//!
//! Files are `version="1.0"`, `header_type="UInt64"`, little endian: each
//! array is one block `u64 byte count` + values in the appended section,
//! located by the `offset` attribute of its `DataArray` tag. Every write is
//! atomic (see [`crate::atomic`]) and validated first: an array whose length
//! does not match the point or cell count is an
//! [`std::io::ErrorKind::InvalidInput`] error naming the array, instead of a
//! file ParaView would reject or, worse, misread.

mod appended;
mod data;
mod parallel;
mod polydata;
mod reader;
mod structured;
mod unstructured;

pub use data::{ArrayData, DataArray};
pub use parallel::{check_pvtp, read_points_joined, read_pvtp, Declared, ParallelIndex};
pub use polydata::PolyData;
pub use reader::{find_array, read_appended_arrays, ReadArray};
pub use structured::StructuredGrid;
pub use unstructured::UnstructuredGrid;

use std::io;

/// VTK cell type codes (the `types` array of a `.vtu`), as defined by VTK's
/// `vtkCellType.h`.
pub mod cell_type {
    /// A single point.
    pub const VERTEX: u8 = 1;
    /// A two-point segment.
    pub const LINE: u8 = 3;
    /// An open chain of points.
    pub const POLY_LINE: u8 = 4;
    /// A linear triangle.
    pub const TRIANGLE: u8 = 5;
    /// A bilinear quadrilateral.
    pub const QUAD: u8 = 9;
}

fn invalid_input(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// Checks that every array holds exactly `count` tuples; `kind` ("point",
/// "cell") makes the message say which section is wrong.
fn check_arrays(arrays: &[crate::vtk::DataArray], count: usize, kind: &str) -> io::Result<()> {
    for a in arrays {
        if a.components == 0 {
            return Err(invalid_input(format!(
                "{kind} data array {:?} has 0 components",
                a.name
            )));
        }
        let expected = a.components.checked_mul(count);
        if expected != Some(a.data.len()) {
            return Err(invalid_input(format!(
                "{kind} data array {:?} has {} values, expected {} components x {count} {kind}s",
                a.name,
                a.data.len(),
                a.components
            )));
        }
    }
    Ok(())
}

/// Bytes the point and cell arrays take in the appended block (each with its 8-byte
/// count), to size the block once.
fn data_bytes(point_data: &[DataArray], cell_data: &[DataArray]) -> usize {
    point_data
        .iter()
        .chain(cell_data)
        .map(|a| a.data.byte_len() + 8)
        .sum()
}

/// Checks that a point index refers to an existing point.
fn check_index(index: i64, n_points: usize, what: &str, cell: usize) -> io::Result<()> {
    if index < 0 || index as u64 >= n_points as u64 {
        return Err(invalid_input(format!(
            "{what} cell {cell} refers to point {index}, but there are {n_points} points"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn array_length_errors_name_the_array() {
        let a = [DataArray::vector3_f64("velocity", vec![0.0; 5])];
        let e = check_arrays(&a, 2, "point").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert!(e.to_string().contains("\"velocity\""), "{e}");
        assert!(check_arrays(&a, 0, "cell").is_err());
        let ok = [DataArray::scalar_f64("m", vec![1.0, 2.0])];
        assert!(check_arrays(&ok, 2, "point").is_ok());
        let zero = [DataArray::new("z", 0, ArrayData::U8(vec![]))];
        assert!(check_arrays(&zero, 0, "point").is_err());
    }

    #[test]
    fn index_bounds() {
        assert!(check_index(0, 1, "verts", 0).is_ok());
        assert!(check_index(1, 1, "verts", 0).is_err());
        assert!(check_index(-1, 5, "lines", 2).is_err());
    }
}
