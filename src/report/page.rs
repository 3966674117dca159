//! Binds the view model to the askama page template (`templates/report/page.html`, with its
//! inline stylesheet and script).

use askama::Template;

use super::Report;

#[derive(Template)]
#[template(path = "report/page.html")]
struct Page<'a> {
    r: &'a Report,
    version: &'static str,
}

impl Page<'_> {
    /// Milliseconds of simulated time as the tables print them.
    fn ms(&self, x: &f64) -> String {
        super::scale::num(*x, 3)
    }
}

pub fn render(r: &Report) -> askama::Result<String> {
    Page {
        r,
        version: env!("CARGO_PKG_VERSION"),
    }
    .render()
}
