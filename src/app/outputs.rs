//! Every output is checked before any work, so that a run never fails after writing some of
//! its outputs for want of another: a file's output must be a regular file or nothing, in a
//! directory that exists; a directory's output a directory or nothing. And outputs that would
//! destroy an input are refused: a file written over the flight it was made from (`import
//! --flight x --out x`, `compare --report` on the flight itself), under any spelling,
//! symbolic or hard link, or an output directory that holds an input (it is replaced whole).

use std::path::Path;

/// Checks every output (module docs): `outputs` are files, `dirs` directories written whole;
/// refuses the first that cannot be written, or that is one of `inputs` (the same file on
/// disk), or a directory holding one. Each is `(option, path)`, the option as the error
/// names it.
///
/// # Errors
/// The output, its option, and what is wrong: where it would go, or the input it would
/// destroy.
pub(crate) fn check_outputs(
    inputs: &[(&str, &Path)],
    outputs: &[(&str, &Path)],
    dirs: &[(&str, &Path)],
) -> anyhow::Result<()> {
    for &(option, out) in outputs {
        writable(option, out, false)?;
    }
    for &(option, dir) in dirs {
        writable(option, dir, true)?;
    }
    for &(out_option, out) in outputs {
        for &(in_option, input) in inputs {
            if crate::fsio::is_same_file(out, input) {
                anyhow::bail!(
                    "{}: {out_option} names the {in_option} file{}: writing it would destroy \
                     the input; give another name",
                    crate::app::shown(out),
                    spelled(out, input)
                );
            }
        }
    }
    for &(dir_option, dir) in dirs {
        let Ok(dir_real) = dir.canonicalize() else {
            continue; // not there yet: it holds nothing
        };
        for &(in_option, input) in inputs {
            if input
                .canonicalize()
                .is_ok_and(|real| real.starts_with(&dir_real))
            {
                anyhow::bail!(
                    "{}: {dir_option} is replaced whole, and it holds the {in_option} file {}; \
                     give another directory",
                    crate::app::shown(dir),
                    crate::app::shown(input)
                );
            }
        }
    }
    Ok(())
}

/// Whether `path` can be written as `option`'s output: nothing there, or a regular file (a
/// directory for `dir`), in a directory that exists.
fn writable(option: &str, path: &Path, dir: bool) -> anyhow::Result<()> {
    let shown = crate::app::shown(path);
    match std::fs::metadata(path) {
        Ok(m) if dir && !m.is_dir() => {
            anyhow::bail!("{shown}: {option} writes a directory: it exists and is not a directory")
        }
        Ok(m) if !dir && m.is_dir() => {
            anyhow::bail!("{shown}: {option} writes a file, and this is a directory")
        }
        Ok(m) if !dir && !m.is_file() => anyhow::bail!(
            "{shown}: {option}: not a regular file ({}: only a regular file is replaced)",
            crate::fsio::describe(&m)
        ),
        Ok(_) => Ok(()),
        Err(_) => {
            let parent = path.parent().filter(|p| !p.as_os_str().is_empty());
            match parent {
                Some(p) if !p.is_dir() => anyhow::bail!(
                    "{shown}: {option}: no directory {} to write it in",
                    crate::app::shown(p)
                ),
                _ => Ok(()),
            }
        }
    }
}

/// The options of `pairs` that were given, each with its path (for [`check_outputs`]).
pub(crate) fn given<'a>(pairs: &[(&'a str, Option<&'a Path>)]) -> Vec<(&'a str, &'a Path)> {
    pairs
        .iter()
        .filter_map(|&(option, path)| path.map(|p| (option, p)))
        .collect()
}

/// ` (as NAME)` when the input is spelled otherwise than the output, else nothing.
fn spelled(out: &Path, input: &Path) -> String {
    if out == input {
        String::new()
    } else {
        format!(" (as {})", crate::app::shown(input))
    }
}
