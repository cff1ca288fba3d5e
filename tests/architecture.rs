//! `docs/ARCHITECTURE.md` stays a page a next engineer reads, true to the code: at most
//! [`MAX_LINES`] lines of at most [`MAX_WIDTH`] characters, every repository path it writes in
//! backticks exists, and its list of compiler phases is the list of phase calls that
//! `graph::compile::compile_with` (`src/graph/compile/mod.rs`) makes, in the same order.
//! (`tests/layering.rs` checks the page's "Layers" table.)

use std::collections::BTreeSet;
use std::path::Path;

/// The most lines the page may have.
const MAX_LINES: usize = 300;
/// The most characters a line of the page may have.
const MAX_WIDTH: usize = 120;
/// The top-level folders of the repository whose paths the page may name in backticks.
const CHECKED_ROOTS: [&str; 9] = ["src", "tests", "shaders", "graph", "layers", "examples", "web", "docs", "assets"];
/// The heading of the page's section that lists the phases.
const PHASES_HEADING: &str = "## Compiler phases";
/// The compiler's function whose body is the list of phases.
const PHASE_LIST_FN: &str = "compile_with";

fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(relative: &str) -> String {
    let path = repo().join(relative);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The page's text outside fenced code blocks, as (line number, line).
fn prose_lines(markdown: &str) -> Vec<(usize, &str)> {
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in markdown.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced {
            out.push((i + 1, line));
        }
    }
    out
}

/// The text of each inline code span of a line (`like this`).
fn code_spans(line: &str) -> impl Iterator<Item = &str> {
    line.split('`').skip(1).step_by(2)
}

/// Every line over [`MAX_WIDTH`] characters, and the page's length if over [`MAX_LINES`].
fn size_errors(markdown: &str) -> Vec<String> {
    let mut errors: Vec<String> = markdown
        .lines()
        .enumerate()
        .filter(|(_, l)| l.chars().count() > MAX_WIDTH)
        .map(|(i, l)| format!("line {}: {} characters (at most {MAX_WIDTH})", i + 1, l.chars().count()))
        .collect();
    let lines = markdown.lines().count();
    if lines > MAX_LINES {
        errors.push(format!("{lines} lines (at most {MAX_LINES})"));
    }
    errors
}

/// The repository path a code span names, if it names one: a span that starts with one of
/// [`CHECKED_ROOTS`] and a `/`, or a WGSL file written as the shaders name it (relative to
/// `shaders/`); none for a span with a pattern or placeholder.
fn as_repo_path(span: &str) -> Option<String> {
    let root = span.split('/').next()?;
    let plain = !span.contains(|c: char| c.is_whitespace() || "*<>{}|".contains(c));
    if !plain || !span.contains('/') {
        None
    } else if CHECKED_ROOTS.contains(&root) {
        Some(span.to_string())
    } else {
        span.ends_with(".wgsl").then(|| format!("shaders/{span}"))
    }
}

/// Every path the page writes in backticks that does not exist in the repository at `root`.
fn missing_paths(markdown: &str, root: &Path) -> Vec<String> {
    let mut seen = BTreeSet::new();
    let mut missing = Vec::new();
    for (line, text) in prose_lines(markdown) {
        for path in code_spans(text).filter_map(as_repo_path) {
            if !root.join(&path).exists() && seen.insert(path.clone()) {
                missing.push(format!("line {line}: `{path}`"));
            }
        }
    }
    missing
}

/// Rust source with its comments and string literals blanked (line breaks kept).
fn strip_comments_and_strings(source: &str) -> String {
    let b = source.as_bytes();
    let mut out = String::with_capacity(source.len());
    let mut i = 0;
    while i < b.len() {
        let skip = if b[i..].starts_with(b"//") {
            b[i..].iter().position(|c| *c == b'\n').unwrap_or(b.len() - i)
        } else if b[i..].starts_with(b"/*") {
            b[i..].windows(2).position(|w| w == b"*/").map_or(b.len() - i, |p| p + 2)
        } else if b[i] == b'"' {
            let mut k = i + 1;
            while k < b.len() && b[k] != b'"' {
                k += if b[k] == b'\\' { 2 } else { 1 };
            }
            (k + 1).min(b.len()) - i
        } else {
            0
        };
        if skip > 0 {
            out.extend(source[i..i + skip].chars().map(|c| if c == '\n' { '\n' } else { ' ' }));
            i += skip;
        } else {
            let c = source[i..].chars().next().unwrap();
            out.push(c);
            i += c.len_utf8();
        }
    }
    out
}

