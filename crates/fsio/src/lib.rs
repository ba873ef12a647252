//! Files in and out.
//!
//! **Out.** Every output is written to a temporary file beside its destination and renamed, so
//! a reader (or a crash) never sees a partial file ([`write_atomic`]). Replacing a file keeps
//! its permissions, and a symbolic link is written through (its target is replaced, the link
//! stays). Outputs of several files (plots, frames) are written into a temporary directory and
//! moved into place as a whole ([`StagedDir`]). Temporaries are registered while they exist:
//! SIGINT, SIGTERM and SIGHUP remove them before the process exits ([`install_signal_cleanup`]),
//! and the temporaries of a process that died without cleaning up (SIGKILL, power loss) are
//! removed by the next run that writes into the same directory.
//!
//! **In.** Every input file is read through [`read_bytes`] / [`read_text`]: regular files only
//! (not `/dev/zero`, a FIFO or a directory) and at most [`InputLimits::max_file_bytes`], so no
//! input makes the program read without end. The limits are set once from the command line
//! ([`set_input_limits`]; `--max-input-mb`, `--allow-external-uris`).

use std::collections::HashSet;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Mutex, PoisonError};

/// A file could not be read or written, or an output was refused before anything was written.
/// Every message names the path.
#[derive(Debug, thiserror::Error)]
pub enum FsError {
    /// An operating-system call failed on `path`.
    #[error("{}: cannot {action}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What was being done ("write", "create", "list", …).
        action: &'static str,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The output was refused (what and why, with the path, in the message).
    #[error("{0}")]
    Refused(String),
}

impl FsError {
    fn io(path: &Path, action: &'static str, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            action,
            source,
        }
    }
}

/// `Err(FsError::Refused(message))` unless `condition` holds.
macro_rules! refuse_unless {
    ($condition:expr, $($message:tt)+) => {
        if !$condition {
            return Err(FsError::Refused(format!($($message)+)));
        }
    };
}

// ---------------------------------------------------------------------------------------------
// Input

/// Default largest input file, MiB (`--max-input-mb`).
pub const DEFAULT_MAX_INPUT_MB: u64 = 1024;

/// Default largest configuration file (model, parameter set, column map, sensor errors),
/// MiB (`--max-config-mb`): such files are a few kB, and a TOML reader may take several
/// times a file's size in memory.
pub const DEFAULT_MAX_CONFIG_MB: u64 = 16;

/// What input files may be: set once at start-up from the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InputLimits {
    /// Largest file read, bytes.
    pub max_file_bytes: u64,
    /// Largest configuration file read ([`read_config_text`]), bytes.
    pub max_config_bytes: u64,
    /// Whether a glTF file may name buffers outside its own directory (absolute paths,
    /// `file://` URIs, `..`).
    pub allow_external_uris: bool,
}

impl Default for InputLimits {
    fn default() -> Self {
        Self {
            max_file_bytes: DEFAULT_MAX_INPUT_MB << 20,
            max_config_bytes: DEFAULT_MAX_CONFIG_MB << 20,
            allow_external_uris: false,
        }
    }
}

static MAX_FILE_BYTES: AtomicU64 = AtomicU64::new(DEFAULT_MAX_INPUT_MB << 20);
static MAX_CONFIG_BYTES: AtomicU64 = AtomicU64::new(DEFAULT_MAX_CONFIG_MB << 20);
static ALLOW_EXTERNAL_URIS: AtomicBool = AtomicBool::new(false);

/// Set the input limits of this process (the command line does, once).
pub fn set_input_limits(limits: InputLimits) {
    MAX_FILE_BYTES.store(limits.max_file_bytes, Ordering::Relaxed);
    MAX_CONFIG_BYTES.store(limits.max_config_bytes, Ordering::Relaxed);
    ALLOW_EXTERNAL_URIS.store(limits.allow_external_uris, Ordering::Relaxed);
}

/// The input limits in force.
pub fn input_limits() -> InputLimits {
    InputLimits {
        max_file_bytes: MAX_FILE_BYTES.load(Ordering::Relaxed),
        max_config_bytes: MAX_CONFIG_BYTES.load(Ordering::Relaxed),
        allow_external_uris: ALLOW_EXTERNAL_URIS.load(Ordering::Relaxed),
    }
}

