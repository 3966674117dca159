//! A hand-written fast path for the frequent line shapes: assignments, calls, labels,
//! declarations (`DECL`, `STRUC`, `ENUM`, `SIGNAL`, `CHANNEL`, `EXT…`), routine and DAT headers,
//! motions (with `WITH`, `CA`, approximation), `IF … THEN` and the other block lines, `WAIT`,
//! `INTERRUPT`, `TRIGGER`, one-keyword lines. It builds exactly the tree the grammar would
//! build — same kinds, same spans, same Pratt nesting — or answers `None` and the line goes to
//! pest. The grammar stays the single definition of the language; a test checks that this path
//! agrees with it on every fixture line and on random lines.
//!
//! Building: every parsing function leaves its result as children pending on the builder's
//! stack or returns it as one [`Child`]; a caller that recovers from a failed attempt rolls the
//! builder back first, and [`parse`] rolls back everything when it answers `None`.

mod decl;
mod expr;
mod motion;
mod stmt;

use super::build::Builder;
use super::cst::{Child, NodeKind, TokenKind};
use super::words;

/// Parse `code` = `text[start..end]`; on success the statement's children are pending on the
/// builder's stack and its kind is returned.
pub(crate) fn parse(b: &mut Builder, start: usize, end: usize) -> Option<NodeKind> {
    let cp = b.checkpoint();
    let text = b.text;
    let mut p = P {
        text,
        b: text.as_bytes(),
        t: b,
        pos: start,
        end,
        depth: 0,
        items: 0,
    };
    match p.line(start) {
        Some(kind) if p.pos == end => Some(kind),
        _ => {
            p.t.rollback(cp);
            None
        }
    }
}

struct P<'t, 'b> {
    text: &'t str,
    b: &'t [u8],
    t: &'b mut Builder<'t>,
    pos: usize,
    end: usize,
    /// Bracket nesting, runs of signs/NOTs and expression items on the line: past the same
    /// limits as the grammar path's pre-check (`line::too_deep`), the fast path gives up.
    depth: usize,
    items: usize,
}

const MAX_DEPTH: usize = 64;
const MAX_ITEMS: usize = 1024;

#[inline]
fn is_idc(b: u8) -> bool {
    IDC[b as usize]
}

/// [`is_idc`] as a table (every word of a line is scanned with it).
static IDC: [bool; 256] = {
    let mut t = [false; 256];
    let mut i = 0;
    while i < 256 {
        let b = i as u8;
        t[i] = b.is_ascii_alphanumeric() || b == b'_' || b == b'$';
        i += 1;
    }
    t
};

/// Binding powers as in `line.rs`'s Pratt table (relative order is all that matters).
const PREFIX_BP: u8 = 70;

/// The longest keyword (`ON_ERROR_PROCEED`) has 16 letters; longer first words are names.
const MAX_KEYWORD: usize = words::MAX_LEN;

/// An upper-cased copy of a short word, without allocating.
struct Upper {
    buf: [u8; MAX_KEYWORD],
    len: usize,
}

impl Upper {
    #[inline]
    fn of(word: &[u8]) -> Upper {
        let mut buf = [0u8; MAX_KEYWORD];
        let len = if word.len() <= MAX_KEYWORD {
            for (u, c) in buf.iter_mut().zip(word) {
                *u = c.to_ascii_uppercase();
            }
            word.len()
        } else {
            0
        };
        Upper { buf, len }
    }

    /// The word in upper case, or empty for a word too long to be a keyword.
    #[inline]
    fn as_bytes(&self) -> &[u8] {
        &self.buf[..self.len]
    }
}

