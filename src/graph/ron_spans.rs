//! Spans of the keys and values of a RON document (graph and layer files), from a parse of its
//! structure: struct fields, map keys, list items, strings and identifiers with their byte
//! offsets, in document order. Compile errors point at a place through a path of anchors
//! ([`RonSpans::locate`]); since the anchors match parsed keys and values, a name written in a
//! comment, inside another string or as part of a longer name is never where an error points.
//!
//! The `ron` crate parses the files into their types; it reports where a syntax error is, but
//! not where a value that parsed came from, so this parser is run on the same text for that.
//! It accepts what the files use (structs with and without names, tuples, lists, maps,
//! strings, raw strings, numbers, identifiers, `//` and nested `/* */` comments) and stops at
//! anything else, keeping what it read.

/// One key or value of the document.
#[derive(Debug, Clone, PartialEq)]
struct Item {
    /// A struct field's name or a map key's text (a string key without its quotes).
    key: Option<String>,
    /// The key was a string (a map key written `"name"`), not an identifier.
    key_quoted: bool,
    /// Byte offset of the key.
    key_start: usize,
    /// The value's string content or identifier (a struct's name, an enum variant, a number).
    word: Option<Word>,
    /// Byte offset of the value.
    value_start: usize,
    /// Index of the item's last descendant (itself when it has none).
    last: usize,
    /// Index of the enclosing item (struct, map, list or tuple), `None` at the top.
    parent: Option<usize>,
}

#[derive(Debug, Clone, PartialEq)]
enum Word {
    /// A string literal's content.
    Str(String),
    /// An identifier or a number.
    Ident(String),
}

/// The items of a document in document order (each before its descendants).
#[derive(Debug, Clone, Default)]
pub(crate) struct RonSpans {
    items: Vec<Item>,
}

impl RonSpans {
    /// Parses `text` as far as it is RON.
    pub fn parse(text: &str) -> RonSpans {
        let mut p = Parser { s: text.as_bytes(), text, i: 0, items: Vec::new() };
        p.skip_trivia();
        p.value(None, None);
        RonSpans { items: p.items }
    }

    /// Byte offset of the place the anchors lead to. Each anchor is searched for after the
    /// previous one's match, within the item that match belongs to: a quoted anchor
    /// (`"\"gbuffer\""`) matches a string, as a map key or a value; an unquoted one (`passes`)
    /// matches a struct field's name or an identifier. A match by key leads into that item's
    /// value; a match of a string value leads to the rest of its enclosing item (the fields of a
    /// pass after its `name`). An anchor not found ends the search at the last match (or the
    /// start of the document).
    pub fn locate(&self, anchors: &[&str]) -> usize {
        let (mut from, mut to) = (0usize, self.items.len());
        let mut skip_key_of = None;
        let mut offset = 0usize;
        for anchor in anchors {
            let (quoted, name) = match anchor.strip_prefix('"').and_then(|a| a.strip_suffix('"')) {
                Some(inner) => (true, inner),
                None => (false, *anchor),
            };
            let found = (from..to).find_map(|i| {
                let item = &self.items[i];
                let key_hit = skip_key_of != Some(i) && item.key.as_deref() == Some(name) && item.key_quoted == quoted;
                let value_hit = match &item.word {
                    Some(Word::Str(s)) => quoted && s == name,
                    Some(Word::Ident(s)) => !quoted && s == name,
                    None => false,
                };
                if key_hit {
                    Some((i, true))
                } else if value_hit {
                    Some((i, false))
                } else {
                    None
                }
            });
            let Some((i, by_key)) = found else { break };
            let item = &self.items[i];
            if by_key {
                offset = item.key_start;
                (from, to) = (i, item.last + 1);
                skip_key_of = Some(i);
            } else {
                offset = item.value_start;
                let scope_end = item.parent.map_or(self.items.len(), |p| self.items[p].last + 1);
                (from, to) = (i + 1, scope_end);
                skip_key_of = None;
            }
        }
        offset
    }
}

/// A key as parsed: its text, whether it was a string, where it starts.
struct Key {
    text: String,
    quoted: bool,
    start: usize,
}

struct Parser<'a> {
    s: &'a [u8],
    text: &'a str,
    i: usize,
    items: Vec<Item>,
}

