//! `.vtp` poly data: points with vertex and/or line cells.

use std::io;
use std::path::Path;

use glam::DVec2;

use super::appended::AppendedFile;
use super::{check_arrays, check_index, data_bytes, invalid_input, DataArray};

/// Points plus vertex and/or line cells, written as `.vtp`
/// (`VTKFile type="PolyData"`).
///
/// Used for particles (one vertex per particle) and walls (polylines).
/// Following VTK, `cell_data` tuples cover the vertex cells first and then
/// the line cells, so each cell array has `verts.len() + lines.len()` tuples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyData {
    /// Point coordinates.
    pub points: Vec<[f64; 3]>,
    /// Vertex cells, each a list of point indices (usually one).
    pub verts: Vec<Vec<i64>>,
    /// Line cells, each a polyline through the listed point indices.
    pub lines: Vec<Vec<i64>>,
    /// Fields with one tuple per point.
    pub point_data: Vec<DataArray>,
    /// Fields with one tuple per cell, verts first then lines.
    pub cell_data: Vec<DataArray>,
}

impl PolyData {
    /// Planar points (z = 0), each its own vertex cell so ParaView renders
    /// them without a glyph filter.
    pub fn from_points_2d(p: &[DVec2]) -> Self {
        Self {
            points: p.iter().map(|q| [q.x, q.y, 0.0]).collect(),
            verts: (0..p.len() as i64).map(|i| vec![i]).collect(),
            ..Self::default()
        }
    }

    /// Number of cells (verts + lines), the tuple count of cell data.
    pub fn n_cells(&self) -> usize {
        self.verts.len() + self.lines.len()
    }

    /// Checks array lengths and cell indices without writing anything.
    pub fn validate(&self) -> io::Result<()> {
        let n = self.points.len();
        check_cells(&self.verts, n, "verts")?;
        check_cells(&self.lines, n, "lines")?;
        check_arrays(&self.point_data, n, "point")?;
        check_arrays(&self.cell_data, self.n_cells(), "cell")
    }

    /// Validates, then writes the `.vtp` atomically.
    pub fn write(&self, path: &Path) -> io::Result<()> {
        self.validate()?;
        let verts = flatten(&self.verts);
        let lines = flatten(&self.lines);
        let data_bytes = data_bytes(&self.point_data, &self.cell_data);
        let capacity = self.points.len() * 24
            + (verts.0.len() + verts.1.len() + lines.0.len() + lines.1.len()) * 8
            + data_bytes
            + 64;
        let mut f = AppendedFile::new("PolyData", capacity);
        f.line(1, "<PolyData>");
        f.line(
            2,
            &format!(
                "<Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"{}\" \
                 NumberOfStrips=\"0\" NumberOfPolys=\"0\">",
                self.points.len(),
                self.verts.len(),
                self.lines.len()
            ),
        );
        f.attribute_section(3, "PointData", &self.point_data);
        f.attribute_section(3, "CellData", &self.cell_data);
        f.line(3, "<Points>");
        f.points(4, &self.points);
        f.line(3, "</Points>");
        // Empty sections are omitted: readers treat a missing section as no
        // cells of that kind.
        for (tag, (conn, offs)) in [("Verts", &verts), ("Lines", &lines)] {
            if offs.is_empty() {
                continue;
            }
            f.line(3, &format!("<{tag}>"));
            f.i64_array(4, "connectivity", conn);
            f.i64_array(4, "offsets", offs);
            f.line(3, &format!("</{tag}>"));
        }
        f.write(path, &["</Piece>", "</PolyData>"])
    }
}

/// Rejects empty cells and out-of-range point indices.
fn check_cells(cells: &[Vec<i64>], n_points: usize, what: &str) -> io::Result<()> {
    for (c, cell) in cells.iter().enumerate() {
        if cell.is_empty() {
            return Err(invalid_input(format!("{what} cell {c} has no points")));
        }
        for &i in cell {
            check_index(i, n_points, what, c)?;
        }
    }
    Ok(())
}

/// VTK XML connectivity + offsets, where each offset is the end (exclusive)
/// of its cell in the connectivity array.
fn flatten(cells: &[Vec<i64>]) -> (Vec<i64>, Vec<i64>) {
    let total: usize = cells.iter().map(Vec::len).sum();
    let mut conn = Vec::with_capacity(total);
    let mut offs = Vec::with_capacity(cells.len());
    for c in cells {
        conn.extend_from_slice(c);
        offs.push(conn.len() as i64);
    }
    (conn, offs)
}