impl<'t> P<'t, '_> {
    #[inline]
    fn tok(kind: TokenKind, start: usize, end: usize) -> Child {
        Builder::token(kind, start, end)
    }

    #[inline]
    fn push(&mut self, c: Child) {
        self.t.push(c);
    }

    #[inline]
    fn end_of(&self, c: Child) -> usize {
        self.t.span_of(c).end as usize
    }

    #[inline]
    fn ws(&mut self) {
        while self.pos < self.end {
            match self.b[self.pos] {
                b' ' | b'\t' | 0x0B | 0x0C => self.pos += 1,
                0xC2 if self.b.get(self.pos + 1) == Some(&0xA0) && self.pos + 1 < self.end => {
                    self.pos += 2
                }
                _ => break,
            }
        }
    }

    #[inline]
    fn peek(&self) -> Option<u8> {
        (self.pos < self.end).then(|| self.b[self.pos])
    }

    #[inline]
    fn word_len(&self) -> usize {
        let mut i = self.pos;
        while i < self.end && is_idc(self.b[i]) {
            i += 1;
        }
        i - self.pos
    }

    /// The word at the cursor, upper-cased (not consumed).
    #[inline]
    fn upper_word(&self) -> Upper {
        Upper::of(&self.b[self.pos..self.pos + self.word_len()])
    }

    /// A whole-word, case-insensitive keyword at the cursor (no blanks skipped).
    #[inline]
    fn kw(&mut self, word: &str) -> Option<Child> {
        self.kw_bytes(word.as_bytes())
    }

    #[inline]
    fn kw_bytes(&mut self, word: &[u8]) -> Option<Child> {
        let n = word.len();
        let here = self.b.get(self.pos..self.pos + n)?;
        if self.pos + n > self.end
            || !here.eq_ignore_ascii_case(word)
            || self.b.get(self.pos + n).is_some_and(|c| is_idc(*c)) && self.pos + n < self.end
        {
            return None;
        }
        let start = self.pos;
        self.pos += n;
        Some(Self::tok(TokenKind::Keyword, start, self.pos))
    }

    /// Like [`kw`](Self::kw), pushed as a child of the node being built.
    fn push_kw(&mut self, word: &str) -> Option<()> {
        self.push_kw_bytes(word.as_bytes())
    }

    fn push_kw_bytes(&mut self, word: &[u8]) -> Option<()> {
        let k = self.kw_bytes(word)?;
        self.push(k);
        Some(())
    }

    /// One of the statement-local `words` at the cursor (`ON`/`OFF` …, `DISTANCE`/`PATH`).
    fn kw_any(&mut self, words: &[&str]) -> Option<Child> {
        let n = self.word_len();
        let w = &self.text[self.pos..self.pos + n];
        if n > 0 && words.iter().any(|k| k.eq_ignore_ascii_case(w)) {
            let start = self.pos;
            self.pos += n;
            return Some(Self::tok(TokenKind::Keyword, start, self.pos));
        }
        None
    }

    /// A keyword with one of `roles` at the cursor.
    fn kw_role(&mut self, roles: u16) -> Option<Child> {
        let n = self.word_len();
        if words::is(&self.b[self.pos..self.pos + n], roles) {
            let start = self.pos;
            self.pos += n;
            return Some(Self::tok(TokenKind::Keyword, start, self.pos));
        }
        None
    }

    #[inline]
    fn punct(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    /// A single `=` (not the start of `==`).
    fn equals(&mut self) -> bool {
        if self.peek() == Some(b'=') && self.b.get(self.pos + 1) != Some(&b'=') {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn ident(&mut self) -> Option<Child> {
        let first = self.peek()?;
        if !(first.is_ascii_alphabetic() || first == b'_' || first == b'$') {
            return None;
        }
        let n = self.word_len();
        // Reserved words have at most 6 letters, and only a few first letters.
        if n <= 6
            && words::may_be_reserved(first)
            && words::is(&self.b[self.pos..self.pos + n], words::RESERVED)
        {
            return None;
        }
        let start = self.pos;
        self.pos += n;
        Some(Self::tok(TokenKind::Ident, start, self.pos))
    }

    fn push_ident(&mut self) -> Option<()> {
        let i = self.ident()?;
        self.push(i);
        Some(())
    }

    fn push_expr(&mut self) -> Option<()> {
        let e = self.expr()?;
        self.push(e);
        Some(())
    }

    // ---- lines ------------------------------------------------------------------------------
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::build::standalone;
    use crate::syntax::line::parse_with_grammar;
    use proptest::prelude::*;

    /// Returns whether the fast path answered.
    fn agrees(code: &str) -> bool {
        let code = code.trim_matches([' ', '\t']);
        match standalone(code, |b| parse(b, 0, code.len())) {
            None => false,
            Some(fast) => {
                let grammar = standalone(code, |b| parse_with_grammar(b, 0, code.len()).ok());
                assert!(
                    grammar.is_some(),
                    "grammar rejects what the fast path accepted: {code:?}"
                );
                assert_eq!(Some(&fast), grammar.as_ref(), "{code:?}");
                true
            }
        }
    }

    #[test]
    fn agrees_with_the_grammar_on_every_fixture_line() {
        let mut total = 0;
        let mut fast = 0;
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/syntax");
        let mut dirs = vec![std::path::PathBuf::from(root)];
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(&dir).expect("fixture dir").flatten() {
                let path = entry.path();
                if path.is_dir() {
                    dirs.push(path);
                    continue;
                }
                let text = crate::syntax::decode(&std::fs::read(&path).expect("read")).text;
                for line in text.split(['\n', '\r']) {
                    let code = line.split(';').next().unwrap_or("").trim();
                    if code.is_empty() || code.starts_with('&') {
                        continue;
                    }
                    total += 1;
                    fast += usize::from(agrees(code));
                }
            }
        }
        // The fast path must carry most real lines, or it is not worth having.
        assert!(fast * 2 > total, "fast path took {fast} of {total} lines");
    }

    #[test]
    fn agrees_on_tricky_shapes() {
        for code in [
            "x = -a[1].b * 2 + c:d",
            "x = NOT a AND b OR c == d",
            "x = 1. + .5E3 - 1E-2 * 'B 101' + 'HfF' + 'c'",
            "x = a * b + c - d / e : f EXOR g B_AND h B_OR i < j",
            "x = -a:b * -c",
            "x = NOT NOT a[1, 2][3].b.c",
            "f(a, , b)",
            "f ( )",
            "x = {E6POS: X 1, Y -2, POINT1[] \"P1\"}",
            "x = {a + b}",
            "x = {X}",
            "x[] = \"abc\"",
            "DECL GLOBAL CONST INT a = 1 , b[2,3] , c",
            "DECL E6POS p={X 1}",
            "DECL CHAR[10] s",
            "PTP_REL {A1 10} C_PTP #TOOL",
            "IF $IN[1] AND NOT b THEN",
            "WAIT FOR a<>b",
            "WAIT SEC 0.5",
            "ENDFCT",
            "x = TRUE",
            "a == b = c",
            "x = - - 1",
            "FOR i = 1 TO n STEP -1",
            "for i=a[1] to b",
            "CASE 1, #two, 'c'",
            "SWITCH mode",
            "WHILE NOT done",
            "UNTIL i >= 10",
            "RETURN",
            "RETURN a + 1",
            "GOTO m1",
            "BRAKE F",
            "INTERRUPT ON 3",
            "interrupt disable",
            "INT i",
            "E6POS p = {X 1, Y 2}",
            "GLOBAL CONST REAL r = 1.5, q",
            "CONST INT n = 3",
            "global bool done",
            "DEF main( )",
            "GLOBAL DEF pick(n:IN, v[]:OUT, m[,] : OUT, s[80]:IN, k)",
            "DEFFCT CHAR[15] name_of(i :IN)",
            "global deffct int f()",
            "DEFDAT cell PUBLIC",
            "DEFDAT cell ( )",
            "defdat $config",
            "SIGNAL s $OUT[1] TO $OUT[8]",
            "GLOBAL SIGNAL s FALSE",
            "DECL GLOBAL SIGNAL s $IN[3]",
            "label:",
            "m1 :",
            "END:",
            "$x:",
            "a_name_longer_than_sixteen_letters = 1",
            "a_name_longer_than_sixteen_letters(1, 2)",
            "GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )",
            "INTERRUPT DECL 4 WHEN $CYCFLAG[2]==FALSE DO A10 (#APPL_ERROR)",
            "interrupt decl 5 when a and b do x = 1",
            "TRIGGER WHEN DISTANCE=0 DELAY=10 DO $OUT[1]=TRUE PRIO=-1",
            "TRIGGER WHEN PATH = -20.5 ONSTART DELAY = 0 DO f(a, b) PRIO = 2",
            "trigger when distance=1 delay=-1 do g()",
            "EXT BAS (BAS_COMMAND :IN, REAL :IN )",
            "EXT  H70 (INT  :IN,SRCH_TYP_2  :OUT,E6POS  :IN)",
            "EXTP f(E6POS :OUT)",
            "EXTFCT INT f(INT :IN)",
            "GLOBAL EXTFCTP REAL[] g(CHAR STRVAR[256] :IN, INT)",
            "EXT e()",
            "STRUC s INT a, REAL b",
            "GLOBAL STRUC SPOT_TYPE INT GUN,S_PAIR_SLCT PAIR,INT CLO_TM",
            "STRUC T CHAR GUN[24],RETR_CMD[24],CHOISE[24]",
            "GLOBAL STRUC S INT ID, n CHAR name[24], REAL t",
            "STRUC S INT a b",
            "STRUC S INT a[2] REAL b, c",
            "DECL STRUC s INT a",
            "DECL GLOBAL STRUC s BOOL b",
            "GLOBAL DECL STRUC s INT a",
            "ENUM e a, b , c",
            "GLOBAL ENUM mode_t auto, manual",
            "DECL ENUM e a",
            "CHANNEL :SER_1 :SER_1 $PSER_1",
            "CHANNEL : a : b",
            "CONFIRM 0",
            "CONFIRM (h)",
            "SPTP XHOME WITH $VEL_AXIS[1] = SVEL_JOINT(100.0), $TOOL = STOOL2(FHOME)",
            "SLIN XP1 WITH $VEL = SVEL_CP(2.0, , LCPDAT1), $TOOL = STOOL2(FP1) C_SPL",
            "SLIN p WITH $VEL.CP=2",
            "CIRC a, b C_DIS",
            "CIRC a, b, CA 400",
            "CIRC x[1], x[2], CA 90.0 C_ORI",
            "LIN p, CA 10",
            "LIN p C_DIS #BASE",
        ] {
            assert!(agrees(code), "fast path should take {code:?}");
        }
        for code in [
            "DECL:",
            "PTPP P1 C_DIS",
            "RETURN a=b",
            "GLOBAL DECL INT x",
            "x = = 1",
            "PTP",
            "f(1) x",
            "INTERRUPT DECL 3 WHEN a DO f(x).y = 1",
            "TRIGGER WHEN DISTANCE=0 DELAY=0 DO f() PRIO",
            "STRUC s",
            "ENUM e",
            "EXT f(INT :INOUT)",
            "CHANNEL :a b",
            "LIN p WITH",
            "CIRC a, b, c",
        ] {
            assert!(
                !agrees(code),
                "fast path should leave {code:?} to the grammar"
            );
        }
    }

    fn piece() -> impl Strategy<Value = &'static str> {
        prop::sample::select(vec![
            "x",
            "$OUT",
            "[",
            "]",
            "(",
            ")",
            "{",
            "}",
            ",",
            ".",
            ":",
            "=",
            "==",
            "<>",
            "<",
            ">=",
            "+",
            "-",
            "*",
            "/",
            "NOT ",
            " AND ",
            " or ",
            "B_NOT ",
            " THEN",
            "IF ",
            "1",
            "2.5",
            ".5",
            "1E3",
            "'B10'",
            "'HF'",
            "'c'",
            "\"s\"",
            "#E",
            "TRUE",
            " ",
            "DECL ",
            "INT ",
            "PTP ",
            "C_DIS",
            "WAIT ",
            "FOR ",
            "SEC ",
            "f(",
            "E6POS:",
            "END",
            "\t",
            " WITH ",
            " CA ",
            " DO ",
            " WHEN ",
            "TRIGGER ",
            "STRUC ",
            "ENUM ",
            "EXT ",
            ":IN",
            " DELAY",
            " PRIO",
            "INTERRUPT ",
            "GLOBAL ",
            "CHANNEL ",
            "CONFIRM ",
            " TO ",
            " ONSTART ",
        ])
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]
        #[test]
        fn agrees_on_random_lines(parts in prop::collection::vec(piece(), 1..14)) {
            agrees(&parts.concat());
        }

        #[test]
        fn agrees_on_random_statements(
            head in prop::sample::select(vec![
                "x = ", "DECL INT a = ", "INT a = ", "GLOBAL REAL r[2] = ", "SIGNAL s ",
                "DEF f(", "DEFFCT INT f(", "IF ", "PTP ", "f(", "WAIT FOR ", "FOR i = ",
                "CASE ", "RETURN ", "INTERRUPT ON ", "SWITCH ", "CONFIRM ",
                "INTERRUPT DECL 3 WHEN ", "GLOBAL INTERRUPT DECL ", "TRIGGER WHEN DISTANCE=",
                "TRIGGER WHEN PATH = 1 DELAY = ", "STRUC s INT ", "ENUM e ", "EXT f(",
                "EXTFCT INT f(", "LIN p WITH $VEL = ", "CIRC a, ", "SLIN ", "CHANNEL :a :b ",
            ]),
            operand in prop::collection::vec(prop::sample::select(vec![
                "a", "1", "-", "NOT ", "(", ")", "[1]", ".b", "{X 1}", " + ", " AND ", ":",
                "==", ",", " DO ", " WHEN ", " DELAY=", " PRIO=", "f()", " = ", " CA ", "#E",
                " C_DIS", " WITH ", ":IN", " TO ",
            ]), 1..10),
            tail in prop::sample::select(vec![
                "", " THEN", ")", " C_PTP", ", b", " TO 5", " TO n STEP 2", " DO f()",
                " DO x = 1", " PRIO = 1", " DELAY = 0 DO g(1)", " WITH $V = 1",
            ]),
        ) {
            agrees(&format!("{head}{}{tail}", operand.concat()));
        }
    }
}

#[cfg(test)]
mod limits {
    use crate::syntax::build::standalone;

    /// The fast path and the grammar path accept the same lines at the depth limits.
    #[test]
    fn same_limits_on_both_paths() {
        for n in [63, 64, 65] {
            for line in [
                format!("x = {}1", "-".repeat(n)),
                format!("x = {}1{}", "(".repeat(n), ")".repeat(n)),
                format!("f({}1{})", "{A ".repeat(n - 1), "}".repeat(n - 1)),
            ] {
                let text = format!("{line}\n");
                let p = crate::syntax::parse(&text);
                let via_grammar = standalone(&line, |b| {
                    crate::syntax::line::parse_with_grammar(b, 0, line.len()).ok()
                })
                .is_some();
                let guard = super::super::line::too_deep_for_tests(&line);
                assert_eq!(
                    p.diagnostics.is_empty(),
                    via_grammar && !guard,
                    "{n}: {}",
                    &line[..12]
                );
            }
        }
    }
}
