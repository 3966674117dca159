//! Text → lossless tree + diagnostics. Never fails.
//!
//! KRL is line-oriented: no statement spans lines. So the text is cut into physical lines, cheap
//! lines (blank, comment-only, `&` header) are classified by hand, every other line is parsed on
//! its own by the grammar, and [`blocks`](super::blocks) nests the lines into routines and control
//! blocks. A line that does not parse becomes an `Error` node plus one `KRL001`; the next line
//! starts fresh.

use super::blocks::{Assembler, PieceKind, Role, code_span};
use super::build::{Builder, Checkpoint};
use super::cst::{Child, Node, NodeData, NodeKind, SyntaxTree, TokenKind};
use super::line::parse_code;
use crate::diag::{Diagnostic, Span};

/// Rule code for syntax errors.
pub const SYNTAX_ERROR: &str = "KRL001";

/// The result of parsing one file: always a tree, plus whatever went wrong.
#[derive(Debug, Clone)]
pub struct Parse {
    pub tree: SyntaxTree,
    pub diagnostics: Vec<Diagnostic>,
}

impl Parse {
    /// The `SourceFile` node.
    pub fn root(&self) -> Node<'_> {
        self.tree.root()
    }

    /// The contract's `--tree` JSON.
    pub fn to_json_tree(&self, text: &str) -> String {
        let mut out = Vec::new();
        self.write_json_tree(text, &mut out)
            .expect("writing to memory does not fail");
        String::from_utf8(out).expect("JSON is UTF-8")
    }

    /// The `--tree` JSON, written as the tree is walked (nothing the size of the output is
    /// built in memory).
    pub fn write_json_tree(
        &self,
        text: &str,
        out: &mut impl std::io::Write,
    ) -> std::io::Result<()> {
        self.root().write_json(text, out)
    }

    /// The typed AST (see [`super::ast`]).
    pub fn ast(&self, text: &str) -> super::ast::SourceFile {
        super::ast::lower(self, text)
    }

    pub fn has_errors(&self) -> bool {
        !self.diagnostics.is_empty()
    }

    /// The tree handed out as [`parse_pieces`] hands out the text, so that one consumer of
    /// pieces serves the whole tree and the streamed file alike. A module's lines go out as
    /// items but the `END`/`ENDDAT` line that closed it, which stays in its `Close` node (as
    /// when streamed): consumers take a `Close` node's lines after the last piece they saw.
    pub fn pieces(&self, mut f: impl FnMut(Piece<'_>)) {
        for node in self.root().nodes() {
            let data = match node.kind {
                NodeKind::Routine => false,
                NodeKind::DatModule => true,
                _ => {
                    f(Piece::Item(node));
                    continue;
                }
            };
            let mut lines = node.nodes();
            let Some(line) = lines.next() else { continue };
            f(Piece::Open { line, data });
            // Only the line that closed the module stays behind: an unclosed module's last line
            // (a stray `ENDFCT` in a DEFDAT) is an item, as it is when streamed.
            let closes = |line: Node<'_>| {
                matches!(
                    (node.kind, line.kind),
                    (NodeKind::Routine, NodeKind::EndLine)
                        | (NodeKind::DatModule, NodeKind::EnddatLine)
                )
            };
            let mut lines = lines.peekable();
            while let Some(item) = lines.next() {
                if lines.peek().is_some() || !closes(item) {
                    f(Piece::Item(item));
                }
            }
            f(Piece::Close(node));
        }
    }
}

/// Parse decoded KRL text.
pub fn parse(text: &str) -> Parse {
    let mut diagnostics = Vec::new();
    let mut b = Builder::new(text);
    let mut asm = Assembler::new();
    each_line(&mut b, &mut asm, &mut diagnostics, |_, _| {});
    let tree = asm.finish(b, &mut diagnostics);
    diagnostics.sort_by_key(|d| d.span.start);
    Parse { tree, diagnostics }
}

