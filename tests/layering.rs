//! The layering of `src/` holds: every import of one top-level module from another is allowed
//! by the "Layers" table of `docs/ARCHITECTURE.md` (parsed from the document, so the two cannot
//! drift), and the files of a top-level module import each other without a cycle.
//!
//! `src/` holds two crates: the library (`lib.rs` and its modules) and the binary (`main.rs`
//! and the modules it declares, such as `cli`), whose files name the library `raygraph::`. The
//! binary's top-level modules are rows of the table like the library's; no library module can
//! name them.
//!
//! An import is a `use` declaration or a path written inline (`crate::a::b`, `super::x`,
//! `child::y`; `raygraph::a` in the binary's files). A path resolves to the file that defines
//! the item, following the `pub use` re-exports of module roots; those re-exports are the
//! module's face, not a dependency of the root file, so they count for the layers but not for
//! file cycles. Comments and string literals are ignored.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// One import: `from` (a file under `src/`, e.g. `accel/cache.rs`) names `path` on `line`,
/// which resolves to the file `to`.
#[derive(Debug, Clone, PartialEq)]
struct Edge {
    from: String,
    line: usize,
    to: String,
    path: String,
    /// A `pub use` in a module root (`mod.rs`, `lib.rs`): a re-export.
    reexport: bool,
}

/// The "Layers" table: each top-level module's layer and the modules it may import.
#[derive(Debug, Default)]
struct Layers {
    layer: BTreeMap<String, u32>,
    may_import: BTreeMap<String, BTreeSet<String>>,
}

/// Names in backticks in a table cell.
fn backticked(cell: &str) -> Vec<String> {
    cell.split('`').skip(1).step_by(2).map(str::to_string).collect()
}

/// What a "may import" cell reads when a row may import every module of the lower layers.
const EVERY_LOWER_LAYER: &str = "every lower layer";

/// Parses the table under the heading `## Layers`: `| layer | modules | may import |`, where
/// "may import" lists modules in backticks, or reads `every lower layer`.
fn parse_layers(markdown: &str) -> Result<Layers, String> {
    let section = format!("\n{markdown}");
    let section = section.split("\n## Layers").nth(1).ok_or("docs/ARCHITECTURE.md has no `## Layers` section")?;
    let section = section.split("\n## ").next().unwrap_or(section);
    let mut layers = Layers::default();
    let mut every_lower = Vec::new();
    for (i, row) in section.lines().filter(|l| l.trim_start().starts_with('|')).enumerate().skip(2) {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        if cells.len() < 5 {
            return Err(format!("docs/ARCHITECTURE.md, Layers table row {}: expected `| layer | modules | may import |`, got `{row}`", i - 1));
        }
        let layer: u32 = cells[1].parse().map_err(|_| format!("docs/ARCHITECTURE.md, Layers table row {}: `{}` is not a layer number", i - 1, cells[1]))?;
        let allowed: BTreeSet<String> = backticked(cells[3]).into_iter().collect();
        for module in backticked(cells[2]) {
            if layers.layer.insert(module.clone(), layer).is_some() {
                return Err(format!("docs/ARCHITECTURE.md, Layers table: `{module}` is listed twice"));
            }
            if cells[3] == EVERY_LOWER_LAYER {
                every_lower.push(module.clone());
            }
            layers.may_import.insert(module, allowed.clone());
        }
    }
    if layers.layer.is_empty() {
        return Err("docs/ARCHITECTURE.md, Layers table: no rows".into());
    }
    for module in every_lower {
        let own = layers.layer[&module];
        let lower = layers.layer.iter().filter(|(_, l)| **l < own).map(|(m, _)| m.clone()).collect();
        layers.may_import.insert(module, lower);
    }
    Ok(layers)
}