#[cfg(test)]
mod tests {
    use super::super::{find_array, read_appended_arrays};
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("grains-core-vtp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    fn walls_and_particles() -> PolyData {
        let centres = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.5, -2.25),
            DVec2::new(1e-9, 3e8),
        ];
        let mut pd = PolyData::from_points_2d(&centres);
        pd.points.push([-1.0, 0.0, 0.0]);
        pd.points.push([1.0, 0.0, 0.0]);
        pd.lines.push(vec![3, 4]);
        pd.point_data.push(DataArray::scalar_f64(
            "radius",
            vec![0.5, 0.25, 1.0, 0.0, 0.0],
        ));
        pd.point_data.push(DataArray::vector2_f64(
            "velocity",
            &[DVec2::new(1.0, 2.0); 5],
        ));
        pd.cell_data
            .push(DataArray::scalar_i32("kind", vec![0, 0, 0, 1]));
        pd
    }

    #[test]
    fn round_trips_points_cells_and_data() {
        let pd = walls_and_particles();
        let path = scratch("rt.vtp");
        pd.write(&path).unwrap();
        let arrays = read_appended_arrays(&path).unwrap();

        let pts = find_array(&arrays, "Points", "Points").unwrap();
        assert_eq!(pts.components, 3);
        let flat: Vec<f64> = pd.points.iter().flatten().copied().collect();
        assert_eq!(pts.values, flat);

        let r = find_array(&arrays, "PointData", "radius").unwrap();
        assert_eq!(r.values, vec![0.5, 0.25, 1.0, 0.0, 0.0]);
        let v = find_array(&arrays, "PointData", "velocity").unwrap();
        assert_eq!(v.components, 3);
        assert_eq!(&v.values[..3], &[1.0, 2.0, 0.0]);
        let k = find_array(&arrays, "CellData", "kind").unwrap();
        assert_eq!(k.values, vec![0.0, 0.0, 0.0, 1.0]);

        let vc = find_array(&arrays, "Verts", "connectivity").unwrap();
        assert_eq!(vc.values, vec![0.0, 1.0, 2.0]);
        let vo = find_array(&arrays, "Verts", "offsets").unwrap();
        assert_eq!(vo.values, vec![1.0, 2.0, 3.0]);
        let lc = find_array(&arrays, "Lines", "connectivity").unwrap();
        assert_eq!(lc.values, vec![3.0, 4.0]);
        let lo = find_array(&arrays, "Lines", "offsets").unwrap();
        assert_eq!(lo.values, vec![2.0]);

        let text = std::fs::read(&path).unwrap();
        let head = String::from_utf8_lossy(&text[..400]);
        assert!(
            head.contains("NumberOfVerts=\"3\" NumberOfLines=\"1\""),
            "{head}"
        );
    }

    #[test]
    fn empty_polydata_is_valid() {
        let path = scratch("empty.vtp");
        PolyData::default().write(&path).unwrap();
        let arrays = read_appended_arrays(&path).unwrap();
        assert_eq!(arrays.len(), 1);
        assert!(arrays[0].values.is_empty());
    }

    #[test]
    fn bad_lengths_and_indices_are_rejected_before_writing() {
        let path = scratch("bad.vtp");
        let mut pd = walls_and_particles();
        pd.cell_data[0].data = super::super::ArrayData::I32(vec![0; 3]);
        let e = pd.write(&path).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert!(e.to_string().contains("\"kind\""), "{e}");
        assert!(!path.exists());

        let mut pd = walls_and_particles();
        pd.lines.push(vec![4, 5]);
        pd.cell_data.clear();
        let e = pd.write(&path).unwrap_err();
        assert!(e.to_string().contains("lines cell 1"), "{e}");

        let mut pd = walls_and_particles();
        pd.verts.push(vec![]);
        pd.cell_data.clear();
        assert!(pd.write(&path).is_err());
    }

    #[test]
    fn names_are_escaped() {
        let mut pd = PolyData::from_points_2d(&[DVec2::ZERO]);
        pd.point_data
            .push(DataArray::scalar_f64("a<b & \"c\"", vec![7.0]));
        let path = scratch("esc.vtp");
        pd.write(&path).unwrap();
        let arrays = read_appended_arrays(&path).unwrap();
        assert_eq!(
            find_array(&arrays, "PointData", "a<b & \"c\"")
                .unwrap()
                .values,
            vec![7.0]
        );
    }
}
