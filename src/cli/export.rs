//! `physframes export`.

use std::io::{BufWriter, Write};
use std::path::PathBuf;

use clap::Args;

use super::SceneArgs;
use crate::blowup::blow_up_message;
use crate::error::{Error, Result};
use crate::output::{write_trajectory, EventLog};

#[derive(Debug, Args)]
pub struct ExportArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Write the CSV to this file instead of standard output.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Write a row per body after every step, not only at frame times.
    #[arg(long)]
    every_step: bool,
    /// Also write the collision log to this CSV file: one row per impulse,
    /// `t,a,b,px,py,nx,ny,vn_before,vn_after,impulse,jt`, in the order applied.
    #[arg(long, value_name = "FILE")]
    events: Option<PathBuf>,
}

pub fn run(args: ExportArgs) -> Result<()> {
    let scene = args.scene.load()?;
    let mut events = match &args.events {
        Some(path) => Some(EventLog::create(path)?),
        None => None,
    };
    let blow_up = match &args.out {
        None => {
            let stdout = std::io::stdout();
            let mut out = BufWriter::new(stdout.lock());
            match write_trajectory(
                &scene,
                args.every_step,
                &mut out,
                events.as_mut().map(|e| e.writer()),
            )
            .and_then(|b| out.flush().map(|()| b))
            {
                Ok(b) => b,
                // A reader that closed the pipe (as `| head` does) has all it wanted.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => None,
                Err(e) => return Err(Error::io("cannot write to", "standard output", e)),
            }
        }
        Some(path) => {
            // Written beside the target, then renamed, so the CSV is never half-written
            // (a device or pipe is written in place: see `output::Output`).
            let tmp = crate::output::Output::create(path)?;
            let mut out = BufWriter::new(tmp);
            let b = write_trajectory(
                &scene,
                args.every_step,
                &mut out,
                events.as_mut().map(|e| e.writer()),
            )
            .map_err(|e| Error::io("cannot write", path.clone(), e))?;
            let tmp = out
                .into_inner()
                .map_err(|e| Error::io("cannot write", path.clone(), e.into_error()))?;
            tmp.finish()
                .map_err(|e| Error::io("cannot move the finished file to", path.clone(), e))?;
            b
        }
    };
    if let Some(events) = events {
        events.finish()?;
    }
    match blow_up {
        Some(b) => Err(Error::BlowUp(format!(
            "{}\nthe rows before it were written",
            blow_up_message(&scene, &b)
        ))),
        None => Ok(()),
    }
}