/// Every table entry that would allow a cycle: a module allowed to import one that is not in a
/// lower layer, or one the table does not name.
fn table_errors(layers: &Layers) -> Vec<String> {
    let mut errors = Vec::new();
    for (module, allowed) in &layers.may_import {
        for other in allowed {
            match layers.layer.get(other) {
                None => errors.push(format!("Layers table: `{module}` may import `{other}`, which is not in the table")),
                Some(l) if *l >= layers.layer[module] => {
                    errors.push(format!("Layers table: `{module}` (layer {}) may import `{other}` (layer {l}), which is not lower", layers.layer[module]))
                }
                Some(_) => {}
            }
        }
    }
    errors
}

/// A token of Rust source without comments and literals: an identifier, `::`, or one
/// punctuation character ([`tokens`] pairs each with its line).
#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    Path,
    Punct(char),
}

/// Length in bytes of the string or char literal starting at `i` (0 if none starts there).
fn literal_len(b: &[u8], i: usize) -> usize {
    let mut j = i;
    if b[j] == b'b' {
        j += 1;
    }
    if j < b.len() && b[j] == b'r' && j + 1 < b.len() && (b[j + 1] == b'"' || b[j + 1] == b'#') {
        let hashes = b[j + 1..].iter().take_while(|c| **c == b'#').count();
        let open = j + 1 + hashes;
        if open >= b.len() || b[open] != b'"' {
            return 0;
        }
        let close: Vec<u8> = std::iter::once(b'"').chain(std::iter::repeat_n(b'#', hashes)).collect();
        let end = b[open + 1..].windows(close.len()).position(|w| w == close.as_slice()).map_or(b.len(), |p| open + 1 + p + close.len());
        return end - i;
    }
    if j < b.len() && b[j] == b'"' {
        let mut k = j + 1;
        while k < b.len() && b[k] != b'"' {
            k += if b[k] == b'\\' { 2 } else { 1 };
        }
        return (k + 1).min(b.len()) - i;
    }
    if j < b.len() && b[j] == b'\'' {
        // A char literal ('x', '\n', '\u{..}'); a lifetime ('a) has no closing quote.
        if j + 2 < b.len() && b[j + 1] == b'\\' {
            return b[j + 3..].iter().position(|c| *c == b'\'').map_or(0, |p| j + 4 + p - i);
        }
        let ch = std::str::from_utf8(&b[j + 1..]).ok().and_then(|s| s.chars().next()).map_or(1, char::len_utf8);
        if j + 1 + ch < b.len() && b[j + 1 + ch] == b'\'' {
            return j + 2 + ch - i;
        }
    }
    0
}

/// The tokens of `source` with their lines.
fn tokens(source: &str) -> Vec<(Tok, usize)> {
    let b = source.as_bytes();
    let (mut out, mut line, mut i) = (Vec::new(), 1, 0);
    while i < b.len() {
        let c = b[i];
        let skip = if b[i..].starts_with(b"//") {
            b[i..].iter().position(|c| *c == b'\n').unwrap_or(b.len() - i)
        } else if b[i..].starts_with(b"/*") {
            b[i..].windows(2).position(|w| w == b"*/").map_or(b.len() - i, |p| p + 2)
        } else if (c == b'"' || c == b'\'' || c == b'b' || c == b'r') && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) {
            literal_len(b, i)
        } else {
            0
        };
        if skip > 0 {
            line += b[i..i + skip].iter().filter(|c| **c == b'\n').count();
            i += skip;
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let n = b[i..].iter().take_while(|c| c.is_ascii_alphanumeric() || **c == b'_').count();
            out.push((Tok::Ident(source[i..i + n].to_string()), line));
            i += n;
        } else if b[i..].starts_with(b"::") {
            out.push((Tok::Path, line));
            i += 2;
        } else {
            if c == b'\n' {
                line += 1;
            } else if !c.is_ascii_whitespace() {
                out.push((Tok::Punct(c as char), line));
            }
            i += 1;
        }
    }
    out
}

