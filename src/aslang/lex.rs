//! Lexical pieces of an AS line: its code part, its names, its argument lists.

use compact_str::CompactString;

/// The code part of a line: everything before a `;` that is not inside a string, and whether
/// it holds a `"` (a code part without one is its own [`without_strings_into`]).
///
/// A byte scan (`"` and `;` are never part of a longer UTF-8 sequence): the line's first `;`
/// ends the code unless a `"` comes before it.
pub(super) fn code_part(line: &str) -> (&str, bool) {
    let b = line.as_bytes();
    let mut from = 0;
    let (mut in_str, mut quoted) = (false, false);
    while let Some(i) = memchr::memchr2(b'"', b';', &b[from..]) {
        let i = from + i;
        match b[i] {
            b'"' => {
                in_str = !in_str;
                quoted = true;
            }
            _ if !in_str => return (&line[..i], quoted),
            _ => {}
        }
        from = i + 1;
    }
    (line, quoted)
}

/// `name` in ASCII lower case, a key of the checks' tables of names (AS and RAPID names fit
/// inline: no allocation, where a `String` per program, call and label was one each).
pub(crate) fn lower_key(name: &str) -> CompactString {
    let mut key = CompactString::from(name);
    key.make_ascii_lowercase();
    key
}

/// `str::trim`, a byte scan when the ends are ASCII (the blanks `char::is_whitespace` takes,
/// vertical tab included).
pub fn trim_blanks(s: &str) -> &str {
    let blank = |c: &u8| matches!(c, b' ' | b'\t'..=b'\r');
    let b = s.as_bytes();
    let start = b.iter().position(|c| !blank(c)).unwrap_or(b.len());
    let end = b.iter().rposition(|c| !blank(c)).map_or(start, |i| i + 1);
    let t = &s[start..end];
    match (t.as_bytes().first(), t.as_bytes().last()) {
        (Some(a), Some(z)) if a.is_ascii() && z.is_ascii() => t,
        _ => t.trim(),
    }
}

/// The code with string literals blanked (so their words are not taken for names), appended to
/// `out` (the checker reuses one buffer for every line): each `"` and each character inside a
/// string becomes one space.
pub(super) fn without_strings_into(code: &str, out: &mut String) {
    let mut in_str = false;
    let mut rest = code;
    while let Some(i) = memchr::memchr(b'"', rest.as_bytes()) {
        let (part, after) = rest.split_at(i);
        push_part(part, in_str, out);
        out.push(' ');
        in_str = !in_str;
        rest = &after[1..];
    }
    push_part(rest, in_str, out);
}

/// A run between quotes: as it is, or one space per character inside a string.
fn push_part(part: &str, in_str: bool, out: &mut String) {
    if in_str {
        out.extend(std::iter::repeat_n(' ', part.chars().count()));
    } else {
        out.push_str(part);
    }
}

/// Whether `code` may hold a name longer than `max` ([`each_name`]): a name is part of a run
/// of name characters, so a line without a run longer than `max` has none (most lines: the
/// check skips the name scan for them).
pub(super) fn may_have_longer_name(code: &str, max: usize) -> bool {
    if code.len() <= max {
        return false;
    }
    let mut run = 0;
    for &c in code.as_bytes() {
        if NAME_BYTE[usize::from(c)] {
            run += 1;
            if run > max {
                return true;
            }
        } else {
            run = 0;
        }
    }
    false
}

/// The bytes of a name's run: ASCII letters and digits, `_` and `.` (a table: the check asks
/// it of every byte of every line).
static NAME_BYTE: [bool; 256] = {
    let mut t = [false; 256];
    let mut c = 0;
    while c < 256 {
        let b = c as u8;
        t[c] = b.is_ascii_alphanumeric() || b == b'_' || b == b'.';
        c += 1;
    }
    t
};

/// Names in a code line, without the local dot and the sigil: `.#cur` → `cur`,
/// `$mm_tx[1]` → `mm_tx`. Numbers (`0.5`, `.5`, `1E5`) are skipped.
#[cfg(test)]
pub(super) fn names(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    each_name(code, |n| out.push(n.to_owned()));
    out
}

/// [`names`] handed to `f` one at a time, without copying them.
pub(super) fn each_name<'c>(code: &'c str, mut f: impl FnMut(&'c str)) {
    let b = code.as_bytes();
    let mut i = 0;
    let is_name = |c: u8| c.is_ascii_alphanumeric() || c == b'_' || c == b'.';
    while i < b.len() {
        let start = i;
        let mut j = i;
        if b[j] == b'.' {
            j += 1;
        }
        if j < b.len() && matches!(b[j], b'#' | b'&' | b'$' | b'@') {
            j += 1;
        }
        if j < b.len() && b[j].is_ascii_alphabetic() {
            let name_start = j;
            while j < b.len() && is_name(b[j]) {
                j += 1;
            }
            // A name right after a digit or a name character is part of a number (1E5).
            let glued = start > 0 && is_name(b[start - 1]) && b[start] != b'.';
            if !glued {
                f(code[name_start..j].trim_end_matches('.'));
            }
            i = j;
        } else if b[i].is_ascii_digit() || b[i] == b'.' {
            i += 1;
            while i < b.len() && is_name(b[i]) {
                i += 1;
            }
        } else {
            i += 1;
        }
    }
}

/// The comma-separated items of an argument or parameter list, ignoring commas inside
/// brackets (`.t[,]`, `f(a, b)`); empty for a blank list.
pub fn split_top_level(list: &str) -> Vec<&str> {
    let mut items = Vec::new();
    each_top_level(list, |item| items.push(item));
    items
}

/// Each of `list`'s items at the top level (outside brackets), trimmed, in order: nothing
/// for a blank list ([`split_top_level`] collects them; a `CALL`'s arity only counts them).
fn each_top_level<'a>(list: &'a str, mut item: impl FnMut(&'a str)) {
    if list.trim().is_empty() {
        return;
    }
    let (mut depth, mut start) = (0i32, 0);
    for (i, c) in list.char_indices() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            ',' if depth == 0 => {
                item(list[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    item(list[start..].trim());
}

/// `(name, argument count)` of a `CALL` statement's target, the name as written.
pub(super) fn call_target(rest: &str) -> (&str, usize) {
    let rest = rest.trim();
    let (name, args) = match rest.find('(') {
        Some(p) => (&rest[..p], Some(&rest[p + 1..])),
        None => (rest.split_whitespace().next().unwrap_or(""), None),
    };
    let arity = args.map_or(0, |a| {
        let inner = a.rsplit_once(')').map_or(a, |(x, _)| x);
        let mut n = 0;
        each_top_level(inner, |_| n += 1);
        n
    });
    (name.trim(), arity)
}
