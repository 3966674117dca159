//! Formatter options and the `[fmt]` table of the config file `check` reads.
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

use crate::lint::ConfigError;

/// Upper-case a class of words, or leave them as written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Case {
    Upper,
    Keep,
}

/// Blanks around a binary operator (or after a comma).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spacing {
    /// As written.
    Keep,
    /// Exactly one space (around an operator; after a comma, none before it).
    One,
    /// No space (word operators such as `AND` keep the one they need).
    None,
}

/// How `fmt` lays out a file. [`FmtOptions::default`] is the documented default style.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FmtOptions {
    /// Spaces per block level. Default 2: the width KUKA's own templates use inside folds, and
    /// the Vim runtime's KRL indent (for the teach pendant's narrow screen). The smartPAD
    /// editor's own width could not be verified [U].
    pub indent_width: usize,
    pub keyword_case: Case,
    pub type_case: Case,
    pub builtin_case: Case,
    pub operator_spacing: Spacing,
    pub comma_spacing: Spacing,
    pub trim_trailing_whitespace: bool,
    /// Runs of blank lines longer than this are cut to it.
    pub max_blank_lines: usize,
    /// Lines inside a matched, non inline-form `;FOLD` … `;ENDFOLD` are one level deeper.
    pub indent_folds: bool,
    /// In a `.dat`, the variable names of consecutive `DECL` lines start in one column.
    pub align_dat_decls: bool,
}

impl Default for FmtOptions {
    fn default() -> FmtOptions {
        FmtOptions {
            indent_width: 2,
            keyword_case: Case::Upper,
            type_case: Case::Upper,
            builtin_case: Case::Upper,
            operator_spacing: Spacing::Keep,
            comma_spacing: Spacing::Keep,
            trim_trailing_whitespace: true,
            max_blank_lines: 1,
            indent_folds: true,
            align_dat_decls: false,
        }
    }
}

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

impl FmtOptions {
    /// Read the `[fmt]` table of a TOML document (other tables belong to other stages). Every
    /// error names the line; an unknown key names the nearest known one.
    pub fn from_toml(path: &str, text: &str) -> Result<FmtOptions, ConfigError> {
        let err = |needle: &str, message: String| ConfigError::at(path, text, needle, message);
        let value = crate::lint::config::parse_toml(path, text)?;
        let mut opts = FmtOptions::default();
        let Some(fmt) = value.get("fmt") else {
            return Ok(opts);
        };
        let Some(fmt) = fmt.as_table() else {
            return Err(err("fmt", "`fmt` must be a table".into()));
        };
        for (key, v) in fmt {
            let case = |v: &toml::Value| match v.as_str() {
                Some("upper") => Ok(Case::Upper),
                Some("keep") => Ok(Case::Keep),
                _ => Err(err(
                    key,
                    format!("`fmt.{key}` must be \"upper\" or \"keep\""),
                )),
            };
            let spacing = |v: &toml::Value| match v.as_str() {
                Some("keep") => Ok(Spacing::Keep),
                Some("one") => Ok(Spacing::One),
                Some("none") => Ok(Spacing::None),
                _ => Err(err(
                    key,
                    format!("`fmt.{key}` must be \"keep\", \"one\" or \"none\""),
                )),
            };
            let boolean = |v: &toml::Value| {
                v.as_bool()
                    .ok_or_else(|| err(key, format!("`fmt.{key}` must be true or false")))
            };
            let count = |v: &toml::Value, max: i64| {
                v.as_integer()
                    .filter(|n| (0..=max).contains(n))
                    .map(|n| n as usize)
                    .ok_or_else(|| {
                        err(key, format!("`fmt.{key}` must be a whole number 0..={max}"))
                    })
            };
            match key.as_str() {
                "indent_width" => opts.indent_width = count(v, 16)?,
                "keyword_case" => opts.keyword_case = case(v)?,
                "type_case" => opts.type_case = case(v)?,
                "builtin_case" => opts.builtin_case = case(v)?,
                "operator_spacing" => opts.operator_spacing = spacing(v)?,
                "comma_spacing" => opts.comma_spacing = spacing(v)?,
                "trim_trailing_whitespace" => opts.trim_trailing_whitespace = boolean(v)?,
                "max_blank_lines" => opts.max_blank_lines = count(v, 1000)?,
                "indent_folds" => opts.indent_folds = boolean(v)?,
                "align_dat_decls" => opts.align_dat_decls = boolean(v)?,
                other => {
                    return Err(err(
                        other,
                        format!(
                            "unknown key `fmt.{other}` (did you mean `{}`?)",
                            nearest_key(other)
                        ),
                    ));
                }
            }
        }
        Ok(opts)
    }
}

fn nearest_key(key: &str) -> &'static str {
    KEYS.iter()
        .map(|k| (crate::catalog::edit_distance(key, k), *k))
        .min()
        .map_or(KEYS[0], |(_, k)| k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_every_key_and_ignores_other_tables() {
        let o = FmtOptions::from_toml(
            "k.toml",
            "[lint]\ndisable=[]\n[fmt]\nindent_width = 4\nkeyword_case = \"keep\"\ntype_case = \"keep\"\nbuiltin_case = \"keep\"\noperator_spacing = \"one\"\ncomma_spacing = \"none\"\ntrim_trailing_whitespace = false\nmax_blank_lines = 2\nindent_folds = false\nalign_dat_decls = true\n",
        )
        .expect("valid");
        assert_eq!(o.indent_width, 4);
        assert_eq!(o.keyword_case, Case::Keep);
        assert_eq!(o.type_case, Case::Keep);
        assert_eq!(o.builtin_case, Case::Keep);
        assert_eq!(o.operator_spacing, Spacing::One);
        assert_eq!(o.comma_spacing, Spacing::None);
        assert!(!o.trim_trailing_whitespace && !o.indent_folds && o.align_dat_decls);
        assert_eq!(o.max_blank_lines, 2);
        assert_eq!(
            FmtOptions::from_toml("k.toml", "[spec]\n").unwrap(),
            FmtOptions::default()
        );
    }

    #[test]
    fn unknown_key_is_located_with_a_hint() {
        let e = FmtOptions::from_toml("k.toml", "[fmt]\nindent_width = 2\nindnet_width = 3\n")
            .unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.message.contains("`indent_width`"), "{}", e.message);
        let e = FmtOptions::from_toml("k.toml", "[fmt]\nkeyword_case = \"lower\"\n").unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.message.contains("\"upper\" or \"keep\""));
        let e = FmtOptions::from_toml("k.toml", "[fmt]\nindent_width = -1\n").unwrap_err();
        assert!(e.message.contains("0..=16"));
    }
}
