//! `[fmt]`: how `fmt` lays out a file (the options `fmt::FmtOptions` documents).
//!
//! ```toml
//! [fmt]
//! indent_width = 2          # spaces per level
//! keyword_case = "upper"    # or "keep"
//! type_case = "upper"       # INT, REAL, BOOL, CHAR, FRAME, POS, E6POS, AXIS, E6AXIS
//! builtin_case = "upper"    # TRUE/FALSE, $ system variables, built-in math functions
//! operator_spacing = "keep" # "one": one space around binary operators and `=`; "none"
//! comma_spacing = "keep"    # "one": one space after a comma, none before; "none"
//! trim_trailing_whitespace = true
//! max_blank_lines = 1       # longer runs of blank lines are cut to this many
//! indent_folds = true       # lines inside a (non inline-form) ;FOLD are one level deeper
//! align_dat_decls = false   # align the names of consecutive DECL lines in a .dat
//! ```

use toml::de::DeTable;

use super::ConfigError;
use super::table::{Doc, Value, unknown_key_help};
use crate::fmt::{Case, FmtOptions, Spacing};

const KEYS: &[&str] = &[
    "indent_width",
    "keyword_case",
    "type_case",
    "builtin_case",
    "operator_spacing",
    "comma_spacing",
    "trim_trailing_whitespace",
    "max_blank_lines",
    "indent_folds",
    "align_dat_decls",
];

pub(super) fn read(doc: &Doc, root: &DeTable) -> Result<FmtOptions, ConfigError> {
    let mut opts = FmtOptions::default();
    let Some(table) = doc.section(root, "fmt")? else {
        return Ok(opts);
    };
    for (key, v) in table {
        let name = format!("fmt.{}", key.get_ref());
        let name = name.as_str();
        match key.get_ref().as_ref() {
            "indent_width" => opts.indent_width = doc.count(v, name, 0..=16)?,
            "keyword_case" => opts.keyword_case = case(doc, v, name)?,
            "type_case" => opts.type_case = case(doc, v, name)?,
            "builtin_case" => opts.builtin_case = case(doc, v, name)?,
            "operator_spacing" => opts.operator_spacing = spacing(doc, v, name)?,
            "comma_spacing" => opts.comma_spacing = spacing(doc, v, name)?,
            "trim_trailing_whitespace" => opts.trim_trailing_whitespace = doc.boolean(v, name)?,
            "max_blank_lines" => opts.max_blank_lines = doc.count(v, name, 0..=1000)?,
            "indent_folds" => opts.indent_folds = doc.boolean(v, name)?,
            "align_dat_decls" => opts.align_dat_decls = doc.boolean(v, name)?,
            other => {
                return Err(doc.err(
                    key,
                    format!("unknown key `{name}`"),
                    unknown_key_help(other, KEYS),
                ));
            }
        }
    }
    Ok(opts)
}

fn case(doc: &Doc, v: &Value, key: &str) -> Result<Case, ConfigError> {
    const TAKES: &str = "\"upper\" or \"keep\"";
    match doc.string(v, key, TAKES)? {
        "upper" => Ok(Case::Upper),
        "keep" => Ok(Case::Keep),
        _ => Err(doc.err(
            v,
            format!("`{key}` must be {TAKES}"),
            format!("write {TAKES}"),
        )),
    }
}

fn spacing(doc: &Doc, v: &Value, key: &str) -> Result<Spacing, ConfigError> {
    const TAKES: &str = "\"keep\", \"one\" or \"none\"";
    match doc.string(v, key, TAKES)? {
        "keep" => Ok(Spacing::Keep),
        "one" => Ok(Spacing::One),
        "none" => Ok(Spacing::None),
        _ => Err(doc.err(
            v,
            format!("`{key}` must be {TAKES}"),
            format!("write {TAKES}"),
        )),
    }
}
