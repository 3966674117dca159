//! CLI cases: every `tests/cmd/*.toml` (trycmd). `TRYCMD=overwrite cargo test --test cli`
//! refreshes expected output; read the diff before committing.

#[test]
fn cli_cases() {
    trycmd::TestCases::new().case("tests/cmd/*.toml");
}