impl Parser<'_> {
    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    /// Skips whitespace and comments (`//` to the line's end, `/* */` nested).
    fn skip_trivia(&mut self) {
        loop {
            match (self.peek(), self.s.get(self.i + 1).copied()) {
                (Some(c), _) if c.is_ascii_whitespace() => self.i += 1,
                (Some(b'/'), Some(b'/')) => {
                    while self.peek().is_some_and(|c| c != b'\n') {
                        self.i += 1;
                    }
                }
                (Some(b'/'), Some(b'*')) => {
                    let mut depth = 0usize;
                    while self.i < self.s.len() {
                        match (self.s[self.i], self.s.get(self.i + 1).copied()) {
                            (b'/', Some(b'*')) => {
                                depth += 1;
                                self.i += 2;
                            }
                            (b'*', Some(b'/')) => {
                                depth -= 1;
                                self.i += 2;
                                if depth == 0 {
                                    break;
                                }
                            }
                            _ => self.i += 1,
                        }
                    }
                }
                _ => return,
            }
        }
    }

    fn is_word_byte(c: u8) -> bool {
        c.is_ascii_alphanumeric() || matches!(c, b'_' | b'.' | b'+' | b'-')
    }

    /// A string literal at the cursor (`"..."` with escapes, or `r#"..."#`): its content.
    fn string(&mut self) -> Option<String> {
        if self.peek() == Some(b'r') {
            let start = self.i + 1;
            let hashes = self.s[start..].iter().take_while(|&&c| c == b'#').count();
            if self.s.get(start + hashes) != Some(&b'"') {
                return None;
            }
            let body = start + hashes + 1;
            let closing = format!("\"{}", "#".repeat(hashes));
            let end = self.text[body..].find(&closing)? + body;
            self.i = end + closing.len();
            return Some(self.text[body..end].to_string());
        }
        if self.peek() != Some(b'"') {
            return None;
        }
        let mut out = String::new();
        self.i += 1;
        let mut chars = self.text[self.i..].char_indices();
        while let Some((k, c)) = chars.next() {
            match c {
                '"' => {
                    self.i += k + 1;
                    return Some(out);
                }
                '\\' => {
                    if let Some((_, e)) = chars.next() {
                        out.push(match e {
                            'n' => '\n',
                            't' => '\t',
                            other => other,
                        });
                    }
                }
                c => out.push(c),
            }
        }
        self.i = self.s.len();
        None
    }

    fn word(&mut self) -> Option<String> {
        let start = self.i;
        while self.peek().is_some_and(Self::is_word_byte) {
            self.i += 1;
        }
        (self.i > start).then(|| self.text[start..self.i].to_string())
    }

    /// Parses one value at the cursor into an item (with `key`), and its contents after it.
    /// Returns false where the text is not RON this parser knows.
    fn value(&mut self, key: Option<Key>, parent: Option<usize>) -> bool {
        let index = self.items.len();
        let (key, key_quoted, key_start) = match key {
            Some(k) => (Some(k.text), k.quoted, k.start),
            None => (None, false, self.i),
        };
        self.items.push(Item { key, key_quoted, key_start, word: None, value_start: self.i, last: index, parent });
        let ok = match self.peek() {
            Some(b'"') => self.string().map(|s| self.items[index].word = Some(Word::Str(s))).is_some(),
            Some(b'r') if matches!(self.s.get(self.i + 1), Some(b'#') | Some(b'"')) => {
                self.string().map(|s| self.items[index].word = Some(Word::Str(s))).is_some()
            }
            Some(b'[') => self.sequence(b']', index, false),
            Some(b'{') => self.sequence(b'}', index, true),
            Some(b'(') => self.sequence(b')', index, false),
            Some(c) if Self::is_word_byte(c) => {
                let w = self.word().unwrap_or_default();
                self.items[index].word = Some(Word::Ident(w));
                self.skip_trivia();
                // A named struct or an enum variant with contents: `Layer(...)`, `Some(3)`.
                if self.peek() == Some(b'(') {
                    self.sequence(b')', index, false)
                } else {
                    true
                }
            }
            _ => false,
        };
        self.items[index].last = self.items.len() - 1;
        ok
    }

    /// The contents of a list, map (`map`: `key: value` entries) or parenthesised body (struct
    /// fields `name: value` or tuple items) up to `close`.
    fn sequence(&mut self, close: u8, parent: usize, map: bool) -> bool {
        self.i += 1;
        loop {
            self.skip_trivia();
            match self.peek() {
                None => return false,
                Some(c) if c == close => {
                    self.i += 1;
                    return true;
                }
                Some(b',') => {
                    self.i += 1;
                    continue;
                }
                _ => {}
            }
            let entry_start = self.i;
            let key = if map {
                let quoted = self.peek() == Some(b'"');
                let k = if quoted { self.string() } else { self.word() };
                self.skip_trivia();
                if self.peek() != Some(b':') {
                    return false;
                }
                self.i += 1;
                k.map(|text| Key { text, quoted, start: entry_start })
            } else if close == b')' && self.field_name_ahead() {
                let k = self.word();
                self.skip_trivia();
                self.i += 1; // the ':'
                k.map(|text| Key { text, quoted: false, start: entry_start })
            } else {
                None
            };
            self.skip_trivia();
            if !self.value(key, Some(parent)) {
                return false;
            }
        }
    }

    /// Whether the cursor is at `identifier :` (a struct field), not a value.
    fn field_name_ahead(&self) -> bool {
        let mut j = self.i;
        if !self.s.get(j).is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_') {
            return false;
        }
        while self.s.get(j).is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_') {
            j += 1;
        }
        while self.s.get(j).is_some_and(|c| c.is_ascii_whitespace()) {
            j += 1;
        }
        self.s.get(j) == Some(&b':') && self.s.get(j + 1) != Some(&b':')
    }
}