/// The paths of a `use` tree (`a::{b, c::{self, d}}`), each as its segments; `as` aliases and
/// globs dropped (`a::*` is `a`).
fn use_paths(toks: &[Tok]) -> Vec<Vec<String>> {
    fn tree(toks: &[Tok], i: &mut usize, prefix: &[String], out: &mut Vec<Vec<String>>) {
        let mut path = prefix.to_vec();
        while let Some(t) = toks.get(*i) {
            match t {
                Tok::Ident(s) if s == "as" => *i += 2,
                // `{self, ..}` names the module of the prefix itself.
                Tok::Ident(s) if s == "self" && !path.is_empty() => *i += 1,
                Tok::Ident(s) => {
                    path.push(s.clone());
                    *i += 1;
                }
                Tok::Path | Tok::Punct('*') => *i += 1,
                Tok::Punct('{') => {
                    *i += 1;
                    while toks.get(*i).is_some_and(|t| *t != Tok::Punct('}')) {
                        tree(toks, i, &path, out);
                        if toks.get(*i) == Some(&Tok::Punct(',')) {
                            *i += 1;
                        }
                    }
                    *i += 1;
                    return;
                }
                _ => break,
            }
        }
        if !path.is_empty() {
            out.push(path);
        }
    }
    let mut out = Vec::new();
    tree(toks, &mut 0, &[], &mut out);
    out
}

/// The library's name, as the binary's files write it, and the first segment of the library's
/// absolute paths.
const LIBRARY: &str = "raygraph";

/// The first segment of the binary's absolute paths: not an identifier, so no path written in
/// the source names it.
const BINARY: &str = "<main.rs>";

/// The module path of a file under `src/` within its crate (`accel/cache.rs` -> `[accel,
/// cache]`; `lib.rs` and `main.rs` -> the crate root).
fn module_of(file: &str) -> Vec<String> {
    let stem = file.trim_end_matches(".rs");
    let mut parts: Vec<String> = stem.split('/').map(str::to_string).collect();
    if parts.last().is_some_and(|p| p == "mod") || stem == "lib" || stem == "main" {
        parts.pop();
    }
    parts
}

/// The top-level modules of the binary: those `main.rs` declares (`mod cli;`).
fn binary_modules(files: &[(String, String)]) -> BTreeSet<String> {
    let Some((_, main)) = files.iter().find(|(f, _)| f == "main.rs") else { return BTreeSet::new() };
    let toks: Vec<Tok> = tokens(main).into_iter().map(|(t, _)| t).collect();
    toks.windows(3)
        .filter_map(|w| match w {
            [Tok::Ident(m), Tok::Ident(name), Tok::Punct(';')] if m == "mod" => Some(name.clone()),
            _ => None,
        })
        .collect()
}

/// The absolute module path of a file under `src/`: its crate ([`LIBRARY`] or [`BINARY`], the
/// crate of `main.rs` and of the modules in `binary`), then [`module_of`].
fn module_path(file: &str, binary: &BTreeSet<String>) -> Vec<String> {
    let root = if file == "main.rs" || binary.contains(&top_of(file)) { BINARY } else { LIBRARY };
    std::iter::once(root.to_string()).chain(module_of(file)).collect()
}

/// The top-level module a file belongs to (`main` for `main.rs`, `lib` for `lib.rs`).
fn top_of(file: &str) -> String {
    match file {
        "main.rs" => "main".into(),
        "lib.rs" => "lib".into(),
        f => module_of(f)[0].clone(),
    }
}

/// The module tree of both crates: absolute module path -> file, and the re-exports of module
/// roots.
struct Crate {
    modules: BTreeMap<Vec<String>, String>,
    reexports: BTreeMap<(Vec<String>, String), Vec<String>>,
}

impl Crate {
    /// The file that defines what `path` (absolute, from a crate's root) names.
    fn resolve(&self, path: &[String], depth: usize) -> String {
        let mut module: Vec<String> = Vec::new();
        for (i, seg) in path.iter().enumerate() {
            let mut next = module.clone();
            next.push(seg.clone());
            if self.modules.contains_key(&next) {
                module = next;
            } else if let Some(target) = self.reexports.get(&(module.clone(), seg.clone())).filter(|_| depth < 8) {
                let full: Vec<String> = target.iter().chain(&path[i + 1..]).cloned().collect();
                return self.resolve(&full, depth + 1);
            } else {
                break;
            }
        }
        self.modules.get(&module).cloned().unwrap_or_else(|| "lib.rs".into())
    }
}

