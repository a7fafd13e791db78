//! The crate's architecture, checked on its source (docs/architecture.md):
//! - the top-level modules form layers ([`LAYERS`]), and no module imports from a layer above
//!   its own;
//! - no two modules import each other: within every folder the sibling modules' imports
//!   (counted from everything inside each) have no cycle, and neither have the files;
//! - no production file has more than [`MAX_FILE_LINES`] lines of code and no function more
//!   than [`MAX_FN_LINES`] lines, except those listed with the reason in [`LONG_FUNCTIONS`].
//!
//! Imports are read from the source text: `use` declarations and `crate::`, `super::`,
//! `self::` and child-module paths in code, with comments, strings and test-only items
//! (`#[cfg(test)]`) left out, and each import followed through `pub use` re-exports to the
//! module that defines the item. A parent's re-exports of its own children are not imports.
//! The checker is tested on small made-up crates that break each rule.

use crate::common::root;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The top-level modules, lowest layer first. A module may import from its own layer and the
/// layers below; `lib.rs` (the crate root) only declares and re-exports.
const LAYERS: &[&[&str]] = &[
    &["error", "panic_guard", "model"],
    &["geom"],
    &["ingest"],
    &["classify"],
    &["medial"],
    &["fit"],
    &["export"],
    &["pipeline"],
    &["batch"],
];

/// Lines of code (not blank, not comments, not tests) a production file may have.
const MAX_FILE_LINES: usize = 1000;
/// Lines (from `fn` to its closing brace) a production function may have.
const MAX_FN_LINES: usize = 150;
/// Functions allowed to be longer, with why (none today).
const LONG_FUNCTIONS: &[(&str, &str)] = &[];

/// One module of the crate: a source file.
struct Module {
    /// `["medial", "trace", "march"]`; empty for `lib.rs`.
    path: Vec<String>,
    file: PathBuf,
    /// The source with comments, strings and test-only items blanked (lines kept).
    code: String,
}

/// An import of module `to` by module `from`, at `file:line`.
#[derive(Clone, Debug)]
struct Import {
    from: Vec<String>,
    to: Vec<String>,
    at: String,
}

fn name(path: &[String]) -> String {
    if path.is_empty() {
        "crate".into()
    } else {
        path.join("::")
    }
}

/// Blanks comments, string and char literals (keeping line breaks), so that what is left is
/// code; lifetimes and labels are kept.
fn strip(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let mut out: Vec<char> = c.clone();
    let blank = |out: &mut Vec<char>, a: usize, b: usize| {
        for ch in out.iter_mut().take(b.min(c.len())).skip(a) {
            if *ch != '\n' {
                *ch = ' ';
            }
        }
    };
    let mut i = 0;
    while i < c.len() {
        let ident_before = i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_');
        if c[i] == '/' && c.get(i + 1) == Some(&'/') {
            let end = (i..c.len()).find(|&k| c[k] == '\n').unwrap_or(c.len());
            blank(&mut out, i, end);
            i = end;
        } else if c[i] == '/' && c.get(i + 1) == Some(&'*') {
            let (mut depth, mut k) = (1, i + 2);
            while k < c.len() && depth > 0 {
                if c[k] == '/' && c.get(k + 1) == Some(&'*') {
                    depth += 1;
                    k += 2;
                } else if c[k] == '*' && c.get(k + 1) == Some(&'/') {
                    depth -= 1;
                    k += 2;
                } else {
                    k += 1;
                }
            }
            blank(&mut out, i, k);
            i = k;
        } else if !ident_before && (c[i] == 'r' || (c[i] == 'b' && c.get(i + 1) == Some(&'r'))) {
            // A raw string r"…", r#"…"#, br"…"; otherwise an identifier starting with r/b.
            let mut k = i + if c[i] == 'b' { 2 } else { 1 };
            let hashes = (k..c.len()).take_while(|&q| c[q] == '#').count();
            k += hashes;
            if c.get(k) == Some(&'"') {
                let close: Vec<char> = std::iter::once('"')
                    .chain(std::iter::repeat_n('#', hashes))
                    .collect();
                let mut q = k + 1;
                while q < c.len() && !c[q..].starts_with(&close) {
                    q += 1;
                }
                let end = (q + close.len()).min(c.len());
                blank(&mut out, i, end);
                i = end;
            } else {
                i += 1;
            }
        } else if c[i] == '"' {
            let mut k = i + 1;
            while k < c.len() && c[k] != '"' {
                k += if c[k] == '\\' { 2 } else { 1 };
            }
            blank(&mut out, i, k + 1);
            i = k + 1;
        } else if c[i] == '\'' {
            // A char literal ('a', '\n', '\u{1F}', '\''), or a lifetime / label ('a).
            if c.get(i + 1) == Some(&'\\') {
                let k = (i + 2..c.len()).find(|&k| c[k] == '\'').unwrap_or(c.len());
                blank(&mut out, i, k + 1);
                i = k + 1;
            } else if c.get(i + 2) == Some(&'\'') {
                blank(&mut out, i, i + 3);
                i += 3;
            } else {
                i += 1;
            }
        } else {
            i += 1;
        }
    }
    out.into_iter().collect()
}

