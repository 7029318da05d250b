//! The bytes of engine snapshots (checkpoints): tagged little-endian arrays, each a
//! `u64` length and then the raw elements, so a state is written and read back bitwise.
//!
//! Every engine writes its own fields in its own fixed order with these; a reader
//! bounds each length (so a corrupted length cannot exhaust memory) and checks it
//! against the others. The integrity of the bytes themselves (a checksum over the whole
//! file) is the container's job.

use glam::DVec2;
use std::io::{self, Read, Write};

/// Why a snapshot could not be read.
#[derive(Debug, thiserror::Error)]
pub enum SnapshotError {
    /// The bytes ended early or could not be read.
    #[error("snapshot truncated or unreadable: {0}")]
    Io(#[from] io::Error),
    /// A length or value is inconsistent with the rest.
    #[error("snapshot inconsistent: {0}")]
    Invalid(String),
}

/// Writes an array's length.
pub fn put_len(w: &mut impl Write, n: usize) -> io::Result<()> {
    w.write_all(&(n as u64).to_le_bytes())
}

/// Writes an array of `f64`.
pub fn put_f64(w: &mut impl Write, v: &[f64]) -> io::Result<()> {
    put_len(w, v.len())?;
    let mut buf = Vec::with_capacity(8 * v.len());
    for x in v {
        buf.extend_from_slice(&x.to_le_bytes());
    }
    w.write_all(&buf)
}

/// Writes an array of vectors (x then y of each).
pub fn put_vec2(w: &mut impl Write, v: &[DVec2]) -> io::Result<()> {
    put_len(w, v.len())?;
    let mut buf = Vec::with_capacity(16 * v.len());
    for x in v {
        buf.extend_from_slice(&x.x.to_le_bytes());
        buf.extend_from_slice(&x.y.to_le_bytes());
    }
    w.write_all(&buf)
}

/// Writes an array of `u32`.
pub fn put_u32(w: &mut impl Write, v: &[u32]) -> io::Result<()> {
    put_len(w, v.len())?;
    let mut buf = Vec::with_capacity(4 * v.len());
    for x in v {
        buf.extend_from_slice(&x.to_le_bytes());
    }
    w.write_all(&buf)
}

/// Writes an array of `u64`.
pub fn put_u64(w: &mut impl Write, v: &[u64]) -> io::Result<()> {
    put_len(w, v.len())?;
    let mut buf = Vec::with_capacity(8 * v.len());
    for x in v {
        buf.extend_from_slice(&x.to_le_bytes());
    }
    w.write_all(&buf)
}

/// Reads an array's length, refusing one above `limit`.
pub fn get_len(r: &mut impl Read, limit: usize) -> Result<usize, SnapshotError> {
    let mut b = [0u8; 8];
    r.read_exact(&mut b)?;
    let n = u64::from_le_bytes(b);
    if n > limit as u64 {
        return Err(SnapshotError::Invalid(format!(
            "array of {n} elements exceeds the limit {limit}"
        )));
    }
    Ok(n as usize)
}

/// Reads `n` elements of `size` bytes. The buffer grows with the bytes actually there,
/// so a corrupted length ends in an error, not in an allocation of its size.
fn get_bytes(r: &mut impl Read, n: usize, size: usize) -> Result<Vec<u8>, SnapshotError> {
    let want = n
        .checked_mul(size)
        .ok_or_else(|| SnapshotError::Invalid(format!("array of {n} elements is too large")))?;
    let mut buf = Vec::new();
    r.take(want as u64).read_to_end(&mut buf)?;
    if buf.len() != want {
        return Err(SnapshotError::Io(io::Error::new(
            io::ErrorKind::UnexpectedEof,
            format!("{} of {want} bytes", buf.len()),
        )));
    }
    Ok(buf)
}

/// Reads an array of `f64` of at most `limit` elements.
pub fn get_f64(r: &mut impl Read, limit: usize) -> Result<Vec<f64>, SnapshotError> {
    let n = get_len(r, limit)?;
    let b = get_bytes(r, n, 8)?;
    Ok(b.chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect())
}

/// Reads an array of vectors of at most `limit` elements.
pub fn get_vec2(r: &mut impl Read, limit: usize) -> Result<Vec<DVec2>, SnapshotError> {
    let n = get_len(r, limit)?;
    let b = get_bytes(r, n, 16)?;
    Ok(b.chunks_exact(16)
        .map(|c| {
            DVec2::new(
                f64::from_le_bytes(c[..8].try_into().expect("8 bytes")),
                f64::from_le_bytes(c[8..].try_into().expect("8 bytes")),
            )
        })
        .collect())
}

/// Reads an array of `u32` of at most `limit` elements.
pub fn get_u32(r: &mut impl Read, limit: usize) -> Result<Vec<u32>, SnapshotError> {
    let n = get_len(r, limit)?;
    let b = get_bytes(r, n, 4)?;
    Ok(b.chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().expect("4 bytes")))
        .collect())
}

