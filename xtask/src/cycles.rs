//! `cargo xtask cycles [DIR...]`: the import cycles between the modules of a crate's
//! source directory (default `crates/sim-host/src`).
//!
//! Every module is a node: each file (`a.rs`, `a/mod.rs`, `lib.rs` for the crate
//! root) and each inline `mod name { … }` in it. A module depends on another when it
//! names it, or an item in it, by a path: in a `use` (`use crate::a::b::{C, d::E}`,
//! `use super::x`, `pub use child::Y`) or in code and macros (`crate::a::f()`,
//! `super::x::Y`, `$crate::a::B`). A path resolves to the longest module prefix
//! that exists. Declaring a child (`mod child;`) is not a dependency, so a parent
//! that re-exports a child depends on it, and a child that imports from its parent
//! closes a cycle. A cycle is a strongly connected set of two or more modules; each
//! is printed with one path that closes each of its edges.
//!
//! The scan is lexical (comments and string literals skipped), so it sees paths in
//! macro bodies too; it does not follow glob imports of items into modules they
//! re-export.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module: its path from the crate root (`[]` for the root).
type Module = Vec<String>;

/// One dependency: from, to, and where (file:line and the path as written).
#[derive(Clone, Debug)]
pub struct Edge {
    /// The module that names the other.
    pub from: Module,
    /// The module named.
    pub to: Module,
    /// `file:line: path`.
    pub at: String,
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    ColonColon,
    Open,
    Close,
    Comma,
    Semi,
    Star,
    Other,
}

/// The tokens of `src` that matter for paths, with their lines.
fn tokens(src: &str) -> Vec<(Tok, usize)> {
    let b = src.as_bytes();
    let (mut i, mut line) = (0, 1);
    let mut out = Vec::new();
    while i < b.len() {
        let c = b[i];
        if c == b'\n' {
            line += 1;
            i += 1;
        } else if c.is_ascii_whitespace() {
            i += 1;
        } else if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i..].starts_with(b"/*") {
            let mut depth = 0;
            while i < b.len() {
                if b[i..].starts_with(b"/*") {
                    depth += 1;
                    i += 2;
                } else if b[i..].starts_with(b"*/") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    line += usize::from(b[i] == b'\n');
                    i += 1;
                }
            }
        } else if c == b'r' && matches!(b.get(i + 1), Some(b'"') | Some(b'#')) && {
            let mut k = i + 1;
            while b.get(k) == Some(&b'#') {
                k += 1;
            }
            b.get(k) == Some(&b'"')
        } {
            // A raw string: r#"…"#.
            let mut k = i + 1;
            let mut hashes = 0;
            while b[k] == b'#' {
                hashes += 1;
                k += 1;
            }
            k += 1;
            loop {
                if k >= b.len() {
                    break;
                }
                if b[k] == b'"'
                    && b[k + 1..]
                        .iter()
                        .take(hashes)
                        .filter(|h| **h == b'#')
                        .count()
                        == hashes
                {
                    k += 1 + hashes;
                    break;
                }
                line += usize::from(b[k] == b'\n');
                k += 1;
            }
            i = k;
        } else if c == b'"' || (c == b'b' && b.get(i + 1) == Some(&b'"')) {
            i += if c == b'b' { 2 } else { 1 };
            while i < b.len() && b[i] != b'"' {
                if b[i] == b'\\' {
                    i += 1;
                }
                line += usize::from(b.get(i) == Some(&b'\n'));
                i += 1;
            }
            i += 1;
        } else if c == b'\'' {
            // A char literal ('x', '\n', '\u{1F600}') or a lifetime ('a).
            if b.get(i + 1) == Some(&b'\\') {
                i += 2;
                while i < b.len() && b[i] != b'\'' {
                    i += 1;
                }
                i += 1;
            } else if b.get(i + 2) == Some(&b'\'') {
                i += 3;
            } else {
                let s = &src[i + 1..];
                let len = s.chars().next().map_or(1, char::len_utf8);
                if s[len..].starts_with('\'') {
                    i += 2 + len;
                } else {
                    i += 1;
                    out.push((Tok::Other, line));
                }
            }
        } else if c.is_ascii_alphabetic()
            || c == b'_'
            || (c == b'$' && b[i + 1..].starts_with(b"crate"))
        {
            let start = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            let word = &src[start..i];
            out.push((Tok::Ident(word.trim_start_matches('$').to_string()), line));
        } else {
            let t = match c {
                b':' if b.get(i + 1) == Some(&b':') => {
                    i += 1;
                    Tok::ColonColon
                }
                b'{' => Tok::Open,
                b'}' => Tok::Close,
                b',' => Tok::Comma,
                b';' => Tok::Semi,
                b'*' => Tok::Star,
                _ => Tok::Other,
            };
            i += if c.is_ascii() {
                1
            } else {
                src[i..].chars().next().map_or(1, char::len_utf8)
            };
            out.push((t, line));
        }
    }
    out
}