#[cfg(test)]
mod tests {
    use super::RonSpans;

    const GRAPH: &str = r#"// "gbuffer" in a comment, and inputs: {"tlas": x}
Graph(
    output: "tonemap.color",
    nodes: {
        /* "ao" as well, /* nested */ "inputs" */
        "albedo_ao": Layer(layer: "resolve"),
        "gbuffer": Layer(layer: "primary", inputs: {"tlas": "accel.tlas"}),
        "ao": Layer(
            layer: "rt_ao",
            inputs: {"position": "gbuffer.position", "geo_normal": "gbuffer.geo_normal"},
            params: {"rays": 64, "range_scale": 0.05},
        ),
        "accel": Accel(merge: true),
    },
)
"#;

    /// Asserts that the anchors lead to the place where `text` continues with `expected`.
    fn check(text: &str, anchors: &[&str], expected: &str) {
        let offset = RonSpans::parse(text).locate(anchors);
        assert!(text[offset..].starts_with(expected), "{anchors:?} led to {:?}", &text[offset..(offset + 30).min(text.len())]);
    }

    #[test]
    fn anchors_match_keys_and_values_never_comments_or_parts_of_names() {
        check(GRAPH, &["nodes", "\"ao\""], "\"ao\": Layer(\n");
        check(GRAPH, &["nodes", "\"gbuffer\"", "inputs", "\"tlas\""], "\"tlas\": \"accel.tlas\"}");
        check(GRAPH, &["nodes", "\"ao\"", "inputs", "\"geo_normal\"", "\"gbuffer.geo_normal\""], "\"gbuffer.geo_normal\"}");
        check(GRAPH, &["nodes", "\"ao\"", "params", "\"range_scale\""], "\"range_scale\": 0.05}");
        check(GRAPH, &["output", "\"tonemap.color\""], "\"tonemap.color\",\n    n");
        check(GRAPH, &["nodes", "\"accel\"", "merge"], "merge: true),\n    },");
    }

    #[test]
    fn a_missing_anchor_stops_at_the_last_match_inside_its_item() {
        // `gbuffer` has no params: the place stays at the node, not at `ao`'s params.
        check(GRAPH, &["nodes", "\"gbuffer\"", "params", "\"rays\""], "\"gbuffer\": Layer(la");
        assert_eq!(RonSpans::parse(GRAPH).locate(&["nowhere"]), 0);
    }

    #[test]
    fn a_string_value_leads_to_the_rest_of_its_struct() {
        let layer = r#"Layer(
    passes: [
        Pass(name: "first", kind: Compute, shader: "a.wgsl", writes: ["color"]),
        Pass(name: "second", kind: Compute, shader: "b.wgsl", reads: ["color"], writes: ["out"]),
    ],
)"#;
        check(layer, &["passes", "\"second\"", "shader"], "shader: \"b.wgsl\", re");
        check(layer, &["passes", "\"second\"", "writes", "\"out\""], "\"out\"]),\n    ],\n)");
        // `first` has no `reads`: the search stops at its name rather than at `second`'s reads.
        check(layer, &["passes", "\"first\"", "reads"], "\"first\", kind: Comp");
    }

    #[test]
    fn raw_strings_escapes_and_broken_text_are_read_as_far_as_they_go() {
        let text = r##"Graph(output: r#"a "quoted" name"#, nodes: {"x\"y": Layer(layer: "l"), "z": "##;
        check(text, &["output", "\"a \"quoted\" name\""], "r#\"a \"quoted\" name\"#");
        check(text, &["nodes", "\"x\"y\"", "layer"], "layer: \"l\"), \"z\": ");
        assert_eq!(RonSpans::parse("").locate(&["nodes"]), 0);
    }
}
