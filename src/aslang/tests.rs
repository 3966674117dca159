use super::lex::names;
use super::*;

const GOOD: &str = ".PROGRAM main()\n  ; a comment; with \"quotes\"\n  FOR .i = 1 TO 3\n    IF .i == 2 THEN\n      CALL f(.i, .$s[1])\n    ELSE\n      CALL g\n    END\n  END\n  DO\n    .x = 0.5 + .5\n  UNTIL .x > 0\n  CASE .x OF\n    VALUE 1, 2:\n      .y = 1\n    ANY :\n      .y = 2\n  END\n  WHILE .y < 3 DO\n    .y = .y + 1\n  END\n.END\n.PROGRAM f(.a,.$b)\n.END\n.PROGRAM g()\n  $s = \"a very long string literal here\"\n.END\n.REALS\nmm_sock = -1\n.END\n";

fn messages(text: &str) -> Vec<String> {
    check(text, Calls::Closed(&[]))
        .into_iter()
        .map(|p| format!("{}: {}", p.line, p.message))
        .collect()
}

#[test]
fn a_well_formed_text_has_no_problems() {
    assert_eq!(messages(GOOD), Vec::<String>::new());
    let text = ".PROGRAM a(.x,.&p)\n.x = 2\n  IF .x THEN\n    DO\n      .x = .x - 1\n    UNTIL .x <= 0\n  ELSE\n    CASE .x OF\n    VALUE 1, 2:\n      GOTO lbl\n    ANY:\n      C1MOVE p\n      C2MOVE p\n    END\n  END\nlbl:\n  WHILE TRUE DO ; loop\n  END\n.END\n.TRANS\np 1 2 3 0 180 180\n.END\n.REALS\nx = -1\n.END\n.STRINGS\n$s = \"a;b\"\n.END\n";
    assert_eq!(messages(text), Vec::<String>::new());
}

#[test]
fn unbalanced_blocks_are_found() {
    let t = ".PROGRAM a()\n  IF x THEN\n  FOR .i = 1 TO 2\n  END\n.END\n";
    assert_eq!(messages(t), ["2: IF without END in `a`"]);
    let t = ".PROGRAM a()\n  END\n  ELSE\n  UNTIL x\n  VALUE 1:\n  CASE x OF\n  ANY\n  END\n.END\n";
    assert_eq!(
        messages(t),
        [
            "2: END without an open block",
            "3: ELSE outside an IF block (or a second ELSE)",
            "4: UNTIL without DO",
            "5: VALUE outside a CASE block",
            "7: ANY without `:`"
        ]
    );
    let t = ".PROGRAM a()\n  DO\n  WHILE x DO\n  UNTIL x\n  END\n.END\n";
    assert_eq!(messages(t)[0], "4: UNTIL closes the WHILE of line 3");
    let t = ".PROGRAM a()\n  DO\n  END\n.END\n";
    assert_eq!(
        messages(t),
        ["3: END closes the DO of line 2 (UNTIL expected)"]
    );
}

#[test]
fn sections_must_close() {
    assert_eq!(
        messages(".PROGRAM a()\n.PROGRAM b()\n.END\n"),
        ["2: `.PROGRAM` inside program `a` (missing .END?)"]
    );
    assert_eq!(
        messages(".REALS\n.PROGRAM b()\n.END\n"),
        ["2: `.PROGRAM` inside the .REALS section of line 1 (missing .END?)"]
    );
    assert_eq!(
        messages(".PROGRAM a()\n  x = 1\n"),
        ["2: program `a` has no .END"]
    );
    assert_eq!(messages("x = 1\n"), ["1: `x = 1` outside a section"]);
    assert_eq!(messages("; a note\n.END\n"), ["2: .END without a section"]);
    assert_eq!(messages(".NOTES\n"), ["1: unknown section .NOTES"]);
    assert_eq!(
        messages(".REALS\nx = 1\n"),
        ["2: .REALS section has no .END"]
    );
}

#[test]
fn data_lines_must_be_well_formed() {
    let t = ".TRANS\np 1 2\n.END\n.JOINTS\nj 1 2 3 4 5 6\n.END\n.REALS\nx 1\n.END\n.STRINGS\n$s = 1\n.END\n";
    assert_eq!(
        messages(t),
        [
            "2: malformed .TRANS line `p 1 2`",
            "5: malformed .JOINTS line `j 1 2 3 4 5 6`",
            "8: malformed .REALS line `x 1`",
            "11: malformed .STRINGS line `$s = 1`"
        ]
    );
}

#[test]
fn gotos_labels_and_circular_moves_are_checked() {
    let t = ".PROGRAM a()\n  GOTO nowhere\n  IF x GOTO here\nhere:\nhere:\n  C1MOVE p\n  LMOVE p\n  C2MOVE p\n.END\n";
    assert_eq!(
        messages(t),
        [
            "2: GOTO to `nowhere`, which is not a label of `a`",
            "5: label `here` defined twice",
            "6: C1MOVE not followed by C2MOVE",
            "8: C2MOVE without C1MOVE"
        ]
    );
    assert_eq!(
        messages(".PROGRAM a()\n  C1MOVE p\n.END\n"),
        ["2: C1MOVE without C2MOVE"]
    );
}