/// Paths of a `use` tree starting at `toks[*i]` (after `use`), with `prefix`.
fn use_tree(toks: &[(Tok, usize)], i: &mut usize, prefix: &[String], out: &mut Vec<Vec<String>>) {
    let mut path = prefix.to_vec();
    loop {
        match toks.get(*i).map(|t| &t.0) {
            Some(Tok::Ident(w)) if w != "as" => {
                path.push(w.clone());
                *i += 1;
            }
            Some(Tok::ColonColon) => *i += 1,
            Some(Tok::Open) => {
                *i += 1;
                loop {
                    match toks.get(*i).map(|t| &t.0) {
                        Some(Tok::Close) => {
                            *i += 1;
                            break;
                        }
                        Some(Tok::Comma) => *i += 1,
                        None => return,
                        _ => use_tree(toks, i, &path, out),
                    }
                }
                return;
            }
            Some(Tok::Star) => {
                *i += 1;
                out.push(path);
                return;
            }
            _ => {
                // `as name`, `,`, `}`, `;`: the path ends.
                if let Some(Tok::Ident(_)) = toks.get(*i).map(|t| &t.0) {
                    *i += 2;
                }
                out.push(path);
                return;
            }
        }
    }
}

/// A path named in a module: its segments, its line, and whether it is in a `use`.
type Named = (Vec<String>, usize, bool);

/// One module of a file: its path, the child modules declared in it, the paths it
/// names.
type Scanned = (Module, BTreeSet<String>, Vec<Named>);

/// A file's modules: the file's own and each inline module in it.
struct Scan {
    modules: Vec<Scanned>,
}

