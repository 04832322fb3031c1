//! `physframes new NAME`: a commented scene template that renders as it is.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Args;

use super::Verbosity;
use crate::error::{Error, Result};

/// The template; `NAME` is replaced by the scene's name.
const TEMPLATE: &str = include_str!("template.toml");

#[derive(Debug, Args)]
pub struct NewArgs {
    /// The scene to create: writes NAME.toml (a path such as scenes/demo works too).
    name: PathBuf,
}

pub fn run(args: NewArgs, verbosity: Verbosity) -> Result<()> {
    let path = toml_path(&args.name);
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let valid = !stem.is_empty()
        && !stem.starts_with('.')
        && stem
            .chars()
            .all(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | '.'));
    if !valid {
        return Err(Error::Usage(format!(
            "`{stem}` cannot name a scene: it names the output folder\nhint: use letters, digits, `-`, `_` and `.`, not starting with `.`"
        )));
    }
    // The template is written beside its target and moved into place only if no file
    // has that name, so an existing scene is never overwritten, even by a race.
    let mut tmp = crate::output::temp_file_beside(&path)?;
    tmp.write_all(TEMPLATE.replace("NAME", &stem).as_bytes())
        .map_err(|e| Error::io("cannot write", tmp.path().to_path_buf(), e))?;
    match tmp.persist_noclobber(&path) {
        Ok(_) => {}
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            return Err(Error::Usage(format!(
                "{} already exists; nothing was written\nhint: choose another name, or remove the file first",
                path.display()
            )));
        }
        Err(e) => return Err(Error::io("cannot write", path, e)),
    }
    if !verbosity.quiet {
        super::say(&format!(
            "wrote {0}; render it with `physframes render {0}`\n",
            path.display()
        ))?;
    }
    Ok(())
}

/// Returns NAME.toml for NAME, and NAME itself when it already ends in `.toml`.
fn toml_path(name: &Path) -> PathBuf {
    if name.extension().is_some_and(|e| e == "toml") {
        return name.to_path_buf();
    }
    let mut os = name.as_os_str().to_os_string();
    os.push(".toml");
    PathBuf::from(os)
}