/// Reads an array of `u64` of at most `limit` elements.
pub fn get_u64(r: &mut impl Read, limit: usize) -> Result<Vec<u64>, SnapshotError> {
    let n = get_len(r, limit)?;
    let b = get_bytes(r, n, 8)?;
    Ok(b.chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect())
}

/// Reads an array that must hold exactly `n` `f64` (a fixed record of scalars or a
/// per-item field); `what` names it in the error.
pub fn get_f64_exact(r: &mut impl Read, n: usize, what: &str) -> Result<Vec<f64>, SnapshotError> {
    let v = get_f64(r, n)?;
    exact(v, n, what)
}

/// Reads an array that must hold exactly `n` vectors.
pub fn get_vec2_exact(
    r: &mut impl Read,
    n: usize,
    what: &str,
) -> Result<Vec<DVec2>, SnapshotError> {
    let v = get_vec2(r, n)?;
    exact(v, n, what)
}

/// Reads an array that must hold exactly `n` `u64`.
pub fn get_u64_exact(r: &mut impl Read, n: usize, what: &str) -> Result<Vec<u64>, SnapshotError> {
    let v = get_u64(r, n)?;
    exact(v, n, what)
}

fn exact<T>(v: Vec<T>, n: usize, what: &str) -> Result<Vec<T>, SnapshotError> {
    if v.len() == n {
        Ok(v)
    } else {
        Err(SnapshotError::Invalid(format!(
            "{what}: {} values, expected {n}",
            v.len()
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrays_round_trip_bitwise_and_lengths_are_bounded() {
        let mut b = Vec::new();
        put_f64(&mut b, &[1.5, f64::NAN, -0.0]).unwrap();
        put_vec2(&mut b, &[DVec2::new(1.0, -2.0)]).unwrap();
        put_u32(&mut b, &[7, 9]).unwrap();
        put_u64(&mut b, &[u64::MAX]).unwrap();
        let r = &mut b.as_slice();
        let f = get_f64(r, 3).unwrap();
        assert_eq!(f[0], 1.5);
        assert!(f[1].is_nan());
        assert_eq!(f[2].to_bits(), (-0.0f64).to_bits());
        assert_eq!(get_vec2(r, 1).unwrap(), vec![DVec2::new(1.0, -2.0)]);
        assert_eq!(get_u32(r, 2).unwrap(), vec![7, 9]);
        assert_eq!(get_u64_exact(r, 1, "x").unwrap(), vec![u64::MAX]);
        let mut b = Vec::new();
        put_f64(&mut b, &[1.0, 2.0]).unwrap();
        assert!(matches!(
            get_f64(&mut b.as_slice(), 1),
            Err(SnapshotError::Invalid(_))
        ));
        assert!(get_f64_exact(&mut b.as_slice(), 3, "x").is_err());
        assert!(matches!(
            get_f64(&mut &b[..12], 2),
            Err(SnapshotError::Io(_))
        ));
        // A length far beyond the bytes there is refused without allocating it.
        let mut huge = Vec::new();
        put_len(&mut huge, usize::MAX / 16).unwrap();
        huge.extend_from_slice(&[0u8; 64]);
        assert!(get_vec2(&mut huge.as_slice(), usize::MAX).is_err());
    }
}