/// The index just past the item starting at `i` (after its attributes): a `{…}` block or
/// up to `;`, whichever comes first outside brackets.
fn item_end(c: &[char], mut i: usize) -> usize {
    let mut depth = 0i32;
    while i < c.len() {
        match c[i] {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            ';' if depth == 0 => return i + 1,
            '{' if depth == 0 => {
                let mut d = 0;
                while i < c.len() {
                    match c[i] {
                        '{' => d += 1,
                        '}' => {
                            d -= 1;
                            if d == 0 {
                                return i + 1;
                            }
                        }
                        _ => {}
                    }
                    i += 1;
                }
                return c.len();
            }
            _ => {}
        }
        i += 1;
    }
    c.len()
}

/// Blanks every `#[cfg(test)]` item of stripped code; returns the code and the names of the
/// test-only modules it declares as files (`#[cfg(test)] mod tests;`).
fn without_tests(code: &str) -> (String, Vec<String>) {
    let c: Vec<char> = code.chars().collect();
    let mut out = c.clone();
    let mut files = vec![];
    let pattern: Vec<char> = "#[cfg(test)]".chars().collect();
    let mut i = 0;
    while i + pattern.len() <= c.len() {
        if c[i..].starts_with(&pattern) {
            let mut k = i + pattern.len();
            // Further attributes and whitespace before the item.
            loop {
                while k < c.len() && c[k].is_whitespace() {
                    k += 1;
                }
                if c.get(k) == Some(&'#') {
                    k = (k..c.len())
                        .find(|&q| c[q] == ']')
                        .map_or(c.len(), |q| q + 1);
                } else {
                    break;
                }
            }
            let end = item_end(&c, k);
            let item: String = c[k..end].iter().collect();
            let words: Vec<&str> = item
                .split(|ch: char| !(ch.is_alphanumeric() || ch == '_'))
                .filter(|w| !w.is_empty())
                .collect();
            if item.trim_end().ends_with(';') {
                if let Some(p) = words.iter().position(|w| *w == "mod") {
                    files.extend(words.get(p + 1).map(|w| w.to_string()));
                }
            }
            for ch in out.iter_mut().take(end).skip(i) {
                if *ch != '\n' {
                    *ch = ' ';
                }
            }
            i = end;
        } else {
            i += 1;
        }
    }
    (out.into_iter().collect(), files)
}

