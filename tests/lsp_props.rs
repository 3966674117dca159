//! Property: random edits at random UTF-16 positions (inserts, deletions, replacements with
//! multi-byte characters, surrogate pairs and every line ending) never make the server fail,
//! and after them the server's text — the open document and the text it analyses — equals the
//! editor's, byte for byte. Requests at random (also invalid) positions never fail either.

use lsp_server::{Message, Notification, Request, RequestId};
use proptest::prelude::*;
use serde_json::{Value, json};

const URI: &str = "file:///ws/R1/prop.src";
const ID: &str = "/ws/R1/prop.src";

const START: &str = "&ACCESS RVP\r\nDEF prop( )\r\n  DECL INT status\r\n  ; Grüße 😀\r\n  MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)\r\n;FOLD INI\r\n  MM_Start_Vis(1, 0, 2, x)\rEND\n";

/// Pieces an edit inserts.
const PIECES: &[&str] = &[
    "",
    "a",
    "ä",
    "😀",
    "\r\n",
    "\r",
    "\n",
    "MM_Start_Vis(",
    ")",
    ",",
    ";FOLD x",
    ";ENDFOLD",
    "END",
    "\"",
    "DEF f()",
    "  ",
    "€",
    "IF x THEN",
    "ENDIF",
    "$OUT[1]",
];

/// Position of char index `c` as an editor computes it (UTF-16 columns; CR, LF, CRLF).
fn position(text: &str, c: usize) -> Value {
    let (mut line, mut col) = (0u32, 0u32);
    let mut chars = text.chars().take(c).peekable();
    while let Some(ch) = chars.next() {
        match ch {
            '\r' if chars.peek() == Some(&'\n') => {}
            '\r' | '\n' => {
                line += 1;
                col = 0;
            }
            _ => col += ch.len_utf16() as u32,
        }
    }
    json!({ "line": line, "character": col })
}

/// A char index an editor could put a cursor at: never between CR and LF.
fn cursor(text: &str, frac: f64) -> usize {
    let chars: Vec<char> = text.chars().collect();
    let mut c = ((chars.len() as f64) * frac) as usize;
    if c > 0 && c < chars.len() && chars[c - 1] == '\r' && chars[c] == '\n' {
        c += 1;
    }
    c.min(chars.len())
}

fn byte_of(text: &str, c: usize) -> usize {
    text.char_indices().nth(c).map_or(text.len(), |(b, _)| b)
}

struct Harness {
    server: krlkit::lsp::Server,
    rx: crossbeam_channel::Receiver<Message>,
    version: i32,
    next_id: i32,
}

impl Harness {
    fn new() -> Harness {
        let (tx, rx) = crossbeam_channel::unbounded();
        let mut server = krlkit::lsp::Server::new(tx, None, krlkit::lsp::Options::default());
        server.handle(Message::Notification(Notification::new(
            "textDocument/didOpen".into(),
            json!({ "textDocument": { "uri": URI, "languageId": "krl", "version": 0, "text": START } }),
        )));
        Harness {
            server,
            rx,
            version: 0,
            next_id: 0,
        }
    }

    fn change(&mut self, range: Value, text: &str) {
        self.version += 1;
        self.server.handle(Message::Notification(Notification::new(
            "textDocument/didChange".into(),
            json!({
                "textDocument": { "uri": URI, "version": self.version },
                "contentChanges": [ { "range": range, "text": text } ],
            }),
        )));
    }

    /// Send a request and return its response (the server answers at once, in process).
    fn request(&mut self, method: &str, params: Value) -> lsp_server::Response {
        self.next_id += 1;
        self.server.handle(Message::Request(Request::new(
            RequestId::from(self.next_id),
            method.into(),
            params,
        )));
        loop {
            match self.rx.try_recv().expect("a response") {
                Message::Response(r) => return r,
                _ => continue,
            }
        }
    }
}

fn edit_strategy() -> impl Strategy<Value = Vec<(f64, f64, usize)>> {
    prop::collection::vec((0.0..=1.0f64, 0.0..0.2f64, 0..PIECES.len()), 1..40)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_edits_keep_the_editors_text(edits in edit_strategy()) {
        let mut h = Harness::new();
        let mut editor = START.to_owned();
        for (i, (at, len, piece)) in edits.into_iter().enumerate() {
            let a = cursor(&editor, at);
            let b = cursor(&editor, (at + len).min(1.0)).max(a);
            let range = json!({ "start": position(&editor, a), "end": position(&editor, b) });
            let (ba, bb) = (byte_of(&editor, a), byte_of(&editor, b));
            editor.replace_range(ba..bb, PIECES[piece]);
            h.change(range, PIECES[piece]);
            prop_assert_eq!(h.server.document_text(ID), Some(editor.as_str()));
            if i % 4 == 0 {
                // A request brings the analysis up to date first.
                let p = json!({ "textDocument": { "uri": URI }, "position": position(&editor, a) });
                for m in ["textDocument/hover", "textDocument/completion", "textDocument/signatureHelp"] {
                    let r = h.request(m, p.clone());
                    prop_assert!(r.response_result.is_ok(), "{m}: {:?}", r.response_result);
                }
                prop_assert_eq!(h.server.analysed_text(ID), Some(editor.as_str()));
            }
        }
        h.server.flush();
        prop_assert_eq!(h.server.analysed_text(ID), Some(editor.as_str()));
        for m in ["textDocument/documentSymbol", "textDocument/foldingRange"] {
            let r = h.request(m, json!({ "textDocument": { "uri": URI } }));
            prop_assert!(r.response_result.is_ok(), "{m}: {:?}", r.response_result);
        }
        prop_assert_eq!(h.server.failures(), 0);
    }

    #[test]
    fn positions_out_of_range_never_fail(
        edits in prop::collection::vec((0u32..20, 0u32..300, 0u32..20, 0u32..300, 0..PIECES.len()), 1..30)
    ) {
        let mut h = Harness::new();
        for (l0, c0, l1, c1, piece) in edits {
            let range = json!({
                "start": { "line": l0, "character": c0 },
                "end": { "line": l1, "character": c1 },
            });
            h.change(range, PIECES[piece]);
            let p = json!({ "textDocument": { "uri": URI }, "position": { "line": l1, "character": c1 } });
            let r = h.request("textDocument/hover", p);
            prop_assert!(r.response_result.is_ok(), "{:?}", r.response_result);
        }
        h.server.flush();
        prop_assert_eq!(h.server.analysed_text(ID), h.server.document_text(ID));
        prop_assert_eq!(h.server.failures(), 0);
    }
}
