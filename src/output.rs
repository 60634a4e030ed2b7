//! Writing the tool's files without ever losing one: where an output goes is settled before
//! the run (never onto the input or onto another output), a regular file is written beside
//! its path and renamed over it only when whole, and links, pipes and devices are written
//! through. `-` is standard output.

use std::ffi::OsString;
use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The hidden files being written, for [`remove_hidden_files`] on a forced exit.
static HIDDEN: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn forget_hidden(path: &Path) {
    if let Ok(mut hidden) = HIDDEN.lock() {
        hidden.retain(|p| p != path);
    }
}

/// Removes every hidden file still being written: for a process about to exit at once (a
/// second Ctrl-C), so that no partial file is left behind.
pub fn remove_hidden_files() {
    if let Ok(hidden) = HIDDEN.lock() {
        for p in hidden.iter() {
            let _ = std::fs::remove_file(p);
        }
    }
}

/// Where an output goes, settled before anything is written.
#[derive(Debug, PartialEq, Eq)]
pub enum Target {
    /// Standard output (`-`).
    Stdout,
    /// A regular file (or none yet): written beside it, then renamed over it.
    File(PathBuf),
    /// A pipe, a device or a socket: written through, as it is.
    Special(PathBuf),
}

/// Whether `path` names standard input or output.
pub fn is_dash(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// The path `path` resolves to (its links followed), for telling two names of one file apart;
/// a path that does not exist yet resolves through its folder.
fn identity(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = std::fs::canonicalize(path) {
        return Some(p);
    }
    let name = path.file_name()?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::canonicalize(dir).ok().map(|d| d.join(name))
}

/// Settles where each named output goes. `input` is the file read (None for standard
/// input); `outputs` are (option name, path). Refuses an output that is the input, two
/// outputs on one file, two on standard output, and a folder.
pub fn plan_outputs(
    input: Option<&Path>,
    outputs: &[(&str, &Path)],
) -> Result<Vec<Target>, String> {
    let input_id = input.and_then(identity);
    let mut seen: Vec<(&str, Option<PathBuf>)> = Vec::new();
    let mut targets = Vec::with_capacity(outputs.len());
    for &(option, path) in outputs {
        if is_dash(path) {
            if let Some((other, _)) = seen.iter().find(|(_, id)| id.is_none()) {
                return Err(format!("{option} -: {other} also goes to standard output"));
            }
            seen.push((option, None));
            targets.push(Target::Stdout);
            continue;
        }
        let shown = path.display();
        if path.as_os_str().is_empty() {
            return Err(format!("{option}: the path is empty"));
        }
        let meta = std::fs::metadata(path).ok();
        if meta.as_ref().is_some_and(|m| m.is_dir()) {
            return Err(format!("{option} {shown}: is a folder"));
        }
        let id = identity(path);
        if let (Some(i), Some(o)) = (&input_id, &id)
            && i == o
        {
            return Err(format!(
                "{option} {shown}: is the scene file being read; choose another path"
            ));
        }
        if let Some((other, _)) = seen
            .iter()
            .find(|(_, other)| other.is_some() && *other == id)
        {
            return Err(format!("{option} {shown}: is also the {other} file"));
        }
        seen.push((option, id.clone()));
        targets.push(match meta {
            Some(m) if !m.is_file() => Target::Special(path.to_path_buf()),
            // A link to a regular file: the file is replaced, the link stays.
            Some(_) => Target::File(id.unwrap_or_else(|| path.to_path_buf())),
            None => Target::File(dangling_target(path).unwrap_or_else(|| path.to_path_buf())),
        });
    }
    Ok(targets)
}

/// Where a link that points at nothing yet points: the file is made there, the link stays.
fn dangling_target(path: &Path) -> Option<PathBuf> {
    let meta = std::fs::symlink_metadata(path).ok()?;
    if !meta.file_type().is_symlink() {
        return None;
    }
    let to = std::fs::read_link(path).ok()?;
    Some(match path.parent() {
        Some(dir) if to.is_relative() => dir.join(to),
        _ => to,
    })
}

/// An output being written. A regular file is written to a hidden file beside it and takes
/// its place only at [`Output::commit`]; dropped without a commit, the hidden file is removed
/// and the path keeps what it had.
pub struct Output {
    writer: BufWriter<Box<dyn Write>>,
    /// (hidden file, final path) for a regular file.
    rename: Option<(PathBuf, PathBuf)>,
}

impl Output {
    /// Opens `target` for writing.
    pub fn open(target: &Target) -> io::Result<Output> {
        let (sink, rename): (Box<dyn Write>, _) = match target {
            Target::Stdout => (Box::new(io::stdout().lock()), None),
            Target::Special(path) => (Box::new(OpenOptions::new().write(true).open(path)?), None),
            Target::File(path) => {
                if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                    std::fs::create_dir_all(dir)?;
                }
                let hidden = hidden_beside(path);
                let file = File::create(&hidden)?;
                if let Ok(mut list) = HIDDEN.lock() {
                    list.push(hidden.clone());
                }
                (Box::new(file), Some((hidden, path.clone())))
            }
        };
        Ok(Output {
            writer: BufWriter::with_capacity(1 << 16, sink),
            rename,
        })
    }

    /// Writes `bytes`.
    pub fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.writer.write_all(bytes)
    }

    /// Flushes what is written and puts it in place (a regular file replaces its path whole).
    pub fn commit(mut self) -> io::Result<()> {
        self.writer.flush()?;
        if let Some((hidden, path)) = self.rename.take() {
            forget_hidden(&hidden);
            let result = std::fs::rename(&hidden, &path);
            if result.is_err() {
                let _ = std::fs::remove_file(&hidden);
            }
            result?;
        }
        Ok(())
    }
}

impl Drop for Output {
    fn drop(&mut self) {
        if let Some((hidden, _)) = self.rename.take() {
            forget_hidden(&hidden);
            let _ = std::fs::remove_file(hidden);
        }
    }
}

/// The hidden file a regular file is written to before it takes its place.
fn hidden_beside(path: &Path) -> PathBuf {
    let mut name = OsString::from(".");
    name.push(path.file_name().unwrap_or_default());
    name.push(format!(".partial-{}", std::process::id()));
    path.with_file_name(name)
}

/// Writes `text` to `target` whole or not at all.
pub fn write_target(target: &Target, text: &str) -> io::Result<()> {
    let mut out = Output::open(target)?;
    out.write_all(text.as_bytes())?;
    out.commit()
}

/// Writes `text` to `path` whole or not at all (`-` is standard output).
pub fn write_whole(path: &Path, text: &str) -> io::Result<()> {
    let targets = plan_outputs(None, &[("output", path)])
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e))?;
    write_target(&targets[0], text)
}

/// Whether `e` says the reader of a pipe went away.
pub fn is_broken_pipe(e: &io::Error) -> bool {
    e.kind() == io::ErrorKind::BrokenPipe
}
