//! The files `tracer render` writes, checked before the first ray and written as one
//! transaction.
//!
//! [`Staged::new`] checks each requested path before anything is rendered: a known format
//! by extension, an existing parent directory, and a temporary file created there (which
//! proves the directory writable). The outputs are then written into their temporary
//! files and [`Staged::commit`] renames them into place; if any write or rename fails,
//! every temporary file and every output already renamed is removed, so a failed run
//! leaves no output at all. Dropping a [`Staged`] without committing removes the
//! temporary files, and so does a signal that ends the process first, once
//! [`remove_on_signal`] is installed.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// The temporary files of every [`Staged`] neither committed nor dropped yet: what
/// [`remove_on_signal`] removes. A commit holds the lock over all its renames, so a
/// signal finds either every output of a run in place or none.
static TEMPORARY: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn temporary() -> MutexGuard<'static, Vec<PathBuf>> {
    TEMPORARY.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Makes SIGINT (Ctrl-C), SIGTERM (`kill`, or a batch system's time limit and
/// cancellation) and SIGHUP (a closed terminal) remove the temporary files of outputs not
/// yet in place, then end the process by that signal as it would have without this (so
/// that a shell or a scheduler sees which signal ended it). Without it, an interrupted
/// render would leave its hidden `.NAME.PID.tmp` files behind.
///
/// Elsewhere than on Unix it does nothing.
///
/// # Errors
/// The signal handlers cannot be installed.
#[cfg(unix)]
pub fn remove_on_signal() -> io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                // Held until the process ends: no output is staged or committed after.
                let files = temporary();
                for f in files.iter() {
                    let _ = fs::remove_file(f);
                }
                // Returns only if the default action could not be taken.
                let _ = signal_hook::low_level::emulate_default_handler(signal);
                std::process::exit(128 + signal);
            }
        })?;
    Ok(())
}

/// See the Unix version.
///
/// # Errors
/// Never.
#[cfg(not(unix))]
pub fn remove_on_signal() -> io::Result<()> {
    Ok(())
}

/// The image formats of `-o`, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit RGB PNG.
    Png,
    /// Little-endian colour PFM, linear 32-bit floats.
    Pfm,
    /// OpenEXR, linear 32-bit float RGB.
    Exr,
}

impl ImageFormat {
    /// The format named by `path`'s extension (any case), if it is one of ours.
    pub fn of(path: &Path) -> Option<Self> {
        match extension(path).as_deref() {
            Some("png") => Some(Self::Png),
            Some("pfm") => Some(Self::Pfm),
            Some("exr") => Some(Self::Exr),
            _ => None,
        }
    }
}

/// The lower-case extension of `path`.
pub fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// One output: where it goes and the temporary file it is written to first.
struct Pending {
    path: PathBuf,
    tmp: PathBuf,
    file: Option<File>,
}

/// Outputs checked and opened as temporary files, not yet in place.
pub struct Staged {
    pending: Vec<Pending>,
    committed: bool,
}

/// The directory `path` goes in (`.` for a bare file name).
fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// The temporary file beside `path`: hidden, named after it and this process.
fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

