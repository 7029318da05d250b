//! Writes a sample `.vtp`, `.vtu` and `.pvd` into the directory given as the
//! first argument, for checking them with external VTK readers.

use std::path::PathBuf;

use grains_core::pvd::PvdSeries;
use grains_core::vtk::{cell_type, DataArray, PolyData, UnstructuredGrid};
use grains_core::DVec2;

fn main() -> std::io::Result<()> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    std::fs::create_dir_all(&dir)?;

    let centres: Vec<DVec2> = (0..5)
        .map(|i| DVec2::new(i as f64, 0.5 * i as f64))
        .collect();
    let mut pd = PolyData::from_points_2d(&centres);
    pd.points
        .extend([[-1.0, -1.0, 0.0], [6.0, -1.0, 0.0], [6.0, 4.0, 0.0]]);
    pd.lines.push(vec![5, 6, 7]);
    pd.point_data.push(DataArray::scalar_f64(
        "radius",
        vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.0, 0.0, 0.0],
    ));
    let mut vel = centres.clone();
    vel.extend([DVec2::ZERO; 3]);
    pd.point_data.push(DataArray::vector2_f64("velocity", &vel));
    pd.cell_data
        .push(DataArray::scalar_i32("kind", vec![0, 0, 0, 0, 0, 1]));
    pd.write(&dir.join("sample.vtp"))?;

    let mut g = UnstructuredGrid {
        points: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
        ],
        ..Default::default()
    };
    g.push_cell(cell_type::QUAD, &[0, 1, 2, 3]);
    g.push_cell(cell_type::TRIANGLE, &[1, 4, 2]);
    g.point_data
        .push(DataArray::scalar_f64("mass", vec![1.0, 2.0, 3.0, 4.0, 5.0]));
    g.point_data.push(DataArray::vector3_f64(
        "v",
        (0..15).map(f64::from).collect(),
    ));
    g.cell_data
        .push(DataArray::scalar_i64("id", vec![7, 1 << 40]));
    g.cell_data.push(DataArray::scalar_u8("flag", vec![1, 0]));
    g.write(&dir.join("sample.vtu"))?;

    let mut s = PvdSeries::new(&dir.join("sample.pvd"));
    s.push_group(1e-7, &[("particles", "sample.vtp"), ("grid", "sample.vtu")])?;
    Ok(())
}
