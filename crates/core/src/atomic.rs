//! Atomic file replacement: write a sibling temporary file, then rename it
//! over the target.
//!
//! A rename within one directory is atomic on POSIX file systems, so a reader
//! (ParaView polling a series, a plotting script tailing a run) sees either
//! the old complete file or the new complete file, never a torn one, and a
//! run killed mid-write leaves at worst a stray hidden temporary file.
//!
//! The data is not `fsync`ed: the goal is protection against readers and
//! interrupted processes, not against power loss, and syncing every frame of
//! a long run would cost far more than it buys.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes temporaries of different threads of one process that write
/// the same target at the same time; the pid alone would make them collide.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Returns the hidden temporary path `.{filename}.tmp.{pid}.{n}` next to
/// `path`.
///
/// It lives in the same directory because `rename` is only atomic (and only
/// possible) within one file system.
pub fn temp_path_for(path: &Path) -> io::Result<PathBuf> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("cannot write {}: path has no file name", path.display()),
        )
    })?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".tmp.{}.{n}", std::process::id()));
    Ok(path.with_file_name(tmp_name))
}

/// Removes the temporary file unless it was renamed into place, so failed
/// writes do not litter the output directory.
struct TempGuard {
    path: PathBuf,
    armed: bool,
}

impl Drop for TempGuard {
    fn drop(&mut self) {
        if self.armed {
            // The write already failed; a failure to clean up must not mask
            // the original error.
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// Atomically replaces `path` with `bytes`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// Atomically replaces `path` with whatever `f` writes.
///
/// `f` receives a buffered writer on the temporary file; the buffer is
/// flushed and the file renamed over `path` only if `f` succeeds. On any
/// error the target is left untouched and the temporary is removed.
pub fn write_atomic_with<F>(path: &Path, f: F) -> io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    write_atomic_via_path(path, |tmp| {
        let write = || -> io::Result<()> {
            let mut w = BufWriter::new(File::create(tmp)?);
            f(&mut w)?;
            w.flush()?;
            // into_inner cannot fail after a successful flush, but report it
            // rather than assume.
            w.into_inner().map_err(|e| e.into_error())?;
            Ok(())
        };
        write().map_err(|e| naming(path, e))
    })
}

/// The error with the path it concerns: an OS error alone ("Permission denied")
/// does not say which file of a run failed.
fn naming(path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
}

/// Atomically replaces `path` with a file that `f` creates at the given
/// temporary path.
///
/// For writers that insist on opening the file themselves (e.g. an image
/// encoder). The temporary path ends with the target's extension, since such
/// writers often pick the format from it. The error type is the caller's, so
/// library errors pass through unchanged.
pub fn write_atomic_via_path<E, F>(path: &Path, f: F) -> Result<(), E>
where
    E: From<io::Error>,
    F: FnOnce(&Path) -> Result<(), E>,
{
    let mut tmp = temp_path_for(path)?;
    if let Some(ext) = path.extension() {
        let mut name = tmp.file_name().unwrap_or_default().to_os_string();
        name.push(".");
        name.push(ext);
        tmp.set_file_name(name);
    }
    let mut guard = TempGuard {
        path: tmp,
        armed: true,
    };
    f(&guard.path)?;
    fs::rename(&guard.path, path).map_err(|e| naming(path, e))?;
    guard.armed = false;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch_dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("grains-core-atomic-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn writes_and_replaces() {
        let dir = scratch_dir("replace");
        let p = dir.join("a.txt");
        write_atomic(&p, b"first").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"first");
        write_atomic(&p, b"second, longer").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"second, longer");
        assert_eq!(entries(&dir), vec!["a.txt".to_string()]);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn failed_closure_keeps_old_file_and_cleans_up() {
        let dir = scratch_dir("fail");
        let p = dir.join("b.txt");
        write_atomic(&p, b"old").unwrap();
        let err = write_atomic_with(&p, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        })
        .unwrap_err();
        assert_eq!(
            err.to_string(),
            format!("cannot write {}: boom", p.display())
        );
        assert_eq!(fs::read(&p).unwrap(), b"old");
        assert_eq!(entries(&dir), vec!["b.txt".to_string()]);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn temp_name_is_hidden_sibling_with_pid() {
        let t = temp_path_for(Path::new("/x/y/frame.vtp")).unwrap();
        assert_eq!(t.parent(), Some(Path::new("/x/y")));
        let name = t.file_name().unwrap().to_string_lossy().into_owned();
        let prefix = format!(".frame.vtp.tmp.{}.", std::process::id());
        assert!(name.starts_with(&prefix), "{name}");
    }

    #[test]
    fn via_path_keeps_extension() {
        let dir = scratch_dir("via");
        let p = dir.join("plot.png");
        let mut seen = PathBuf::new();
        write_atomic_via_path::<io::Error, _>(&p, |tmp| {
            seen = tmp.to_path_buf();
            fs::write(tmp, b"png")
        })
        .unwrap();
        assert_eq!(seen.extension().unwrap(), "png");
        assert_eq!(fs::read(&p).unwrap(), b"png");
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn missing_directory_and_bad_path_are_errors() {
        let p = std::env::temp_dir().join("grains-core-no-such-dir/x/y.txt");
        assert!(write_atomic(&p, b"x").is_err());
        let e = write_atomic(Path::new("/"), b"x").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
    }
}
