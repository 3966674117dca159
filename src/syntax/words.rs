//! Every KRL keyword once, with what the parsers need to know of it. The fast path
//! (`fast`), the grammar's entry choice (`line`) and rename's reserved-word check read this
//! table; `krl.pest` spells the same words as grammar rules (it is the grammar card and the
//! fast path's oracle), and a test keeps the two equal.

/// Never an identifier (the grammar's `reserved`): operator words and the words inside
/// statements (`THEN`, `DO`, `TO`, `STEP`, `WHEN`).
pub(crate) const RESERVED: u16 = 1;
/// Never names a type in a declaration without `DECL` (the grammar's `not_a_type`).
pub(crate) const NOT_A_TYPE: u16 = 1 << 1;
/// A motion keyword (the grammar's `motion_kw`).
pub(crate) const MOTION: u16 = 1 << 2;
/// An approximation keyword (the grammar's `approx`).
pub(crate) const APPROX: u16 = 1 << 3;
/// Can start a statement other than a declaration, assignment, call or label.
pub(crate) const STATEMENT: u16 = 1 << 4;
/// Starts the lines the grammar's `line_kw` entry covers.
pub(crate) const KW_LED: u16 = 1 << 5;
/// A first word for which a line is never a plain call or assignment in the grammar's order.
pub(crate) const NOT_PLAIN: u16 = 1 << 6;
/// A keyword only inside a statement (`ON`, `WITH`, `PRIO` …): a name everywhere else.
pub(crate) const CONTEXT: u16 = 0;

/// A keyword in upper case and its roles.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Word {
    pub text: &'static str,
    pub roles: u16,
}

const fn w(text: &'static str, roles: u16) -> Word {
    Word { text, roles }
}

