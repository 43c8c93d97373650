//! What each command of `fixshade` does, once [`crate::cli`] has parsed its
//! arguments: load, render, measure, write files, and return the text to print or a
//! [`CliError`] with its exit code.

pub mod bake;
pub mod demo;
pub mod list;
pub mod scene;
pub mod tables;

/// A failure with its exit code: 2 for bad usage, 1 otherwise.
#[derive(Debug)]
pub struct CliError {
    /// Exit code.
    pub code: i32,
    /// One sentence for the user.
    pub message: String,
}

/// Bad usage (exit code 2).
pub fn usage(msg: impl Into<String>) -> CliError {
    CliError {
        code: 2,
        message: msg.into(),
    }
}

/// A failure (exit code 1): an unreadable file, a bad scene, a render error.
pub fn fail(msg: impl Into<String>) -> CliError {
    CliError {
        code: 1,
        message: msg.into(),
    }
}
