//! Reads back the arrays of a raw-appended VTK XML file written by this
//! module, for round-trip tests and for tools that post-process frames.
//!
//! It understands exactly the layout the writer produces (UInt64 headers,
//! little endian, raw appended data); anything else is an
//! [`io::ErrorKind::InvalidData`] error, never a panic.

use std::fs;
use std::io;
use std::path::Path;

use crate::xml::{attr, invalid, tags, Tag};

/// One array read from a file, widened to `f64` (exact for all values the
/// writer's integer types hold up to 2^53).
#[derive(Clone, Debug, PartialEq)]
pub struct ReadArray {
    /// Element enclosing the array: `Points`, `PointData`, `CellData`,
    /// `Verts`, `Lines` or `Cells`.
    pub section: String,
    /// The `Name` attribute.
    pub name: String,
    /// The VTK element type (`Float64`, `Int64`, ...).
    pub vtk_type: String,
    /// Values per tuple.
    pub components: usize,
    /// All values, tuple by tuple.
    pub values: Vec<f64>,
}

/// The first array with the given section and name.
pub fn find_array<'a>(arrays: &'a [ReadArray], section: &str, name: &str) -> Option<&'a ReadArray> {
    arrays
        .iter()
        .find(|a| a.section == section && a.name == name)
}

/// Reads every `DataArray` of a `.vtp`/`.vtu` file, in document order.
pub fn read_appended_arrays(path: &Path) -> io::Result<Vec<ReadArray>> {
    let bytes = fs::read(path)?;
    let (header, data) = split_appended(&bytes)?;
    let header =
        std::str::from_utf8(header).map_err(|_| invalid("VTK XML header is not UTF-8".into()))?;

    let mut out = Vec::new();
    each_open(header, |name, attrs, section| {
        if name == "VTKFile" {
            check_file_attrs(attrs)?;
        } else if name == "AppendedData" && attr(attrs, "encoding") != Some("raw") {
            return Err(invalid("only raw appended data is supported".into()));
        }
        if name == "DataArray" {
            out.push(read_array(section.to_string(), attrs, data)?);
        }
        Ok(())
    })?;
    Ok(out)
}

/// Calls `f` on each opening tag of `text` with its name, attributes and the name of
/// the element enclosing it (empty at the top); closing tags must match. Returns how
/// many elements are still open at the end (a header cut at its appended data has
/// some).
pub(crate) fn each_open(
    text: &str,
    mut f: impl FnMut(&str, &[(String, String)], &str) -> io::Result<()>,
) -> io::Result<usize> {
    let mut stack: Vec<String> = Vec::new();
    for tag in tags(text)? {
        match tag {
            Tag::Close { name } => {
                if stack.pop().as_deref() != Some(name.as_str()) {
                    return Err(invalid(format!("mismatched closing tag </{name}>")));
                }
            }
            Tag::Open {
                name,
                attrs,
                self_closing,
                ..
            } => {
                f(&name, &attrs, stack.last().map_or("", String::as_str))?;
                if !self_closing {
                    stack.push(name);
                }
            }
        }
    }
    Ok(stack.len())
}

/// Splits the file at the `_` marker of `<AppendedData>`: XML before,
/// binary after.
fn split_appended(bytes: &[u8]) -> io::Result<(&[u8], &[u8])> {
    let key = b"<AppendedData";
    let start = bytes
        .windows(key.len())
        .position(|w| w == key)
        .ok_or_else(|| invalid("no <AppendedData> section".into()))?;
    let gt = bytes[start..]
        .iter()
        .position(|&b| b == b'>')
        .ok_or_else(|| invalid("unterminated <AppendedData> tag".into()))?;
    let after = start + gt + 1;
    let us = bytes[after..]
        .iter()
        .position(|&b| b == b'_')
        .ok_or_else(|| invalid("no '_' marker in appended data".into()))?;
    let marker = after + us;
    Ok((&bytes[..marker], &bytes[marker + 1..]))
}

fn check_file_attrs(attrs: &[(String, String)]) -> io::Result<()> {
    if attr(attrs, "header_type") != Some("UInt64") {
        return Err(invalid("only header_type=\"UInt64\" is supported".into()));
    }
    if attr(attrs, "byte_order") != Some("LittleEndian") {
        return Err(invalid("only LittleEndian files are supported".into()));
    }
    if attr(attrs, "compressor").is_some() {
        return Err(invalid("compressed files are not supported".into()));
    }
    Ok(())
}