/// `path` as written where the module is `module` (absolute: the file's own, or an inline
/// module's inside it), made absolute; `None` for a path that does not start in `src/`.
fn absolute(crate_: &Crate, module: &[String], path: &[String]) -> Option<Vec<String>> {
    let (first, rest) = path.split_first()?;
    let own_crate = module.first()?;
    let root = match first.as_str() {
        "crate" => Some(own_crate.as_str()),
        LIBRARY if own_crate == BINARY => Some(LIBRARY),
        _ => None,
    };
    if let Some(root) = root {
        return Some(std::iter::once(root.to_string()).chain(rest.iter().cloned()).collect());
    }
    if first == "super" || first == "self" {
        let mut base = module.to_vec();
        let mut rest = path;
        while rest.first().is_some_and(|s| s == "super") {
            base.pop();
            rest = &rest[1..];
        }
        if rest.first().is_some_and(|s| s == "self") {
            rest = &rest[1..];
        }
        return Some(base.into_iter().chain(rest.iter().cloned()).collect());
    }
    let mut child = module.to_vec();
    child.push(first.clone());
    crate_.modules.contains_key(&child).then(|| module.iter().chain(path).cloned().collect())
}

/// A `use` declaration: its line, whether it is `pub`, its paths and the tokens it covers.
struct UseDecl {
    line: usize,
    is_pub: bool,
    paths: Vec<Vec<String>>,
    tokens: std::ops::Range<usize>,
}

/// The `use` declarations of a file.
fn use_declarations(toks: &[(Tok, usize)]) -> Vec<UseDecl> {
    let mut uses = Vec::new();
    for i in 0..toks.len() {
        if toks[i].0 != Tok::Ident("use".into()) || (i > 0 && toks[i - 1].0 == Tok::Path) {
            continue;
        }
        let end = (i..toks.len()).find(|j| toks[*j].0 == Tok::Punct(';')).unwrap_or(toks.len());
        let is_pub = (i >= 1 && toks[i - 1].0 == Tok::Ident("pub".into()))
            || (i >= 1 && toks[i - 1].0 == Tok::Punct(')') && toks[..i].iter().rev().take(6).any(|t| t.0 == Tok::Ident("pub".into())));
        let body: Vec<Tok> = toks[i + 1..end].iter().map(|t| t.0.clone()).collect();
        uses.push(UseDecl { line: toks[i].1, is_pub, paths: use_paths(&body), tokens: i..end });
    }
    uses
}

/// The module path at every token: the file's module plus the inline `mod name { .. }` blocks
/// open there.
fn modules_at(toks: &[(Tok, usize)], file_module: &[String]) -> Vec<Vec<String>> {
    let (mut out, mut stack, mut depth) = (Vec::with_capacity(toks.len()), Vec::<(String, usize)>::new(), 0usize);
    for (i, (t, _)) in toks.iter().enumerate() {
        match t {
            Tok::Punct('{') => {
                depth += 1;
                if i >= 2 && toks[i - 2].0 == Tok::Ident("mod".into()) {
                    if let Tok::Ident(name) = &toks[i - 1].0 {
                        stack.push((name.clone(), depth));
                    }
                }
            }
            Tok::Punct('}') => {
                if stack.last().is_some_and(|(_, d)| *d == depth) {
                    stack.pop();
                }
                depth = depth.saturating_sub(1);
            }
            _ => {}
        }
        out.push(file_module.iter().cloned().chain(stack.iter().map(|(n, _)| n.clone())).collect());
    }
    out
}

