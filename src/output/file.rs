//! Writing one file: atomically where that is possible, in place where it is not.
//!
//! A path that names a regular file, or nothing yet, is written to a temporary file
//! beside it that [`Output::finish`] renames into place, so a reader never sees half a
//! file and an interrupted run leaves the old one as it was.
//!
//! A path that names anything else (a device such as `/dev/null` or `/dev/stdout`, a
//! named pipe, a socket) is opened and written in place. Renaming over it would
//! replace it with a regular file: run as root, `physframes export --out /dev/null`
//! once turned the machine's `/dev/null` into a file that every later program's
//! discarded output went into, and that `rustc` then read as its program.
//!
//! A symbolic link is followed: the file it points to is replaced, and the link stays.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// A file being written to its path: see the module's documentation.
#[derive(Debug)]
pub struct Output {
    sink: Sink,
    /// Where the bytes end up: the path asked for, with a symbolic link followed.
    target: PathBuf,
}

#[derive(Debug)]
enum Sink {
    /// A temporary file beside `target`, renamed onto it when finished.
    Replace(TempFile),
    /// `target` itself, opened for writing: a device, pipe or socket.
    InPlace(std::fs::File),
}

impl Output {
    /// Starts writing the file that will be `path`. A folder is refused here, before
    /// any work is done, rather than when the finished file cannot be moved onto it.
    pub fn create(path: &Path) -> Result<Output> {
        let target = follow_link(path);
        match std::fs::metadata(&target) {
            Ok(m) if m.is_dir() => Err(Error::Usage(format!(
                "{} is a folder; name a file to write",
                path.display()
            ))),
            Ok(m) if !m.is_file() => {
                let file = std::fs::OpenOptions::new()
                    .write(true)
                    .open(&target)
                    .map_err(|e| Error::io("cannot open", path, e))?;
                Ok(Output {
                    sink: Sink::InPlace(file),
                    target,
                })
            }
            _ => Ok(Output {
                sink: Sink::Replace(temp_file_beside(&target)?),
                target,
            }),
        }
    }

    /// Returns the open file the bytes go to now.
    pub fn as_file(&self) -> &std::fs::File {
        match &self.sink {
            Sink::Replace(tmp) => tmp.as_file(),
            Sink::InPlace(file) => file,
        }
    }

    /// Returns the path the bytes go to now, for a program that writes them itself:
    /// the temporary file, or the device or pipe.
    pub fn writing_path(&self) -> &Path {
        match &self.sink {
            Sink::Replace(tmp) => tmp.path(),
            Sink::InPlace(_) => &self.target,
        }
    }

    /// Flushes a temporary file to the disk, so that the rename in [`Output::finish`]
    /// cannot be seen before its contents; a device or pipe has nothing to sync.
    pub fn sync(&self) -> std::io::Result<()> {
        match &self.sink {
            Sink::Replace(tmp) => tmp.as_file().sync_all(),
            Sink::InPlace(_) => Ok(()),
        }
    }

    /// Finishes the file: renames the temporary file into place, replacing what was
    /// there, or does nothing more for a device or pipe.
    pub fn finish(self) -> std::io::Result<()> {
        match self.sink {
            Sink::Replace(tmp) => tmp.persist(&self.target),
            Sink::InPlace(_) => Ok(()),
        }
    }
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.sink {
            Sink::Replace(tmp) => tmp.write(buf),
            Sink::InPlace(file) => file.write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.sink {
            Sink::Replace(tmp) => tmp.flush(),
            Sink::InPlace(file) => file.flush(),
        }
    }
}

/// Returns `path` with a symbolic link at its end followed to what it names. A link
/// to nothing is left as it is, and is replaced by the file written.
fn follow_link(path: &Path) -> PathBuf {
    match path.symlink_metadata() {
        Ok(m) if m.file_type().is_symlink() => {
            std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
        }
        _ => path.to_path_buf(),
    }
}

/// Writes `bytes` to `path`: atomically for a regular file (a temporary file in the
/// same folder, then renamed over `path`), in place for a device or pipe.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut out = Output::create(path)?;
    out.write_all(bytes)
        .map_err(|e| Error::io("cannot write", out.writing_path().to_path_buf(), e))?;
    out.finish()
        .map_err(|e| Error::io("cannot move a finished file to", path, e))?;
    Ok(())
}

/// Creates a temporary file in the folder of `path`, to be renamed onto it when
/// complete. Its permissions are those of an ordinary new file (0666 less the umask,
/// usually 0644), not the owner-only 0600 of temporary files, since it becomes one.
/// Most writers want [`Output`], which also handles devices and pipes.
pub fn temp_file_beside(path: &Path) -> Result<TempFile> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    TempFile::new_in(dir).map_err(|e| Error::io("cannot create a temporary file in", dir, e))
}