/// Open an input file for reading, refusing anything but a regular file (following symbolic
/// links) without waiting on it: a FIFO would block a plain open until a writer comes.
///
/// # Errors
/// The OS error, or `InvalidInput` saying what the path is instead.
pub fn open_regular(path: &Path) -> std::io::Result<std::fs::File> {
    use std::io::{Error, ErrorKind};
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, libc::O_NONBLOCK);
    let file = options.open(path)?;
    let meta = file.metadata()?;
    if meta.is_dir() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "is a directory, not a file",
        ));
    }
    if !meta.is_file() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "not a regular file (a device, FIFO or socket is not read)",
        ));
    }
    Ok(file)
}

/// Read a whole input file: a regular file (following symbolic links) of at most
/// [`InputLimits::max_file_bytes`].
///
/// # Errors
/// The OS error, or `InvalidInput` saying that the path is not a regular file or is larger than
/// the limit (and how to raise it). The message does not repeat the path.
pub fn read_bytes(path: &Path) -> std::io::Result<Vec<u8>> {
    read_bounded(
        path,
        MAX_FILE_BYTES.load(Ordering::Relaxed),
        "--max-input-mb",
    )
}

/// [`read_bytes`] with the limit `limit` bytes, which `option` raises.
fn read_bounded(path: &Path, limit: u64, option: &str) -> std::io::Result<Vec<u8>> {
    use std::io::{Error, ErrorKind};
    let file = open_regular(path)?;
    let meta = file.metadata()?;
    let too_big = |size: u64| {
        Error::new(
            ErrorKind::InvalidInput,
            format!(
                "the file is {size} bytes, more than the limit of {limit} bytes (raise it with \
                 {option})"
            ),
        )
    };
    if meta.len() > limit {
        return Err(too_big(meta.len()));
    }
    // The file may grow while it is read: read one byte more than the limit to tell.
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

/// [`read_bytes`] as UTF-8 text.
///
/// # Errors
/// As [`read_bytes`], and `InvalidData` naming the line of the first byte that is not UTF-8.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    utf8(read_bytes(path)?)
}

/// A configuration file (a model, parameter set, column map or sensor-error spec) as UTF-8
/// text: [`read_text`] under [`InputLimits::max_config_bytes`] (`--max-config-mb`), far
/// below the limit of flight data.
///
/// # Errors
/// As [`read_text`].
pub fn read_config_text(path: &Path) -> std::io::Result<String> {
    let limit = MAX_CONFIG_BYTES.load(Ordering::Relaxed);
    utf8(read_bounded(path, limit, "--max-config-mb")?)
}

/// Bytes as UTF-8 text, or `InvalidData` naming the line of the first byte that is not.
fn utf8(bytes: Vec<u8>) -> std::io::Result<String> {
    String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("not UTF-8 text (line {line})"),
        )
    })
}

/// Whether `a` and `b` name one file on disk, under any spelling, symbolic link or hard link
/// (the same device and inode). False when either cannot be looked at.
pub fn is_same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => same_identity(&x, &y, a, b),
        _ => false,
    }
}

#[cfg(unix)]
fn same_identity(x: &std::fs::Metadata, y: &std::fs::Metadata, _: &Path, _: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    x.dev() == y.dev() && x.ino() == y.ino()
}

#[cfg(not(unix))]
fn same_identity(_: &std::fs::Metadata, _: &std::fs::Metadata, a: &Path, b: &Path) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
}

/// Whether `a` and `b` are regular files holding the same bytes: a copy is the same data
/// under another name. Read in chunks, the sizes compared first; false when either cannot
/// be read.
pub fn same_contents(a: &Path, b: &Path) -> bool {
    let (Ok(mut x), Ok(mut y)) = (open_regular(a), open_regular(b)) else {
        return false;
    };
    match (x.metadata(), y.metadata()) {
        (Ok(mx), Ok(my)) if mx.len() == my.len() => {}
        _ => return false,
    }
    let (mut bx, mut by) = (vec![0u8; 1 << 16], vec![0u8; 1 << 16]);
    loop {
        let (Ok(n), Ok(m)) = (read_full(&mut x, &mut bx), read_full(&mut y, &mut by)) else {
            return false;
        };
        if n != m || bx[..n] != by[..m] {
            return false;
        }
        if n < bx.len() {
            return true;
        }
    }
}

