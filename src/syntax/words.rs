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
#[cfg(test)]
#[derive(Debug, Clone, Copy)]
pub(crate) struct Word {
    pub text: &'static [u8],
    pub roles: u16,
}

/// The table and its lookup from one list: [`WORDS`] for the tests that compare it with the
/// grammar, a `match` for the parsers, which ask for almost every word (a `match` on bytes
/// is several times faster than searching the table).
macro_rules! keywords {
    ($($word:literal: $roles:expr,)*) => {
        /// Every keyword, sorted (a test checks it); the tests compare it with the grammar.
        #[cfg(test)]
        pub(crate) const WORDS: &[Word] = &[$(Word { text: $word, roles: $roles },)*];

        /// The roles of the keyword spelled `upper` (already upper case).
        #[inline]
        pub(crate) fn roles_upper(upper: &[u8]) -> Option<u16> {
            match upper {
                $($word => Some($roles),)*
                _ => None,
            }
        }
    };
}

keywords! {
    b"AND": RESERVED,
    b"ANIN": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"ANOUT": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"BRAKE": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"B_AND": RESERVED,
    b"B_EXOR": RESERVED,
    b"B_NOT": RESERVED,
    b"B_OR": RESERVED,
    b"CA": CONTEXT,
    b"CASE": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"CHANNEL": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"CIRC": NOT_A_TYPE | MOTION | STATEMENT,
    b"CIRC_REL": NOT_A_TYPE | MOTION | STATEMENT,
    b"CONFIRM": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"CONST": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"CONST_VEL": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"CONTINUE": NOT_A_TYPE | STATEMENT,
    b"C_DIS": APPROX,
    b"C_ORI": APPROX,
    b"C_PTP": APPROX,
    b"C_SPL": APPROX,
    b"C_VEL": APPROX,
    b"DECL": NOT_A_TYPE,
    b"DEF": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"DEFAULT": NOT_A_TYPE | STATEMENT,
    b"DEFDAT": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"DEFFCT": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"DELAY": CONTEXT,
    b"DISABLE": CONTEXT,
    b"DISTANCE": CONTEXT,
    b"DO": RESERVED,
    b"ELSE": NOT_A_TYPE | STATEMENT,
    b"ENABLE": CONTEXT,
    b"END": NOT_A_TYPE | STATEMENT,
    b"ENDDAT": NOT_A_TYPE | STATEMENT,
    b"ENDFCT": NOT_A_TYPE | STATEMENT,
    b"ENDFOR": NOT_A_TYPE | STATEMENT,
    b"ENDIF": NOT_A_TYPE | STATEMENT,
    b"ENDLOOP": NOT_A_TYPE | STATEMENT,
    b"ENDSKIP": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"ENDSPLINE": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"ENDSWITCH": NOT_A_TYPE | STATEMENT,
    b"ENDWHILE": NOT_A_TYPE | STATEMENT,
    b"ENUM": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"EXIT": NOT_A_TYPE | STATEMENT,
    b"EXOR": RESERVED,
    b"EXT": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"EXTFCT": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"EXTFCTP": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"EXTP": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"F": CONTEXT,
    b"FLT": CONTEXT,
    b"FOR": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"GLOBAL": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"GOTO": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"HALT": NOT_A_TYPE | STATEMENT,
    b"IF": NOT_A_TYPE | STATEMENT,
    b"IMPORT": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"INTERRUPT": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"IS": CONTEXT,
    b"LIN": NOT_A_TYPE | MOTION | STATEMENT,
    b"LIN_REL": NOT_A_TYPE | MOTION | STATEMENT,
    b"LOOP": NOT_A_TYPE | STATEMENT,
    b"MOVE_EMI": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"NOT": RESERVED,
    b"OFF": CONTEXT,
    b"ON": CONTEXT,
    b"ONSTART": CONTEXT,
    b"ON_ERROR_PROCEED": NOT_A_TYPE | STATEMENT,
    b"OR": RESERVED,
    b"PART": CONTEXT,
    b"PATH": CONTEXT,
    b"PRIO": CONTEXT,
    b"PTP": NOT_A_TYPE | MOTION | STATEMENT,
    b"PTP_REL": NOT_A_TYPE | MOTION | STATEMENT,
    b"PTP_SPLINE": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"PUBLIC": CONTEXT,
    b"REPEAT": NOT_A_TYPE | STATEMENT,
    b"RESUME": NOT_A_TYPE | STATEMENT,
    b"RETURN": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"SCIRC": NOT_A_TYPE | MOTION | STATEMENT,
    b"SCIRC_REL": NOT_A_TYPE | MOTION | STATEMENT,
    b"SEC": CONTEXT,
    b"SIGNAL": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"SKIP": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"SLIN": NOT_A_TYPE | MOTION | STATEMENT,
    b"SLIN_REL": NOT_A_TYPE | MOTION | STATEMENT,
    b"SPL": NOT_A_TYPE | MOTION | STATEMENT,
    b"SPLINE": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"SPTP": NOT_A_TYPE | MOTION | STATEMENT,
    b"SPTP_REL": NOT_A_TYPE | MOTION | STATEMENT,
    b"START": CONTEXT,
    b"STEP": RESERVED,
    b"STRUC": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"SWITCH": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"THEN": RESERVED,
    b"TIME_BLOCK": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"TO": RESERVED,
    b"TRIGGER": NOT_A_TYPE | STATEMENT | KW_LED | NOT_PLAIN,
    b"UNTIL": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"WAIT": NOT_A_TYPE | STATEMENT,
    b"WHEN": RESERVED,
    b"WHILE": NOT_A_TYPE | STATEMENT | NOT_PLAIN,
    b"WITH": CONTEXT,
}