/// Every production module of the crate under `src` (`main.rs`, the binary, left out).
fn modules(src: &Path) -> Vec<Module> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|e| e == "rs") {
                out.push(p);
            }
        }
    }
    let mut files = vec![];
    walk(src, &mut files);
    let mut all = vec![];
    let mut test_files = BTreeSet::new();
    for file in files {
        let rel = file.strip_prefix(src).unwrap();
        let mut path: Vec<String> = rel
            .with_extension("")
            .iter()
            .map(|s| s.to_string_lossy().into_owned())
            .collect();
        if path == ["main"] {
            continue;
        }
        if path.last().is_some_and(|l| l == "mod" || l == "lib") {
            path.pop();
        }
        let text = std::fs::read_to_string(&file).unwrap();
        let (code, tests) = without_tests(&strip(&text));
        for t in tests {
            let mut p = path.clone();
            p.push(t);
            test_files.insert(p);
        }
        let file = Path::new(src.file_name().unwrap_or_default()).join(rel);
        all.push(Module { path, file, code });
    }
    // Test-only files, and everything inside them.
    all.retain(|m| !test_files.iter().any(|t| m.path.starts_with(t)));
    all
}

/// A `use` tree, expanded: each leaf as a path and the name it is imported as.
fn expand_use(tree: &str) -> Vec<(Vec<String>, Option<String>)> {
    fn split_top(s: &str) -> Vec<String> {
        let (mut parts, mut depth, mut cur) = (vec![], 0, String::new());
        for ch in s.chars() {
            match ch {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    parts.push(std::mem::take(&mut cur));
                    continue;
                }
                _ => {}
            }
            cur.push(ch);
        }
        parts.push(cur);
        parts
            .into_iter()
            .map(|p| p.trim().to_string())
            .filter(|p| !p.is_empty())
            .collect()
    }
    fn go(prefix: &[String], tree: &str, out: &mut Vec<(Vec<String>, Option<String>)>) {
        let tree = tree.trim();
        if let Some(open) = tree.find('{') {
            let head: Vec<String> = tree[..open]
                .split("::")
                .map(|s| s.trim().to_string())
                .filter(|s| !s.is_empty())
                .collect();
            let close = tree.rfind('}').unwrap_or(tree.len());
            let mut p = prefix.to_vec();
            p.extend(head);
            for sub in split_top(&tree[open + 1..close]) {
                go(&p, &sub, out);
            }
            return;
        }
        let (path, alias) = match tree.split_once(" as ") {
            Some((a, b)) => (a, Some(b.trim().to_string())),
            None => (tree, None),
        };
        let mut p = prefix.to_vec();
        for seg in path.split("::").map(str::trim).filter(|s| !s.is_empty()) {
            if seg == "self" && !p.is_empty() {
                continue; // `a::{self}` imports `a`
            }
            p.push(seg.to_string());
        }
        out.push((p, alias));
    }
    let mut out = vec![];
    go(&[], tree, &mut out);
    out
}

