//! Outputs that would destroy an input are refused before any work: a file written over the
//! flight it was made from (`import --flight x --out x`, `compare --report` on the flight
//! itself), under any spelling, symbolic or hard link, or an output directory that holds an
//! input (it is replaced whole).

use std::path::Path;

/// Refuses the first output of `outputs` that is one of `inputs` (the same file on disk), or
/// that is a directory (`dirs`: the outputs written as whole directories) holding one. Each
/// is `(option, path)`, the option as the error names it.
///
/// # Errors
/// The output, its option, and the input it would destroy.
pub(crate) fn refuse_inputs_as_outputs(
    inputs: &[(&str, &Path)],
    outputs: &[(&str, &Path)],
    dirs: &[(&str, &Path)],
) -> anyhow::Result<()> {
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

/// ` (as NAME)` when the input is spelled otherwise than the output, else nothing.
fn spelled(out: &Path, input: &Path) -> String {
    if out == input {
        String::new()
    } else {
        format!(" (as {})", crate::app::shown(input))
    }
}