/// Reads until `buf` is full or the end: the bytes read.
fn read_full(r: &mut impl std::io::Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match r.read(&mut buf[n..])? {
            0 => break,
            k => n += k,
        }
    }
    Ok(n)
}

/// The memory this process may still allocate, bytes, as far as the system says: the least of
/// `MemAvailable` (`/proc/meminfo`) and the room left under the control group's limit (cgroup
/// v2 `memory.max` − `memory.current`, or v1 `memory.limit_in_bytes` − `memory.usage_in_bytes`).
/// `None` where none of them can be read (not Linux).
pub fn available_memory() -> Option<u64> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let number = |p: &str| read(p).and_then(|t| t.trim().parse::<u64>().ok());
    let mut best: Option<u64> = None;
    let mut take = |v: u64| best = Some(best.map_or(v, |b| b.min(v)));
    if let Some(info) = read("/proc/meminfo") {
        if let Some(kb) = info.lines().find_map(|l| {
            l.strip_prefix("MemAvailable:")
                .and_then(|r| r.trim().strip_suffix("kB"))
                .and_then(|v| v.trim().parse::<u64>().ok())
        }) {
            take(kb.saturating_mul(1024));
        }
    }
    for (limit, usage) in [
        ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),
        (
            "/sys/fs/cgroup/memory/memory.limit_in_bytes",
            "/sys/fs/cgroup/memory/memory.usage_in_bytes",
        ),
    ] {
        // "max" (no limit) does not parse and is skipped.
        if let (Some(limit), Some(usage)) = (number(limit), number(usage)) {
            take(limit.saturating_sub(usage));
        }
    }
    // The process's own address-space limit (`ulimit -v`), less what it maps already: an
    // allocation past it aborts however much memory the machine has.
    if let Some(room) = address_space_room(|p| read(p)) {
        take(room);
    }
    best
}

/// Room left under the soft `RLIMIT_AS` (none when unlimited or unknown): the limit less
/// the process's virtual size (`/proc/self/statm`, pages).
fn address_space_room(read: impl Fn(&str) -> Option<String>) -> Option<u64> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: `getrlimit` writes the limit into the struct it is given.
    if unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } != 0
        || limit.rlim_cur == libc::RLIM_INFINITY
    {
        return None;
    }
    // SAFETY: `sysconf` only reads a configuration value.
    let page = u64::try_from(unsafe { libc::sysconf(libc::_SC_PAGESIZE) }).unwrap_or(4096);
    let mapped = read("/proc/self/statm")
        .and_then(|t| t.split_whitespace().next()?.parse::<u64>().ok())
        .map_or(0, |pages| pages.saturating_mul(page));
    Some(limit.rlim_cur.saturating_sub(mapped))
}

// ---------------------------------------------------------------------------------------------
// Temporaries

/// Temporaries (files and directories) that exist now; removed by the signal handler.
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Directories already swept of dead processes' temporaries by this process.
static SWEPT: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);

fn register(path: &Path) {
    TEMPORARIES
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .push(path.to_path_buf());
}

fn unregister(path: &Path) {
    TEMPORARIES
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .retain(|p| p != path);
}

static SIGNALLED: AtomicBool = AtomicBool::new(false);

/// Whether a signal is ending the process: the signal thread is removing the temporaries and
/// will exit with the signal's status (a failure the removal caused on another thread is not
/// to be reported, nor another exit status given).
pub fn signalled() -> bool {
    SIGNALLED.load(Ordering::SeqCst)
}

