//! Reading input files: only a regular file is read (a pipe such as `/dev/stdout` would block
//! forever, a device such as `/dev/zero` never ends), and at most a stated number of bytes.

use std::io::Read;
use std::path::Path;

/// The largest input file read: far more than any set of points or matrix these programs
/// handle in reasonable time.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// What `path` is when it exists and is not a regular file (`"a pipe"`, `"a directory"`, `"a
/// device or another special file"`); `None` for a regular file or a path that does not exist.
pub fn irregular(path: &Path) -> std::io::Result<Option<&'static str>> {
    let kind = match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() => return Ok(None),
        Ok(meta) => meta.file_type(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e),
    };
    Ok(Some(if kind.is_dir() {
        "a directory"
    } else if is_pipe(kind) {
        "a pipe"
    } else {
        "a device or another special file"
    }))
}

#[cfg(unix)]
fn is_pipe(kind: std::fs::FileType) -> bool {
    std::os::unix::fs::FileTypeExt::is_fifo(&kind)
}

#[cfg(not(unix))]
fn is_pipe(_: std::fs::FileType) -> bool {
    false
}

/// The text of the regular file `path` given to `--flag`, refused (with the reason) when it is
/// another kind of file or larger than [`MAX_INPUT_BYTES`], without reading more than that.
pub fn read_text(path: &str, flag: &str) -> Result<String, String> {
    let cannot = |e: std::io::Error| format!("cannot read --{flag} '{path}': {e}");
    if let Some(what) = irregular(Path::new(path)).map_err(cannot)? {
        return Err(format!(
            "--{flag} '{path}' is {what}: --{flag} takes a regular file"
        ));
    }
    let mut text = String::new();
    std::fs::File::open(path)
        .map_err(cannot)?
        .take(MAX_INPUT_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(cannot)?;
    if text.len() as u64 > MAX_INPUT_BYTES {
        return Err(format!(
            "--{flag} '{path}' is larger than {MAX_INPUT_BYTES} bytes (64 MiB), the most read"
        ));
    }
    Ok(text)
}
