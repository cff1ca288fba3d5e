//! Every function stays readable: no function in `src/` (the library and the command line),
//! `web/src/`, `tests/`, `examples/`, the fuzz targets or `build.rs` is longer than [`MAX_LINES`]
//! lines, counted from its `fn` line to its closing brace. A longer one is named as
//! `file:line fn name (N lines)`.

use std::path::{Path, PathBuf};

/// The most lines a function may span, its `fn` line and closing brace included.
const MAX_LINES: usize = 80;

/// `source` with comments, string and char literals made spaces (newlines kept), so that only
/// code is left to count braces in.
fn code_only(source: &str) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out: Vec<char> = chars.clone();
    let blank = |out: &mut Vec<char>, from: usize, to: usize| out[from..to].iter_mut().filter(|c| **c != '\n').for_each(|c| *c = ' ');
    let mut i = 0;
    while i < chars.len() {
        let rest = &chars[i..];
        let after_ident = i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_');
        let len = if rest.starts_with(&['/', '/']) {
            rest.iter().position(|c| *c == '\n').unwrap_or(rest.len())
        } else if rest.starts_with(&['/', '*']) {
            block_comment_len(rest)
        } else if !after_ident && rest.starts_with(&['b', '\'']) {
            char_len(&rest[1..]) + 1
        } else if !after_ident && (rest[0] == '"' || rest[0] == 'r' || rest[0] == 'b') {
            string_len(rest)
        } else if !after_ident && rest[0] == '\'' {
            char_len(rest)
        } else {
            0
        };
        if len > 0 {
            blank(&mut out, i, i + len);
            i += len;
        } else {
            i += 1;
        }
    }
    out.into_iter().collect()
}

/// Length of the (possibly nested) block comment at the start of `s`.
fn block_comment_len(s: &[char]) -> usize {
    let (mut depth, mut i) = (0usize, 0usize);
    while i < s.len() {
        if s[i..].starts_with(&['/', '*']) {
            depth += 1;
            i += 2;
        } else if s[i..].starts_with(&['*', '/']) {
            depth -= 1;
            i += 2;
            if depth == 0 {
                return i;
            }
        } else {
            i += 1;
        }
    }
    s.len()
}

/// Length of the string literal (`"..."`, `b"..."`, `r#"..."#`, `br"..."`) at the start of `s`;
/// 0 if none starts there.
fn string_len(s: &[char]) -> usize {
    let mut j = usize::from(s[0] == 'b');
    if s.get(j) == Some(&'r') {
        let hashes = s[j + 1..].iter().take_while(|c| **c == '#').count();
        let open = j + 1 + hashes;
        if s.get(open) != Some(&'"') {
            return 0;
        }
        let close: Vec<char> = std::iter::once('"').chain(std::iter::repeat_n('#', hashes)).collect();
        return s[open + 1..].windows(close.len()).position(|w| w == close.as_slice()).map_or(s.len(), |p| open + 1 + p + close.len());
    }
    if s.get(j) != Some(&'"') {
        return 0;
    }
    j += 1;
    while j < s.len() && s[j] != '"' {
        j += if s[j] == '\\' { 2 } else { 1 };
    }
    (j + 1).min(s.len())
}

/// Length of the char literal at the start of `s` (`'x'`, `'\n'`, `'\u{..}'`); 0 for a
/// lifetime (`'a`), which has no closing quote.
fn char_len(s: &[char]) -> usize {
    if s.get(1) == Some(&'\\') {
        return s[2..].iter().skip(1).position(|c| *c == '\'').map_or(0, |p| p + 4);
    }
    if s.get(2) == Some(&'\'') {
        3
    } else {
        0
    }
}

/// A function too long: where it starts, its name and how many lines it spans.
struct LongFn {
    file: PathBuf,
    line: usize,
    name: String,
    lines: usize,
}

