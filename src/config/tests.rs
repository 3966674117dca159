use super::*;
use crate::catalog::Interface;
use crate::diag::Severity;
use crate::fmt::{Case, Spacing};

fn err(text: &str) -> ConfigError {
    Config::parse(text, "k.toml").expect_err("must be rejected")
}

#[test]
fn one_file_holds_the_spec_lint_and_fmt() {
    let c = Config::parse(
        "server_port = 50001\ninterface = \"2.x\"\n[lint]\ndisable = [\"mm008\"]\n[lint.severity]\nMM011 = \"error\"\n[fmt]\nindent_width = 4\n",
        "k.toml",
    )
    .expect("valid");
    assert_eq!(c.spec.server_port, 50001);
    assert_eq!(c.spec.interface, Interface::V2);
    assert!(c.lint.disabled.contains("MM008"));
    assert_eq!(c.lint.severity.get("MM011"), Some(&Severity::Error));
    assert_eq!(
        c.lint.interface,
        Some(Interface::V2),
        "the spec's interface counts"
    );
    assert_eq!(c.fmt.indent_width, 4);
    assert_eq!(c.path.as_deref(), Some("k.toml"));
}

#[test]
fn lint_interface_comes_first() {
    let c = Config::parse(
        "interface = \"2.x\"\n[lint]\ninterface = \"1.x\"\n",
        "k.toml",
    )
    .unwrap();
    assert_eq!(c.lint.interface, Some(Interface::V1));
    let e = err("[lint]\ninterface = \"3\"\n");
    assert_eq!((e.line, e.col), (2, 13));
    assert!(e.message.contains("1.x"), "{e}");
}

#[test]
fn every_fmt_key_is_read() {
    let o = Config::parse(
        "[fmt]\nindent_width = 4\nkeyword_case = \"keep\"\ntype_case = \"keep\"\nbuiltin_case = \"keep\"\noperator_spacing = \"one\"\ncomma_spacing = \"none\"\ntrim_trailing_whitespace = false\nmax_blank_lines = 2\nindent_folds = false\nalign_dat_decls = true\n",
        "k.toml",
    )
    .expect("valid")
    .fmt;
    assert_eq!(o.indent_width, 4);
    assert_eq!(o.keyword_case, Case::Keep);
    assert_eq!(o.type_case, Case::Keep);
    assert_eq!(o.builtin_case, Case::Keep);
    assert_eq!(o.operator_spacing, Spacing::One);
    assert_eq!(o.comma_spacing, Spacing::None);
    assert!(!o.trim_trailing_whitespace && !o.indent_folds && o.align_dat_decls);
    assert_eq!(o.max_blank_lines, 2);
    assert_eq!(
        Config::parse("", "k.toml").unwrap().fmt,
        FmtOptions::default()
    );
}

#[test]
fn errors_name_line_column_and_a_fix() {
    let e = err("[fmt]\nindent_width = 2\nindnet_width = 3\n");
    assert_eq!((e.line, e.col), (3, 1));
    assert_eq!(e.message, "unknown key `fmt.indnet_width`");
    assert!(e.help.contains("`indent_width`"), "{}", e.help);
    let e = err("[fmt]\nkeyword_case = \"lower\"\n");
    assert_eq!((e.line, e.col), (2, 16));
    assert!(e.message.contains("\"upper\" or \"keep\""), "{e}");
    let e = err("[fmt]\nindent_width = -1\n");
    assert!(e.message.contains("0 to 16"), "{e}");
    let e = err("[lint]\ndisable = [\"MM008\", \"MM080\"]\n");
    assert_eq!((e.line, e.col), (2, 21));
    assert!(e.help.contains("did you mean `MM010`"), "{}", e.help);
    let e = err("[lint]\ndisabel = []\n");
    assert!(e.help.contains("`disable`"), "{}", e.help);
    let e = err("[lnt]\ndisable = []\n");
    assert_eq!(e.message, "unknown key `lnt`");
    assert!(e.help.contains("`lint`"), "{}", e.help);
    let e = err("fmt = 3\n");
    assert!(e.message.contains("must be a table"), "{e}");
    let e = err("[lint.severity]\nMM011 = \"fatal\"\n");
    assert_eq!((e.line, e.col), (2, 9));
}

#[test]
fn a_missing_file_says_how_to_make_one() {
    let e = Config::read(Path::new("/nonexistent/krlkit.toml")).unwrap_err();
    assert_eq!(e.line, 0);
    assert!(e.help.contains("krlkit init"), "{}", e.help);
}

#[test]
fn reads_lint_packages() {
    let c = Config::parse("[lint]\npackages = [\"RSI_KRC2\"]\n", "k.toml").unwrap();
    assert_eq!(c.lint.packages, ["rsi_krc2"]);
    let e = err("[lint]\npackages = [\"arc\"]\n");
    assert_eq!(e.line, 2);
    assert!(format!("{e:?}").contains("rsi_krc2"), "{e:?}");
}