/// The crate's imports between modules, each followed through re-exports.
fn imports(mods: &[Module]) -> Vec<Import> {
    let known: BTreeSet<Vec<String>> = mods.iter().map(|m| m.path.clone()).collect();
    let is_child = |m: &[String], seg: &str| {
        let mut p = m.to_vec();
        p.push(seg.to_string());
        known.contains(&p)
    };
    // A path as written in module `m`, made absolute; `None` for other crates and for
    // names that are not module paths.
    let absolute = |m: &[String], segs: &[String]| -> Option<Vec<String>> {
        let first = segs.first()?;
        let (mut base, rest): (Vec<String>, &[String]) = match first.as_str() {
            "crate" => (vec![], &segs[1..]),
            "self" => (m.to_vec(), &segs[1..]),
            "super" => {
                let mut b = m.to_vec();
                let mut k = 0;
                while segs.get(k).is_some_and(|s| s == "super") {
                    b.pop();
                    k += 1;
                }
                (b, &segs[k..])
            }
            s if is_child(m, s) => (m.to_vec(), segs),
            _ => return None,
        };
        base.extend(rest.iter().cloned());
        Some(base)
    };
    // Uses and re-exports per module, with the line of each.
    struct Use {
        module: usize,
        line: usize,
        public: bool,
        path: Vec<String>,
        alias: Option<String>,
    }
    let mut uses = vec![];
    let mut code_without_uses = vec![];
    let use_re = |code: &str| -> Vec<(usize, usize, bool, String)> {
        // (start, end, public, tree)
        let mut found = vec![];
        let b = code.as_bytes();
        let mut i = 0;
        while let Some(k) = code[i..].find("use ") {
            let at = i + k;
            let word_start = at == 0 || !(b[at - 1].is_ascii_alphanumeric() || b[at - 1] == b'_');
            if !word_start {
                i = at + 4;
                continue;
            }
            let end = code[at..].find(';').map_or(code.len(), |e| at + e);
            let before = code[..at].trim_end();
            let public = before.ends_with("pub")
                || before.ends_with(')') && {
                    let open = before.rfind("pub(");
                    open.is_some_and(|o| before[o..].starts_with("pub("))
                };
            found.push((at, end, public, code[at + 4..end].to_string()));
            i = end;
        }
        found
    };
    for (k, m) in mods.iter().enumerate() {
        let mut code = m.code.clone();
        for (start, end, public, tree) in use_re(&m.code) {
            let line = m.code[..start].matches('\n').count() + 1;
            for (path, alias) in expand_use(&tree) {
                if let Some(abs) = absolute(&m.path, &path) {
                    uses.push(Use {
                        module: k,
                        line,
                        public,
                        path: abs,
                        alias,
                    });
                }
            }
            code.replace_range(start..end, &" ".repeat(end - start));
        }
        code_without_uses.push(code);
    }
    // Re-exports: module → (name → absolute path it stands for).
    let mut reexports: BTreeMap<Vec<String>, BTreeMap<String, Vec<String>>> = BTreeMap::new();
    for u in uses.iter().filter(|u| u.public) {
        let name = u.alias.clone().or_else(|| u.path.last().cloned());
        if let Some(name) = name.filter(|n| n != "*") {
            reexports
                .entry(mods[u.module].path.clone())
                .or_default()
                .insert(name, u.path.clone());
        }
    }
    // The module that defines what an absolute path names.
    let resolve = |abs: &[String]| -> Vec<String> {
        let mut path = abs.to_vec();
        for _ in 0..16 {
            let depth = (0..=path.len())
                .rev()
                .find(|&d| known.contains(&path[..d]))
                .unwrap_or(0);
            let module = path[..depth].to_vec();
            let Some(next) = path
                .get(depth)
                .and_then(|item| reexports.get(&module)?.get(item))
            else {
                return module;
            };
            let mut p = next.clone();
            p.extend(path[depth + 1..].iter().cloned());
            path = p;
        }
        path
    };
    let mut out = vec![];
    for u in &uses {
        let m = &mods[u.module];
        let to = resolve(&u.path);
        // A parent re-exporting its own descendants does not depend on them.
        if u.public && to.starts_with(&m.path) {
            continue;
        }
        out.push(Import {
            from: m.path.clone(),
            to,
            at: format!("{}:{}", m.file.display(), u.line),
        });
    }
    // Paths in code: crate::…, super::…, self::… and child::….
    for (k, m) in mods.iter().enumerate() {
        let code = &code_without_uses[k];
        let b = code.as_bytes();
        let mut i = 0;
        while i < b.len() {
            let starts = (b[i].is_ascii_alphabetic() || b[i] == b'_')
                && (i == 0
                    || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b':'));
            if !starts {
                i += 1;
                continue;
            }
            let mut j = i;
            let mut segs = vec![];
            loop {
                let s = j;
                while j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_') {
                    j += 1;
                }
                segs.push(code[s..j].to_string());
                if code[j..].starts_with("::")
                    && code[j + 2..]
                        .bytes()
                        .next()
                        .is_some_and(|c| c.is_ascii_alphabetic() || c == b'_')
                {
                    j += 2;
                } else {
                    break;
                }
            }
            if segs.len() > 1 {
                if let Some(abs) = absolute(&m.path, &segs) {
                    let to = resolve(&abs);
                    if to != m.path {
                        let line = code[..i].matches('\n').count() + 1;
                        out.push(Import {
                            from: m.path.clone(),
                            to,
                            at: format!("{}:{}", m.file.display(), line),
                        });
                    }
                }
            }
            i = j.max(i + 1);
        }
    }
    out.retain(|imp| imp.from != imp.to);
    out
}

