//! Reading a file a user named, so that no file can make a read run away:
//! only a regular file is opened (a path naming `/dev/zero`, a FIFO with no
//! writer or a directory is refused before it is opened, so nothing blocks),
//! no more than a stated size is read, and an XML text is checked for its
//! nesting, in time linear in its length, before a parser that is not is
//! given it.

use std::io::Read;
use std::path::Path;

/// The most a text file of settings (a robot file, a scenario, a recorded
/// trial's `dataset.json`) may hold, bytes.
pub const SETTINGS_LIMIT: u64 = 16 << 20;
/// The most a URDF may hold, bytes (the published quadrupeds' are under 100 kB).
pub const URDF_LIMIT: u64 = 64 << 20;
/// The most a mesh file may hold, bytes.
pub const MESH_LIMIT: u64 = 256 << 20;
/// The most a table (a CSV file: a recorded trial's events, a leaderboard, a
/// sweep) may hold, bytes: a day-long trial's events are about 200 MB.
pub const TABLE_LIMIT: u64 = 1 << 30;
/// The deepest an XML element may be nested (libxml2's default; a URDF's
/// deepest is 4 or 5).
pub const XML_DEPTH_LIMIT: usize = 256;

/// Why a file could not be read: what is wrong, naming the file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FileError {
    /// It could not be read (it does not exist, say).
    #[error("cannot read {path}: {reason}")]
    Io {
        /// The file.
        path: String,
        /// Why.
        reason: String,
    },
    /// It is not a regular file.
    #[error("{path} is {kind}, not a regular file")]
    NotAFile {
        /// The file.
        path: String,
        /// What it is.
        kind: &'static str,
    },
    /// It is larger than its kind of file may be.
    #[error("{path} is larger than {limit} bytes, the most such a file may hold")]
    TooLarge {
        /// The file.
        path: String,
        /// The limit, bytes.
        limit: u64,
    },
    /// It is not UTF-8 text.
    #[error("{path} is not UTF-8 text (a bad byte at {at})")]
    NotText {
        /// The file.
        path: String,
        /// Where the first bad byte is.
        at: usize,
    },
}

/// Checks that `path` names a regular file of at most `limit` bytes, without
/// opening it.
pub fn check(path: &Path, limit: u64) -> Result<(), FileError> {
    let name = || path.display().to_string();
    let meta = std::fs::metadata(path).map_err(|e| FileError::Io {
        path: name(),
        reason: e.to_string(),
    })?;
    if !meta.is_file() {
        return Err(FileError::NotAFile {
            path: name(),
            kind: kind(&meta),
        });
    }
    if meta.len() > limit {
        return Err(FileError::TooLarge {
            path: name(),
            limit,
        });
    }
    Ok(())
}

/// The bytes of the regular file `path`, at most `limit` of them.
pub fn read(path: &Path, limit: u64) -> Result<Vec<u8>, FileError> {
    check(path, limit)?;
    let io = |e: std::io::Error| FileError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    };
    let mut bytes = Vec::new();
    // Bounded again as it is read: the file may have grown since.
    std::fs::File::open(path)
        .map_err(io)?
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(FileError::TooLarge {
            path: path.display().to_string(),
            limit,
        });
    }
    Ok(bytes)
}

/// The text of the regular file `path`, at most `limit` bytes of UTF-8.
pub fn read_text(path: &Path, limit: u64) -> Result<String, FileError> {
    String::from_utf8(read(path, limit)?).map_err(|e| FileError::NotText {
        path: path.display().to_string(),
        at: e.utf8_error().valid_up_to(),
    })
}

/// A regular file of at most `limit` bytes, opened for reading as a stream
/// (bounded: it reads no more than `limit` bytes).
pub fn open(path: &Path, limit: u64) -> Result<std::io::Take<std::fs::File>, FileError> {
    check(path, limit)?;
    std::fs::File::open(path)
        .map(|f| f.take(limit))
        .map_err(|e| FileError::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        })
}