/// Tokens of Rust source without comments: identifiers, `::`, and single punctuation.
fn tokens(source: &str) -> Vec<String> {
    let code = strip_comments_and_strings(source);
    let mut out = Vec::new();
    let mut chars = code.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        if c.is_alphanumeric() || c == '_' {
            let mut end = i + c.len_utf8();
            while let Some(&(j, d)) = chars.peek() {
                if !(d.is_alphanumeric() || d == '_') {
                    break;
                }
                end = j + d.len_utf8();
                chars.next();
            }
            out.push(code[i..end].to_string());
        } else if c == ':' && chars.peek().is_some_and(|&(_, d)| d == ':') {
            chars.next();
            out.push("::".into());
        } else if !c.is_whitespace() {
            out.push(c.to_string());
        }
    }
    out
}

/// The child modules a module file declares (`mod name;`, any visibility).
fn child_modules(toks: &[String]) -> BTreeSet<String> {
    toks.windows(3).filter(|w| w[0] == "mod" && w[2] == ";").map(|w| w[1].clone()).collect()
}

/// The body of `fn name` (the tokens between its braces), if the file defines it.
fn fn_body<'a>(toks: &'a [String], name: &str) -> Option<&'a [String]> {
    let at = toks.windows(2).position(|w| w[0] == "fn" && w[1] == name)?;
    let open = at + toks[at..].iter().position(|t| t == "{")?;
    let mut depth = 0usize;
    for (k, t) in toks.iter().enumerate().skip(open) {
        match t.as_str() {
            "{" => depth += 1,
            "}" => {
                depth -= 1;
                if depth == 0 {
                    return Some(&toks[open + 1..k]);
                }
            }
            _ => {}
        }
    }
    None
}

/// The phases `fn name` of a compiler module runs, in order: each call `child::function(..)` into
/// one of the file's child modules, first occurrence only; a call of another function of the
/// same file (a helper the list was split into) contributes its own phases at that place.
fn phase_calls(toks: &[String], name: &str) -> Vec<String> {
    fn walk(toks: &[String], name: &str, modules: &BTreeSet<String>, stack: &mut Vec<String>, out: &mut Vec<String>) {
        let Some(body) = fn_body(toks, name) else { return };
        stack.push(name.to_string());
        for (i, t) in body.iter().enumerate() {
            let after_path = i > 0 && (body[i - 1] == "::" || body[i - 1] == ".");
            let next = |k: usize| body.get(i + k).map(String::as_str);
            if modules.contains(t) && !after_path && next(1) == Some("::") && next(3).is_some_and(|n| n == "(" || n == "::") {
                let call = format!("{t}::{}", body[i + 2]);
                if !out.contains(&call) {
                    out.push(call);
                }
            } else if !after_path && next(1) == Some("(") && !stack.contains(t) && fn_body(toks, t).is_some() {
                walk(toks, t, modules, stack, out);
            }
        }
        stack.pop();
    }
    let modules = child_modules(toks);
    let mut out = Vec::new();
    walk(toks, name, &modules, &mut Vec::new(), &mut out);
    out
}

/// The page's phase list: the first code span of each numbered item under [`PHASES_HEADING`].
fn documented_phases(markdown: &str) -> Result<Vec<String>, String> {
    let text = format!("\n{markdown}");
    let start = text.find(&format!("\n{PHASES_HEADING}")).ok_or(format!("docs/ARCHITECTURE.md has no `{PHASES_HEADING}` section"))?;
    let section = text[start + 1 + PHASES_HEADING.len()..].split("\n## ").next().unwrap_or_default();
    let mut phases = Vec::new();
    for line in section.lines().map(str::trim_start) {
        let digits = line.chars().take_while(char::is_ascii_digit).count();
        if digits == 0 || !line[digits..].starts_with(". ") {
            continue;
        }
        match code_spans(line).next() {
            Some(span) if span.contains("::") => phases.push(span.to_string()),
            _ => return Err(format!("docs/ARCHITECTURE.md, {PHASES_HEADING}: item `{line}` names no phase as `module::function`")),
        }
    }
    if phases.is_empty() {
        return Err(format!("docs/ARCHITECTURE.md, {PHASES_HEADING}: no numbered list of phases"));
    }
    Ok(phases)
}