impl Staged {
    /// Checks every path in `paths` (a label for messages and the path) and creates its
    /// temporary file.
    ///
    /// # Errors
    /// One line `PATH: message` for a path that names no file, a missing parent
    /// directory, a directory that cannot be written, or two outputs with one path.
    pub fn new(paths: &[&Path]) -> Result<Self, String> {
        let mut staged = Self {
            pending: Vec::new(),
            committed: false,
        };
        for (i, &path) in paths.iter().enumerate() {
            if paths[..i].contains(&path) {
                return Err(format!("{}: named as two outputs", path.display()));
            }
            if path.file_name().is_none() || path.is_dir() {
                return Err(format!("{}: is a directory, not a file", path.display()));
            }
            let dir = parent(path);
            if !dir.is_dir() {
                return Err(format!(
                    "{}: directory {} does not exist",
                    path.display(),
                    dir.display()
                ));
            }
            let tmp = temp_path(path);
            // Listed before it exists: a signal in between finds nothing to remove.
            temporary().push(tmp.clone());
            let file = OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&tmp)
                .map_err(|e| {
                    format!(
                        "{}: cannot write in directory {}: {e}",
                        path.display(),
                        dir.display()
                    )
                })?;
            staged.pending.push(Pending {
                path: path.to_path_buf(),
                tmp,
                file: Some(file),
            });
        }
        Ok(staged)
    }

    /// Writes output `index` (in the order given to [`Staged::new`]) into its temporary
    /// file with `write`, and syncs it.
    ///
    /// # Errors
    /// `PATH: cannot write WHAT: error`.
    pub fn write(
        &mut self,
        index: usize,
        what: &str,
        write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
    ) -> Result<(), String> {
        let p = &mut self.pending[index];
        let label = p.path.display().to_string();
        let file = p
            .file
            .take()
            .ok_or_else(|| format!("{label}: written twice"))?;
        let mut w = BufWriter::new(file);
        let done = write(&mut w)
            .and_then(|()| w.flush())
            .and_then(|()| w.into_inner().map_err(|e| e.into_error()))
            .and_then(|f| f.sync_all());
        done.map_err(|e| format!("{label}: cannot write {what}: {e}"))
    }

    /// Renames every temporary file into place. If one rename fails, the outputs
    /// already renamed are removed too.
    ///
    /// # Errors
    /// `PATH: cannot write output: error`.
    pub fn commit(mut self) -> Result<(), String> {
        // Held over every rename (see `TEMPORARY`); `Drop` takes the files off the list.
        let _listed = temporary();
        for i in 0..self.pending.len() {
            let p = &self.pending[i];
            if let Err(e) = fs::rename(&p.tmp, &p.path) {
                let msg = format!("{}: cannot write output: {e}", p.path.display());
                for done in &self.pending[..i] {
                    let _ = fs::remove_file(&done.path);
                }
                return Err(msg);
            }
        }
        self.committed = true;
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        let mut listed = temporary();
        if !self.committed {
            for p in &self.pending {
                let _ = fs::remove_file(&p.tmp);
            }
        }
        listed.retain(|t| self.pending.iter().all(|p| &p.tmp != t));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_by_extension() {
        assert_eq!(
            ImageFormat::of(Path::new("a/b.PNG")),
            Some(ImageFormat::Png)
        );
        assert_eq!(ImageFormat::of(Path::new("b.exr")), Some(ImageFormat::Exr));
        assert_eq!(ImageFormat::of(Path::new("b.pfm")), Some(ImageFormat::Pfm));
        assert_eq!(ImageFormat::of(Path::new("b.jpg")), None);
        assert_eq!(ImageFormat::of(Path::new("b")), None);
        assert_eq!(parent(Path::new("b.png")), Path::new("."));
    }

    #[test]
    fn dropped_without_commit_leaves_nothing() {
        let d = std::env::temp_dir().join(format!("tracer-staged-{}", std::process::id()));
        fs::create_dir_all(&d).unwrap();
        let (a, b) = (d.join("a.png"), d.join("b.json"));
        {
            let mut s = Staged::new(&[&a, &b]).unwrap();
            s.write(0, "image", |w| w.write_all(b"x")).unwrap();
        }
        assert_eq!(fs::read_dir(&d).unwrap().count(), 0);
        let mut s = Staged::new(&[&a, &b]).unwrap();
        s.write(0, "image", |w| w.write_all(b"x")).unwrap();
        s.write(1, "stats", |w| w.write_all(b"{}")).unwrap();
        s.commit().unwrap();
        assert_eq!(fs::read(&a).unwrap(), b"x");
        assert_eq!(fs::read_dir(&d).unwrap().count(), 2);
        assert!(Staged::new(&[&a, &a]).is_err());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_failed_rename_takes_back_the_outputs_already_in_place() {
        let d = std::env::temp_dir().join(format!("tracer-staged-rename-{}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        let (a, b) = (d.join("a.png"), d.join("b.json"));
        let mut s = Staged::new(&[&a, &b]).unwrap();
        s.write(0, "image", |w| w.write_all(b"x")).unwrap();
        s.write(1, "stats", |w| w.write_all(b"{}")).unwrap();
        // A directory (not empty) appears where the second output goes: its rename fails.
        fs::create_dir_all(b.join("in-the-way")).unwrap();
        let err = s.commit().unwrap_err();
        assert!(
            err.starts_with(&format!("{}: cannot write output", b.display())),
            "{err}"
        );
        assert!(!a.exists());
        assert_eq!(
            fs::read_dir(&d).unwrap().count(),
            1,
            "only the directory is left"
        );
        fs::remove_dir_all(&d).unwrap();
    }
}