#[test]
fn long_names_and_non_ascii_are_found() {
    let t = ".PROGRAM a_program_name_16(.abcdefghijklmnop)\n  .$sixteen_chars_xx = \"ok string longer than fifteen\"\n  x = 1 ; caf\u{e9}\n.END\n.REALS\nsixteen_chars_xx = 1\n.END\n";
    assert_eq!(
        messages(t),
        [
            "1: program name `a_program_name_16` is longer than 15",
            "1: parameter `.abcdefghijklmnop` is empty or longer than 15",
            "2: name `sixteen_chars_xx` is longer than 15",
            "3: non-ASCII character",
            "6: name `sixteen_chars_xx` is longer than 15"
        ]
    );
}

#[test]
fn array_parameters_count_once() {
    let t =
        ".PROGRAM f(.t[,],.$s[])\n  .t[1,1] = 0\n.END\n.PROGRAM g()\n  CALL f(x[,],$y[])\n.END\n";
    assert_eq!(messages(t), Vec::<String>::new());
}

#[test]
fn calls_must_resolve_with_the_right_arity() {
    let t = ".PROGRAM a(.x)\n  CALL a(1, 2)\n  CALL nowhere\n  CALL ext(1)\n.END\n";
    assert_eq!(
        messages(t),
        [
            "2: CALL a with 2 arguments; it takes 1",
            "3: CALL of unknown program `nowhere`",
            "4: CALL of unknown program `ext`"
        ]
    );
    let known = check(t, Calls::Closed(&[("ext", 1)]));
    assert!(
        known.iter().all(|p| !p.message.contains("ext")),
        "{known:?}"
    );
    let open: Vec<String> = check(t, Calls::Open)
        .iter()
        .map(|p| p.to_string())
        .collect();
    assert_eq!(open, ["line 2: CALL a with 2 arguments; it takes 1"]);
}

/// A call is resolved against the first program of its name wherever that program stands
/// (before or after the call, whatever a second definition takes), and the problems come in
/// line order as calls were made, whether the call was resolved when it came or at the end.
#[test]
fn calls_resolve_against_the_first_definition_before_or_after_them() {
    let t = concat!(
        ".PROGRAM b(.x)\n.END\n",
        ".PROGRAM a()\n",
        "  CALL c(1)\n",
        "  CALL B(1, 2)\n",
        "  CALL c(1, 2)\n",
        "  CALL b(7)\n",
        "  CALL B\n",
        ".END\n",
        ".PROGRAM c(.y, .z)\n.END\n",
        ".PROGRAM b()\n.END\n",
        ".PROGRAM d()\n  CALL b(1)\n  CALL b\n  CALL c(1)\n.END\n",
    );
    assert_eq!(
        messages(t),
        [
            "4: CALL c with 1 arguments; it takes 2",
            "5: CALL b with 2 arguments; it takes 1",
            "8: CALL b with 0 arguments; it takes 1",
            "12: program `b` defined twice",
            "16: CALL b with 0 arguments; it takes 1",
            "17: CALL c with 1 arguments; it takes 2",
        ]
    );
}

#[test]
fn names_skip_numbers_and_strip_sigils() {
    assert_eq!(
        names(".#cur = $mm_tx[1] + .5 + 1.25 + 1E5 + .v[.i] + x.y"),
        ["cur", "mm_tx", "v", "i", "x.y"]
    );
}

#[test]
fn blanks_around_a_line_are_trimmed_as_str_trim_does() {
    // A vertical tab, a no-break space and an em space around block heads: the block still
    // opens and closes, the label is defined (only the non-ASCII lines are found).
    let text =
        ".PROGRAM a()\n\x0bIF .x THEN\x0b\n\u{a0}\tEND\u{2003}\nlbl:\u{a0}\n GOTO lbl\n.END\n";
    assert_eq!(
        messages(text),
        vec!["3: non-ASCII character", "4: non-ASCII character"]
    );
}

#[test]
fn strings_and_non_ascii_blanks_are_read_as_without_them() {
    // A case head's `:` inside a string does not count; a long name inside one is no name; a
    // line's first word after a string is found; a block head followed by a non-ASCII blank
    // opens its block (the lines without a `"` and the ASCII lines take a shorter path).
    let text = ".PROGRAM a()\n  CASE .x OF\n  VALUE 1 \"a:\"\n  VALUE 2:\n  END\n  PRINT \"a_name_longer_than_fifteen\"\n  \"x\" = 1\n  IF\u{2003}.x THEN\n  END\n.END\n";
    assert_eq!(
        messages(text),
        ["3: VALUE without `:`", "8: non-ASCII character"]
    );
}

#[test]
fn heads_and_keywords_are_read_in_any_case() {
    // Section heads and statement heads in lower and mixed case, local variables' lines (which
    // start with a dot, as section heads do), a word that only starts like a keyword: read as
    // their upper-case forms are, the messages naming the upper-case head.
    let text = ".Program a()\n  .x = 1\n  .end_x = 2\n  if .x Then\n  For .i = 1 to 2\n  enD\n  Else\n  end\n  case .x of\n  value 1:\n  Any :\n  end\n  do\n  until .x\n  iffy\n  Value 2:\n  .Reals\n.end\n.reals\nx = 1\n.Trans\n.END\n";
    assert_eq!(
        messages(text),
        [
            "16: VALUE outside a CASE block",
            "17: `.REALS` inside program `a` (missing .END?)",
            "21: `.TRANS` inside the .REALS section of line 19 (missing .END?)",
        ]
    );
}