/// The inline paths of a file outside its `use` declarations: (token index, segments).
fn inline_paths(toks: &[(Tok, usize)], skip: &[std::ops::Range<usize>]) -> Vec<(usize, Vec<String>)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < toks.len() {
        if let Some(r) = skip.iter().find(|r| r.contains(&i)) {
            i = r.end;
            continue;
        }
        let starts = matches!(toks[i].0, Tok::Ident(_)) && (i == 0 || toks[i - 1].0 != Tok::Path) && toks.get(i + 1).is_some_and(|t| t.0 == Tok::Path);
        if !starts {
            i += 1;
            continue;
        }
        let mut path = Vec::new();
        let mut j = i;
        while let Some((Tok::Ident(s), _)) = toks.get(j) {
            path.push(s.clone());
            if toks.get(j + 1).is_some_and(|t| t.0 == Tok::Path) {
                j += 2;
            } else {
                break;
            }
        }
        out.push((i, path));
        i = j + 1;
    }
    out
}

/// Every import edge between `files` (path under `src/`, source), in the library and the binary.
fn edges(files: &[(String, String)]) -> Vec<Edge> {
    let binary = binary_modules(files);
    let module_of = |file: &str| module_path(file, &binary);
    let is_root = |file: &str| file.ends_with("mod.rs") || file == "lib.rs" || file == "main.rs";
    let modules = files.iter().map(|(f, _)| (module_of(f), f.clone())).collect();
    let mut crate_ = Crate { modules, reexports: BTreeMap::new() };
    let parsed: Vec<_> = files.iter().map(|(f, s)| (f, tokens(s))).collect();
    for (file, toks) in &parsed {
        for decl in use_declarations(toks).into_iter().filter(|u| u.is_pub && is_root(file)) {
            for p in decl.paths {
                if let (Some(abs), Some(name)) = (absolute(&crate_, &module_of(file), &p), p.last()) {
                    crate_.reexports.insert((module_of(file), name.clone()), abs);
                }
            }
        }
    }
    let mut out = Vec::new();
    for (file, toks) in &parsed {
        let is_root = is_root(file);
        let at = modules_at(toks, &module_of(file));
        let uses = use_declarations(toks);
        let ranges: Vec<std::ops::Range<usize>> = uses.iter().map(|u| u.tokens.clone()).collect();
        let mut found: Vec<(usize, Vec<String>, bool, usize)> = Vec::new();
        for u in uses {
            found.extend(u.paths.into_iter().map(|p| (u.line, p, u.is_pub && is_root, u.tokens.start)));
        }
        found.extend(inline_paths(toks, &ranges).into_iter().map(|(i, p)| (toks[i].1, p, false, i)));
        for (line, path, reexport, tok) in found {
            let Some(abs) = absolute(&crate_, &at[tok], &path) else { continue };
            let to = crate_.resolve(&abs, 0);
            if &to != *file {
                out.push(Edge { from: file.to_string(), line, to, path: path.join("::"), reexport });
            }
        }
    }
    out
}

/// Every edge between top-level modules that the table does not allow, and every top-level
/// module the table does not name.
fn forbidden(edges: &[Edge], layers: &Layers) -> Vec<String> {
    let mut errors = BTreeSet::new();
    for e in edges {
        let (from, to) = (top_of(&e.from), top_of(&e.to));
        if from == to || to == "lib" {
            continue;
        }
        match layers.may_import.get(&from) {
            None => {
                errors.insert(format!("src/{}: module `{from}` is not in the Layers table of docs/ARCHITECTURE.md", e.from));
            }
            Some(allowed) if !allowed.contains(&to) => {
                let list: Vec<&str> = allowed.iter().map(String::as_str).collect();
                let may = if list.is_empty() { "no module of the crate".to_string() } else { format!("only {}", list.join(", ")) };
                errors.insert(format!("src/{}:{}: `{}` imports `{to}` (src/{}): `{from}` may import {may}", e.from, e.line, e.path, e.to));
            }
            Some(_) => {}
        }
    }
    errors.into_iter().collect()
}

