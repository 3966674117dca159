//! The Mech-Mind interface in the editor: hover text, completion snippets and signature help
//! for the `MM_*` subprograms, all rendered from the catalog (nothing restated here).

use lsp_types::{
    CompletionItem, CompletionItemKind, Documentation, InsertTextFormat, MarkupContent, MarkupKind,
    ParameterInformation, ParameterLabel, SignatureHelp, SignatureInformation,
};

use crate::catalog::{Interface, Param, Subprogram, catalog};

/// The subprogram called `name` in the interface version the workspace is checked against.
pub fn subprogram(iface: Interface, name: &str) -> Option<&'static Subprogram> {
    catalog().subprogram_in(iface, name)
}

fn markdown(value: String) -> Documentation {
    Documentation::MarkupContent(MarkupContent {
        kind: MarkupKind::Markdown,
        value,
    })
}

/// `**Job** `IN INT` — Mech-Vision project ID. Range: 1 to 99.`
pub fn param_text(p: &Param) -> String {
    let mut s = format!(
        "**{}** `{} {}` — {}",
        p.ident(),
        p.dir.krl(),
        p.ty,
        p.meaning
    );
    if let Some(unit) = &p.unit {
        s.push_str(&format!(". Unit: {unit}"));
    }
    if let Some(range) = p.range_text() {
        s.push_str(&format!(". Range: {range}"));
    }
    if p.status {
        s.push_str(". Carries the status code");
    }
    s.push('.');
    s
}

/// Hover for a call of `sub`: signature, summary, then the parameter under the cursor (or all).
pub fn hover(sub: &Subprogram, arg: Option<usize>) -> String {
    let mut s = format!("```krl\n{}\n```\n{}\n", sub.signature(), sub.summary);
    match arg.and_then(|i| sub.params.get(i)) {
        Some(p) => s.push_str(&format!("\n{}\n", param_text(p))),
        None => {
            for p in &sub.params {
                s.push_str(&format!("\n- {}", param_text(p)));
            }
            if !sub.params.is_empty() {
                s.push('\n');
            }
        }
    }
    if sub.status_global {
        s.push_str("\nThe status code is left in the global `MM_Last_Status`.\n");
    }
    if !sub.after.is_empty() {
        s.push_str(&format!("\nCall after: `{}`.\n", sub.after.join("`, `")));
    }
    s
}

/// Every subprogram of `iface` as a snippet: `MM_Get_Pose(${1:Pos_Num}, ${2:Pose}, …)`.
pub fn completions(iface: Interface) -> Vec<CompletionItem> {
    catalog()
        .subprograms_of(iface)
        .iter()
        .map(|sub| {
            let args: Vec<String> = sub
                .params
                .iter()
                .enumerate()
                .map(|(i, p)| format!("${{{}:{}}}", i + 1, p.ident()))
                .collect();
            CompletionItem {
                label: sub.name.clone(),
                kind: Some(CompletionItemKind::FUNCTION),
                detail: Some(sub.signature()),
                documentation: Some(markdown(hover(sub, None))),
                insert_text: Some(format!("{}({})", sub.name, args.join(", "))),
                insert_text_format: Some(InsertTextFormat::SNIPPET),
                ..CompletionItem::default()
            }
        })
        .collect()
}

/// Signature help for a call of `sub` with the cursor in argument `arg`.
pub fn signature_help(sub: &Subprogram, arg: usize) -> SignatureHelp {
    let label = sub.signature();
    // Parameter labels as offsets into the signature (UTF-16; the catalog is ASCII).
    let mut params = Vec::new();
    let mut at = sub.name.len() + 1;
    for p in &sub.params {
        let text = format!("{}:{}", p.name, p.dir.krl());
        params.push(ParameterInformation {
            label: ParameterLabel::LabelOffsets([at as u32, (at + text.len()) as u32]),
            documentation: Some(markdown(param_text(p))),
        });
        at += text.len() + 1;
    }
    SignatureHelp {
        signatures: vec![SignatureInformation {
            label,
            documentation: Some(markdown(sub.summary.clone())),
            parameters: Some(params),
            active_parameter: Some(arg as u32),
        }],
        active_signature: Some(0),
        active_parameter: Some(arg as u32),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameter_labels_point_into_the_signature() {
        for sub in Interface::ALL
            .into_iter()
            .flat_map(|i| catalog().subprograms_of(i))
        {
            let help = signature_help(sub, 0);
            let sig = &help.signatures[0];
            for (p, info) in sub.params.iter().zip(sig.parameters.as_ref().unwrap()) {
                let ParameterLabel::LabelOffsets([a, b]) = info.label else {
                    panic!("offsets expected")
                };
                assert_eq!(
                    &sig.label[a as usize..b as usize],
                    format!("{}:{}", p.name, p.dir.krl())
                );
            }
        }
    }

    /// A 2.x workspace gets the 2.x signatures and routines, a 1.x one the seed's.
    #[test]
    fn the_interface_version_picks_the_signatures() {
        let v2 = subprogram(Interface::V2, "mm_start_vis").unwrap();
        assert!(hover(v2, None).contains("MM_Status"), "{}", hover(v2, None));
        assert!(
            !hover(subprogram(Interface::V1, "MM_Start_Vis").unwrap(), None).contains("MM_Status")
        );
        assert!(subprogram(Interface::V1, "MM_Stop_Viz").is_none());
        let labels = |i| {
            completions(i)
                .into_iter()
                .map(|c| c.label)
                .collect::<Vec<_>>()
        };
        assert!(labels(Interface::V2).contains(&"MM_Stop_Viz".to_string()));
        assert!(!labels(Interface::V2).contains(&"MM_Set_Pos".to_string()));
        assert!(labels(Interface::V1).contains(&"MM_Set_Pos".to_string()));
    }

    #[test]
    fn hover_names_meaning_unit_and_range() {
        let sub = subprogram(Interface::V1, "mm_init_socket").unwrap();
        let text = hover(sub, Some(3));
        assert!(text.contains("**Time_Out** `IN INT`"), "{text}");
        assert!(text.contains("Unit: s"), "{text}");
        assert!(text.contains("Range: >= 1"), "{text}");
    }
}
