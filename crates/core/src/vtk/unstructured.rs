//! `.vtu` unstructured grids (MPM background grids, FEM meshes).

use std::io;
use std::path::Path;

use super::appended::AppendedFile;
use super::{cell_type, check_arrays, check_index, data_bytes, invalid_input, DataArray};

/// An unstructured grid, written as `.vtu` (`VTKFile type="UnstructuredGrid"`).
///
/// Cells are stored VTK-style: `connectivity` lists the point indices of all
/// cells back to back, `offsets[c]` is the end (exclusive) of cell `c` in
/// `connectivity`, and `types[c]` is its [`cell_type`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UnstructuredGrid {
    /// Point coordinates.
    pub points: Vec<[f64; 3]>,
    /// Point indices of all cells, concatenated.
    pub connectivity: Vec<i64>,
    /// End of each cell in `connectivity`.
    pub offsets: Vec<i64>,
    /// VTK cell type of each cell (see [`cell_type`]).
    pub types: Vec<u8>,
    /// Fields with one tuple per point.
    pub point_data: Vec<DataArray>,
    /// Fields with one tuple per cell.
    pub cell_data: Vec<DataArray>,
}

impl UnstructuredGrid {
    /// Appends a cell; returns its index. Keeps `offsets` consistent so
    /// callers need not do the bookkeeping.
    pub fn push_cell(&mut self, kind: u8, points: &[i64]) -> usize {
        self.connectivity.extend_from_slice(points);
        self.offsets.push(self.connectivity.len() as i64);
        self.types.push(kind);
        self.types.len() - 1
    }

    /// Number of cells.
    pub fn n_cells(&self) -> usize {
        self.types.len()
    }

    /// Checks cell bookkeeping, indices and array lengths without writing.
    pub fn validate(&self) -> io::Result<()> {
        let n_points = self.points.len();
        if self.offsets.len() != self.types.len() {
            return Err(invalid_input(format!(
                "offsets has {} entries but types has {}",
                self.offsets.len(),
                self.types.len()
            )));
        }
        let mut start = 0i64;
        for (c, (&end, &kind)) in self.offsets.iter().zip(&self.types).enumerate() {
            if end < start || end as u64 > self.connectivity.len() as u64 {
                return Err(invalid_input(format!(
                    "offsets[{c}] = {end} is out of order or past the end of connectivity ({})",
                    self.connectivity.len()
                )));
            }
            let cell = &self.connectivity[start as usize..end as usize];
            if let Some(n) = fixed_size(kind) {
                if cell.len() != n {
                    return Err(invalid_input(format!(
                        "cell {c} of type {kind} has {} points, expected {n}",
                        cell.len()
                    )));
                }
            } else if cell.is_empty() {
                return Err(invalid_input(format!("cell {c} has no points")));
            }
            for &i in cell {
                check_index(i, n_points, "grid", c)?;
            }
            start = end;
        }
        if start as usize != self.connectivity.len() {
            return Err(invalid_input(format!(
                "connectivity has {} entries but the cells use {start}",
                self.connectivity.len()
            )));
        }
        check_arrays(&self.point_data, n_points, "point")?;
        check_arrays(&self.cell_data, self.n_cells(), "cell")
    }

    /// Validates, then writes the `.vtu` atomically.
    pub fn write(&self, path: &Path) -> io::Result<()> {
        self.validate()?;
        let data_bytes = data_bytes(&self.point_data, &self.cell_data);
        let capacity = self.points.len() * 24
            + (self.connectivity.len() + self.offsets.len()) * 8
            + self.types.len()
            + data_bytes
            + 64;
        let mut f = AppendedFile::new("UnstructuredGrid", capacity);
        f.line(1, "<UnstructuredGrid>");
        f.line(
            2,
            &format!(
                "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
                self.points.len(),
                self.n_cells()
            ),
        );
        f.attribute_section(3, "PointData", &self.point_data);
        f.attribute_section(3, "CellData", &self.cell_data);
        f.line(3, "<Points>");
        f.points(4, &self.points);
        f.line(3, "</Points>");
        f.line(3, "<Cells>");
        f.i64_array(4, "connectivity", &self.connectivity);
        f.i64_array(4, "offsets", &self.offsets);
        f.u8_array(4, "types", &self.types);
        f.line(3, "</Cells>");
        f.write(path, &["</Piece>", "</UnstructuredGrid>"])
    }
}