/// The longest keyword (`ON_ERROR_PROCEED`) has 16 letters.
pub(crate) const MAX_LEN: usize = 16;

/// `upper` (already upper case) is a keyword with one of `roles`.
#[inline]
pub(crate) fn is_upper(upper: &[u8], roles: u16) -> bool {
    roles_upper(upper).is_some_and(|r| r & roles != 0)
}

/// Whether a word starting with `first` (any case) can be a [`RESERVED`] word: most names
/// are answered without looking the word up (a test keeps this equal to the table).
#[inline]
pub(crate) fn may_be_reserved(first: u8) -> bool {
    matches!(
        first.to_ascii_uppercase(),
        b'A' | b'B' | b'D' | b'E' | b'N' | b'O' | b'S' | b'T' | b'W'
    )
}

/// The roles of the keyword spelled `word` in any case.
#[inline]
pub(crate) fn roles(word: &[u8]) -> Option<u16> {
    if word.len() > MAX_LEN {
        return None;
    }
    let mut buf = [0u8; MAX_LEN];
    for (u, c) in buf.iter_mut().zip(word) {
        *u = c.to_ascii_uppercase();
    }
    roles_upper(&buf[..word.len()])
}

/// `word` (any case) is a keyword with one of `roles`.
#[inline]
pub(crate) fn is(word: &[u8], roles: u16) -> bool {
    self::roles(word).is_some_and(|r| r & roles != 0)
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
            .map(text)
            .collect()
    }

    fn text(w: &Word) -> String {
        String::from_utf8(w.text.to_vec()).expect("ASCII")
    }

    #[test]
    fn sorted_unique_upper_and_short() {
        for pair in WORDS.windows(2) {
            assert!(pair[0].text < pair[1].text, "{}", text(&pair[1]));
        }
        for w in WORDS {
            assert_eq!(w.text, w.text.to_ascii_uppercase().as_slice());
            assert!(w.text.len() <= MAX_LEN, "{}", text(w));
            assert_eq!(roles_upper(w.text), Some(w.roles));
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
        let table: BTreeSet<String> = WORDS.iter().map(text).collect();
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
    fn reserved_words_start_with_the_letters_the_prefilter_lets_through() {
        let firsts: BTreeSet<u8> = with(RESERVED).iter().map(|w| w.as_bytes()[0]).collect();
        for b in 0..=255u8 {
            assert_eq!(
                may_be_reserved(b),
                firsts.contains(&b.to_ascii_uppercase()),
                "{:?}",
                b as char
            );
        }
    }

    #[test]
    fn lookup_ignores_case_and_refuses_long_words() {
        assert!(roles(b"endwhile").is_some());
        assert!(is(b"EndWhile", STATEMENT));
        assert!(roles(b"ON_ERROR_PROCEEDX").is_none());
        assert!(roles(b"pick").is_none());
        assert!(is_keyword("lin_rel") && !is_keyword("with") && !is_keyword("x"));
    }
}