type Graph = BTreeMap<Vec<String>, BTreeSet<Vec<String>>>;

/// The strongly connected components of more than one node (each a set of modules that
/// import each other, directly or around a cycle), by Tarjan's algorithm.
fn cycles(edges: &Graph) -> Vec<Vec<Vec<String>>> {
    struct Tarjan<'a> {
        edges: &'a Graph,
        index: BTreeMap<Vec<String>, usize>,
        low: BTreeMap<Vec<String>, usize>,
        stack: Vec<Vec<String>>,
        on_stack: BTreeSet<Vec<String>>,
        out: Vec<Vec<Vec<String>>>,
    }
    impl Tarjan<'_> {
        fn visit(&mut self, n: &Vec<String>) {
            let i = self.index.len();
            self.index.insert(n.clone(), i);
            self.low.insert(n.clone(), i);
            self.stack.push(n.clone());
            self.on_stack.insert(n.clone());
            for m in self.edges.get(n).into_iter().flatten() {
                if !self.index.contains_key(m) {
                    self.visit(m);
                    let l = self.low[n].min(self.low[m]);
                    self.low.insert(n.clone(), l);
                } else if self.on_stack.contains(m) {
                    let l = self.low[n].min(self.index[m]);
                    self.low.insert(n.clone(), l);
                }
            }
            if self.low[n] == self.index[n] {
                let mut comp = vec![];
                while let Some(m) = self.stack.pop() {
                    self.on_stack.remove(&m);
                    let done = &m == n;
                    comp.push(m);
                    if done {
                        break;
                    }
                }
                if comp.len() > 1 {
                    comp.sort();
                    self.out.push(comp);
                }
            }
        }
    }
    let mut t = Tarjan {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: vec![],
        on_stack: BTreeSet::new(),
        out: vec![],
    };
    for n in edges.keys() {
        if !t.index.contains_key(n) {
            t.visit(n);
        }
    }
    t.out
}

/// Everything wrong with the crate under `src`, one line each.
fn violations(src: &Path, layers: &[&[&str]]) -> Vec<String> {
    let mods = modules(src);
    let imps = imports(&mods);
    let mut bad = vec![];
    let layer_of = |top: &str| layers.iter().position(|l| l.contains(&top));
    for m in &mods {
        if let Some(top) = m.path.first() {
            if layer_of(top).is_none() {
                bad.push(format!("module {top} is in no layer (add it to LAYERS)"));
            }
        }
    }
    // Layers.
    for imp in &imps {
        let (Some(a), Some(b)) = (imp.from.first(), imp.to.first()) else {
            continue;
        };
        if let (Some(la), Some(lb)) = (layer_of(a), layer_of(b)) {
            if lb > la {
                bad.push(format!(
                    "{}: {} imports {} from a layer above it",
                    imp.at,
                    name(&imp.from),
                    name(&imp.to)
                ));
            }
        }
    }
    // The imports between the members of a cycle, with where each is.
    let describe = |comp: &[Vec<String>], graph: &Graph, agg: bool| -> String {
        let mut steps = vec![];
        for a in comp {
            for b in graph
                .get(a)
                .into_iter()
                .flatten()
                .filter(|b| comp.contains(b))
            {
                let at = imps
                    .iter()
                    .find(|i| {
                        if agg {
                            i.from.starts_with(a) && i.to.starts_with(b)
                        } else {
                            &i.from == a && &i.to == b
                        }
                    })
                    .map_or(String::new(), |i| i.at.clone());
                steps.push(format!("{} -> {} ({at})", name(a), name(b)));
            }
        }
        steps.join(", ")
    };
    // Cycles between files.
    let mut files: Graph = BTreeMap::new();
    for imp in &imps {
        files
            .entry(imp.from.clone())
            .or_default()
            .insert(imp.to.clone());
    }
    for c in cycles(&files) {
        bad.push(format!(
            "import cycle between files: {}",
            describe(&c, &files, false)
        ));
    }
    // Cycles between the sibling modules of each folder (everything inside each counted).
    let folders: BTreeSet<Vec<String>> = mods
        .iter()
        .flat_map(|m| (0..m.path.len()).map(|d| m.path[..d].to_vec()))
        .collect();
    for folder in folders {
        let child = |p: &[String]| {
            (p.len() > folder.len() && p.starts_with(&folder)).then(|| p[..=folder.len()].to_vec())
        };
        let mut sib: Graph = BTreeMap::new();
        for imp in &imps {
            if let (Some(a), Some(b)) = (child(&imp.from), child(&imp.to)) {
                if a != b {
                    sib.entry(a).or_default().insert(b);
                }
            }
        }
        for c in cycles(&sib) {
            bad.push(format!(
                "modules in {} import each other: {}",
                name(&folder),
                describe(&c, &sib, true)
            ));
        }
    }
    bad
}