/// What differs between the page's list and the code's: phases missing from the page, phases
/// the code does not run, and the first place where the order differs.
fn phase_list_errors(page: &[String], code: &[String]) -> Vec<String> {
    let mut errors = Vec::new();
    for phase in code.iter().filter(|p| !page.contains(p)) {
        errors.push(format!("missing from the page: `{phase}`"));
    }
    for phase in page.iter().filter(|p| !code.contains(p)) {
        errors.push(format!("on the page but not run by {PHASE_LIST_FN}: `{phase}`"));
    }
    let page_common: Vec<&String> = page.iter().filter(|p| code.contains(p)).collect();
    let code_common: Vec<&String> = code.iter().filter(|p| page.contains(p)).collect();
    if let Some(k) = page_common.iter().zip(&code_common).position(|(a, b)| a != b) {
        errors.push(format!("out of order: the page lists `{}` where the code runs `{}` (phase {} of those both name)", page_common[k], code_common[k], k + 1));
    }
    let mut duplicates = BTreeSet::new();
    for phase in page.iter().filter(|p| page.iter().filter(|q| q == p).count() > 1) {
        if duplicates.insert(phase) {
            errors.push(format!("listed more than once on the page: `{phase}`"));
        }
    }
    errors
}

#[test]
fn the_page_is_short_and_narrow() {
    let errors = size_errors(&read("docs/ARCHITECTURE.md"));
    assert!(errors.is_empty(), "docs/ARCHITECTURE.md:\n{}", errors.join("\n"));
}

#[test]
fn every_path_on_the_page_exists() {
    let missing = missing_paths(&read("docs/ARCHITECTURE.md"), repo());
    assert!(missing.is_empty(), "paths docs/ARCHITECTURE.md names that do not exist:\n{}", missing.join("\n"));
}

#[test]
fn the_phase_list_is_the_compilers() {
    let page = documented_phases(&read("docs/ARCHITECTURE.md")).unwrap_or_else(|e| panic!("{e}"));
    let code = phase_calls(&tokens(&read("src/graph/compile/mod.rs")), PHASE_LIST_FN);
    assert!(code.len() >= 10, "only {} phase calls found in {PHASE_LIST_FN} (src/graph/compile/mod.rs): the scanner is broken: {code:?}", code.len());
    let errors = phase_list_errors(&page, &code);
    assert!(
        errors.is_empty(),
        "docs/ARCHITECTURE.md, \"{PHASES_HEADING}\" against {PHASE_LIST_FN} in src/graph/compile/mod.rs:\n{}\n\nthe code runs, in order:\n{}",
        errors.join("\n"),
        code.iter().enumerate().map(|(i, p)| format!("{}. `{p}`", i + 1)).collect::<Vec<_>>().join("\n")
    );
}

#[test]
fn the_checkers_catch_what_they_should() {
    let long = format!("# x\n{}\n", "a".repeat(MAX_WIDTH + 1));
    assert_eq!(size_errors(&long), vec![format!("line 2: {} characters (at most {MAX_WIDTH})", MAX_WIDTH + 1)]);
    assert_eq!(size_errors(&"x\n".repeat(MAX_LINES + 1)), vec![format!("{} lines (at most {MAX_LINES})", MAX_LINES + 1)]);

    let page = "See `src/lib.rs`, `src/nowhere.rs`, `graph/*.ron`, `Plan`, `trace/trace.wgsl`, `x/no.wgsl`.\n```\n`src/fenced.rs`\n```\n";
    assert_eq!(missing_paths(page, repo()), vec!["line 1: `src/nowhere.rs`".to_string(), "line 1: `shaders/x/no.wgsl`".to_string()]);

    let source = r#"
        //! `fake::call()` in a comment
        mod a;
        pub(crate) mod b;
        pub fn compile_with() -> R {
            let x = a::first(1)?;
            helper(&x);
            let s = "b::in_a_string()";
            b::third::<T>(x);
            a::first(2)?;
            Ok(other::not_a_child(x))
        }
        fn helper(x: &X) { b::second(x); helper(x); }
    "#;
    let code = phase_calls(&tokens(source), "compile_with");
    assert_eq!(code, vec!["a::first", "b::second", "b::third"]);

    let markdown = "## Compiler phases\n\n1. `a::first`: one;\n2. `b::third`: three,\n   wrapped;\n3. `b::second`: two;\n4. `c::extra`\n\n## Next\n5. `z::z`\n";
    let page = documented_phases(markdown).unwrap();
    assert_eq!(page, vec!["a::first", "b::third", "b::second", "c::extra"]);
    let code: Vec<String> = ["a::first", "b::second", "b::third", "d::missing"].map(String::from).to_vec();
    assert_eq!(
        phase_list_errors(&page, &code),
        vec![
            "missing from the page: `d::missing`".to_string(),
            format!("on the page but not run by {PHASE_LIST_FN}: `c::extra`"),
            "out of order: the page lists `b::third` where the code runs `b::second` (phase 2 of those both name)".to_string(),
        ]
    );
    assert!(documented_phases("## Compiler phases\n\n1. parse the file\n").is_err());
}
