//! Why a mesh could not be built.

use std::fmt;

/// Why a mesh could not be built: which file (or built-in model), which line if
/// one applies, and what was wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshError {
    /// File name as given, or `<builtin sphere>` / `<builtin teapot>` for
    /// built-in models.
    pub file: String,
    /// 1-based line number, when the error belongs to one line.
    pub line: Option<usize>,
    /// What was expected or found, without the file and line.
    pub message: String,
}

impl MeshError {
    /// An error of `file` (at `line`) saying `message`.
    pub fn new(file: &str, line: Option<usize>, message: impl Into<String>) -> Self {
        MeshError {
            file: file.to_owned(),
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for MeshError {
    /// `file:line: message`, or `file: message` when no line applies.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.file, line, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for MeshError {}
