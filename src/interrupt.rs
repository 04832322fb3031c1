//! Ctrl-C, and the signals that ask a process to end: every command stops at once,
//! with exit code 130 for Ctrl-C (SIGINT), 143 for SIGTERM (what `kill`, Slurm at a time
//! limit and container runtimes send) and 129 for SIGHUP (a closed terminal), and
//! leaves no temporary file.
//!
//! physframes writes every file to a temporary file beside it and renames it into place
//! when complete (see [`crate::output`]), so a file that exists is complete whenever the
//! process stops. What an interrupt could leave is the temporary file of a write in
//! progress (a frame, a checkpoint, a CSV, an animation). Each temporary file and
//! folder is therefore listed here from the moment it is created to the moment it is
//! renamed or removed, and the handlers that [`install`] sets up remove every one
//! listed, then exit with 128 plus the signal's number. It holds the list's lock while it removes
//! and exits, so that no temporary file is created, and none is listed late, meanwhile.
//!
//! Stopping at once, rather than asking long loops to look at a flag, means that no
//! loop can forget to look: a simulation deep inside one frame of 10^12 body-steps stops
//! as promptly as a render between frames. Frames written stay valid, and
//! `render --resume` draws only the missing ones.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// The exit code of a command stopped by Ctrl-C: 128 + SIGINT's number 2, as shells
/// report a process killed by SIGINT.
pub const EXIT_CODE: u8 = 130;

/// The temporary files and folders that exist now, to remove on an interrupt.
static TEMPORARY: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Locks the list, whatever a panicking thread left it as: a path too many is harmless.
fn temporary() -> MutexGuard<'static, Vec<PathBuf>> {
    TEMPORARY.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The exit code of a command stopped by SIGTERM: 128 + 15.
pub const TERMINATED: u8 = 143;

/// The exit code of a command stopped by SIGHUP: 128 + 1.
pub const HUNG_UP: u8 = 129;

/// Sets up the handlers: SIGINT through `ctrlc` (on every platform), SIGTERM and SIGHUP
/// through `signal-hook` on Unix. Called once by the command line; a failure to set
/// one up (a handler already set) leaves the default behaviour, which stops the process
/// too, only without removing its temporary files.
pub fn install() {
    let _ = ctrlc::set_handler(|| stop_now(EXIT_CODE));
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGHUP, SIGTERM};
        if let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGTERM, SIGHUP]) {
            let _ = std::thread::Builder::new()
                .name("physframes-signals".into())
                .spawn(move || {
                    if let Some(signal) = signals.forever().next() {
                        stop_now(if signal == SIGHUP {
                            HUNG_UP
                        } else {
                            TERMINATED
                        });
                    }
                });
        }
    }
}

/// Removes every listed temporary file and folder, says so, and exits with `code`.
/// Runs on a handler's own thread, not in the signal handler, so it may lock, remove
/// files and print.
fn stop_now(code: u8) {
    let list = temporary();
    for path in list.iter() {
        remove(path);
    }
    eprintln!(
        "\ninterrupted: every file written is complete and no temporary file is left; \
         run `render` again with --resume to finish a render"
    );
    // Exits holding the lock, so no thread lists a new temporary file meanwhile.
    std::process::exit(i32::from(code));
}

/// Removes a temporary file or folder, if it is still there.
fn remove(path: &Path) {
    match path.symlink_metadata() {
        Ok(meta) if meta.is_dir() => {
            let _ = std::fs::remove_dir_all(path);
        }
        Ok(_) => {
            let _ = std::fs::remove_file(path);
        }
        Err(_) => {}
    }
}

/// A temporary file or folder listed for removal on an interrupt; dropping it takes
/// it off the list (it must then be gone, renamed or removed, already).
#[derive(Debug)]
pub struct Listed {
    path: PathBuf,
}

impl Drop for Listed {
    fn drop(&mut self) {
        let mut list = temporary();
        if let Some(i) = list.iter().rposition(|p| *p == self.path) {
            list.swap_remove(i);
        }
    }
}

/// Creates a temporary file or folder with `create` and lists the path `path_of` gives
/// for it, both under the list's lock, so that an interrupt finds it listed whenever
/// it exists.
pub fn create_listed<T>(
    create: impl FnOnce() -> io::Result<T>,
    path_of: impl FnOnce(&T) -> &Path,
) -> io::Result<(T, Listed)> {
    let mut list = temporary();
    let made = create()?;
    let path = path_of(&made).to_path_buf();
    list.push(path.clone());
    Ok((made, Listed { path }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_listed_temporary_file_leaves_the_list_when_dropped() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let (file, listed) =
            create_listed(|| tempfile::NamedTempFile::new_in(dir.path()), |f| f.path())
                .expect("create");
        let path = file.path().to_path_buf();
        assert!(temporary().contains(&path));
        drop(file);
        drop(listed);
        assert!(!temporary().contains(&path));
    }
}
