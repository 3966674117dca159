//! RAPID's reserved words, and the predefined names the translated module uses, which KRL
//! names must not take (RAPID is case-insensitive: names are compared in lower case).

/// The RAPID kernel's reserved words (`abb-rapid.md` §1.4).
const RESERVED: [&str; 67] = [
    "alias",
    "and",
    "backward",
    "case",
    "connect",
    "const",
    "default",
    "div",
    "do",
    "else",
    "elseif",
    "endfor",
    "endfunc",
    "endif",
    "endmodule",
    "endproc",
    "endrecord",
    "endtest",
    "endtrap",
    "endwhile",
    "error",
    "exit",
    "false",
    "for",
    "from",
    "func",
    "goto",
    "if",
    "inout",
    "local",
    "mod",
    "module",
    "nostepin",
    "not",
    "noview",
    "or",
    "pers",
    "proc",
    "raise",
    "readonly",
    "record",
    "retry",
    "return",
    "step",
    "sysmodule",
    "task",
    "test",
    "then",
    "to",
    "trap",
    "true",
    "trynext",
    "undo",
    "var",
    "viewonly",
    "while",
    "with",
    "xor",
    // Data types the module declares.
    "num",
    "bool",
    "string",
    "robtarget",
    "jointtarget",
    "tooldata",
    "wobjdata",
    "intnum",
    "speeddata",
];

/// Instructions, functions and predefined data the module writes: a KRL name equal to one
/// would hide it.
const PREDEFINED: [&str; 46] = [
    "main",
    "movej",
    "movel",
    "movec",
    "moveabsj",
    "setdo",
    "pulsedo",
    "waitdi",
    "waituntil",
    "waittime",
    "stop",
    "crobt",
    "cjointt",
    "offs",
    "reltool",
    "eulerzyx",
    "orientzyx",
    "confj",
    "confl",
    "velset",
    "abs",
    "sqrt",
    "sin",
    "cos",
    "tan",
    "acos",
    "atan2",
    "round",
    "trunc",
    "strlen",
    "tpwrite",
    "fine",
    "vmax",
    "tool0",
    "wobj0",
    "high",
    "low",
    "pi",
    "zonedata",
    "pose",
    "confdata",
    "orient",
    "pos",
    "krl_flag",
    "idelete",
    "isignaldi",
];

pub fn is_reserved(lower: &str) -> bool {
    RESERVED.contains(&lower) || PREDEFINED.contains(&lower) || numbered(lower)
}

/// `v100`, `z10`, `do3`, `di5`, `tool1`, `wobj2`, `ir4`: predefined speeds and zones, the
/// default signal names and the names the module gives tools, work objects and interrupts.
fn numbered(lower: &str) -> bool {
    ["v", "z", "do", "di", "tool", "wobj", "ir"]
        .iter()
        .any(|p| {
            lower
                .strip_prefix(p)
                .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reserved_and_predefined_names() {
        for n in [
            "test", "step", "from", "case", "main", "v100", "z10", "do3", "di17", "fine",
        ] {
            assert!(is_reserved(n), "{n}");
        }
        for n in ["pick", "vel", "zone", "door", "di", "tool_x"] {
            assert!(!is_reserved(n), "{n}");
        }
    }
}