/// Every cycle between the files of one top-level module, each as its path
/// `a.rs:line -> b.rs:line -> a.rs`. Re-exports of module roots are not edges here.
fn cycles(edges: &[Edge]) -> Vec<String> {
    let mut graph: BTreeMap<&str, BTreeMap<&str, usize>> = BTreeMap::new();
    for e in edges.iter().filter(|e| !e.reexport && top_of(&e.from) == top_of(&e.to)) {
        graph.entry(&e.from).or_default().entry(&e.to).or_insert(e.line);
    }
    let mut state: BTreeMap<&str, u8> = BTreeMap::new(); // 1: on the stack, 2: done
    let mut found = Vec::new();
    fn visit<'a>(
        n: &'a str,
        graph: &BTreeMap<&'a str, BTreeMap<&'a str, usize>>,
        state: &mut BTreeMap<&'a str, u8>,
        stack: &mut Vec<&'a str>,
        found: &mut Vec<String>,
    ) {
        state.insert(n, 1);
        stack.push(n);
        for (&m, _) in graph.get(n).into_iter().flatten() {
            match state.get(m) {
                Some(1) => {
                    let start = stack.iter().position(|s| *s == m).unwrap_or(0);
                    let mut cycle: Vec<String> = stack[start..].windows(2).map(|w| format!("src/{}:{}", w[0], graph[w[0]][w[1]])).collect();
                    cycle.push(format!("src/{}:{}", n, graph[n][m]));
                    cycle.push(format!("src/{m}"));
                    found.push(cycle.join(" -> "));
                }
                None => visit(m, graph, state, stack, found),
                _ => {}
            }
        }
        stack.pop();
        state.insert(n, 2);
    }
    let nodes: Vec<&str> = graph.keys().copied().collect();
    for n in nodes {
        if !state.contains_key(n) {
            visit(n, &graph, &mut state, &mut Vec::new(), &mut found);
        }
    }
    found
}

/// Every `.rs` file under `dir` as (path relative to `root` with `/`, source).
fn read_sources(root: &Path, dir: &Path, out: &mut Vec<(String, String)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())).map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            read_sources(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let rel = path.strip_prefix(root).unwrap().components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/");
            out.push((rel, std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))));
        }
    }
}

fn repo_layers() -> Layers {
    let doc = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/ARCHITECTURE.md");
    let text = std::fs::read_to_string(&doc).unwrap_or_else(|e| panic!("{}: {e}", doc.display()));
    parse_layers(&text).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_layers_table_only_looks_down() {
    let layers = repo_layers();
    let errors = table_errors(&layers);
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    read_sources(&src, &src, &mut files);
    let tops: BTreeSet<String> = files.iter().map(|(f, _)| top_of(f)).filter(|t| t != "lib").collect();
    let missing: Vec<&String> = tops.iter().filter(|t| !layers.layer.contains_key(*t)).collect();
    assert!(missing.is_empty(), "modules missing from the Layers table of docs/ARCHITECTURE.md: {missing:?}");
}

#[test]
fn src_imports_follow_the_layers() {
    let layers = repo_layers();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    read_sources(&src, &src, &mut files);
    let edges = edges(&files);
    assert!(edges.len() > 300, "only {} imports found in src/: the scanner is broken", edges.len());
    let errors = forbidden(&edges, &layers);
    assert!(errors.is_empty(), "imports the Layers table of docs/ARCHITECTURE.md forbids:\n{}", errors.join("\n"));
}

#[test]
fn no_file_cycles_within_a_module() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    read_sources(&src, &src, &mut files);
    let found = cycles(&edges(&files));
    assert!(found.is_empty(), "import cycles between files:\n{}", found.join("\n"));
}

/// A small crate with a forbidden import (inline and through a re-export) and a file cycle.
fn synthetic() -> Vec<(String, String)> {
    let f = |p: &str, s: &str| (p.to_string(), s.to_string());
    vec![
        f("lib.rs", "pub mod low;\npub mod high;\n"),
        f("low/mod.rs", "//! uses crate::high::nothing in a comment only\npub mod a;\npub mod b;\npub use a::Thing;\n"),
        f("low/a.rs", "use super::b::helper;\npub struct Thing;\nfn f() { let s = \"crate::high::x\"; helper(); }\n"),
        f("low/b.rs", "pub fn helper() {}\nfn g() -> usize {\n    crate::high::top::count()\n}\nfn h(_: &super::Thing) {}\n"),
        f("high/mod.rs", "pub mod top;\n"),
        f("high/top.rs", "use crate::low::{self, Thing};\npub fn count() -> usize { 0 }\n"),
    ]
}