/// Point count of the fixed-size cell types, so a wrong count is caught here
/// rather than rendered as garbage.
fn fixed_size(kind: u8) -> Option<usize> {
    match kind {
        cell_type::VERTEX => Some(1),
        cell_type::LINE => Some(2),
        cell_type::TRIANGLE => Some(3),
        cell_type::QUAD => Some(4),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{find_array, read_appended_arrays};
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("grains-core-vtu-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// A unit square split into one quad and, beside it, two triangles.
    fn mesh() -> UnstructuredGrid {
        let mut g = UnstructuredGrid {
            points: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [2.0, 0.0, 0.0],
                [2.0, 1.0, 0.0],
            ],
            ..Default::default()
        };
        g.push_cell(cell_type::QUAD, &[0, 1, 2, 3]);
        g.push_cell(cell_type::TRIANGLE, &[1, 4, 5]);
        g.push_cell(cell_type::TRIANGLE, &[1, 5, 2]);
        g.point_data.push(DataArray::scalar_f64(
            "mass",
            vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
        ));
        g.cell_data
            .push(DataArray::scalar_i64("id", vec![10, 11, 1 << 40]));
        g
    }

    #[test]
    fn round_trips_cells_and_data() {
        let g = mesh();
        let path = scratch("rt.vtu");
        g.write(&path).unwrap();
        let a = read_appended_arrays(&path).unwrap();
        let conn = find_array(&a, "Cells", "connectivity").unwrap();
        assert_eq!(conn.values, vec![0., 1., 2., 3., 1., 4., 5., 1., 5., 2.]);
        assert_eq!(
            find_array(&a, "Cells", "offsets").unwrap().values,
            vec![4., 7., 10.]
        );
        assert_eq!(
            find_array(&a, "Cells", "types").unwrap().values,
            vec![9., 5., 5.]
        );
        assert_eq!(
            find_array(&a, "CellData", "id").unwrap().values,
            vec![10., 11., (1u64 << 40) as f64]
        );
        assert_eq!(
            find_array(&a, "PointData", "mass").unwrap().values,
            vec![1., 2., 3., 4., 5., 6.]
        );
        assert_eq!(find_array(&a, "Points", "Points").unwrap().values.len(), 18);
    }

    #[test]
    fn inconsistent_cells_are_rejected() {
        let path = scratch("bad.vtu");
        let mut g = mesh();
        g.types.pop();
        assert!(g.write(&path).is_err());

        let mut g = mesh();
        g.offsets[1] = 3;
        assert!(g.validate().is_err());

        let mut g = mesh();
        g.connectivity.push(0);
        assert!(g.validate().is_err());

        let mut g = mesh();
        g.types[1] = cell_type::QUAD;
        let e = g.validate().unwrap_err();
        assert!(e.to_string().contains("cell 1"), "{e}");

        let mut g = mesh();
        g.connectivity[0] = 6;
        assert!(g.validate().is_err());

        let mut g = mesh();
        g.cell_data[0] = DataArray::scalar_i64("id", vec![1]);
        let e = g.validate().unwrap_err();
        assert!(e.to_string().contains("\"id\""), "{e}");
        assert!(!path.exists());
    }

    #[test]
    fn empty_grid_writes() {
        let path = scratch("empty.vtu");
        UnstructuredGrid::default().write(&path).unwrap();
        assert_eq!(read_appended_arrays(&path).unwrap().len(), 4);
    }
}