fn kind(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a FIFO (a named pipe)";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if meta.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

/// Checks XML text for what would make a parser slow: its elements must nest
/// at most [`XML_DEPTH_LIMIT`] deep (urdf-rs's parser takes time quadratic in
/// the depth). A scan of the tags, linear in the text and lenient about
/// everything else, which the parser then judges. The error says where.
pub fn check_xml(text: &str) -> Result<(), String> {
    match nested_beyond(text, XML_DEPTH_LIMIT) {
        Some(line) => Err(format!(
            "elements nested more than {XML_DEPTH_LIMIT} deep (at line {line})"
        )),
        None => Ok(()),
    }
}

/// The line of the first element nested deeper than `limit`, if any: a scan
/// of the tags (comments, CDATA, processing instructions and declarations
/// skipped; quoted attribute values may hold `>`), linear in the text.
fn nested_beyond(text: &str, limit: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let after = |from: usize, end: &str| text[from..].find(end).map(|k| from + k + end.len());
    let (mut i, mut depth) = (0, 0usize);
    while let Some(k) = text[i..].find('<') {
        let at = i + k;
        let rest = &text[at..];
        let next = if rest.starts_with("<!--") {
            after(at + 4, "-->")
        } else if rest.starts_with("<![CDATA[") {
            after(at + 9, "]]>")
        } else if rest.starts_with("<?") {
            after(at + 2, "?>")
        } else if rest.starts_with("<!") {
            after(at + 2, ">")
        } else if rest.starts_with("</") {
            depth = depth.saturating_sub(1);
            after(at + 2, ">")
        } else {
            // A start tag: its end is the first `>` outside quotes.
            let mut quote = None;
            let mut end = None;
            for (j, &b) in bytes.iter().enumerate().skip(at + 1) {
                match (quote, b) {
                    (None, b'"' | b'\'') => quote = Some(b),
                    (Some(q), b) if b == q => quote = None,
                    (None, b'>') => {
                        end = Some(j);
                        break;
                    }
                    _ => {}
                }
            }
            if let Some(j) = end {
                if bytes[j - 1] != b'/' {
                    depth += 1;
                    if depth > limit {
                        return Some(text[..at].matches('\n').count() + 1);
                    }
                }
            }
            end.map(|j| j + 1)
        };
        match next {
            Some(n) => i = n,
            None => return None, // unterminated: the parser will say so
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_device_a_directory_and_a_large_file_are_refused_before_reading() {
        #[cfg(unix)]
        {
            let e = read_text(Path::new("/dev/zero"), SETTINGS_LIMIT).expect_err("a device");
            assert!(e.to_string().contains("a character device"), "{e}");
        }
        let dir = std::env::temp_dir();
        let e = read(&dir, SETTINGS_LIMIT).expect_err("a directory");
        assert!(e.to_string().contains("a directory"), "{e}");
        let big = dir.join(format!("files-big-{}", std::process::id()));
        std::fs::write(&big, vec![b'x'; 100]).expect("write");
        let e = read(&big, 99).expect_err("too large");
        assert!(e.to_string().contains("larger than 99 bytes"), "{e}");
        assert_eq!(read(&big, 100).expect("at the limit").len(), 100);
        std::fs::write(&big, [0xff, 0xfe]).expect("write");
        let e = read_text(&big, 100).expect_err("not UTF-8");
        assert!(e.to_string().contains("not UTF-8"), "{e}");
        let _ = std::fs::remove_file(&big);
    }

    #[test]
    #[cfg(target_os = "linux")]
    fn a_fifo_with_no_writer_is_refused_not_waited_on() {
        let fifo = std::env::temp_dir().join(format!("files-fifo-{}", std::process::id()));
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            return; // no mkfifo here: nothing to check
        }
        let e = read_text(&fifo, SETTINGS_LIMIT).expect_err("a FIFO");
        assert!(e.to_string().contains("a FIFO"), "{e}");
        let _ = std::fs::remove_file(&fifo);
    }

    #[test]
    fn deep_xml_is_refused_in_time_linear_in_its_length() {
        let deep = |n: usize| format!("{}{}", "<a>".repeat(n), "</a>".repeat(n));
        assert!(check_xml(&deep(XML_DEPTH_LIMIT)).is_ok());
        let e = check_xml(&deep(XML_DEPTH_LIMIT + 1)).expect_err("too deep");
        assert!(e.contains("nested more than 256 deep"), "{e}");
        // 100,000 levels, the case that took urdf-rs's parser 5 s: refused.
        let e = check_xml(&deep(100_000)).expect_err("too deep");
        assert!(e.contains("nested more than"), "{e}");
        // Tags in comments, CDATA and quoted values do not nest.
        let hidden = format!(
            "<r><!-- {} --><![CDATA[{}]]><a v=\"{}\"/></r>",
            "<a>".repeat(1000),
            "<a>".repeat(1000),
            "<a>".repeat(1000)
        );
        assert!(check_xml(&hidden).is_ok());
        assert!(check_xml("<?xml version=\"1.0\"?><!-- a --><robot name=\"r\"/>").is_ok());
    }
}
