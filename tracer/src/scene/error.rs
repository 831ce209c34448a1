//! The error type shared by the scene readers.

use std::error::Error;
use std::fmt;
use std::io;

/// Why a scene file could not be loaded.
///
/// It displays as exactly one line, `FILE:LINE: message`, or `FILE: message` when the
/// problem is not tied to a line (the file cannot be read, is not valid gzip, or an OBJ
/// file has no faces). `FILE` is the path as the caller gave it, `LINE` is 1-based, and
/// the message is lowercase and names the offending token. Control characters in the
/// path or the message are escaped so the line stays one line.
///
/// # Examples
/// ```
/// use tracer::scene::parse_nff;
/// let err = parse_nff("v\nfrom 0 0\n", "cam.nff").unwrap_err();
/// assert_eq!(err.to_string(), "cam.nff:2: expected 3 numbers after `from`, found 2");
/// assert_eq!(err.line(), Some(2));
/// ```
#[derive(Debug)]
pub struct SceneError {
    file: String,
    line: Option<u32>,
    message: String,
    source: Option<io::Error>,
}

impl SceneError {
    /// An error at the 1-based `line` of `file`.
    pub fn at(file: &str, line: u32, message: impl Into<String>) -> Self {
        Self {
            file: one_line(file),
            line: Some(line),
            message: one_line(&message.into()),
            source: None,
        }
    }

    /// An error about `file` as a whole, displayed as `FILE: message`.
    pub fn whole_file(file: &str, message: impl Into<String>) -> Self {
        Self {
            file: one_line(file),
            line: None,
            message: one_line(&message.into()),
            source: None,
        }
    }

    /// `file` could not be read: `FILE: cannot read file: <reason>`, where the reason is
    /// the operating system's text without its `(os error N)` suffix.
    pub fn io(file: &str, err: io::Error) -> Self {
        Self::whole_file(file, format!("cannot read file: {}", io_reason(&err))).with_source(err)
    }

    /// Attaches the underlying I/O error, returned by [`Error::source`].
    pub(crate) fn with_source(mut self, err: io::Error) -> Self {
        self.source = Some(err);
        self
    }

    /// The file name as given by the caller.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The 1-based line, if the error is tied to one.
    pub fn line(&self) -> Option<u32> {
        self.line
    }

    /// The message without the `FILE:LINE: ` prefix.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.file, line, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl Error for SceneError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        self.source.as_ref().map(|e| e as &(dyn Error + 'static))
    }
}

/// The operating system's description of `err` without the ` (os error N)` suffix that
/// `io::Error`'s `Display` appends.
pub(crate) fn io_reason(err: &io::Error) -> String {
    let text = err.to_string();
    match text.find(" (os error ") {
        Some(i) => text[..i].to_owned(),
        None => text,
    }
}

/// A file token for a message: lossy UTF-8, control characters escaped, at most 40
/// characters (longer tokens end in `...`).
pub(crate) fn quote(token: &[u8]) -> String {
    const MAX: usize = 40;
    let text = String::from_utf8_lossy(token);
    let mut out = String::new();
    for (i, c) in text.chars().enumerate() {
        if i == MAX {
            out.push_str("...");
            break;
        }
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// `text` with control characters (newlines in particular) escaped.
fn one_line(text: &str) -> String {
    if !text.chars().any(char::is_control) {
        return text.to_owned();
    }
    text.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_default().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_with_and_without_line() {
        assert_eq!(
            SceneError::at("a.nff", 3, "boom").to_string(),
            "a.nff:3: boom"
        );
        assert_eq!(
            SceneError::whole_file("a.nff", "boom").to_string(),
            "a.nff: boom"
        );
    }

    #[test]
    fn newlines_are_escaped() {
        let e = SceneError::at("a\nb.nff", 1, "x\ny");
        assert_eq!(e.to_string(), "a\\nb.nff:1: x\\ny");
        assert_eq!(e.to_string().lines().count(), 1);
    }

    #[test]
    fn io_errors_drop_the_os_error_suffix() {
        let err = io::Error::from_raw_os_error(2);
        let e = SceneError::io("missing.nff", err);
        assert_eq!(
            e.to_string(),
            "missing.nff: cannot read file: No such file or directory"
        );
        assert!(e.source().is_some());
    }

    #[test]
    fn quote_truncates_and_escapes() {
        assert_eq!(quote(b"a\tb"), "a\\tb");
        let long = [b'x'; 50];
        assert_eq!(quote(&long), format!("{}...", "x".repeat(40)));
        assert_eq!(quote(&[0xff, b'a']), "\u{fffd}a");
    }
}