/// Remove every registered temporary (files and directories); used on signals.
pub fn remove_temporaries() {
    let list = std::mem::take(&mut *TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner));
    for p in list {
        // Another thread may still be writing into a temporary directory: try again while
        // files appear in it.
        for _ in 0..50 {
            if std::fs::remove_dir_all(&p)
                .or_else(|_| std::fs::remove_file(&p))
                .is_ok()
                || std::fs::symlink_metadata(&p).is_err()
            {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
    }
}

/// Install the handler that removes the temporaries on SIGINT, SIGTERM and SIGHUP and exits
/// with 128 + the signal's number (the shell's status for it). Call once, from `main`.
///
/// # Errors
/// The OS refused the handler.
pub fn install_signal_cleanup() -> Result<(), FsError> {
    #[cfg(unix)]
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    #[cfg(unix)]
    let wanted = [SIGINT, SIGTERM, SIGHUP];
    #[cfg(not(unix))]
    let wanted = [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM];
    let mut signals = signal_hook::iterator::Signals::new(wanted)
        .map_err(|e| FsError::io(Path::new("signal handler"), "install", e))?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                SIGNALLED.store(true, Ordering::SeqCst);
                remove_temporaries();
                std::process::exit(128 + signal);
            }
        })
        .map_err(|e| FsError::io(Path::new("signal thread"), "start", e))?;
    Ok(())
}

/// What every temporary's name carries between the destination's name and the PID: the mark
/// that says wireflight wrote it (`.NAME.wireflight.tmp-PID`). The sweep removes nothing
/// without it, so `.notes.tmp-123` of another program is never touched.
const TEMP_MARK: &str = ".wireflight.tmp-";

/// The file inside a staged directory that says wireflight made it (removed before the
/// directory is moved into place). The sweep removes a directory only when it holds this file.
const STAGED_MARKER: &str = ".wireflight-staged";

/// The name of this process's temporary for `name`: `.NAME.wireflight.tmp-PID`.
fn temp_name(name: &str) -> String {
    format!(".{name}{TEMP_MARK}{}", std::process::id())
}

/// The PID in a temporary's name (`.NAME.wireflight.tmp-PID`), if `name` is one.
fn temp_pid(name: &str) -> Option<u32> {
    let (stem, pid) = name.strip_prefix('.')?.rsplit_once(TEMP_MARK)?;
    if stem.is_empty() || pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// Whether the process `pid` is alive (Linux: `/proc/PID`; elsewhere assumed alive unless the
/// temporary is a day old).
fn alive(pid: u32, modified: Option<std::time::SystemTime>) -> bool {
    if Path::new("/proc/self").exists() {
        return Path::new("/proc").join(pid.to_string()).exists();
    }
    modified
        .and_then(|m| m.elapsed().ok())
        .is_none_or(|age| age.as_secs() < 86_400)
}

/// Whether `meta` belongs to the user running this process (Linux: the owner of `/proc/self`
/// is the effective user; elsewhere not checked).
fn owned_by_us(meta: &std::fs::Metadata) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let Ok(me) = std::fs::metadata("/proc/self") {
            return meta.uid() == me.uid();
        }
    }
    let _ = meta;
    true
}

/// Remove the temporaries that dead wireflight processes left in `dir`, once per directory and
/// process. Only what wireflight provably wrote goes: a name `.NAME.wireflight.tmp-PID` of a
/// dead PID, owned by this user, and either a regular file or a directory holding the
/// staging marker. Anything else (another program's `.x.tmp-1`, a symbolic link, someone
/// else's file) is left alone.
fn sweep(dir: &Path) {
    {
        let mut swept = SWEPT.lock().unwrap_or_else(PoisonError::into_inner);
        if !swept
            .get_or_insert_with(HashSet::new)
            .insert(dir.to_path_buf())
        {
            return;
        }
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some(pid) = temp_pid(name) else { continue };
        if pid == std::process::id() {
            continue;
        }
        let p = entry.path();
        // Not following a symbolic link.
        let Ok(meta) = std::fs::symlink_metadata(&p) else {
            continue;
        };
        if !owned_by_us(&meta) || alive(pid, meta.modified().ok()) {
            continue;
        }
        if meta.file_type().is_file() {
            let _ = std::fs::remove_file(&p);
        } else if meta.file_type().is_dir()
            && std::fs::symlink_metadata(p.join(STAGED_MARKER)).is_ok_and(|m| m.is_file())
        {
            let _ = std::fs::remove_dir_all(&p);
        }
    }
}

fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// What a path that is not a regular file is, in words: `a device`, `a FIFO`, `a socket`,
/// `a directory`.
pub fn describe(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a directory"
    } else {
        "not a plain file"
    }
}

/// `text` safe to print on a terminal: every control character except newline and tab is
/// written as an escape (`\u{1b}` for ESC), so a file name or a field read from a file cannot
/// set the terminal's title, move the cursor or clear the screen. Text without control
/// characters is returned as it is.
pub fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    let unsafe_char = |c: char| c.is_control() && c != '\n' && c != '\t';
    if !text.chars().any(unsafe_char) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if unsafe_char(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

// ---------------------------------------------------------------------------------------------
// Output

/// Write `bytes` to `path` atomically: into a temporary file beside it, then rename. An
/// existing file keeps its permissions; a symbolic link is written through.
///
/// # Errors
/// I/O errors, with the path in the message.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), FsError> {
    // `out/`: a directory's name, not a file's (renaming onto it says only "Not a
    // directory").
    refuse_unless!(
        !path.as_os_str().as_encoded_bytes().ends_with(b"/"),
        "{}: ends in `/`, which names a directory; give the name of a file to write",
        path.display()
    );
    // Through a symbolic link: replace what it points to.
    let target = match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path)
            .map_err(|e| FsError::io(path, "follow the symbolic link", e))?,
        _ => path.to_path_buf(),
    };
    let dir = parent_dir(&target);
    let name = target
        .file_name()
        .ok_or_else(|| FsError::Refused(format!("{}: not a file path", path.display())))?;
    // Only a regular file is replaced: renaming over a device (`/dev/null`), a FIFO or a
    // socket would put a plain file in its place.
    if let Ok(meta) = std::fs::metadata(&target) {
        refuse_unless!(
            meta.is_file(),
            "{}: exists and is not a regular file ({}); an output replaces only a regular \
             file, so name a new file",
            path.display(),
            describe(&meta)
        );
    }
    sweep(dir);
    let tmp = dir.join(temp_name(&name.to_string_lossy()));
    let old_mode = std::fs::metadata(&target).ok().map(|m| m.permissions());
    register(&tmp);
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        if let Some(mode) = old_mode {
            f.set_permissions(mode)?;
        }
        f.sync_all()?;
        std::fs::rename(&tmp, &target)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    unregister(&tmp);
    result.map_err(|e| FsError::io(path, "write", e))
}

/// Write a directory of files as a whole through a [`StagedDir`]: a reader (or a crash) sees
/// either all of them or none.
///
/// `marker` names one of `files` that says who wrote the directory (e.g. a manifest). An
/// existing `dir` is replaced only when it is empty or holds a file of that name, i.e. was
/// written by an earlier run of the same command; anything else is refused, so that a mistyped
/// output path never deletes someone's directory.
///
/// # Errors
/// A file name that is not a plain name, `marker` not among `files`, `dir` existing as a file
/// or as a directory of something else, I/O errors; each with the path in the message. The
/// temporary directory is removed on failure.
pub fn write_dir_atomic(
    dir: &Path,
    files: &[(String, Vec<u8>)],
    marker: &str,
) -> Result<(), FsError> {
    for (name, _) in files {
        let plain = Path::new(name)
            .file_name()
            .is_some_and(|f| f == std::ffi::OsStr::new(name));
        refuse_unless!(
            plain && !name.starts_with('.'),
            "`{name}` is not a plain file name"
        );
    }
    refuse_unless!(
        files.iter().any(|(n, _)| n == marker),
        "the marker file `{marker}` is not among the files to write"
    );
    if dir.is_dir() {
        let mut entries = std::fs::read_dir(dir).map_err(|e| FsError::io(dir, "read", e))?;
        let empty = entries.next().is_none();
        refuse_unless!(
            empty || dir.join(marker).is_file(),
            "{}: exists and was not written by this command (no `{marker}` in it); choose a \
             new or empty directory",
            dir.display()
        );
        if !empty {
            only_listed_files(dir, marker)?;
        }
    }
    let staged = StagedDir::new(dir)?;
    for (file, bytes) in files {
        let path = staged.path().join(file);
        let written = std::fs::File::create(&path).and_then(|mut f| {
            f.write_all(bytes)?;
            f.sync_all()
        });
        written.map_err(|e| FsError::io(&path, "write", e))?;
    }
    // The marker vouches for the directory as a whole (its files are this command's).
    staged.commit_replace(|_| true)
}

