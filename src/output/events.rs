//! The collision log: one CSV row per impulse, in the order the impulses were applied,
//! so that anyone can audit the restitution law (vn_after = -e·vn_before) row by row.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::sim::ContactEvent;

/// The header of the collision log. a and b are body names; (nx, ny) is the unit normal
/// from b to a; (px, py) the contact point; vn the normal part of v_AP - v_BP before
/// and after; impulse the j applied to a along n (and -j to b); jt the friction impulse
/// applied to a along t = n⊥ = (-ny, nx) (and -jt to b).
pub const EVENTS_HEADER: &str = "t,a,b,px,py,nx,ny,vn_before,vn_after,impulse,jt";

/// A collision log being written beside its final path, and moved there when finished,
/// so that a reader never sees half a file.
pub struct EventLog {
    path: PathBuf,
    out: BufWriter<super::Output>,
}

impl EventLog {
    /// Starts the log that will be `path`, writing its header.
    pub fn create(path: &Path) -> Result<Self> {
        let tmp = super::Output::create(path)?;
        let mut out = BufWriter::new(tmp);
        writeln!(out, "{EVENTS_HEADER}").map_err(|e| Error::io("cannot write", path, e))?;
        Ok(EventLog {
            path: path.to_path_buf(),
            out,
        })
    }

    /// Appends one row per impulse; `names` are the scene's body names.
    pub fn write(&mut self, events: &[ContactEvent], names: &[&str]) -> Result<()> {
        write_events(&mut self.out, events, names)
            .map_err(|e| Error::io("cannot write", &self.path, e))
    }

    /// Returns where the rows go, for [`super::write_trajectory`].
    pub fn writer(&mut self) -> &mut dyn Write {
        &mut self.out
    }

    /// Moves the finished log to its path.
    pub fn finish(self) -> Result<()> {
        let path = self.path;
        let tmp = self
            .out
            .into_inner()
            .map_err(|e| Error::io("cannot write", &path, e.into_error()))?;
        tmp.finish()
            .map_err(|e| Error::io("cannot move the finished file to", &path, e))?;
        Ok(())
    }
}

/// Writes one row per impulse, numbers in Rust's shortest round-trip form.
pub fn write_events(
    out: &mut impl Write,
    events: &[ContactEvent],
    names: &[&str],
) -> std::io::Result<()> {
    for e in events {
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{}",
            e.t,
            names[e.a],
            names[e.b],
            e.point.x,
            e.point.y,
            e.normal.x,
            e.normal.y,
            e.vn_before,
            e.vn_after,
            e.impulse,
            e.jt
        )?;
    }
    Ok(())
}
