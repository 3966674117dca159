use crate::diag::{Diagnostic, Severity, Span};
use crate::eki::Framing;
use crate::generate;
use crate::lint::EkiChannel;
use crate::lint::context::FileCtx;
use crate::lint::registry::{Check, Rule};
use crate::lint::walk;
use crate::sema::Resolved;
use crate::syntax::ast::ExprKind;

use super::well_formed_calls;

pub static RULE: Rule = Rule {
    code: "MM009",
    name: "eki-config-mismatch",
    severity: Severity::Error,
    summary: "`MM_Init_Socket` names an XML file, alive flag or receive flag that does not match the EKI XML config",
    doc: "## What it checks\n`MM_Init_Socket(XML_Name, Alive_Flag, Recv_Flag, Time_Out)` is compared with the EthernetKRL XML config: the one given with `--eki-xml`, else the XML files with an `ETHERNETKRL` root found in the scanned tree. `XML_Name` (a string literal) must equal the XML file's name without `.xml`, case included (EKI channel names are case-sensitive). `Alive_Flag` must equal `CONFIGURATION/INTERNAL/ALIVE@Set_Flag` and `Recv_Flag` must equal `RECEIVE/RAW/ELEMENT@Set_Flag` of that file (values from literals or constants). When the generated package is among the checked files, the XML's framing must be the package's: RAW `STREAM` for an ASCII package (its `MM_Comm` declares `MM_Parse`), RAW `BYTE` for a HEX one (`MM_Parse_Hex`); Mech-Mind's shipped `XML_Kuka_MMIND.xml` is HEX (RAW `BYTE` `Size` 660). Without any EKI XML, or when an argument's value is not known, the rule is silent.\n\n## Why it matters\n`EKI_Init` fails when the channel name is wrong, and with the wrong flags the package waits forever for a reply flag that is never set (timeouts, or a hang).\n\n## Example\n```krl\nMM_Init_Socket(\"XML_Kuka_MMIND\", 873, 872, 60)   ; the XML sets the receive flag 871\n```\n\n## Fix\nUse the channel name and the flag numbers of the XML file (or regenerate the package and XML from one spec with `krlkit gen`). For a framing mismatch, install the package's own XML and select the package's format in Mech-Vision, or regenerate with the spec's `codec` set to the XML's (`hex-le` for Mech-Mind's shipped file).",
    check: Check::Model(check),
};

fn check(ctx: &FileCtx, out: &mut Vec<Diagnostic>) {
    let channels = &ctx.project.channels;
    if channels.is_empty() {
        return;
    }
    let values = &ctx.flow().values;
    for c in well_formed_calls(ctx) {
        if c.sub.name != "MM_Init_Socket" {
            continue;
        }
        let Some(Some(xml)) = c.args.first() else {
            continue;
        };
        let ExprKind::Str(name) = &xml.kind else {
            continue;
        };
        let Some(ch) = channels.iter().find(|ch| ch.name == *name) else {
            let near = channels
                .iter()
                .find(|ch| ch.name.eq_ignore_ascii_case(name));
            let names: Vec<&str> = channels.iter().map(|c| c.name.as_str()).collect();
            let msg = match near {
                Some(ch) => format!(
                    "EKI channel `{name}` differs in case from the XML file `{}` (channel names are case-sensitive)",
                    ch.path
                ),
                None => format!(
                    "no EKI XML config named `{name}.xml` (found: {})",
                    names.join(", ")
                ),
            };
            let mut d = Diagnostic::error(RULE.code, xml.span, msg).with_help(format!(
                "use the channel name `{}`",
                near.map_or(names[0], |c| c.name.as_str())
            ));
            if let Some(ch) = near {
                d = d.with_related(&ch.path, Span::empty(0), "the EKI channel's config");
            }
            out.push(d);
            continue;
        };
        if let Some(d) = framing_mismatch(ctx, ch, xml.span) {
            out.push(d);
        }
        for (i, what, want) in [
            (1usize, "alive", ch.alive_flag()),
            (2, "receive", ch.receive_flag()),
        ] {
            let Some(want) = want else { continue };
            let Some(Some(arg)) = c.args.get(i) else {
                continue;
            };
            let Some(got) =
                walk::literal_number(arg).or_else(|| values.get(&arg.span.start).copied())
            else {
                continue;
            };
            if got != want as f64 {
                out.push(
                    Diagnostic::error(
                        RULE.code,
                        arg.span,
                        format!("{what} flag {got} does not match the EKI config `{}`, which sets flag {want}", ch.path),
                    )
                    .with_help(format!("pass {want}"))
                    .with_related(&ch.path, Span::empty(0), "the EKI channel's config"),
                );
            }
        }
    }
}

/// The channel XML frames records otherwise than the package among the checked files: its
/// `MM_Comm` parses HEX frames (`MM_Parse_Hex`) or ASCII text (`MM_Parse`). Typically the
/// vendor's HEX `XML_Kuka_MMIND.xml` left beside an ASCII package: EKI then never raises the
/// receive flag (or hands the parser binary), so every call ends in a timeout or a bad reply.
fn framing_mismatch(ctx: &FileCtx, ch: &EkiChannel, at: Span) -> Option<Diagnostic> {
    let xml = ch.config.framing()?;
    let pos = ctx.sema.position(ctx.id, at.start);
    let declared = |name| matches!(ctx.sema.lookup_call(pos, name), Resolved::Routine(_));
    let (package, parser) = if declared(generate::PARSER_HEX) {
        (Framing::Byte { size: 0 }, generate::PARSER_HEX)
    } else if declared(generate::PARSER_ASCII) {
        (Framing::Stream, generate::PARSER_ASCII)
    } else {
        return None;
    };
    if xml.same_codec(package) {
        return None;
    }
    let (speaks, codec) = match package {
        Framing::Stream => ("ASCII", "hex-le"),
        Framing::Byte { .. } => ("HEX", "ascii"),
    };
    Some(
        Diagnostic::error(
            RULE.code,
            at,
            format!(
                "the EKI config `{}` frames records as {xml}, but the package speaks {speaks} (its MM_Comm parses replies with {parser})",
                ch.path
            ),
        )
        .with_help(format!(
            "install the package's own channel XML (`krlkit gen` writes it) and select {speaks} in Mech-Vision, or regenerate the package with `codec = \"{codec}\"`"
        ))
        .with_related(&ch.path, Span::empty(0), "the EKI channel's config"),
    )
}
