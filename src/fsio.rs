//! Files: every output is written to a temporary file beside its destination and renamed, so
//! a reader (or a crash) never sees a partial file.

use std::io::Write;
use std::path::Path;

use anyhow::Context;

/// Write `bytes` to `path` atomically: into a temporary file beside it, then rename.
///
/// # Errors
/// I/O errors, with the path in the message.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file path", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("{}: cannot write", path.display()))
}

/// Write a directory of files as a whole: they are written into a temporary directory beside
/// `dir`, which is then renamed to `dir`, so a reader (or a crash) sees either all of them or
/// none.
///
/// `marker` names one of `files` that says who wrote the directory (e.g. a manifest). An
/// existing `dir` is replaced only when it is empty or holds a file of that name, i.e. was
/// written by an earlier run of the same command; anything else is refused, so that a mistyped
/// output path never deletes someone's directory. The old directory is moved aside before the
/// new one is renamed into place and removed after.
///
/// # Errors
/// A file name that is not a plain name, `marker` not among `files`, `dir` existing as a file
/// or as a directory of something else, I/O errors; each with the path in the message. The
/// temporary directory is removed on failure.
pub fn write_dir_atomic(
    dir: &Path,
    files: &[(String, Vec<u8>)],
    marker: &str,
) -> anyhow::Result<()> {
    for (name, _) in files {
        let plain = Path::new(name)
            .file_name()
            .is_some_and(|f| f == std::ffi::OsStr::new(name));
        anyhow::ensure!(
            plain && !name.starts_with('.'),
            "`{name}` is not a plain file name"
        );
    }
    anyhow::ensure!(
        files.iter().any(|(n, _)| n == marker),
        "the marker file `{marker}` is not among the files to write"
    );
    let name = dir
        .file_name()
        .with_context(|| format!("{}: not a directory path", dir.display()))?
        .to_string_lossy()
        .into_owned();
    let parent = match dir.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    if dir.exists() {
        anyhow::ensure!(
            dir.is_dir(),
            "{}: exists and is not a directory",
            dir.display()
        );
        let mut entries =
            std::fs::read_dir(dir).with_context(|| format!("{}: cannot read", dir.display()))?;
        let empty = entries.next().is_none();
        anyhow::ensure!(
            empty || dir.join(marker).is_file(),
            "{}: exists and was not written by this command (no `{marker}` in it); choose a \
             new or empty directory",
            dir.display()
        );
    }
    std::fs::create_dir_all(&parent)
        .with_context(|| format!("{}: cannot create", parent.display()))?;
    let pid = std::process::id();
    let tmp = parent.join(format!(".{name}.tmp-{pid}"));
    let old = parent.join(format!(".{name}.old-{pid}"));
    let written = (|| -> std::io::Result<()> {
        std::fs::create_dir(&tmp)?;
        for (file, bytes) in files {
            let mut f = std::fs::File::create(tmp.join(file))?;
            f.write_all(bytes)?;
            f.sync_all()?;
        }
        Ok(())
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e).with_context(|| format!("{}: cannot write", tmp.display()));
    }
    // Move the old directory aside (if any), the new one in, then drop the old one. If the
    // second rename fails the old one goes back.
    let had_old = dir.exists();
    let swapped = (|| -> std::io::Result<()> {
        if had_old {
            std::fs::rename(dir, &old)?;
        }
        if let Err(e) = std::fs::rename(&tmp, dir) {
            if had_old {
                let _ = std::fs::rename(&old, dir);
            }
            return Err(e);
        }
        Ok(())
    })();
    if let Err(e) = swapped {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e).with_context(|| format!("{}: cannot write", dir.display()));
    }
    if had_old {
        // The new directory is in place; a leftover old one is only clutter.
        let _ = std::fs::remove_dir_all(&old);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files(names: &[&str]) -> Vec<(String, Vec<u8>)> {
        names
            .iter()
            .map(|n| (n.to_string(), n.as_bytes().to_vec()))
            .collect()
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_directory_is_written_whole_and_replaced_whole() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("a/b/out");
        write_dir_atomic(&out, &files(&["m.txt", "1.png", "2.png"]), "m.txt").unwrap();
        assert_eq!(listing(&out), ["1.png", "2.png", "m.txt"]);
        // A second run replaces all of it: no file of the first run is left.
        write_dir_atomic(&out, &files(&["m.txt", "3.png"]), "m.txt").unwrap();
        assert_eq!(listing(&out), ["3.png", "m.txt"]);
        assert_eq!(std::fs::read(out.join("3.png")).unwrap(), b"3.png");
        // No temporaries beside it.
        assert_eq!(listing(&root.path().join("a/b")), ["out"]);
        // An empty directory is fine too.
        let empty = root.path().join("empty");
        std::fs::create_dir(&empty).unwrap();
        write_dir_atomic(&empty, &files(&["m.txt"]), "m.txt").unwrap();
        assert_eq!(listing(&empty), ["m.txt"]);
    }

    #[test]
    fn someone_elses_directory_is_left_alone() {
        let root = tempfile::tempdir().unwrap();
        let theirs = root.path().join("theirs");
        std::fs::create_dir(&theirs).unwrap();
        std::fs::write(theirs.join("thesis.tex"), b"x").unwrap();
        let err = write_dir_atomic(&theirs, &files(&["m.txt"]), "m.txt").unwrap_err();
        assert!(
            format!("{err:#}").contains("not written by this command"),
            "{err:#}"
        );
        assert_eq!(listing(&theirs), ["thesis.tex"]);
        let file = root.path().join("file");
        std::fs::write(&file, b"x").unwrap();
        assert!(write_dir_atomic(&file, &files(&["m.txt"]), "m.txt").is_err());
        for bad in ["../x", "a/b", ".hidden", ""] {
            assert!(
                write_dir_atomic(&root.path().join("o"), &files(&["m.txt", bad]), "m.txt").is_err()
            );
        }
        assert!(write_dir_atomic(&root.path().join("o"), &files(&["a.png"]), "m.txt").is_err());
        assert_eq!(listing(root.path()), ["file", "theirs"]);
    }
}