/// Production files over [`MAX_FILE_LINES`] lines of code and functions over
/// [`MAX_FN_LINES`] lines not in [`LONG_FUNCTIONS`].
fn too_long(src: &Path) -> Vec<String> {
    let mut bad = vec![];
    for m in modules(src) {
        let lines = m.code.lines().filter(|l| !l.trim().is_empty()).count();
        if lines > MAX_FILE_LINES {
            bad.push(format!("{}: {lines} lines of code", m.file.display()));
        }
        let c: Vec<char> = m.code.chars().collect();
        let text: String = c.iter().collect();
        let mut i = 0;
        while let Some(k) = text[i..].find("fn ") {
            let at = i + k;
            i = at + 3;
            let b = text.as_bytes();
            if at > 0 && (b[at - 1].is_ascii_alphanumeric() || b[at - 1] == b'_') {
                continue;
            }
            let fname: String = text[at + 3..]
                .chars()
                .take_while(|ch| ch.is_alphanumeric() || *ch == '_')
                .collect();
            // byte offset → char index (the stripped code is ASCII outside literals, but
            // identifiers and docs may not be: count chars).
            let ci = text[..at].chars().count();
            let end = item_end(&c, ci);
            let body: String = c[ci..end].iter().collect();
            if !body.trim_end().ends_with('}') {
                continue; // a declaration without a body
            }
            let n = body.matches('\n').count() + 1;
            let qualified = format!("{}::{fname}", name(&m.path));
            if n > MAX_FN_LINES && !LONG_FUNCTIONS.iter().any(|(f, _)| *f == qualified) {
                let line = text[..at].matches('\n').count() + 1;
                bad.push(format!(
                    "{}:{line}: fn {fname} has {n} lines",
                    m.file.display()
                ));
            }
        }
    }
    bad
}

