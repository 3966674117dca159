//! Python's reserved names, and the names the generated script defines itself, which KRL
//! names must not take. KRL names become lower case (Python is case-sensitive, KRL is not), so
//! only lower-case names can clash: the script's classes and constants are capitalised, and its
//! own functions and objects are listed here.

use crate::transpile::front::names::NameRules;

/// Python keywords (soft keywords such as `match` may be used as names).
const KEYWORDS: [&str; 35] = [
    "false", "none", "true", "and", "as", "assert", "async", "await", "break", "class", "continue",
    "def", "del", "elif", "else", "except", "finally", "for", "from", "global", "if", "import",
    "in", "is", "lambda", "nonlocal", "not", "or", "pass", "raise", "return", "try", "while",
    "with", "yield",
];

/// Built-ins a user name would shadow (the generated code calls some of them).
const BUILTINS: [&str; 47] = [
    "abs",
    "all",
    "any",
    "bool",
    "bytes",
    "callable",
    "chr",
    "dict",
    "dir",
    "divmod",
    "enumerate",
    "eval",
    "exec",
    "exit",
    "filter",
    "float",
    "format",
    "getattr",
    "globals",
    "hasattr",
    "hash",
    "id",
    "input",
    "int",
    "isinstance",
    "iter",
    "len",
    "list",
    "locals",
    "map",
    "max",
    "min",
    "next",
    "object",
    "open",
    "ord",
    "pow",
    "print",
    "range",
    "repr",
    "round",
    "set",
    "sorted",
    "str",
    "sum",
    "tuple",
    "type",
];

/// Modules the script imports and the names it defines (see `templates/py/script.py`).
pub const SCRIPT_NAMES: [&str; 28] = [
    "math",
    "os",
    "re",
    "socket",
    "sys",
    "time",
    "flexivrdk",
    "robot",
    "mm",
    "main",
    "connect",
    "robot_serial",
    "to_coord",
    "to_jpos",
    "wait_reached",
    "move_l",
    "move_ptp",
    "move_j",
    "move_rel",
    "zone_code",
    "set_out",
    "set_out_bits",
    "out_state",
    "get_in",
    "get_in_bits",
    "halt",
    "switch_tool",
    "pos_act",
];

/// More names the script defines.
const SCRIPT_NAMES_2: [&str; 13] = [
    "to_int",
    "pose_from_flexiv",
    "axis_act",
    "flange_pose",
    "vision_joints",
    "frame_mul",
    "frame_inv",
    "kuka_out",
    "move_l_path",
    "pos_in_base",
    "timer_get",
    "timer_set",
    "timer_stop",
];

pub fn is_reserved(name: &str) -> bool {
    // One set of the lists, made once: every routine and global is asked about (a search
    // of the lists was 123 comparisons a name).
    static RESERVED: std::sync::OnceLock<rustc_hash::FxHashSet<&'static str>> =
        std::sync::OnceLock::new();
    RESERVED
        .get_or_init(|| {
            let lists = [&KEYWORDS[..], &BUILTINS, &SCRIPT_NAMES, &SCRIPT_NAMES_2];
            lists.into_iter().flatten().copied().collect()
        })
        .contains(name)
}

/// Python identifier rules for translated names: no practical length limit, but KRL names are
/// at most 24 characters anyway; the cut only guards against odd input.
pub const NAME_RULES: NameRules = NameRules {
    max_len: 64,
    is_reserved,
    language: "Python",
    routine: "routine",
    routines_with_globals: true,
    package: &super::mm::GLOBALS,
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transpile::front::names::target_name;

    /// The set holds every listed name and nothing else.
    #[test]
    fn the_reserved_set_is_the_lists() {
        for list in [&KEYWORDS[..], &BUILTINS, &SCRIPT_NAMES, &SCRIPT_NAMES_2] {
            for n in list {
                assert!(is_reserved(n), "{n}");
            }
        }
        for n in ["speed", "pick", "Pass", "", "robot_"] {
            assert!(!is_reserved(n), "{n}");
        }
    }

    #[test]
    fn keywords_and_script_names_are_reserved() {
        assert_eq!(target_name("Pass", &NAME_RULES).0, "pass_");
        assert_eq!(target_name("ROBOT", &NAME_RULES).0, "robot_");
        assert_eq!(target_name("mm", &NAME_RULES).0, "mm_");
        assert_eq!(target_name("speed", &NAME_RULES).0, "speed");
        assert_eq!(target_name("$my_var", &NAME_RULES).0, "x_my_var");
    }
}