/// Refuses a directory holding a file its `marker` does not list (the first tab-separated
/// field of each line that is not a `#` comment): a file the user put there beside an earlier
/// run's outputs would be lost when the directory is replaced.
fn only_listed_files(dir: &Path, marker: &str) -> Result<(), FsError> {
    let listing =
        read_text(&dir.join(marker)).map_err(|e| FsError::io(&dir.join(marker), "read", e))?;
    let listed: HashSet<&str> = listing
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| l.split('\t').next())
        .chain([marker])
        .collect();
    let entries = std::fs::read_dir(dir).map_err(|e| FsError::io(dir, "read", e))?;
    for entry in entries {
        let entry = entry.map_err(|e| FsError::io(dir, "read", e))?;
        let name = entry.file_name();
        let name = name.to_string_lossy();
        refuse_unless!(
            listed.contains(name.as_ref()),
            "{}: holds `{name}`, which its `{marker}` does not list (not an output of this \
             command); the directory is replaced as a whole, so name a new or empty one",
            dir.display()
        );
    }
    Ok(())
}

/// An output directory written as a whole: files go into a temporary directory beside it
/// (`.NAME.wireflight.tmp-PID`), and [`commit_merge`](Self::commit_merge) or
/// [`commit_replace`](Self::commit_replace) moves them into place. Dropped without a commit
/// (an error on the way), the temporary directory is removed and the destination is untouched.
#[derive(Debug)]
pub struct StagedDir {
    dest: PathBuf,
    tmp: PathBuf,
    committed: bool,
}

impl StagedDir {
    /// Stage the output directory `dest`.
    ///
    /// # Errors
    /// `dest` exists and is not a directory, or the temporary directory cannot be made.
    pub fn new(dest: &Path) -> Result<Self, FsError> {
        if dest.exists() && !dest.is_dir() {
            return Err(FsError::Refused(format!(
                "{}: exists and is not a directory",
                dest.display()
            )));
        }
        let abs = if dest.is_absolute() {
            dest.to_path_buf()
        } else {
            std::env::current_dir()
                .map_err(|e| FsError::io(Path::new("."), "find the working directory", e))?
                .join(dest)
        };
        let name = abs
            .components()
            .next_back()
            .and_then(|c| match c {
                std::path::Component::Normal(n) => Some(n.to_string_lossy().into_owned()),
                _ => None,
            })
            .ok_or_else(|| {
                FsError::Refused(format!(
                    "{}: name a directory (not `.`, `..` or `/`) for the output",
                    dest.display()
                ))
            })?;
        let parent = parent_dir(&abs).to_path_buf();
        std::fs::create_dir_all(&parent).map_err(|e| FsError::io(&parent, "create", e))?;
        sweep(&parent);
        let tmp = parent.join(temp_name(&name));
        let _ = std::fs::remove_dir_all(&tmp);
        register(&tmp);
        std::fs::create_dir(&tmp).map_err(|e| FsError::io(&tmp, "create", e))?;
        let marker = tmp.join(STAGED_MARKER);
        std::fs::write(&marker, b"").map_err(|e| FsError::io(&marker, "create", e))?;
        Ok(Self {
            dest: dest.to_path_buf(),
            tmp,
            committed: false,
        })
    }

    /// Where to write the files now.
    pub fn path(&self) -> &Path {
        &self.tmp
    }

    /// The destination.
    pub fn dest(&self) -> &Path {
        &self.dest
    }

    /// Move every staged file into the destination (created if needed), replacing files of the
    /// same name and keeping the others.
    ///
    /// # Errors
    /// I/O errors, naming the file.
    pub fn commit_merge(mut self) -> Result<(), FsError> {
        self.unmark()?;
        std::fs::create_dir_all(&self.dest).map_err(|e| FsError::io(&self.dest, "create", e))?;
        for entry in std::fs::read_dir(&self.tmp).map_err(|e| FsError::io(&self.tmp, "list", e))? {
            let entry = entry.map_err(|e| FsError::io(&self.tmp, "list", e))?;
            let to = self.dest.join(entry.file_name());
            std::fs::rename(entry.path(), &to).map_err(|e| FsError::io(&to, "write", e))?;
        }
        self.finish();
        Ok(())
    }