/// Sorted by bytes (a test checks it), so a lookup is a binary search.
pub(crate) const WORDS: &[Word] = &[
    w("AND", RESERVED),
    w("ANIN", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("ANOUT", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("BRAKE", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("B_AND", RESERVED),
    w("B_EXOR", RESERVED),
    w("B_NOT", RESERVED),
    w("B_OR", RESERVED),
    w("CA", CONTEXT),
    w("CASE", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("CHANNEL", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("CIRC", NOT_A_TYPE | MOTION | STATEMENT),
    w("CIRC_REL", NOT_A_TYPE | MOTION | STATEMENT),
    w("CONFIRM", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("CONST", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("CONST_VEL", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("CONTINUE", NOT_A_TYPE | STATEMENT),
    w("C_DIS", APPROX),
    w("C_ORI", APPROX),
    w("C_PTP", APPROX),
    w("C_SPL", APPROX),
    w("C_VEL", APPROX),
    w("DECL", NOT_A_TYPE),
    w("DEF", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("DEFAULT", NOT_A_TYPE | STATEMENT),
    w("DEFDAT", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("DEFFCT", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("DELAY", CONTEXT),
    w("DISABLE", CONTEXT),
    w("DISTANCE", CONTEXT),
    w("DO", RESERVED),
    w("ELSE", NOT_A_TYPE | STATEMENT),
    w("ENABLE", CONTEXT),
    w("END", NOT_A_TYPE | STATEMENT),
    w("ENDDAT", NOT_A_TYPE | STATEMENT),
    w("ENDFCT", NOT_A_TYPE | STATEMENT),
    w("ENDFOR", NOT_A_TYPE | STATEMENT),
    w("ENDIF", NOT_A_TYPE | STATEMENT),
    w("ENDLOOP", NOT_A_TYPE | STATEMENT),
    w("ENDSKIP", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("ENDSPLINE", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("ENDSWITCH", NOT_A_TYPE | STATEMENT),
    w("ENDWHILE", NOT_A_TYPE | STATEMENT),
    w("ENUM", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("EXIT", NOT_A_TYPE | STATEMENT),
    w("EXOR", RESERVED),
    w("EXT", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("EXTFCT", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("EXTFCTP", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("EXTP", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("F", CONTEXT),
    w("FLT", CONTEXT),
    w("FOR", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("GLOBAL", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("GOTO", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("HALT", NOT_A_TYPE | STATEMENT),
    w("IF", NOT_A_TYPE | STATEMENT),
    w("IMPORT", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("INTERRUPT", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("IS", CONTEXT),
    w("LIN", NOT_A_TYPE | MOTION | STATEMENT),
    w("LIN_REL", NOT_A_TYPE | MOTION | STATEMENT),
    w("LOOP", NOT_A_TYPE | STATEMENT),
    w("MOVE_EMI", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("NOT", RESERVED),
    w("OFF", CONTEXT),
    w("ON", CONTEXT),
    w("ONSTART", CONTEXT),
    w("ON_ERROR_PROCEED", NOT_A_TYPE | STATEMENT),
    w("OR", RESERVED),
    w("PART", CONTEXT),
    w("PATH", CONTEXT),
    w("PRIO", CONTEXT),
    w("PTP", NOT_A_TYPE | MOTION | STATEMENT),
    w("PTP_REL", NOT_A_TYPE | MOTION | STATEMENT),
    w("PTP_SPLINE", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("PUBLIC", CONTEXT),
    w("REPEAT", NOT_A_TYPE | STATEMENT),
    w("RESUME", NOT_A_TYPE | STATEMENT),
    w("RETURN", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("SCIRC", NOT_A_TYPE | MOTION | STATEMENT),
    w("SCIRC_REL", NOT_A_TYPE | MOTION | STATEMENT),
    w("SEC", CONTEXT),
    w("SIGNAL", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("SKIP", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("SLIN", NOT_A_TYPE | MOTION | STATEMENT),
    w("SLIN_REL", NOT_A_TYPE | MOTION | STATEMENT),
    w("SPL", NOT_A_TYPE | MOTION | STATEMENT),
    w("SPLINE", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("SPTP", NOT_A_TYPE | MOTION | STATEMENT),
    w("SPTP_REL", NOT_A_TYPE | MOTION | STATEMENT),
    w("START", CONTEXT),
    w("STEP", RESERVED),
    w("STRUC", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("SWITCH", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("THEN", RESERVED),
    w("TIME_BLOCK", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("TO", RESERVED),
    w("TRIGGER", NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN),
    w("UNTIL", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("WAIT", NOT_A_TYPE | STATEMENT),
    w("WHEN", RESERVED),
    w("WHILE", NOT_A_TYPE | STATEMENT | NOT_PLAIN),
    w("WITH", CONTEXT),
];

/// The longest keyword (`ON_ERROR_PROCEED`) has 16 letters.
pub(crate) const MAX_LEN: usize = 16;

/// The keyword spelled `upper` (already upper case).
pub(crate) fn lookup_upper(upper: &[u8]) -> Option<&'static Word> {
    WORDS
        .binary_search_by(|w| w.text.as_bytes().cmp(upper))
        .ok()
        .map(|i| &WORDS[i])
}

/// `upper` (already upper case) is a keyword with one of `roles`.
pub(crate) fn is_upper(upper: &[u8], roles: u16) -> bool {
    lookup_upper(upper).is_some_and(|w| w.roles & roles != 0)
}

/// The keyword spelled `word` in any case.
pub(crate) fn lookup(word: &[u8]) -> Option<&'static Word> {
    if word.len() > MAX_LEN {
        return None;
    }
    let mut buf = [0u8; MAX_LEN];
    for (u, c) in buf.iter_mut().zip(word) {
        *u = c.to_ascii_uppercase();
    }
    lookup_upper(&buf[..word.len()])
}

/// `word` (any case) is a keyword with one of `roles`.
pub(crate) fn is(word: &[u8], roles: u16) -> bool {
    lookup(word).is_some_and(|w| w.roles & roles != 0)
}

/// A KRL keyword: a word that starts a statement or a block, an operator word, a motion or
/// approximation keyword. The grammar reads some of these as names where context allows;
/// tools that create names (rename) refuse them all.
pub fn is_keyword(word: &str) -> bool {
    is(
        word.as_bytes(),
        RESERVED | NOT_A_TYPE | MOTION | APPROX | STATEMENT,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    const GRAMMAR: &str = include_str!("krl.pest");

    /// The words of the grammar rule `name` (its `^"WORD"` literals).
    fn rule(name: &str) -> BTreeSet<String> {
        let start = GRAMMAR
            .lines()
            .position(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("no rule {name} in krl.pest"));
        let mut text = String::new();
        for l in GRAMMAR.lines().skip(start) {
            text.push_str(l);
            text.push('\n');
            if l.trim_end().ends_with('}') {
                break;
            }
        }
        literals(&text)
    }

    fn literals(text: &str) -> BTreeSet<String> {
        text.split("^\"")
            .skip(1)
            .filter_map(|s| s.split('"').next())
            .map(str::to_owned)
            .collect()
    }

    fn with(roles: u16) -> BTreeSet<String> {
        WORDS
            .iter()
            .filter(|w| w.roles & roles != 0)
            .map(|w| w.text.to_owned())
            .collect()
    }

    #[test]
    fn sorted_unique_upper_and_short() {
        for pair in WORDS.windows(2) {
            assert!(
                pair[0].text.as_bytes() < pair[1].text.as_bytes(),
                "{}",
                pair[1].text
            );
        }
        for w in WORDS {
            assert_eq!(w.text, w.text.to_ascii_uppercase());
            assert!(w.text.len() <= MAX_LEN, "{}", w.text);
        }
    }

    #[test]
    fn the_grammar_spells_the_same_lists() {
        assert_eq!(rule("reserved"), with(RESERVED));
        assert_eq!(rule("not_a_type"), with(NOT_A_TYPE));
        assert_eq!(rule("motion_kw"), with(MOTION));
        assert_eq!(rule("approx"), with(APPROX));
    }

    #[test]
    fn every_grammar_keyword_is_in_the_table() {
        let keywords: BTreeSet<String> = GRAMMAR
            .lines()
            .filter(|l| l.starts_with("K_"))
            .flat_map(literals)
            .collect();
        let table: BTreeSet<String> = WORDS.iter().map(|w| w.text.to_owned()).collect();
        let missing: Vec<_> = keywords.difference(&table).collect();
        assert!(missing.is_empty(), "{missing:?}");
        // And every word of the table is a keyword somewhere in the grammar.
        let operators: BTreeSet<String> = GRAMMAR
            .lines()
            .filter(|l| l.starts_with("op_"))
            .flat_map(literals)
            .collect();
        for w in &table {
            assert!(
                keywords.contains(w)
                    || operators.contains(w)
                    || rule("motion_kw").contains(w)
                    || rule("approx").contains(w),
                "{w} is in no grammar rule"
            );
        }
    }

    #[test]
    fn lookup_ignores_case_and_refuses_long_words() {
        assert!(lookup(b"endwhile").is_some());
        assert!(lookup(b"EndWhile").is_some_and(|w| w.roles & STATEMENT != 0));
        assert!(lookup(b"ON_ERROR_PROCEEDX").is_none());
        assert!(lookup(b"pick").is_none());
        assert!(is_keyword("lin_rel") && !is_keyword("with") && !is_keyword("x"));
    }
}
