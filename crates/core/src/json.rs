//! Atomic JSON output (run summaries, metadata).

use std::io;
use std::path::Path;

use serde::Serialize;

use crate::atomic::write_atomic;

/// Writes `value` as pretty-printed JSON (plus a final newline), atomically.
pub fn write_json_pretty<T: Serialize + ?Sized>(path: &Path, value: &T) -> io::Result<()> {
    let mut bytes = serde_json::to_vec_pretty(value).map_err(io::Error::other)?;
    bytes.push(b'\n');
    write_atomic(path, &bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_pretty_json() {
        let dir = std::env::temp_dir().join(format!("grains-core-json-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("s.json");
        let v = serde_json::json!({"a": [1, 2], "b": "x"});
        write_json_pretty(&p, &v).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.ends_with("}\n") && text.contains("\n  \"a\""));
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back, v);
    }
}