fn read_array(section: String, attrs: &[(String, String)], data: &[u8]) -> io::Result<ReadArray> {
    let name = attr(attrs, "Name").unwrap_or_default().to_string();
    let ctx = |msg: &str| invalid(format!("DataArray {name:?}: {msg}"));
    if attr(attrs, "format") != Some("appended") {
        return Err(ctx("only format=\"appended\" is supported"));
    }
    let components: usize = match attr(attrs, "NumberOfComponents") {
        None => 1,
        Some(s) => s.parse().map_err(|_| ctx("bad NumberOfComponents"))?,
    };
    let offset: usize = attr(attrs, "offset")
        .ok_or_else(|| ctx("missing offset"))?
        .parse()
        .map_err(|_| ctx("bad offset"))?;
    let vtk_type = attr(attrs, "type").ok_or_else(|| ctx("missing type"))?;

    let len_end = offset
        .checked_add(8)
        .ok_or_else(|| ctx("offset overflows"))?;
    let len_bytes = data
        .get(offset..len_end)
        .ok_or_else(|| ctx("offset past end of file"))?;
    let mut len8 = [0u8; 8];
    len8.copy_from_slice(len_bytes);
    let n_bytes = usize::try_from(u64::from_le_bytes(len8)).map_err(|_| ctx("block too large"))?;
    let block = len_end
        .checked_add(n_bytes)
        .and_then(|end| data.get(len_end..end))
        .ok_or_else(|| ctx("block runs past end of file"))?;

    let values = decode(vtk_type, block).ok_or_else(|| ctx("unsupported type or ragged block"))?;
    if components == 0 || values.len() % components != 0 {
        return Err(ctx("value count is not a multiple of NumberOfComponents"));
    }
    Ok(ReadArray {
        section,
        name,
        vtk_type: vtk_type.to_string(),
        components,
        values,
    })
}

/// Decodes a little-endian block of the named type; `None` for unknown types
/// or a byte count that is not a whole number of elements.
fn decode(vtk_type: &str, block: &[u8]) -> Option<Vec<f64>> {
    fn each<const N: usize>(block: &[u8], f: impl Fn([u8; N]) -> f64) -> Option<Vec<f64>> {
        if !block.len().is_multiple_of(N) {
            return None;
        }
        Some(
            block
                .chunks_exact(N)
                .map(|c| {
                    let mut a = [0u8; N];
                    a.copy_from_slice(c);
                    f(a)
                })
                .collect(),
        )
    }
    match vtk_type {
        "Float64" => each::<8>(block, f64::from_le_bytes),
        "Float32" => each::<4>(block, |b| f32::from_le_bytes(b) as f64),
        "Int64" => each::<8>(block, |b| i64::from_le_bytes(b) as f64),
        "UInt64" => each::<8>(block, |b| u64::from_le_bytes(b) as f64),
        "Int32" => each::<4>(block, |b| i32::from_le_bytes(b) as f64),
        "UInt32" => each::<4>(block, |b| u32::from_le_bytes(b) as f64),
        "Int8" => each::<1>(block, |b| b[0] as i8 as f64),
        "UInt8" => each::<1>(block, |b| b[0] as f64),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("grains-core-read-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        fs::write(&p, bytes).unwrap();
        p
    }

    fn file_with(array_tag: &str, blob: &[u8]) -> Vec<u8> {
        let mut v = format!(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" byte_order=\"LittleEndian\" \
             header_type=\"UInt64\"><PolyData><Piece><PointData>{array_tag}</PointData>\
             </Piece></PolyData><AppendedData encoding=\"raw\">_"
        )
        .into_bytes();
        v.extend_from_slice(blob);
        v.extend_from_slice(b"</AppendedData></VTKFile>");
        v
    }

    #[test]
    fn reads_a_hand_made_file() {
        let mut blob = 4u64.to_le_bytes().to_vec();
        blob.extend_from_slice(&2.5f32.to_le_bytes());
        let tag = r#"<DataArray type="Float32" Name="f" format="appended" offset="0"/>"#;
        let p = scratch("hand.vtp", &file_with(tag, &blob));
        let a = read_appended_arrays(&p).unwrap();
        assert_eq!(a.len(), 1);
        assert_eq!(a[0].section, "PointData");
        assert_eq!(a[0].values, vec![2.5]);
    }

    #[test]
    fn corrupt_files_are_errors() {
        let tag = r#"<DataArray type="Float64" Name="f" format="appended" offset="0"/>"#;
        // Block claims more bytes than exist.
        let mut blob = 800u64.to_le_bytes().to_vec();
        blob.extend_from_slice(&[0u8; 8]);
        let p = scratch("short.vtp", &file_with(tag, &blob));
        let e = read_appended_arrays(&p).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidData);
        assert!(e.to_string().contains("\"f\""), "{e}");
        // Offset past the end.
        let far = r#"<DataArray type="Float64" Name="f" format="appended" offset="99"/>"#;
        let p = scratch("far.vtp", &file_with(far, &blob));
        assert!(read_appended_arrays(&p).is_err());
        // Ragged block.
        let mut blob = 7u64.to_le_bytes().to_vec();
        blob.extend_from_slice(&[0u8; 7]);
        let p = scratch("ragged.vtp", &file_with(tag, &blob));
        assert!(read_appended_arrays(&p).is_err());
        // Not a VTK file at all, and a truncated one.
        let p = scratch("junk.vtp", b"hello");
        assert!(read_appended_arrays(&p).is_err());
        let p = scratch("trunc.vtp", &file_with(tag, &[])[..60]);
        assert!(read_appended_arrays(&p).is_err());
    }
}
