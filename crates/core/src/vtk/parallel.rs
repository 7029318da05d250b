//! `.pvtp`: the index of poly data written in pieces (one `.vtp` per rank of a run
//! spread over ranks), which ParaView opens as one data set. The index holds no
//! values, only the arrays every piece has (name, type, components) and the pieces'
//! file names relative to it, so writing it needs nothing from the other ranks.

use std::io;
use std::path::Path;

use super::reader::{each_open, ReadArray};
use super::{invalid_input, read_appended_arrays, DataArray, PolyData};
use crate::atomic::write_atomic;
use crate::xml::{attr, escape_attr, invalid};

/// One array an index declares: the section (`PPointData`, `PCellData`, `PPoints`),
/// name, VTK type and components every piece's array of that name must have.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Declared {
    /// `PPointData`, `PCellData` or `PPoints`.
    pub section: String,
    /// The `Name` attribute.
    pub name: String,
    /// The VTK element type (`Float64`, `Int64`, ...).
    pub vtk_type: String,
    /// Values per tuple.
    pub components: usize,
}

/// A `.pvtp` read back: what it declares and its pieces, in order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParallelIndex {
    /// The declared arrays, in document order.
    pub arrays: Vec<Declared>,
    /// The pieces' `Source` attributes (paths relative to the index).
    pub pieces: Vec<String>,
}

impl PolyData {
    /// Writes `path`, a `PPolyData` index over `pieces` (file names relative to
    /// `path`'s directory), declaring this poly data's point and cell arrays: a piece
    /// written by any rank has them, whatever its particle count (none included).
    pub fn write_pvtp(&self, path: &Path, pieces: &[String]) -> io::Result<()> {
        if let Some(bad) = pieces.iter().find(|p| p.is_empty()) {
            return Err(invalid_input(format!("piece name {bad:?} is empty")));
        }
        let mut x = String::with_capacity(512 + 80 * pieces.len());
        x.push_str("<?xml version=\"1.0\"?>\n");
        x.push_str(
            "<VTKFile type=\"PPolyData\" version=\"1.0\" byte_order=\"LittleEndian\" \
             header_type=\"UInt64\">\n",
        );
        x.push_str("  <PPolyData GhostLevel=\"0\">\n");
        let declare = |x: &mut String, tag: &str, arrays: &[DataArray]| {
            if arrays.is_empty() {
                return;
            }
            x.push_str(&format!("    <{tag}>\n"));
            for a in arrays {
                declare_one(x, a.data.vtk_type(), &a.name, a.components);
            }
            x.push_str(&format!("    </{tag}>\n"));
        };
        declare(&mut x, "PPointData", &self.point_data);
        declare(&mut x, "PCellData", &self.cell_data);
        x.push_str("    <PPoints>\n");
        declare_one(&mut x, "Float64", "Points", 3);
        x.push_str("    </PPoints>\n");
        for p in pieces {
            x.push_str(&format!("    <Piece Source=\"{}\"/>\n", escape_attr(p)));
        }
        x.push_str("  </PPolyData>\n</VTKFile>\n");
        write_atomic(path, x.as_bytes())
    }
}

fn declare_one(x: &mut String, vtk_type: &str, name: &str, components: usize) {
    x.push_str(&format!(
        "      <PDataArray type=\"{vtk_type}\" Name=\"{}\" NumberOfComponents=\"{components}\"/>\n",
        escape_attr(name)
    ));
}

/// Reads a `.pvtp`'s declarations and pieces.
pub fn read_pvtp(path: &Path) -> io::Result<ParallelIndex> {
    let text = std::fs::read_to_string(path)?;
    let mut index = ParallelIndex {
        arrays: Vec::new(),
        pieces: Vec::new(),
    };
    let mut kind = None;
    let open = each_open(&text, |name, attrs, section| {
        match name {
            "VTKFile" => kind = attr(attrs, "type").map(str::to_string),
            "PDataArray" => {
                let name = attr(attrs, "Name").unwrap_or_default().to_string();
                let components = attr(attrs, "NumberOfComponents")
                    .unwrap_or("1")
                    .parse()
                    .map_err(|_| invalid(format!("PDataArray {name:?}: bad components")))?;
                index.arrays.push(Declared {
                    section: section.to_string(),
                    vtk_type: attr(attrs, "type").unwrap_or_default().to_string(),
                    name,
                    components,
                });
            }
            "Piece" => index.pieces.push(
                attr(attrs, "Source")
                    .ok_or_else(|| invalid("Piece without Source".into()))?
                    .to_string(),
            ),
            _ => {}
        }
        Ok(())
    })?;
    if kind.as_deref() != Some("PPolyData") || open > 0 {
        return Err(invalid(format!(
            "{}: not a complete PPolyData file",
            path.display()
        )));
    }
    Ok(index)
}