/// Parses each physical line of `b`'s text into `asm`; `after` runs once a line is in.
fn each_line(
    b: &mut Builder,
    asm: &mut Assembler,
    diagnostics: &mut Vec<Diagnostic>,
    mut after: impl FnMut(&mut Builder, &mut Assembler),
) {
    let bytes = b.text.as_bytes();
    let mut start = 0;
    while start < bytes.len() {
        let (content_end, line_end) = line_bounds(bytes, start);
        let (line, role) = parse_line(b, start, content_end, line_end, diagnostics);
        asm.push(b, line, role, diagnostics);
        after(b, asm);
        start = line_end;
    }
}

/// One piece of a file as [`parse_pieces`] hands it out, in text order.
#[derive(Debug, Clone, Copy)]
pub enum Piece<'a> {
    /// A routine (`data` false) or data list opens: its `DEF`/`DEFFCT`/`DEFDAT` line.
    Open { line: Node<'a>, data: bool },
    /// A line or a whole block directly inside the open routine or data list, or at top level
    /// when none is open (exactly the children [`parse`] gives those nodes, in order).
    Item(Node<'a>),
    /// The routine or data list is finished: its node with the span [`parse`] gives it, but
    /// holding only its first line and its `END` line (if any); the items between were handed
    /// out before.
    Close(Node<'a>),
}

/// The nodes a stream of pieces holds, each once and in text order: an `Open`'s first line, an
/// `Item`, and the lines of a `Close` node not handed out before it (its `END` line).
/// Consumers of pieces that want lines walk with this.
#[derive(Debug, Default, Clone, Copy)]
pub struct PieceNodes {
    /// End of the last piece seen (a `Close` piece repeats its first line).
    seen: u32,
}

impl PieceNodes {
    pub fn each<'a>(&mut self, piece: Piece<'a>, mut f: impl FnMut(Node<'a>)) {
        match piece {
            Piece::Open { line: node, .. } | Piece::Item(node) => {
                f(node);
                self.seen = node.span.end;
            }
            Piece::Close(node) => {
                let seen = self.seen;
                node.nodes().filter(|c| c.span.start >= seen).for_each(f);
                self.seen = node.span.end;
            }
        }
    }
}

/// [`parse`] one piece at a time: `f` sees every top-level line or block and every line or
/// block directly inside a routine or data list as soon as it is finished, and its storage is
/// reused after. Memory follows the largest block, not the file (a 50 MB routine is parsed
/// in a few kilobytes of tree). Returns the diagnostics [`parse`] reports.
pub fn parse_pieces(text: &str, mut f: impl FnMut(Piece<'_>)) -> Vec<Diagnostic> {
    each_hand_out(text, |b, pieces, _| {
        for &(kind, id) in pieces {
            f(piece_of(kind, b.view(id)));
        }
    })
}

/// The parse of [`parse_pieces`]: `hand_out` gets the builder and the pieces recorded since
/// its last call (their nodes live until it returns), and where an `Item`'s nodes and
/// children start in the builder's tree (see [`Assembler::hand_out`]).
fn each_hand_out(
    text: &str,
    mut hand_out: impl FnMut(&Builder, &[(PieceKind, u32)], Checkpoint),
) -> Vec<Diagnostic> {
    let mut diagnostics = Vec::new();
    let mut b = Builder::pieces(text);
    let mut asm = Assembler::for_pieces();
    each_line(&mut b, &mut asm, &mut diagnostics, |b, asm| {
        asm.hand_out(b, &mut hand_out)
    });
    asm.close_all(&mut b, &mut diagnostics);
    asm.hand_out(&mut b, &mut hand_out);
    diagnostics.sort_by_key(|d| d.span.start);
    diagnostics
}

fn piece_of(kind: PieceKind, node: Node<'_>) -> Piece<'_> {
    match kind {
        PieceKind::Open => Piece::Open {
            line: node,
            data: false,
        },
        PieceKind::OpenDat => Piece::Open {
            line: node,
            data: true,
        },
        PieceKind::Item => Piece::Item(node),
        PieceKind::Close => Piece::Close(node),
    }
}

/// From this size on, `check` parses a file on a second thread ([`parse_pieces_ahead`]).
/// Below it a file's pieces take under ~20 ms to parse and consume, and such files come many at
/// a time (a controller's ~1000 files are checked in parallel, one per core): a thread per
/// file, and the copy of every piece to hand it across, would cost more than the overlap gives
/// back. A file this large is its own run's critical path (one 50 MB program on an otherwise
/// idle core).
pub const AHEAD_BYTES: usize = 1 << 20;

/// [`parse_pieces`], with the parse a bounded number of pieces ahead of `f` on a second thread
/// when `thread` (each piece's tree is copied to cross: it pays for `check`'s first pass on a
/// file of [`AHEAD_BYTES`] or more; `fmt`'s layout is too light to pay for it): `near` sees
/// each piece on the parser's thread, `f` the same pieces after it, in order, on this one.
/// Returns the diagnostics [`parse_pieces`] returns; without a thread, the same.
pub fn parse_pieces_ahead(
    thread: bool,
    text: &str,
    near: impl FnMut(Piece<'_>) + Send,
    f: impl FnMut(Piece<'_>),
) -> Vec<Diagnostic> {
    let (ahead, size) = (crate::pipeline::BATCHES, crate::pipeline::BATCH);
    pieces_ahead(thread, (ahead, size), text, near, f)
}

/// [`parse_pieces`] on a second thread when `thread`, each piece's tree copied across to `f`
/// on this one, in order, at most a few hundred pieces ahead ([`ACROSS_BATCHES`] batches of
/// [`ACROSS_CHUNKS`] chunks): the translation's first parse, whose other side (the AST
/// lowering, outline and summary) takes about as long as the parse; the few pieces in flight
/// keep its memory where the parse on one thread had it. Without a thread, [`parse_pieces`].
pub fn parse_pieces_across(thread: bool, text: &str, f: impl FnMut(Piece<'_>)) -> Vec<Diagnostic> {
    pieces_ahead(thread, (ACROSS_BATCHES, ACROSS_CHUNKS), text, |_| {}, f)
}

/// How many batches of how many chunks [`parse_pieces_across`] lets wait: more held 15 MB
/// more of a 50 MB translation's memory to the end (the chunks' blocks in the parser's
/// arena), for no time.
const ACROSS_BATCHES: usize = 1;
const ACROSS_CHUNKS: usize = 16;

/// [`parse_pieces_ahead`], with up to `ahead` batches of `size` chunks waiting.
fn pieces_ahead(
    thread: bool,
    (ahead, size): (usize, usize),
    text: &str,
    mut near: impl FnMut(Piece<'_>) + Send,
    mut f: impl FnMut(Piece<'_>),
) -> Vec<Diagnostic> {
    if !thread {
        return parse_pieces(text, |piece| {
            near(piece);
            f(piece);
        });
    }
    crate::pipeline::pipelined_batches(
        true,
        ahead,
        size,
        |sink| {
            let mut chunk = PieceChunk::default();
            let diagnostics = each_hand_out(text, |b, pieces, floor| {
                if pieces.is_empty() {
                    return;
                }
                for &(kind, id) in pieces {
                    near(piece_of(kind, b.view(id)));
                }
                // Lines inside a module hold only what was built after its first line: that
                // line is not copied again with each of them.
                let floor = match pieces.iter().all(|&(kind, _)| kind == PieceKind::Item) {
                    true => floor,
                    false => Checkpoint::START,
                };
                chunk.append(b.tree(), pieces, floor);
                if chunk.pieces.len() >= CHUNK_PIECES || chunk.tree.nodes.len() >= CHUNK_NODES {
                    let next = PieceChunk::like(&chunk);
                    sink.push(std::mem::replace(&mut chunk, next));
                }
            });
            if !chunk.pieces.is_empty() {
                sink.push(chunk);
            }
            diagnostics
        },
        |chunk: &PieceChunk| {
            for &(kind, id) in &chunk.pieces {
                f(piece_of(kind, chunk.tree.node(id)));
            }
        },
    )
}

/// How many pieces, or nodes, a [`PieceChunk`] gathers before it is handed on: a few lines'
/// worth, so that the parser runs at most a few thousand lines ahead (the pipeline holds a
/// few hundred chunks) and a chunk's storage is allocated once for many pieces.
const CHUNK_PIECES: usize = 16;
const CHUNK_NODES: usize = 4096;

/// Pieces copied out of the parser's tree, to be handed to another thread: the builder's
/// tree as it was at each hand-out from `floor` on (it is rolled back after), one after the
/// other, node and child indices moved along.
#[derive(Default)]
struct PieceChunk {
    tree: SyntaxTree,
    pieces: Vec<(PieceKind, u32)>,
}

impl PieceChunk {
    /// A chunk with room for one like `last` (a chunk's storage is allocated once, not grown).
    fn like(last: &PieceChunk) -> PieceChunk {
        let room = |n: usize| n + n / 4 + 16;
        PieceChunk {
            tree: SyntaxTree {
                nodes: Vec::with_capacity(room(last.tree.nodes.len())),
                children: Vec::with_capacity(room(last.tree.children.len())),
            },
            pieces: Vec::with_capacity(room(last.pieces.len())),
        }
    }

    /// Copy `tree` from `floor` on (the pieces' nodes, and what they hold, are all there).
    fn append(&mut self, tree: &SyntaxTree, pieces: &[(PieceKind, u32)], floor: Checkpoint) {
        let (lo, first) = (floor.nodes() as u32, floor.children() as u32);
        // Indices at or after the floor move by these (wrapping: the chunk may be shorter).
        let nodes = (self.tree.nodes.len() as u32).wrapping_sub(lo);
        let children = (self.tree.children.len() as u32).wrapping_sub(first);
        self.tree
            .nodes
            .extend(tree.nodes[lo as usize..].iter().map(|d| NodeData {
                first: d.first.wrapping_add(children),
                ..*d
            }));
        self.tree
            .children
            .extend(tree.children[first as usize..].iter().map(|c| match *c {
                Child::Node(id) => Child::Node(id.wrapping_add(nodes)),
                token => token,
            }));
        self.pieces.extend(
            pieces
                .iter()
                .map(|&(kind, id)| (kind, id.wrapping_add(nodes))),
        );
    }
}

/// The `--tree` JSON of [`Parse::write_json_tree`], written piece by piece as the file is
/// parsed ([`parse_pieces`]): memory follows the largest block, not the file. Returns the
/// diagnostics [`parse`] reports.
pub fn write_json_tree(
    text: &str,
    out: &mut impl std::io::Write,
) -> std::io::Result<Vec<Diagnostic>> {
    out.write_all(b"{\"kind\":\"SourceFile\",\"children\":[")?;
    let mut json = JsonPieces {
        first: [true, true],
        depth: 0,
        seen: 0,
    };
    let mut result = Ok(());
    let diagnostics = parse_pieces(text, |piece| {
        if result.is_ok() {
            result = json.piece(piece, text, out);
        }
    });
    result?;
    out.write_all(b"]}")?;
    Ok(diagnostics)
}

/// Where [`write_json_tree`] is.
struct JsonPieces {
    /// Whether the open list (the file's, the open module's) has no child yet.
    first: [bool; 2],
    depth: usize,
    /// Where the last piece ended (a `Close` node repeats its first line).
    seen: u32,
}

impl JsonPieces {
    fn child(
        &mut self,
        node: Node<'_>,
        text: &str,
        out: &mut impl std::io::Write,
    ) -> std::io::Result<()> {
        if !std::mem::take(&mut self.first[self.depth]) {
            out.write_all(b",")?;
        }
        self.seen = node.span.end;
        node.write_json(text, out)
    }

    fn piece(
        &mut self,
        piece: Piece<'_>,
        text: &str,
        out: &mut impl std::io::Write,
    ) -> std::io::Result<()> {
        match piece {
            Piece::Open { line, data } => {
                if !std::mem::take(&mut self.first[0]) {
                    out.write_all(b",")?;
                }
                let kind = if data {
                    NodeKind::DatModule
                } else {
                    NodeKind::Routine
                };
                write!(out, "{{\"kind\":\"{kind:?}\",\"children\":[")?;
                self.depth = 1;
                self.first[1] = true;
                self.child(line, text, out)
            }
            Piece::Item(node) => self.child(node, text, out),
            Piece::Close(node) => {
                let seen = self.seen;
                for n in node.nodes().filter(|n| n.span.start >= seen) {
                    self.child(n, text, out)?;
                }
                self.depth = 0;
                self.seen = node.span.end;
                out.write_all(b"]}")
            }
        }
    }
}

/// The diagnostics [`parse`] would report, without keeping the tree: memory grows with the
/// deepest open block, not with the file (what `krlkit parse` needs).
pub fn diagnostics(text: &str) -> Vec<Diagnostic> {
    let mut diagnostics = Vec::new();
    let mut b = Builder::outline(text);
    let mut asm = Assembler::new();
    let bytes = text.as_bytes();
    let mut start = 0;
    while start < bytes.len() {
        let (content_end, line_end) = line_bounds(bytes, start);
        let cp = b.checkpoint();
        let (line, role) = parse_line(&mut b, start, content_end, line_end, &mut diagnostics);
        start = line_end;
        let Child::Node(id) = line else { continue };
        let kind = b.kind_of(id);
        if matches!(
            kind,
            NodeKind::BlankLine | NodeKind::CommentLine | NodeKind::HeaderLine
        ) {
            b.rollback(cp);
            continue;
        }
        // The line as the assembler sees it: its kind, span and code span.
        let span = b.span_of(line);
        let code = code_span(&b, line);
        b.rollback(cp);
        b.set_fill_gaps(false);
        let line = b.compact_line(kind, span, code);
        asm.push(&mut b, line, role, &mut diagnostics);
        b.set_fill_gaps(true);
    }
    b.set_fill_gaps(false);
    drop(asm.finish(b, &mut diagnostics));
    diagnostics.sort_by_key(|d| d.span.start);
    diagnostics
}

/// End of the line's content and end of the line including its terminator.
fn line_bounds(bytes: &[u8], start: usize) -> (usize, usize) {
    let rel = memchr::memchr2(b'\n', b'\r', &bytes[start..]);
    match rel {
        None => (bytes.len(), bytes.len()),
        Some(r) => {
            let end = start + r;
            if bytes[end] == b'\r' && bytes.get(end + 1) == Some(&b'\n') {
                (end, end + 2)
            } else {
                (end, end + 1)
            }
        }
    }
}

fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | 0x0B | 0x0C)
}

/// One physical line as a finished node (not yet placed in a block).
fn parse_line(
    b: &mut Builder,
    start: usize,
    content_end: usize,
    line_end: usize,
    diagnostics: &mut Vec<Diagnostic>,
) -> (Child, Role) {
    let text = b.text;
    let bytes = text.as_bytes();
    let span = Span::new(start, line_end);
    let code_start = start
        + bytes[start..content_end]
            .iter()
            .take_while(|&&c| is_blank(c))
            .count();
    let mark = b.mark();
    if code_start > start {
        b.push_token(TokenKind::Whitespace, start, code_start);
    }
    let finish = |b: &mut Builder, kind| {
        if line_end > content_end {
            b.push_token(TokenKind::Newline, content_end, line_end);
        }
        b.finish(mark, kind, span)
    };

    if code_start == content_end {
        return (finish(b, NodeKind::BlankLine), Role::None);
    }
    if bytes[code_start] == b'&' {
        b.push_token(TokenKind::Header, code_start, content_end);
        return (finish(b, NodeKind::HeaderLine), Role::None);
    }
    let comment_start = find_comment(bytes, code_start, content_end);
    let code_end = code_start
        + bytes[code_start..comment_start]
            .iter()
            .rposition(|&c| !is_blank(c))
            .map_or(0, |p| p + 1);
    let trailing = |b: &mut Builder| {
        if comment_start > code_end {
            b.push_token(TokenKind::Whitespace, code_end, comment_start);
        }
        if comment_start < content_end {
            b.push_token(
                comment_kind(&text[comment_start..content_end]),
                comment_start,
                content_end,
            );
        }
    };
    if code_end == code_start {
        trailing(b);
        return (finish(b, NodeKind::CommentLine), Role::None);
    }
    let cp = b.checkpoint();
    match parse_code(b, code_start, code_end) {
        Ok(kind) => {
            // The statement's children are pending on the stack, so they become the line's
            // (the line node has the statement's kind). Bytes between them, and blanks the line
            // splitter does not know (a no-break space) before or after the statement, are
            // filled in as gap tokens when the line is finished.
            trailing(b);
            (finish(b, kind), Role::of(kind))
        }
        Err(err) => {
            b.rollback(cp);
            let role = Role::guess(&text[code_start..code_end]);
            let at = err.at.min(code_end);
            diagnostics.push(Diagnostic::error(
                SYNTAX_ERROR,
                Span::new(at, (at + err.len).min(code_end)),
                err.message,
            ));
            b.push_token(TokenKind::Error, code_start, code_end);
            trailing(b);
            (finish(b, NodeKind::Error), role)
        }
    }
}

/// First `;` that is not inside a string or character literal (or `end` if none).
fn find_comment(bytes: &[u8], start: usize, end: usize) -> usize {
    let mut quote: Option<u8> = None;
    let mut i = start;
    while i < end {
        match quote {
            Some(q) => match memchr::memchr(q, &bytes[i..end]) {
                Some(p) => {
                    quote = None;
                    i += p + 1;
                }
                None => break,
            },
            None => match memchr::memchr3(b';', b'"', b'\'', &bytes[i..end]) {
                Some(p) if bytes[i + p] == b';' => return i + p,
                Some(p) => {
                    quote = Some(bytes[i + p]);
                    i += p + 1;
                }
                None => break,
            },
        }
    }
    if quote.is_some() {
        // An unterminated literal: fall back to the first `;` so the comment survives.
        if let Some(p) = bytes[start..end].iter().position(|&b| b == b';') {
            return start + p;
        }
    }
    end
}

fn comment_kind(comment: &str) -> TokenKind {
    let body = comment[1..].trim_start_matches([' ', '\t']);
    let upper = body.get(..7).unwrap_or(body);
    if upper.len() >= 7 && upper.eq_ignore_ascii_case("ENDFOLD") {
        TokenKind::FoldClose
    } else if body
        .get(..4)
        .is_some_and(|w| w.eq_ignore_ascii_case("FOLD"))
    {
        TokenKind::FoldOpen
    } else {
        TokenKind::Comment
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a run of [`parse_pieces_ahead`] hands out: each piece (with its whole subtree)
    /// as `near` saw it, as `f` saw it, and the diagnostics.
    fn handed_out(thread: bool, text: &str) -> (Vec<String>, Vec<String>, Vec<Diagnostic>) {
        let (mut near, mut far) = (Vec::new(), Vec::new());
        let diagnostics = parse_pieces_ahead(
            thread,
            text,
            |p| near.push(format!("{p:?}")),
            |p| far.push(format!("{p:?}")),
        );
        (near, far, diagnostics)
    }

    /// On a second thread, the pieces are those of [`parse_pieces`], node for node, in order,
    /// to both callbacks: on every repository file, and on all of them in one text (thousands
    /// of pieces, across many chunks and batches, blocks left open and syntax errors).
    #[test]
    fn pieces_parsed_ahead_are_the_pieces() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let files = crate::files::walk(&[root.join("tests/fixtures"), root.join("krl")]).found;
        assert!(files.len() > 100);
        let mut all = String::new();
        for f in &files {
            let text = crate::syntax::decode(&std::fs::read(&f.path).unwrap()).text;
            all.push_str(&text);
            let mut pieces = Vec::new();
            let diagnostics = parse_pieces(&text, |p| pieces.push(format!("{p:?}")));
            let one = (pieces.clone(), pieces, diagnostics);
            assert!(handed_out(true, &text) == one, "{}", f.path.display());
            assert!(handed_out(false, &text) == one, "{}", f.path.display());
        }
        let (near, far, diagnostics) = handed_out(true, &all);
        // More than two of the pipeline's batches (256 chunks each).
        assert!(near.len() > 2 * 256 * CHUNK_PIECES, "{} pieces", near.len());
        assert!(!diagnostics.is_empty());
        assert!((near, far, diagnostics) == handed_out(false, &all));
    }
}