    /// Replace the destination by the staged directory as a whole. The destination, if it
    /// exists, may hold only files that `ours` recognises (earlier outputs of the same kind);
    /// anything else is refused rather than deleted.
    ///
    /// # Errors
    /// The destination holds other files, or I/O errors.
    pub fn commit_replace(mut self, ours: impl Fn(&str) -> bool) -> Result<(), FsError> {
        self.unmark()?;
        if self.dest.is_dir() {
            let listing =
                std::fs::read_dir(&self.dest).map_err(|e| FsError::io(&self.dest, "list", e))?;
            for entry in listing {
                let entry = entry.map_err(|e| FsError::io(&self.dest, "list", e))?;
                let name = entry.file_name();
                let name = name.to_string_lossy();
                if !ours(&name) || !entry.file_type().is_ok_and(|t| t.is_file()) {
                    return Err(FsError::Refused(format!(
                        "{}: holds `{name}`, which is not an output of this kind; the \
                         directory is replaced as a whole, so name a new or empty one",
                        self.dest.display()
                    )));
                }
            }
            let old = parent_dir(&self.tmp).join(format!(
                ".{}.old-{}",
                self.tmp
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                std::process::id()
            ));
            std::fs::rename(&self.dest, &old).map_err(|e| FsError::io(&self.dest, "replace", e))?;
            register(&old);
            let moved = std::fs::rename(&self.tmp, &self.dest);
            if moved.is_err() {
                let _ = std::fs::rename(&old, &self.dest);
            }
            let _ = std::fs::remove_dir_all(&old);
            unregister(&old);
            moved.map_err(|e| FsError::io(&self.dest, "write", e))?;
        } else {
            std::fs::rename(&self.tmp, &self.dest)
                .map_err(|e| FsError::io(&self.dest, "write", e))?;
        }
        self.finish();
        Ok(())
    }