/// Reads a `.pvtp` and checks it as ParaView would need it: every piece exists and has
/// exactly the declared point and cell arrays (name, type, components) and `Float64`
/// points with three components. Returns the index and each piece's arrays, in order.
pub fn check_pvtp(path: &Path) -> io::Result<(ParallelIndex, Vec<Vec<ReadArray>>)> {
    let index = read_pvtp(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut pieces = Vec::with_capacity(index.pieces.len());
    for source in &index.pieces {
        let arrays = read_appended_arrays(&dir.join(source))
            .map_err(|e| invalid(format!("piece {source}: {e}")))?;
        let held = |section: &str| -> Vec<(String, String, usize)> {
            arrays
                .iter()
                .filter(|a| a.section == section)
                .map(|a| (a.name.clone(), a.vtk_type.clone(), a.components))
                .collect()
        };
        let declared = |section: &str| -> Vec<(String, String, usize)> {
            index
                .arrays
                .iter()
                .filter(|a| a.section == section)
                .map(|a| (a.name.clone(), a.vtk_type.clone(), a.components))
                .collect()
        };
        for (piece, index) in [
            ("PointData", "PPointData"),
            ("CellData", "PCellData"),
            ("Points", "PPoints"),
        ] {
            if held(piece) != declared(index) {
                return Err(invalid(format!(
                    "piece {source}: its {piece} arrays {:?} are not the declared {:?}",
                    held(piece),
                    declared(index)
                )));
            }
        }
        pieces.push(arrays);
    }
    Ok((index, pieces))
}

/// The points and point arrays of a frame file: a `.vtp`'s (every array, as
/// [`read_appended_arrays`] reads them), or a checked `.pvtp`'s pieces joined in piece
/// order (points and point data only: each piece's cells index its own points).
pub fn read_points_joined(path: &Path) -> io::Result<Vec<ReadArray>> {
    if path.extension().and_then(|e| e.to_str()) != Some("pvtp") {
        return read_appended_arrays(path);
    }
    let (_, pieces) = check_pvtp(path)?;
    let mut joined: Vec<ReadArray> = Vec::new();
    for a in pieces.into_iter().flatten() {
        if a.section != "Points" && a.section != "PointData" {
            continue;
        }
        match joined
            .iter_mut()
            .find(|j| j.section == a.section && j.name == a.name)
        {
            Some(j) => j.values.extend(a.values),
            None => joined.push(a),
        }
    }
    Ok(joined)
}

#[cfg(test)]
mod tests {
    use super::super::find_array;
    use super::*;
    use glam::DVec2;
    use std::path::PathBuf;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir()
            .join(format!("grains-core-pvtp-{}", std::process::id()))
            .join(name);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn piece(ids: &[i64]) -> PolyData {
        let pos: Vec<DVec2> = ids.iter().map(|&i| DVec2::new(i as f64, 0.5)).collect();
        let mut p = PolyData::from_points_2d(&pos);
        p.point_data = vec![
            DataArray::scalar_i64("id", ids.to_vec()),
            DataArray::vector2_f64("velocity", &pos),
        ];
        p
    }

    #[test]
    fn an_index_over_pieces_reads_back_and_checks() {
        let dir = scratch("read");
        let pieces = [piece(&[3, 1]), piece(&[]), piece(&[2])];
        let mut names = Vec::new();
        for (r, p) in pieces.iter().enumerate() {
            let name = format!("f_r{r:03}.vtp");
            p.write(&dir.join(&name)).unwrap();
            names.push(name);
        }
        let path = dir.join("f.pvtp");
        pieces[1].write_pvtp(&path, &names).unwrap();
        let (index, arrays) = check_pvtp(&path).unwrap();
        assert_eq!(index.pieces, names);
        let declared: Vec<_> = index
            .arrays
            .iter()
            .map(|d| (d.section.as_str(), d.name.as_str(), d.vtk_type.as_str()))
            .collect();
        assert_eq!(
            declared,
            [
                ("PPointData", "id", "Int64"),
                ("PPointData", "velocity", "Float64"),
                ("PPoints", "Points", "Float64")
            ]
        );
        assert_eq!(index.arrays[1].components, 3);
        assert_eq!(arrays.len(), 3);
        let joined = read_points_joined(&path).unwrap();
        let ids = &find_array(&joined, "PointData", "id").unwrap().values;
        assert_eq!(
            find_array(&joined, "Points", "Points")
                .unwrap()
                .values
                .len(),
            9
        );
        assert!(find_array(&joined, "Verts", "offsets").is_none());
        assert_eq!(ids, &[3.0, 1.0, 2.0]);
    }

    #[test]
    fn a_missing_or_unlike_piece_is_found() {
        let dir = scratch("unlike");
        let path = dir.join("f.pvtp");
        let a = piece(&[1]);
        a.write(&dir.join("a.vtp")).unwrap();
        a.write_pvtp(&path, &["a.vtp".into(), "gone.vtp".into()])
            .unwrap();
        let e = check_pvtp(&path).unwrap_err();
        assert!(e.to_string().contains("gone.vtp"), "{e}");

        let mut b = piece(&[2]);
        b.point_data[0] = DataArray::scalar_i32("id", vec![2]);
        b.write(&dir.join("b.vtp")).unwrap();
        a.write_pvtp(&path, &["a.vtp".into(), "b.vtp".into()])
            .unwrap();
        let e = check_pvtp(&path).unwrap_err();
        assert!(
            e.to_string().contains("b.vtp") && e.to_string().contains("Int32"),
            "{e}"
        );

        assert!(a.write_pvtp(&path, &[String::new()]).is_err());
        std::fs::write(&path, "<VTKFile type=\"PPolyData\"><PPolyData>").unwrap();
        assert!(read_pvtp(&path).is_err());
    }
}