/// A temporary file named `.physframes-*.tmp`, removed when dropped unless it was
/// renamed into place, and listed with [`crate::interrupt`] while it exists, so that
/// Ctrl-C removes it too.
#[derive(Debug)]
pub struct TempFile {
    // Dropped first: the file is removed before it leaves the list.
    file: tempfile::NamedTempFile,
    _listed: crate::interrupt::Listed,
}

impl TempFile {
    /// Creates a temporary file in `dir`.
    pub fn new_in(dir: &Path) -> std::io::Result<TempFile> {
        let mut builder = tempfile::Builder::new();
        builder.prefix(".physframes-").suffix(".tmp");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
        let (file, listed) =
            crate::interrupt::create_listed(|| builder.tempfile_in(dir), |f| f.path())?;
        Ok(TempFile {
            file,
            _listed: listed,
        })
    }

    /// Returns the temporary file's path.
    pub fn path(&self) -> &Path {
        self.file.path()
    }

    /// Returns the open file.
    pub fn as_file(&self) -> &std::fs::File {
        self.file.as_file()
    }

    /// Renames the file onto `path`, replacing what is there. Writers use
    /// [`Output::finish`], which never renames over a device or pipe.
    fn persist(self, path: &Path) -> std::io::Result<()> {
        self.file.persist(path).map(drop).map_err(|e| e.error)
    }

    /// Renames the file onto `path` only if nothing has that name; fails with
    /// `AlreadyExists` otherwise.
    pub fn persist_noclobber(self, path: &Path) -> std::io::Result<()> {
        self.file
            .persist_noclobber(path)
            .map(drop)
            .map_err(|e| e.error)
    }
}

impl Write for TempFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names_in(dir: &Path) -> Vec<std::ffi::OsString> {
        let mut names: Vec<_> = std::fs::read_dir(dir)
            .expect("list")
            .map(|e| e.expect("entry").file_name())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn atomic_writes_leave_no_temporary_file() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = dir.path().join("a.bin");
        write_atomic(&path, b"first").expect("write");
        write_atomic(&path, b"second").expect("overwrite");
        assert_eq!(std::fs::read(&path).expect("read"), b"second");
        assert_eq!(
            names_in(dir.path()),
            vec![std::ffi::OsString::from("a.bin")]
        );
    }

    #[test]
    fn an_unfinished_output_leaves_the_old_file_and_no_temporary_one() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = dir.path().join("a.csv");
        std::fs::write(&path, b"old").expect("write");
        let mut out = Output::create(&path).expect("create");
        out.write_all(b"half of the new").expect("write");
        drop(out);
        assert_eq!(std::fs::read(&path).expect("read"), b"old");
        assert_eq!(
            names_in(dir.path()),
            vec![std::ffi::OsString::from("a.csv")]
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_is_followed_and_stays_a_link() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let real = dir.path().join("real.csv");
        let link = dir.path().join("link.csv");
        std::fs::write(&real, b"old").expect("write");
        std::os::unix::fs::symlink(&real, &link).expect("symlink");
        write_atomic(&link, b"new").expect("write through the link");
        let kind = link.symlink_metadata().expect("link").file_type();
        assert!(kind.is_symlink(), "the link was replaced by a file");
        assert_eq!(std::fs::read(&real).expect("read"), b"new");
    }

    /// A named pipe stands for every path that is not a regular file (`/dev/null`,
    /// `/dev/stdout`): it is written in place, never renamed over. A pipe in a
    /// temporary folder is used rather than `/dev/null`, so that a regression breaks
    /// this test and not the machine.
    #[cfg(unix)]
    #[test]
    fn a_pipe_is_written_in_place_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().expect("a temporary folder");
        let pipe = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&pipe).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("skipped: `mkfifo` is not available");
            return;
        }
        let reader = {
            let pipe = pipe.clone();
            std::thread::spawn(move || std::fs::read(pipe).expect("read the pipe"))
        };
        write_atomic(&pipe, b"through the pipe").expect("write to the pipe");
        // Checked before joining: a reader left waiting on a replaced pipe must fail
        // the test, not hang it.
        let kind = pipe.symlink_metadata().expect("pipe").file_type();
        assert!(kind.is_fifo(), "the pipe was replaced by a file");
        assert_eq!(reader.join().expect("reader"), b"through the pipe");
        assert_eq!(names_in(dir.path()), vec![std::ffi::OsString::from("pipe")]);
    }

    #[test]
    fn a_folder_is_refused_before_any_work() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let err = Output::create(dir.path()).expect_err("a folder is not a file");
        assert!(err.to_string().contains("is a folder"), "{err}");
    }
}
