//! Builds a VTK XML file whose arrays live in one raw appended block.
//!
//! Raw appended data (rather than inline base64) keeps million-point frames
//! fast to write and compact on disk: the bytes are copied, never encoded.
//! Each block is a `UInt64` byte count followed by the little-endian values,
//! and each `DataArray` tag records its block's offset from the `_` marker.

use std::io::{self, Write};
use std::path::Path;

use super::data::{extend_f64, extend_i64, ArrayData, DataArray};
use crate::atomic::write_atomic_with;
use crate::xml::escape_attr;

/// Accumulates the XML header and the appended block side by side, so that
/// offsets are known as each array tag is emitted.
pub(crate) struct AppendedFile {
    header: String,
    blob: Vec<u8>,
}

impl AppendedFile {
    /// Starts a file of the given `VTKFile type` (`PolyData`,
    /// `UnstructuredGrid`); `blob_capacity` pre-sizes the binary block so a
    /// large frame is not copied by repeated growth.
    pub(crate) fn new(file_type: &str, blob_capacity: usize) -> Self {
        let mut header = String::with_capacity(2048);
        header.push_str("<?xml version=\"1.0\"?>\n");
        header.push_str(&format!(
            "<VTKFile type=\"{file_type}\" version=\"1.0\" byte_order=\"LittleEndian\" \
             header_type=\"UInt64\">\n"
        ));
        Self {
            header,
            blob: Vec::with_capacity(blob_capacity),
        }
    }

    /// Appends one line of markup at the given nesting depth.
    pub(crate) fn line(&mut self, depth: usize, text: &str) {
        for _ in 0..depth {
            self.header.push_str("  ");
        }
        self.header.push_str(text);
        self.header.push('\n');
    }

    /// Emits a `DataArray` tag and appends its block; `fill` writes exactly
    /// `byte_len` bytes.
    fn array_with(
        &mut self,
        depth: usize,
        vtk_type: &str,
        name: &str,
        components: usize,
        byte_len: usize,
        fill: impl FnOnce(&mut Vec<u8>),
    ) {
        let offset = self.blob.len();
        self.line(
            depth,
            &format!(
                "<DataArray type=\"{vtk_type}\" Name=\"{}\" NumberOfComponents=\"{components}\" \
                 format=\"appended\" offset=\"{offset}\"/>",
                escape_attr(name)
            ),
        );
        self.blob.reserve(8 + byte_len);
        self.blob
            .extend_from_slice(&(byte_len as u64).to_le_bytes());
        fill(&mut self.blob);
        debug_assert_eq!(self.blob.len(), offset + 8 + byte_len);
    }

    /// Emits a user data array.
    pub(crate) fn data_array(&mut self, depth: usize, a: &DataArray) {
        let data: &ArrayData = &a.data;
        self.array_with(
            depth,
            data.vtk_type(),
            &a.name,
            a.components,
            data.byte_len(),
            |b| data.extend_le_bytes(b),
        );
    }

    /// Emits the `Points` array (three `Float64` components).
    pub(crate) fn points(&mut self, depth: usize, points: &[[f64; 3]]) {
        self.array_with(depth, "Float64", "Points", 3, points.len() * 24, |b| {
            extend_f64(b, points.as_flattened())
        });
    }

    /// Emits an `Int64` array (connectivity, offsets).
    pub(crate) fn i64_array(&mut self, depth: usize, name: &str, v: &[i64]) {
        self.array_with(depth, "Int64", name, 1, v.len() * 8, |b| extend_i64(b, v));
    }

    /// Emits a `UInt8` array (cell types).
    pub(crate) fn u8_array(&mut self, depth: usize, name: &str, v: &[u8]) {
        self.array_with(depth, "UInt8", name, 1, v.len(), |b| b.extend_from_slice(v));
    }

    /// Emits `<PointData>`/`<CellData>` with its arrays; nothing if empty.
    pub(crate) fn attribute_section(&mut self, depth: usize, tag: &str, arrays: &[DataArray]) {
        if arrays.is_empty() {
            return;
        }
        self.line(depth, &format!("<{tag}>"));
        for a in arrays {
            self.data_array(depth + 1, a);
        }
        self.line(depth, &format!("</{tag}>"));
    }

    /// Closes the document and writes it atomically to `path`. `closing`
    /// holds the end tags of the dataset element (e.g. `</Piece>`,
    /// `</PolyData>`), outermost last.
    pub(crate) fn write(mut self, path: &Path, closing: &[&str]) -> io::Result<()> {
        let depth = closing.len();
        for (i, tag) in closing.iter().enumerate() {
            self.line(depth - i, tag);
        }
        self.line(1, "<AppendedData encoding=\"raw\">");
        // The marker is indented like the rest for readability; readers
        // locate the data by the `_`, not by column.
        self.header.push_str("    _");
        write_atomic_with(path, |w: &mut dyn Write| {
            w.write_all(self.header.as_bytes())?;
            w.write_all(&self.blob)?;
            w.write_all(b"\n  </AppendedData>\n</VTKFile>\n")
        })
    }
}
