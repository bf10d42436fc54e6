//! Failures the command reports (a message and whether it was a usage error: exit status 2,
//! else 1), and the checks of arguments and output paths that the subcommands make before any
//! work.

use std::path::Path;

use uvflat_core::Error;

/// A failure to report: the message, and whether it was a usage error.
pub(crate) struct Failure {
    pub(crate) message: String,
    pub(crate) usage: bool,
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        let hint = match e {
            Error::MultipleComponents { .. } => " (`uvflat unwrap --atlas` unwraps every component)",
            _ => "",
        };
        Failure { message: format!("{e}{hint}"), usage: false }
    }
}

pub(crate) fn usage(message: impl Into<String>) -> Failure {
    Failure { message: message.into(), usage: true }
}

/// Lines per period or per grid unit: a whole number ≥ 1 (checked before any work).
pub(crate) fn check_density(flag: &str, value: f64) -> Result<(), Failure> {
    if value >= 1.0 && value.fract() == 0.0 {
        Ok(())
    } else {
        Err(usage(format!("{flag} must be a whole number >= 1 (got {value})")))
    }
}

/// Refuses, before any work, output files that could not all be written or would overwrite
/// one another: two options naming one file, a path that is a directory, a directory that does
/// not exist. (Writing the main OBJ and then failing on a side output left a partial result.)
pub(crate) fn check_outputs(outputs: &[(&str, Option<&Path>)]) -> Result<(), Failure> {
    let given: Vec<(&str, &Path)> = outputs.iter().filter_map(|&(flag, path)| path.map(|p| (flag, p))).collect();
    for (i, &(flag, path)) in given.iter().enumerate() {
        if path.is_dir() {
            return Err(usage(format!("{flag} {} is a directory", path.display())));
        }
        let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        if !parent.is_dir() {
            return Err(usage(format!("{flag} {}: the directory {} does not exist", path.display(), parent.display())));
        }
        if let Some(&(other, _)) = given[..i].iter().find(|&&(_, q)| same_file(path, q)) {
            return Err(usage(format!("{other} and {flag} name the same file {}", path.display())));
        }
    }
    Ok(())
}

/// Whether two output paths name the same file (their directories resolved).
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    let resolved = |p: &Path| {
        let parent = p.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        Some(parent.canonicalize().ok()?.join(p.file_name()?))
    };
    a == b || matches!((resolved(a), resolved(b)), (Some(x), Some(y)) if x == y)
}