#[test]
fn layers_have_no_upward_imports_and_no_cycles() {
    let bad = violations(&root().join("src"), LAYERS);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn no_production_file_or_function_is_too_long() {
    let bad = too_long(&root().join("src"));
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// A made-up crate: `files` as (path under src, text).
fn crate_with(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (path, text) in files {
        let p = dir.path().join(path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    }
    dir
}

const TOY_LAYERS: &[&[&str]] = &[&["model"], &["geom"], &["medial"]];

#[test]
fn the_checker_accepts_a_layered_crate() {
    let dir = crate_with(&[
        ("lib.rs", "pub mod model; pub mod geom; pub mod medial;\npub use medial::Axis;"),
        ("model.rs", "pub struct Model;"),
        ("geom/mod.rs", "mod eval;\npub use eval::eval;"),
        ("geom/eval.rs", "use crate::model::Model;\npub fn eval(_: &Model) {}"),
        (
            "medial/mod.rs",
            "mod axis; mod trace;\npub use axis::Axis;\npub use trace::trace;",
        ),
        ("medial/axis.rs", "pub struct Axis;"),
        (
            "medial/trace.rs",
            "use super::axis::Axis;\npub fn trace() -> Axis { crate::geom::eval(&crate::model::Model); Axis }",
        ),
    ]);
    let bad = violations(dir.path(), TOY_LAYERS);
    assert!(bad.is_empty(), "{bad:?}");
}

#[test]
fn the_checker_rejects_an_upward_import() {
    // geom's evaluation reaching up to the medial axis, once in a `use`, once inline; and
    // the same import inside a test module, which is allowed.
    for text in [
        "use crate::medial::Axis;\npub fn eval() {}",
        "pub fn eval() { let _ = crate::medial::trace(); }",
        "pub fn eval() {}\n#[cfg(test)]\nmod tests { use crate::medial::Axis; }",
    ] {
        let dir = crate_with(&[
            ("lib.rs", "pub mod model; pub mod geom; pub mod medial;"),
            ("model.rs", "pub struct Model;"),
            ("geom.rs", text),
            ("medial/mod.rs", "mod axis;\npub use axis::{trace, Axis};"),
            ("medial/axis.rs", "pub struct Axis;\npub fn trace() {}"),
        ]);
        let bad = violations(dir.path(), TOY_LAYERS);
        if text.contains("cfg(test)") {
            assert!(bad.is_empty(), "{bad:?}");
        } else {
            assert!(
                bad.iter()
                    .any(|b| b.contains("geom imports medial::axis from a layer above it")),
                "{text}: {bad:?}"
            );
        }
    }
}

#[test]
fn the_checker_rejects_two_modules_importing_each_other() {
    // trace holds a sheets type while sheets uses trace's: a cycle between siblings, seen
    // through the parent's re-exports and from a file inside trace/.
    let dir = crate_with(&[
        ("lib.rs", "pub mod medial;"),
        (
            "medial/mod.rs",
            "mod sheets; mod trace;\npub use sheets::Groups;\npub use trace::Axis;",
        ),
        (
            "medial/sheets.rs",
            "use crate::medial::Axis;\npub struct Groups;",
        ),
        ("medial/trace/mod.rs", "mod march;\npub struct Axis;"),
        (
            "medial/trace/march.rs",
            "pub fn march(_: super::super::Groups) {}",
        ),
    ]);
    let bad = violations(dir.path(), &[&["medial"]]);
    assert!(
        bad.iter()
            .any(|b| b.starts_with("modules in medial import each other")),
        "{bad:?}"
    );
    // And a cycle between a parent's own code and its child.
    let dir = crate_with(&[
        ("lib.rs", "pub mod ingest;"),
        (
            "ingest/mod.rs",
            "mod step;\npub fn is_iges() -> bool { step::read() }",
        ),
        (
            "ingest/step.rs",
            "pub fn read() -> bool { super::is_iges() }",
        ),
    ]);
    let bad = violations(dir.path(), &[&["ingest"]]);
    assert!(
        bad.iter()
            .any(|b| b.starts_with("import cycle between files")),
        "{bad:?}"
    );
}

#[test]
fn the_checker_sees_through_comments_strings_and_lifetimes() {
    let dir = crate_with(&[
        ("lib.rs", "pub mod model; pub mod geom;"),
        ("model.rs", "pub struct Model;"),
        (
            "geom.rs",
            "// use crate::medial::Axis;\n/* crate::medial::x */\npub fn f<'a>(s: &'a str) -> &'a str { let _ = \"crate::medial::y\"; let _ = '\"'; let _ = r#\"crate::medial\"#; s }",
        ),
    ]);
    let bad = violations(dir.path(), &[&["model"], &["geom"], &["medial"]]);
    assert!(bad.is_empty(), "{bad:?}");
}

#[test]
fn the_length_check_finds_a_long_function() {
    let body = "    let x = 1;\n".repeat(MAX_FN_LINES);
    let text = format!("pub mod model;\npub fn long() {{\n{body}}}\n#[cfg(test)]\nmod tests {{ fn also_long() {{\n{body}}} }}\n");
    let dir = crate_with(&[("lib.rs", &text), ("model.rs", "pub struct Model;")]);
    let bad = too_long(dir.path());
    assert_eq!(bad.len(), 1, "{bad:?}");
    assert!(bad[0].contains("fn long has"), "{bad:?}");
}
