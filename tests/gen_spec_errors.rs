//! Every bad spec fixture yields one located error message (snapshotted).

use krlkit::spec::Spec;

#[test]
fn spec_errors() {
    insta::glob!("fixtures/specs/err/*.toml", |path| {
        let text = std::fs::read_to_string(path).unwrap();
        let name = format!(
            "fixtures/specs/err/{}",
            path.file_name().unwrap().to_string_lossy()
        );
        let err = Spec::parse(&text, &name).expect_err("fixture must be rejected");
        assert!(err.line > 0, "error must be located: {err}");
        insta::assert_snapshot!(err.to_string());
    });
}

#[test]
fn good_specs_parse() {
    insta::glob!("fixtures/specs/ok/*.toml", |path| {
        let text = std::fs::read_to_string(path).unwrap();
        Spec::parse(&text, "x").unwrap_or_else(|e| panic!("{e}"));
    });
}