/// Every function of `source` (nested ones too) as (line of `fn`, name, lines spanned); a
/// declaration without a body (`fn f();`) is skipped.
fn functions(source: &str) -> Vec<(usize, String, usize)> {
    let code: Vec<char> = code_only(source).chars().collect();
    let line_at = |i: usize| code[..i].iter().filter(|c| **c == '\n').count() + 1;
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = Vec::new();
    for i in 0..code.len().saturating_sub(2) {
        let keyword = code[i..].starts_with(&['f', 'n']) && !is_ident(code[i + 2]) && (i == 0 || !is_ident(code[i - 1]));
        if !keyword {
            continue;
        }
        let name_start = i + 2 + code[i + 2..].iter().take_while(|c| c.is_whitespace()).count();
        let name: String = code[name_start..].iter().take_while(|c| is_ident(**c)).collect();
        if name.is_empty() {
            continue; // a function pointer type, `fn(..)`
        }
        if let Some(end) = body_end(&code, name_start + name.len()) {
            out.push((line_at(i), name, line_at(end) - line_at(i) + 1));
        }
    }
    out
}

/// Index of the brace closing the body that follows a signature ending somewhere after
/// `from`; `None` for a declaration (`;` outside brackets before any `{`).
fn body_end(code: &[char], from: usize) -> Option<usize> {
    let mut brackets = 0i32;
    let mut i = from;
    while i < code.len() {
        match code[i] {
            '(' | '[' => brackets += 1,
            ')' | ']' => brackets -= 1,
            ';' if brackets == 0 => return None,
            '{' if brackets == 0 => break,
            _ => {}
        }
        i += 1;
    }
    let mut depth = 0i32;
    for (j, c) in code.iter().enumerate().skip(i) {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return Some(j);
                }
            }
            _ => {}
        }
    }
    None
}

/// The `.rs` files at `path` (a file, or a directory searched recursively), sorted.
fn rust_files(path: &Path) -> Vec<PathBuf> {
    if path.is_file() {
        return vec![path.to_path_buf()];
    }
    let mut out = Vec::new();
    for entry in std::fs::read_dir(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display())) {
        let p = entry.unwrap().path();
        if p.is_dir() {
            out.extend(rust_files(&p));
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
    out.sort();
    out
}

/// The functions of the files at `path` (relative to the crate) longer than [`MAX_LINES`].
fn long_functions(path: &str) -> Vec<LongFn> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut long = Vec::new();
    for file in rust_files(&root.join(path)) {
        let source = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("cannot read {}: {e}", file.display()));
        let rel = file.strip_prefix(root).unwrap_or(&file).to_path_buf();
        for (line, name, lines) in functions(&source) {
            if lines > MAX_LINES {
                long.push(LongFn { file: rel.clone(), line, name, lines });
            }
        }
    }
    long
}

fn assert_short(path: &str) {
    let long = long_functions(path);
    let listed: Vec<String> = long.iter().map(|f| format!("{}:{} fn {} ({} lines)", f.file.display(), f.line, f.name, f.lines)).collect();
    assert!(listed.is_empty(), "functions in {path} longer than {MAX_LINES} lines; split them into named steps:\n{}", listed.join("\n"));
}

#[test]
fn every_function_in_src_is_short() {
    assert_short("src");
}

#[test]
fn every_function_of_the_web_build_is_short() {
    assert_short("web/src");
}

#[test]
fn every_function_of_the_tests_examples_and_build_script_is_short() {
    for path in ["tests", "examples", "fuzz/fuzz_targets", "build.rs"] {
        assert_short(path);
    }
}

#[test]
fn counts_from_fn_line_to_closing_brace_ignoring_literals_and_comments() {
    let source = "fn short() {\n    let s = \"}}}\";\n    let c = '}';\n    let q = b'\"';\n    // }\n    /* { */\n}\n\nfn declared();\nfn long<'a>(x: [u8; 2]) -> &'a str {\n    let r = r#\"{\"#;\n    \"\"\n}\n";
    let found = functions(source);
    assert_eq!(found, vec![(1, "short".to_string(), 7), (10, "long".to_string(), 4)]);
}
