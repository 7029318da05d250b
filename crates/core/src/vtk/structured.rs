//! `.vts` structured grids: a logically rectangular block of points (for example a
//! polar grid of bins), with per-point and per-cell fields.

use std::io;
use std::path::Path;

use super::appended::AppendedFile;
use super::{check_arrays, data_bytes, invalid_input, DataArray};

/// A structured grid, written as `.vts` (`VTKFile type="StructuredGrid"`).
///
/// `dims` counts points along i, j, k; `points` lists them with i fastest, then j,
/// then k (VTK's order). Cells are the `max(n − 1, 1)` intervals along each direction,
/// also i fastest, so a 2D grid has `dims[2] = 1` and `(ni − 1)(nj − 1)` cells. A
/// curvilinear grid such as a ring of polar bins is just points placed on circles:
/// ParaView draws the cells as the quadrilaterals between them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StructuredGrid {
    /// Points along i, j and k.
    pub dims: [usize; 3],
    /// Point coordinates, i fastest.
    pub points: Vec<[f64; 3]>,
    /// Fields with one tuple per point.
    pub point_data: Vec<DataArray>,
    /// Fields with one tuple per cell, i fastest.
    pub cell_data: Vec<DataArray>,
}

impl StructuredGrid {
    /// Number of points, the product of `dims`.
    pub fn n_points(&self) -> usize {
        self.dims.iter().product()
    }

    /// Number of cells: intervals along each direction, a flat direction counting one.
    pub fn n_cells(&self) -> usize {
        if self.n_points() == 0 {
            return 0;
        }
        self.dims
            .iter()
            .map(|&n| n.saturating_sub(1).max(1))
            .product()
    }

    /// Checks the point count and array lengths without writing anything.
    pub fn validate(&self) -> io::Result<()> {
        let n = self.n_points();
        if self.points.len() != n {
            return Err(invalid_input(format!(
                "structured grid of {}x{}x{} points has {} points",
                self.dims[0],
                self.dims[1],
                self.dims[2],
                self.points.len()
            )));
        }
        check_arrays(&self.point_data, n, "point")?;
        check_arrays(&self.cell_data, self.n_cells(), "cell")
    }

    /// Validates, then writes the `.vts` atomically.
    pub fn write(&self, path: &Path) -> io::Result<()> {
        self.validate()?;
        let data_bytes = data_bytes(&self.point_data, &self.cell_data);
        let mut f = AppendedFile::new("StructuredGrid", self.points.len() * 24 + data_bytes + 64);
        let [ni, nj, nk] = self.dims.map(|n| n.saturating_sub(1));
        let extent = format!("0 {ni} 0 {nj} 0 {nk}");
        f.line(1, &format!("<StructuredGrid WholeExtent=\"{extent}\">"));
        f.line(2, &format!("<Piece Extent=\"{extent}\">"));
        f.attribute_section(3, "PointData", &self.point_data);
        f.attribute_section(3, "CellData", &self.cell_data);
        f.line(3, "<Points>");
        f.points(4, &self.points);
        f.line(3, "</Points>");
        f.write(path, &["</Piece>", "</StructuredGrid>"])
    }
}

#[cfg(test)]
mod tests {
    use super::super::{find_array, read_appended_arrays};
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("grains-core-vts-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// A 3 × 4 point polar patch: 2 × 3 cells.
    fn patch() -> StructuredGrid {
        let mut points = Vec::new();
        for j in 0..4 {
            let a = j as f64 * 0.3;
            for i in 0..3 {
                let r = 1.0 + i as f64;
                points.push([r * a.cos(), r * a.sin(), 0.0]);
            }
        }
        StructuredGrid {
            dims: [3, 4, 1],
            points,
            point_data: vec![DataArray::scalar_f64("r", (0..12).map(f64::from).collect())],
            cell_data: vec![DataArray::scalar_f64(
                "phi",
                vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6],
            )],
        }
    }

    #[test]
    fn round_trips_points_and_data() {
        let g = patch();
        assert_eq!(g.n_cells(), 6);
        let path = scratch("patch.vts");
        g.write(&path).unwrap();
        let arrays = read_appended_arrays(&path).unwrap();
        let pts = find_array(&arrays, "Points", "Points").unwrap();
        let flat: Vec<f64> = g.points.iter().flatten().copied().collect();
        assert_eq!(pts.values, flat);
        let phi = find_array(&arrays, "CellData", "phi").unwrap();
        assert_eq!(phi.values, vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6]);
        let r = find_array(&arrays, "PointData", "r").unwrap();
        assert_eq!(r.values.len(), 12);
        let head = String::from_utf8_lossy(&std::fs::read(&path).unwrap()[..300]).to_string();
        assert!(head.contains("WholeExtent=\"0 2 0 3 0 0\""), "{head}");
        assert!(head.contains("type=\"StructuredGrid\""), "{head}");
    }

    #[test]
    fn wrong_counts_are_rejected_before_writing() {
        let path = scratch("bad.vts");
        let mut g = patch();
        g.points.pop();
        assert!(g
            .write(&path)
            .unwrap_err()
            .to_string()
            .contains("11 points"));
        let mut g = patch();
        g.cell_data[0] = DataArray::scalar_f64("phi", vec![0.0; 5]);
        let e = g.write(&path).unwrap_err();
        assert!(e.to_string().contains("\"phi\""), "{e}");
        assert!(!path.exists());
        assert_eq!(StructuredGrid::default().n_cells(), 0);
    }
}
