//! Checks of the formatter's promises written independently of `src/fmt` (plain text scans),
//! shared by the fixture, property and corpus tests.

#![allow(dead_code)]

/// Physical lines with their endings (LF, CRLF, lone CR), covering the text exactly.
pub fn lines(text: &str) -> Vec<(&str, &str)> {
    let mut out = Vec::new();
    let mut rest = text;
    while !rest.is_empty() {
        let end = rest.find(['\r', '\n']).unwrap_or(rest.len());
        let tail = &rest[end..];
        let len = if tail.starts_with("\r\n") {
            2
        } else if tail.starts_with(['\r', '\n']) {
            1
        } else {
            0
        };
        out.push((&rest[..end], &tail[..len]));
        rest = &tail[len..];
    }
    out
}

fn is_blank(line: &str) -> bool {
    line.chars().all(|c| c.is_whitespace())
}

fn comment_word(line: &str) -> Option<String> {
    let t = line.trim_start_matches([' ', '\t']);
    let c = t.strip_prefix(';')?;
    Some(
        c.chars()
            .take_while(|c| c.is_ascii_alphabetic())
            .collect::<String>()
            .to_ascii_uppercase(),
    )
}

/// Indices of the lines the formatter must not touch: `&` headers, inline-form folds (from the
/// `;FOLD … %{` line through its `;ENDFOLD`), lines with a `%{` comment, lines a syntax
/// diagnostic touches.
pub fn protected(text: &str) -> Vec<bool> {
    let ls = lines(text);
    let mut prot = vec![false; ls.len()];
    let mut stack: Vec<(usize, bool)> = Vec::new();
    for (i, (l, _)) in ls.iter().enumerate() {
        let t = l.trim_start_matches([' ', '\t']);
        if t.starts_with('&') || l.contains(";%{") || (t.starts_with(';') && t.contains("%{")) {
            prot[i] = true;
        }
        match comment_word(l).as_deref() {
            Some("FOLD") => stack.push((i, t.contains("%{"))),
            Some("ENDFOLD") => {
                if let Some((open, true)) = stack.pop() {
                    prot[open..=i].iter_mut().for_each(|p| *p = true);
                }
            }
            _ => {}
        }
    }
    for (open, inline) in stack {
        if inline {
            prot[open..].iter_mut().for_each(|p| *p = true);
        }
    }
    let parse = krlkit::syntax::parse(text);
    let mut starts = Vec::with_capacity(ls.len());
    let mut pos = 0usize;
    for (l, e) in &ls {
        starts.push(pos);
        pos += l.len() + e.len();
    }
    for d in &parse.diagnostics {
        let (s, e) = (d.span.start as usize, d.span.end as usize);
        for (i, &start) in starts.iter().enumerate() {
            let end = start + ls[i].0.len() + ls[i].1.len();
            if start <= e && s < end.max(start + 1) {
                prot[i] = true;
            }
        }
    }
    prot
}

/// Non-blank lines correspond one to one (only blank lines may go); every protected one is
/// byte-identical and every line keeps its own line ending.
pub fn assert_protected_kept(before: &str, after: &str, name: &str) {
    let prot = protected(before);
    let b: Vec<(usize, (&str, &str))> = lines(before)
        .into_iter()
        .enumerate()
        .filter(|(i, (l, _))| !is_blank(l) || prot[*i])
        .collect();
    let a: Vec<(&str, &str)> = lines(after);
    let mut ai = a.iter().filter(|(l, _)| !is_blank(l)).peekable();
    let mut aj = 0usize;
    let a_all = &a;
    for (i, (line, ending)) in b {
        if is_blank(line) {
            // A protected blank line: it must still be there, byte for byte, in order.
            while aj < a_all.len() && a_all[aj] != (line, ending) {
                aj += 1;
            }
            assert!(
                aj < a_all.len(),
                "{name}: protected blank line {} lost",
                i + 1
            );
            continue;
        }
        let Some(&(l2, e2)) = ai.next() else {
            panic!("{name}: line {} lost", i + 1);
        };
        assert_eq!(ending, e2, "{name}: line {} changed its line ending", i + 1);
        if prot[i] {
            assert_eq!(line, l2, "{name}: protected line {} changed", i + 1);
        }
        if let Some(pos) = a_all.iter().skip(aj).position(|x| x.0 == l2) {
            aj += pos;
        }
    }
    assert!(ai.peek().is_none(), "{name}: lines added");
}
