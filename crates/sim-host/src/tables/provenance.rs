//! Where a generated document comes from: the commit it was made from, and the
//! command that made it, in one line that the currency tests skip.

use std::process::Command;

/// How the provenance line starts (the currency checks skip the line).
pub const PREFIX: &str = "Made from ";

/// The commit of the working tree: `git rev-parse --short HEAD`, with " with
/// uncommitted changes" when `git status --porcelain` lists anything; "unknown
/// commit" when git is unavailable or this is not a repository.
pub fn commit() -> String {
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["rev-parse", "--short", "HEAD"]) {
        Some(h) if !h.is_empty() => {
            let dirty = git(&["status", "--porcelain"]).is_some_and(|s| !s.is_empty());
            if dirty {
                format!("commit `{h}` with uncommitted changes")
            } else {
                format!("commit `{h}`")
            }
        }
        _ => "unknown commit".to_string(),
    }
}

/// `Made from commit `abc1234` by `COMMAND`.`
pub fn made_line(command: &str) -> String {
    format!("{PREFIX}{} by `{command}`.", commit())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_names_a_commit_and_the_command() {
        let l = made_line("fixshade report");
        assert!(l.starts_with(PREFIX), "{l}");
        assert!(l.ends_with("by `fixshade report`."), "{l}");
        assert!(l.contains("commit"), "{l}");
    }
}