/// Scans the tokens of the file of module `base`.
fn scan(src: &str, base: &Module) -> Scan {
    let toks = tokens(src);
    let mut modules: Vec<Scanned> = vec![(base.clone(), BTreeSet::new(), Vec::new())];
    // The stack of open inline modules: (index in `modules`, brace depth at its `{`).
    let mut stack: Vec<(usize, usize)> = vec![(0, 0)];
    let mut depth = 0;
    let mut i = 0;
    while i < toks.len() {
        let cur = stack.last().unwrap().0;
        match &toks[i].0 {
            Tok::Open => depth += 1,
            Tok::Close => {
                if stack.len() > 1 && stack.last().unwrap().1 == depth {
                    stack.pop();
                }
                depth -= 1;
            }
            Tok::Ident(w) if w == "mod" => {
                if let Some((Tok::Ident(name), _)) = toks.get(i + 1) {
                    let name = name.clone();
                    modules[cur].1.insert(name.clone());
                    if toks.get(i + 2).map(|t| &t.0) == Some(&Tok::Open) {
                        let mut m = modules[cur].0.clone();
                        m.push(name);
                        modules.push((m, BTreeSet::new(), Vec::new()));
                        depth += 1;
                        stack.push((modules.len() - 1, depth));
                        i += 3;
                        continue;
                    }
                }
            }
            Tok::Ident(w) if w == "use" => {
                let line = toks[i].1;
                let mut j = i + 1;
                let mut paths = Vec::new();
                use_tree(&toks, &mut j, &[], &mut paths);
                for p in paths {
                    modules[cur].2.push((p, line, true));
                }
                i = j;
                continue;
            }
            Tok::Ident(w)
                if (w == "crate" || w == "super" || w == "self")
                    && toks.get(i + 1).map(|t| &t.0) == Some(&Tok::ColonColon)
                    && !(i > 0 && toks[i - 1].0 == Tok::ColonColon) =>
            {
                let line = toks[i].1;
                let mut path = vec![w.clone()];
                let mut j = i + 1;
                while toks.get(j).map(|t| &t.0) == Some(&Tok::ColonColon) {
                    match toks.get(j + 1).map(|t| &t.0) {
                        Some(Tok::Ident(seg)) => {
                            path.push(seg.clone());
                            j += 2;
                        }
                        _ => break,
                    }
                }
                modules[cur].2.push((path, line, false));
                i = j;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    Scan { modules }
}

/// The module of each `.rs` file under `dir`: `lib.rs`/`main.rs` the root, `a.rs`
/// and `a/mod.rs` the module `a`, `a/b.rs` the module `a::b`.
fn files(dir: &Path) -> Vec<(PathBuf, Module)> {
    fn walk(dir: &Path, rel: &Module, out: &mut Vec<(PathBuf, Module)>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        let mut entries: Vec<_> = entries.flatten().map(|e| e.path()).collect();
        entries.sort();
        for p in entries {
            let name = p
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .to_string();
            if p.is_dir() {
                let mut r = rel.clone();
                r.push(name);
                walk(&p, &r, out);
            } else if let Some(stem) = name.strip_suffix(".rs") {
                let mut m = rel.clone();
                if !(stem == "mod" || (rel.is_empty() && (stem == "lib" || stem == "main"))) {
                    m.push(stem.to_string());
                }
                out.push((p, m));
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, &Vec::new(), &mut out);
    // A binary's main.rs is a crate of its own: keep the library's root.
    if out.iter().any(|(p, _)| p.ends_with("lib.rs")) {
        out.retain(|(p, m)| !(m.is_empty() && p.ends_with("main.rs")));
    }
    out
}

fn name(m: &Module) -> String {
    if m.is_empty() {
        "crate".into()
    } else {
        m.join("::")
    }
}

/// Every dependency between the modules of the crate in `dir`.
pub fn edges(dir: &Path) -> Result<Vec<Edge>, String> {
    let mut scans = Vec::new();
    for (path, module) in files(dir) {
        let src = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let rel = path
            .strip_prefix(dir)
            .unwrap_or(&path)
            .display()
            .to_string();
        scans.push((rel, scan(&src, &module)));
    }
    let known: BTreeSet<Module> = scans
        .iter()
        .flat_map(|(_, s)| s.modules.iter().map(|m| m.0.clone()))
        .collect();
    let mut out = Vec::new();
    for (file, s) in &scans {
        for (module, children, paths) in &s.modules {
            for (path, line, in_use) in paths {
                // The absolute path of what is named.
                let mut abs: Module = match path.first().map(String::as_str) {
                    Some("crate") => Vec::new(),
                    Some("self") => module.clone(),
                    Some("super") => module.clone(),
                    Some(first) if *in_use && children.contains(first) => module.clone(),
                    _ => continue,
                };
                let mut rest = &path[..];
                if rest.first().map(String::as_str) == Some("crate") {
                    rest = &rest[1..];
                }
                while let Some(seg) = rest.first() {
                    match seg.as_str() {
                        "super" => {
                            abs.pop();
                        }
                        "self" => {}
                        _ => break,
                    }
                    rest = &rest[1..];
                }
                // The longest prefix that is a module.
                let mut to = abs.clone();
                for seg in rest {
                    let mut m = to.clone();
                    m.push(seg.clone());
                    if !known.contains(&m) {
                        break;
                    }
                    to = m;
                }
                if to != *module {
                    out.push(Edge {
                        from: module.clone(),
                        to,
                        at: format!("{file}:{line}: {}", path.join("::")),
                    });
                }
            }
        }
    }
    Ok(out)
}

/// The cycles among `edges`: each a set of two or more modules that all reach one
/// another, with one edge per pair of consecutive members (Tarjan's algorithm).
pub fn cycles(edges: &[Edge]) -> Vec<Vec<Edge>> {
    let mut graph: BTreeMap<&Module, BTreeSet<&Module>> = BTreeMap::new();
    for e in edges {
        graph.entry(&e.from).or_default().insert(&e.to);
        graph.entry(&e.to).or_default();
    }
    struct T<'a> {
        graph: &'a BTreeMap<&'a Module, BTreeSet<&'a Module>>,
        index: BTreeMap<&'a Module, usize>,
        low: BTreeMap<&'a Module, usize>,
        stack: Vec<&'a Module>,
        on: BTreeSet<&'a Module>,
        next: usize,
        sccs: Vec<Vec<&'a Module>>,
    }
    fn visit<'a>(t: &mut T<'a>, v: &'a Module) {
        t.index.insert(v, t.next);
        t.low.insert(v, t.next);
        t.next += 1;
        t.stack.push(v);
        t.on.insert(v);
        for &w in &t.graph[v] {
            if !t.index.contains_key(w) {
                visit(t, w);
                let lw = t.low[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if t.on.contains(w) {
                let iw = t.index[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if t.low[v] == t.index[v] {
            let mut scc = Vec::new();
            while let Some(w) = t.stack.pop() {
                t.on.remove(w);
                scc.push(w);
                if w == v {
                    break;
                }
            }
            if scc.len() > 1 {
                t.sccs.push(scc);
            }
        }
    }
    let mut t = T {
        graph: &graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        next: 0,
        sccs: Vec::new(),
    };
    for v in graph.keys().copied().collect::<Vec<_>>() {
        if !t.index.contains_key(v) {
            visit(&mut t, v);
        }
    }
    t.sccs
        .into_iter()
        .map(|scc| {
            let set: BTreeSet<&Module> = scc.iter().copied().collect();
            let mut inner: Vec<Edge> = Vec::new();
            for e in edges {
                if set.contains(&e.from)
                    && set.contains(&e.to)
                    && !inner.iter().any(|x| x.from == e.from && x.to == e.to)
                {
                    inner.push(e.clone());
                }
            }
            inner
        })
        .collect()
}

/// The cycles of the crate in `dir`, as text (empty if there are none).
pub fn report(dir: &Path) -> Result<(usize, String), String> {
    let e = edges(dir)?;
    let found = cycles(&e);
    let mut text = String::new();
    for (k, c) in found.iter().enumerate() {
        let mut members: BTreeSet<String> = BTreeSet::new();
        for e in c {
            members.insert(name(&e.from));
        }
        text.push_str(&format!(
            "cycle {} ({} modules: {}):\n",
            k + 1,
            members.len(),
            members.into_iter().collect::<Vec<_>>().join(", ")
        ));
        for e in c {
            text.push_str(&format!(
                "  {} -> {}  ({})\n",
                name(&e.from),
                name(&e.to),
                e.at
            ));
        }
    }
    Ok((found.len(), text))
}

/// `cargo xtask cycles [DIR...]`: prints each directory's cycles; fails if any.
pub fn run(root: &Path, dirs: &[String]) -> Result<(), String> {
    let dirs: Vec<PathBuf> = if dirs.is_empty() {
        vec![root.join("crates/sim-host/src")]
    } else {
        dirs.iter().map(PathBuf::from).collect()
    };
    let mut total = 0;
    for d in &dirs {
        let (n, text) = report(d)?;
        let modules = files(d).len();
        if n == 0 {
            eprintln!("xtask: {}: {modules} files, no import cycle", d.display());
        } else {
            eprintln!(
                "xtask: {}: {modules} files, {n} import cycle(s):\n{text}",
                d.display()
            );
        }
        total += n;
    }
    if total == 0 {
        Ok(())
    } else {
        Err(format!("{total} import cycle(s)"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, files: &[(&str, &str)]) {
        for (p, src) in files {
            let p = dir.join(p);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, src).unwrap();
        }
    }

    /// The simulator's modules form layers: no import cycle.
    #[test]
    fn sim_host_has_no_import_cycle() {
        let dir = crate::qemu::root().join("crates/sim-host/src");
        assert!(files(&dir).len() > 30);
        let (n, text) = report(&dir).unwrap();
        assert_eq!(n, 0, "import cycles in crates/sim-host/src:\n{text}");
        // The edges it sees: the CLI depends on the commands, the scene on nothing
        // above it.
        let e = edges(&dir).unwrap();
        let has =
            |from: &str, to: &str| e.iter().any(|e| name(&e.from) == from && name(&e.to) == to);
        assert!(has("cli", "commands"));
        assert!(has("render::frame", "render::dispatch"));
        // Every dependency between the top-level modules goes down the layers of
        // `crates/sim-host/src/lib.rs`.
        let layers = [
            "cli", "commands", "tables", "render", "image", "chart", "scene",
        ];
        let layer = |m: &Module| m.first().and_then(|f| layers.iter().position(|l| l == f));
        for e in &e {
            if let (Some(a), Some(b)) = (layer(&e.from), layer(&e.to)) {
                assert!(
                    a <= b,
                    "{} -> {} goes up the layers ({})",
                    name(&e.from),
                    name(&e.to),
                    e.at
                );
            }
        }
    }

    /// The core's modules have no import cycle either (`raster::pixel` reaches the
    /// Cortex-M loops of `raster::asm`, which import nothing; `raster::dsp` the
    /// span stage).
    #[test]
    fn core_has_no_import_cycle() {
        let dir = crate::qemu::root().join("crates/core-nostd/src");
        assert!(files(&dir).len() > 30);
        let (n, text) = report(&dir).unwrap();
        assert_eq!(n, 0, "import cycles in crates/core-nostd/src:\n{text}");
    }

    /// Cycles through `use` trees, re-exports, `super`, inline paths, macros and
    /// inline modules are found; comments, strings and child declarations are not
    /// dependencies.
    #[test]
    fn finds_cycles_of_every_kind_of_path() {
        let dir = std::env::temp_dir().join(format!("xtask-cycles-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        write(
            &dir,
            &[
                (
                    "lib.rs",
                    "pub mod a;\npub mod b;\npub mod c;\npub mod d;\n// crate::d::x in a comment\n",
                ),
                ("a/mod.rs", "pub mod inner;\npub use inner::X;\n"),
                (
                    "a/inner.rs",
                    "use crate::{b::{self, Y}, c};\npub struct X;\n",
                ),
                ("b.rs", "pub struct Y;\nfn f() { let _ = super::a::X; }\n"),
                (
                    "c.rs",
                    "const S: &str = \"crate::d::Z\";\nmacro_rules! m { () => { $crate::d::Z } }\n",
                ),
                (
                    "d.rs",
                    "pub struct Z;\nmod tests { use crate::c; }\nfn g() { crate::c::h(); }\n",
                ),
            ],
        );
        let (n, text) = report(&dir).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(n, 2, "{text}");
        assert!(text.contains("a -> a::inner"), "{text}");
        assert!(text.contains("a::inner -> b"), "{text}");
        assert!(text.contains("b -> a"), "{text}");
        assert!(text.contains("c -> d"), "{text}");
        assert!(text.contains("d -> c"), "{text}");
        // `d::tests -> c` is no cycle: `d` does not depend on `d::tests`.
        assert!(!text.contains("d::tests"), "{text}");
    }
}