#[test]
fn the_checker_catches_a_forbidden_edge_and_a_cycle() {
    let layers =
        parse_layers("# x\n\n## Layers\n\n| layer | modules | may import |\n| --- | --- | --- |\n| 0 | `low` | — |\n| 1 | `high` | `low` |\n\n## Next\n")
            .unwrap();
    assert!(table_errors(&layers).is_empty());
    let edges = edges(&synthetic());
    let errors = forbidden(&edges, &layers);
    assert_eq!(errors, vec!["src/low/b.rs:3: `crate::high::top::count` imports `high` (src/high/top.rs): `low` may import no module of the crate".to_string()]);
    let found = cycles(&edges);
    assert_eq!(found, vec!["src/low/a.rs:1 -> src/low/b.rs:5 -> src/low/a.rs".to_string()], "{edges:#?}");
    // `high` imports `low` (allowed); the re-export `Thing` resolves to its defining file.
    assert!(edges.iter().any(|e| e.from == "high/top.rs" && e.to == "low/a.rs" && e.path == "crate::low::Thing"), "{edges:#?}");
    let every = parse_layers(
        "## Layers\n\n| layer | modules | may import |\n| --- | --- | --- |\n| 0 | `a`, `b` | — |\n| 1 | `c` | `a` |\n| 2 | `d` | every lower layer |\n",
    )
    .unwrap();
    let below_d: BTreeSet<String> = ["a", "b", "c"].into_iter().map(String::from).collect();
    assert_eq!(every.may_import["d"], below_d);
    let bad = parse_layers("## Layers\n\n| layer | modules | may import |\n| --- | --- | --- |\n| 0 | `low` | `high` |\n| 1 | `high` | `low` |\n").unwrap();
    assert_eq!(table_errors(&bad), vec!["Layers table: `low` (layer 0) may import `high` (layer 1), which is not lower".to_string()]);
}

/// The binary beside the library of [`synthetic`]: `main.rs` declares `cli`, whose file names
/// the library `raygraph::` (once a module `cli` may not import) and climbs back up to `main.rs`.
#[test]
fn the_checker_reads_the_binary_and_its_modules() {
    let layers = parse_layers(
        "## Layers\n\n| layer | modules | may import |\n| --- | --- | --- |\n| 0 | `low` | — |\n| 1 | `high` | `low` |\n| 2 | `cli` | `low` |\n| 3 | `main` | `cli` |\n",
    )
    .unwrap();
    let mut files = synthetic();
    let f = |p: &str, s: &str| (p.to_string(), s.to_string());
    files.push(f("main.rs", "mod cli;\nfn main() {\n    cli::run::go();\n}\npub fn exit() {}\n"));
    files.push(f("cli/mod.rs", "pub mod run;\n"));
    files.push(f("cli/run.rs", "use raygraph::low::Thing;\npub fn go() {\n    raygraph::high::top::count();\n    crate::exit();\n}\n"));
    let edges = edges(&files);
    assert!(edges.iter().any(|e| e.from == "main.rs" && e.to == "cli/run.rs" && e.path == "cli::run::go"), "{edges:#?}");
    assert!(edges.iter().any(|e| e.from == "cli/run.rs" && e.to == "low/a.rs" && e.path == "raygraph::low::Thing"), "{edges:#?}");
    assert_eq!(
        forbidden(&edges, &layers),
        vec![
            "src/cli/run.rs:3: `raygraph::high::top::count` imports `high` (src/high/top.rs): `cli` may import only low".to_string(),
            "src/cli/run.rs:4: `crate::exit` imports `main` (src/main.rs): `cli` may import only low".to_string(),
            "src/low/b.rs:3: `crate::high::top::count` imports `high` (src/high/top.rs): `low` may import no module of the crate".to_string(),
        ]
    );
}