    /// Remove the staging marker before the directory's files are moved into place.
    fn unmark(&self) -> Result<(), FsError> {
        let marker = self.tmp.join(STAGED_MARKER);
        match std::fs::remove_file(&marker) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                Err(FsError::io(&marker, "remove", e))
            }
            _ => Ok(()),
        }
    }

    fn finish(&mut self) {
        self.committed = true;
        let _ = std::fs::remove_dir_all(&self.tmp);
        unregister(&self.tmp);
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.tmp);
            unregister(&self.tmp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Files named `names`, each holding its name; a marker `m.txt` among them lists the
    /// others, one a line, as the commands' markers do.
    fn files(names: &[&str]) -> Vec<(String, Vec<u8>)> {
        let listing: String = names.iter().map(|n| format!("{n}\tpicture\n")).collect();
        names
            .iter()
            .map(|n| {
                let bytes = match *n {
                    "m.txt" => format!("# a marker\n{listing}").into_bytes(),
                    _ => n.as_bytes().to_vec(),
                };
                (n.to_string(), bytes)
            })
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
        // A file the marker does not list (the user's) is not replaced with the rest.
        std::fs::write(out.join("mine.png"), b"mine").unwrap();
        let err = write_dir_atomic(&out, &files(&["m.txt", "4.png"]), "m.txt").unwrap_err();
        assert!(format!("{err:#}").contains("holds `mine.png`"), "{err:#}");
        assert_eq!(listing(&out), ["3.png", "m.txt", "mine.png"]);
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

    #[test]
    fn atomic_write_keeps_the_mode_and_writes_through_links() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("t.txt");
        std::fs::write(&target, "old").unwrap();
        std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o640)).unwrap();
        let link = dir.path().join("link.txt");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
        let mode = std::fs::metadata(&target).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o640);
    }

    #[test]
    fn dead_processes_temporaries_are_swept() {
        let dir = tempfile::tempdir().unwrap();
        // PID beyond pid_max: never alive.
        let stale = dir.path().join(".out.csv.wireflight.tmp-4294967295");
        std::fs::write(&stale, "partial").unwrap();
        let stale_dir = dir.path().join(".plots.wireflight.tmp-4294967294");
        std::fs::create_dir(&stale_dir).unwrap();
        std::fs::write(stale_dir.join(STAGED_MARKER), b"").unwrap();
        std::fs::write(stale_dir.join("a.png"), b"x").unwrap();
        write_atomic(&dir.path().join("other.csv"), b"x").unwrap();
        assert!(!stale.exists() && !stale_dir.exists());
    }

    #[test]
    fn the_sweep_leaves_what_wireflight_did_not_write() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // Another program's temporaries, with a dead PID.
        std::fs::write(d.join(".notes.tmp-4294967295"), b"mine").unwrap();
        std::fs::create_dir(d.join(".work.tmp-4294967294")).unwrap();
        std::fs::write(d.join(".work.tmp-4294967294/keep"), b"x").unwrap();
        // wireflight's name, but a directory without the staging marker, and a link.
        std::fs::create_dir(d.join(".data.wireflight.tmp-4294967293")).unwrap();
        std::fs::write(d.join("target"), b"t").unwrap();
        std::os::unix::fs::symlink(d.join("target"), d.join(".l.wireflight.tmp-4294967292"))
            .unwrap();
        std::fs::write(d.join(".x.wireflight.tmp-12a"), b"x").unwrap();
        write_atomic(&d.join("new.csv"), b"x").unwrap();
        assert_eq!(
            listing(d),
            [
                ".data.wireflight.tmp-4294967293",
                ".l.wireflight.tmp-4294967292",
                ".notes.tmp-4294967295",
                ".work.tmp-4294967294",
                ".x.wireflight.tmp-12a",
                "new.csv",
                "target"
            ]
        );
        assert!(d.join(".work.tmp-4294967294/keep").exists());
    }

    #[test]
    fn outputs_never_replace_devices_or_fifos() {
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let err = write_atomic(&fifo, b"x").unwrap_err();
        assert!(format!("{err}").contains("not a regular file"), "{err}");
        assert!(std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo());
        // A link to a device: refused before anything is written; /dev/null stays a device.
        let link = dir.path().join("null");
        std::os::unix::fs::symlink("/dev/null", &link).unwrap();
        assert!(write_atomic(&link, b"x").is_err());
        assert!(write_atomic(Path::new("/dev/null"), b"x").is_err());
        assert!(std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device());
        assert_eq!(listing(dir.path()), ["null", "pipe"]);
        // A directory is no file either.
        std::fs::create_dir(dir.path().join("d")).unwrap();
        assert!(write_atomic(&dir.path().join("d"), b"x").is_err());
    }

    #[test]
    fn staged_directories_carry_no_marker_into_place() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let staged = StagedDir::new(&out).unwrap();
        std::fs::write(staged.path().join("a.png"), b"x").unwrap();
        staged.commit_replace(|_| true).unwrap();
        assert_eq!(listing(&out), ["a.png"]);
        let staged = StagedDir::new(&out).unwrap();
        std::fs::write(staged.path().join("b.png"), b"x").unwrap();
        staged.commit_merge().unwrap();
        assert_eq!(listing(&out), ["a.png", "b.png"]);
    }

    #[test]
    fn printable_escapes_control_characters() {
        assert!(matches!(
            printable("plain\ttext\n"),
            std::borrow::Cow::Borrowed(_)
        ));
        assert_eq!(
            printable("a\u{1b}]0;pwned\u{7}b\r\u{9b}2J\nc"),
            r"a\u{1b}]0;pwned\u{7}b\r\u{9b}2J".to_string() + "\nc"
        );
    }

    #[test]
    fn reads_refuse_devices_directories_and_big_files() {
        let dir = tempfile::tempdir().unwrap();
        assert!(read_bytes(Path::new("/dev/zero")).is_err());
        assert!(read_bytes(dir.path()).is_err());
        let f = dir.path().join("big");
        std::fs::write(&f, vec![b'x'; 100]).unwrap();
        assert_eq!(read_bytes(&f).unwrap().len(), 100);
    }
}
