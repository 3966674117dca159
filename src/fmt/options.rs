//! Formatter options. `config` reads them from the `[fmt]` table of `krlkit.toml`.

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
