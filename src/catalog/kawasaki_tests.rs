//! Kawasaki catalog self-checks: the mm_* programs agree with seed 001 character for character,
//! with the KUKA side they name, with the protocol commands and with the AS limits.

use super::*;
use crate::spec::Spec;

/// The 20 programs of seed 001, each exactly as its "Command Format" line prints it.
const SEED_001_FORMATS: &[&str] = &[
    "mm_init_skt(.ip1,.ip2,.ip3,.ip4,.port)",
    "mm_start_vis(.job,.pos_num_need,.sendpos_type,.#start_vis)",
    "mm_get_visdata(.job,.pos_num,.ret)",
    "mm_get_pose(.index,.&targetpos,.label,.speed)",
    "mm_get_jps(.index,.#targetpos,.label,.speed)",
    "mm_switch_model(.job,.model_number)",
    "mm_get_vispath(.job,.getpos_type,.pos_num,.vispos_num,.ret)",
    "mm_get_dydata(.job,.pos_num,.count,.ret)",
    "mm_get_dolist(.resource)",
    "mm_set_dolist()",
    "mm_start_viz(.sendpos_type,.#start_viz)",
    "mm_set_branch(.branch_num,.exit_num)",
    "mm_set_index(.skill_num,.index_num)",
    "mm_get_vizdata(.getpos_type,.pos_num,.vispos_num,.ret)",
    "mm_get_plandata(.resource,.getpos_type,.pos_num,.vispos_index,.ret)",
    "mm_get_property(.group_num,.return_value)",
    "mm_set_property(.group_num)",
    "mm_set_boxsize(.job,.length,.width,.height)",
    "mm_get_notify(.msg)",
    "calibrate()",
];

/// KUKA subprogram → Kawasaki program, as the mapping table (Kawasaki reference 1.12) has it.
const MAPPING: &[(&str, Option<&str>)] = &[
    ("MM_Init_Socket", Some("mm_init_skt")),
    ("MM_Start_Vis", Some("mm_start_vis")),
    ("MM_Get_VisData", Some("mm_get_visdata")),
    ("MM_Start_Viz", Some("mm_start_viz")),
    ("MM_Get_VizData", Some("mm_get_vizdata")),
    ("MM_Get_Pose", Some("mm_get_pose")),
    ("MM_Get_Jps", Some("mm_get_jps")),
    ("MM_Switch_Model", Some("mm_switch_model")),
    ("MM_Set_Branch", Some("mm_set_branch")),
    ("MM_Set_Index", Some("mm_set_index")),
    ("MM_Get_Status", None),
    ("MM_Set_BoxSize", Some("mm_set_boxsize")),
    ("MM_Get_DoList", Some("mm_get_dolist")),
    ("MM_Set_DoList", Some("mm_set_dolist")),
    ("MM_Set_Pos", None),
    ("MM_CALIB", Some("calibrate")),
    ("MM_Get_Dy_Data", Some("mm_get_dydata")),
    ("MM_Get_DyPose", None),
    ("MM_Get_PlanData", Some("mm_get_plandata")),
    ("MM_Get_PlanJps", None),
    ("MM_Get_PlanPose", None),
    ("MM_Get_VisPath", Some("mm_get_vispath")),
];

#[test]
fn every_seed_001_program_is_present_with_its_format() {
    let got: Vec<String> = catalog().kawasaki.iter().map(|k| k.signature()).collect();
    assert_eq!(got, SEED_001_FORMATS);
}

#[test]
fn the_seed_001_document_contains_every_format_and_seed_global() {
    // Guards the hand-typed lists against the seed itself, where the seed is at hand.
    let Some(text) = super::tests::seed_text("001_") else {
        return;
    };
    for f in SEED_001_FORMATS {
        let line = format!("\n{f}\n");
        assert!(text.contains(&line), "seed 001 lacks the format line {f}");
    }
    for g in &catalog().kawasaki_globals {
        let named = text.contains(&format!("{}[i", g.name));
        assert_eq!(
            named,
            g.origin == GlobalOrigin::Seed,
            "{}: origin does not match the seed",
            g.name
        );
    }
}

#[test]
fn names_fit_the_as_limit_and_sigils_match_the_kind() {
    let cat = catalog();
    let max = cat.kawasaki_limits.name_max;
    let mut names: Vec<String> = cat
        .kawasaki
        .iter()
        .map(|k| k.name.to_ascii_lowercase())
        .collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), SEED_001_FORMATS.len());
    for k in &cat.kawasaki {
        assert!(k.name.len() <= max, "{}", k.name);
        for p in &k.params {
            assert!(p.ident().len() <= max, "{}: {}", k.name, p.name);
            let sigil = p
                .name
                .strip_prefix('.')
                .unwrap_or_else(|| panic!("{}: {} is not a local (.name)", k.name, p.name));
            let expect = p.kind.sigil();
            assert!(
                sigil.starts_with(expect) && !sigil[expect.len()..].starts_with(['#', '&', '$']),
                "{}: {} does not carry the sigil of {:?}",
                k.name,
                p.name,
                p.kind
            );
        }
    }
    for g in &cat.kawasaki_globals {
        assert!(g.name.len() <= max, "{}", g.name);
    }
}

#[test]
fn kawasaki_references_resolve() {
    let cat = catalog();
    let spec = Spec::default();
    for k in &cat.kawasaki {
        for c in &k.commands {
            assert!(cat.command(*c).is_some(), "{}: command {c}", k.name);
        }
        let kuka = k.kuka.as_ref().map(|n| {
            cat.subprogram(n)
                .unwrap_or_else(|| panic!("{}: no KUKA subprogram {n}", k.name))
        });
        for p in &k.params {
            assert_eq!(
                p.status,
                p.dir == Direction::Out && p.name == ".ret",
                "{}: {}",
                k.name,
                p.name
            );
            if let Some(kp) = &p.kuka {
                let sp = kuka.unwrap_or_else(|| panic!("{}: {} names {kp}", k.name, p.name));
                let kp = sp
                    .param(kp)
                    .unwrap_or_else(|| panic!("{}: {} names {kp}", k.name, p.name));
                assert_eq!(kp.dir, p.dir, "{}: {}", k.name, p.name);
                assert_eq!(kp.status, p.status, "{}: {}", k.name, p.name);
            }
            if let Some(key) = &p.spec {
                assert!(spec.key_value(key).is_some(), "{}: spec key {key}", k.name);
            }
            let sources = usize::from(p.kuka.is_some())
                + usize::from(p.spec.is_some())
                + usize::from(p.default.is_some());
            match p.dir {
                Direction::Out => {
                    assert!(p.spec.is_none() && p.default.is_none(), "{}", p.name)
                }
                // An IN value of a program a transpiler produces comes from exactly one place.
                Direction::In if kuka.is_some() => {
                    assert_eq!(sources, 1, "{}: {}", k.name, p.name)
                }
                Direction::In => assert_eq!(sources, 0, "{}: {}", k.name, p.name),
            }
            if let Some(d) = p.default {
                assert!(p.in_range(d), "{}: default {d} out of range", p.name);
            }
            if let (Some(a), Some(b)) = (p.min, p.max) {
                assert!(a <= b, "{}: {}", k.name, p.name);
            }
        }
    }
}

#[test]
fn the_kuka_correspondence_is_stated_once_and_matches_the_mapping_table() {
    let cat = catalog();
    assert_eq!(cat.subprograms.len(), MAPPING.len());
    for (kuka, kawasaki) in MAPPING {
        let sp = cat.subprogram(kuka).unwrap();
        assert_eq!(sp.kawasaki().map(|k| k.name.as_str()), *kawasaki, "{kuka}");
        if let Some(k) = sp.kawasaki() {
            assert_eq!(k.kuka_subprogram().map(|s| s.name.as_str()), Some(*kuka));
        }
    }
    // No KUKA subprogram is claimed by two Kawasaki programs.
    let mut claimed: Vec<&str> = cat
        .kawasaki
        .iter()
        .filter_map(|k| k.kuka.as_deref())
        .collect();
    let n = claimed.len();
    claimed.sort();
    claimed.dedup();
    assert_eq!(claimed.len(), n);
    for only in ["mm_get_property", "mm_set_property", "mm_get_notify"] {
        assert!(cat.kawasaki_command(only).unwrap().kuka.is_none(), "{only}");
    }
}

#[test]
fn seed_001_ranges_and_kinds() {
    let cat = catalog();
    let k = |n: &str| cat.kawasaki_command(n).unwrap();
    let start = k("mm_start_vis");
    assert_eq!(
        start.param(".sendpos_type").unwrap().range_text().unwrap(),
        "0, 1, 2 or 3"
    );
    assert_eq!(
        start.param("pos_num_need").unwrap().range_text().unwrap(),
        ">= 0"
    );
    assert!(
        !start.param(".job").unwrap().has_range(),
        "seed 001 states none"
    );
    assert_eq!(start.param(".#start_vis").unwrap().kind, AsKind::Joint);
    assert_eq!(
        k("mm_get_pose").param(".&targetpos").unwrap().kind,
        AsKind::Pose
    );
    assert_eq!(
        k("mm_start_viz").param(".sendpos_type").unwrap().values,
        [0, 1, 2]
    );
    let plan = k("mm_get_plandata");
    assert_eq!(
        plan.param(".getpos_type").unwrap().range_text().unwrap(),
        "1 to 4"
    );
    assert_eq!(plan.param(".resource").unwrap().default, Some(0.0));
    assert_eq!(plan.commands, [210, 111]);
    assert_eq!(k("mm_get_dolist").commands, [206, 106]);
    assert_eq!(k("mm_get_notify").commands, [601]);
    assert_eq!(cat.command(601).unwrap().success, None);
    assert_eq!(k("mm_get_visdata").status_param().unwrap().name, ".ret");
    assert!(k("calibrate").params.is_empty());
}

#[test]
fn global_sizes_equal_the_limits_and_fillers_exist() {
    let cat = catalog();
    let l = &cat.limits;
    let size = |n: &str| cat.kawasaki_global(n).unwrap().size.clone();
    assert_eq!(size("vis_pos_x"), [l.point_capacity]);
    assert_eq!(size("vis_custom_data"), [l.point_capacity, l.user_data_len]);
    assert_eq!(
        size("vis_plan_result"),
        [l.point_capacity, cat.kawasaki_limits.plan_results_len]
    );
    assert_eq!(size("mm_do_list"), [l.do_list_len]);
    assert!(size("mm_status").is_empty());
    let mut names: Vec<&str> = cat
        .kawasaki_globals
        .iter()
        .map(|g| g.name.as_str())
        .collect();
    let n = names.len();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), n);
    for g in &cat.kawasaki_globals {
        assert!(!g.filled_by.is_empty(), "{}", g.name);
        for f in &g.filled_by {
            assert!(cat.kawasaki_command(f).is_some(), "{}: {f}", g.name);
        }
        if g.size.len() == 1 && g.name != "mm_do_list" {
            assert_eq!(g.size, [l.point_capacity], "{}", g.name);
        }
    }
}

#[test]
fn vision_move_layouts_differ_by_the_inserted_group_orientation() {
    let cat = catalog();
    assert_eq!(cat.kuka_plan_len(), cat.limits.plan_results_len);
    assert_eq!(
        cat.kawasaki_plan_len(),
        cat.kawasaki_limits.plan_results_len
    );
    assert_eq!(cat.kawasaki_plan_len(), cat.kuka_plan_len() + 1);
    let map: Vec<Option<u32>> = (0..=21).map(|k| cat.kawasaki_plan_index(k)).collect();
    let mut want: Vec<Option<u32>> = vec![None];
    want.extend((1..=16).map(Some));
    want.extend((18..=21).map(Some));
    want.push(None);
    assert_eq!(map, want);
    // Kawasaki element 17 is the part KUKA lacks.
    let mut at = 0;
    for f in &cat.vision_move_fields {
        if at < 17 && 17 <= at + f.count {
            assert!(!f.kuka && f.name == "group_orientation");
        }
        at += f.count;
    }
}

/// What a translation computes from a Kawasaki command (`computes`), and what a client reads
/// (`client_reads`), names KUKA routines and their parameters: a misspelt one would silently
/// fall back to "reads every parameter" (checked: `MM_J` → `MM_X` fails it).
#[test]
fn computed_routines_and_client_reads_name_kuka_parameters() {
    let cat = catalog();
    let has =
        |sub: &Subprogram, p: &str| sub.params.iter().any(|q| q.ident().eq_ignore_ascii_case(p));
    let mut computed = 0;
    for c in cat.kawasaki_computed_all() {
        let sub = cat
            .subprogram(&c.kuka)
            .unwrap_or_else(|| panic!("{} is not a KUKA routine", c.kuka));
        assert!(
            sub.kawasaki().is_none(),
            "{} has a command of its own",
            c.kuka
        );
        for p in &c.reads {
            assert!(has(sub, p), "{} has no parameter {p}", c.kuka);
        }
        computed += 1;
    }
    assert!(computed > 0);
    for sub in &cat.subprograms {
        for p in sub.client_reads.iter().flatten() {
            assert!(has(sub, p), "{} has no parameter {p}", sub.name);
        }
    }
}

/// What a Kawasaki command `sets` after the call names KUKA outputs of its KUKA routine that
/// the command does not produce (checked: `Last_Data` → `Pos_Num` fails it).
#[test]
fn set_outputs_are_kuka_outputs_without_counterpart() {
    let cat = catalog();
    let mut sets = 0;
    for k in &cat.kawasaki {
        for set in &k.sets {
            let kuka = k.kuka.as_deref().expect("a command of a KUKA routine");
            let sub = cat.subprogram(kuka).expect("a KUKA routine");
            let q = sub
                .params
                .iter()
                .find(|q| q.ident().eq_ignore_ascii_case(&set.kuka))
                .unwrap_or_else(|| panic!("{kuka} has no parameter {}", set.kuka));
            assert_eq!(q.dir, crate::catalog::Direction::Out, "{}", set.kuka);
            assert!(
                k.params.iter().all(|p| !p
                    .kuka
                    .as_deref()
                    .is_some_and(|n| n.eq_ignore_ascii_case(&set.kuka))),
                "{} produces {}",
                k.name,
                set.kuka
            );
            sets += 1;
        }
    }
    assert!(sets > 0);
}

/// Every output of a KUKA routine whose arguments a translation passes to a Kawasaki command
/// (its own, or the one it is computed from, e.g. `MM_Get_DyPose` → `mm_get_pose`) is
/// produced by the command or set after it (`sets`), so none is refused as a catalog defect
/// (checked: removing `sets` from `mm_get_visdata` fails it).
#[test]
fn every_kuka_output_has_a_kawasaki_source() {
    let cat = catalog();
    let is = |a: &str, b: &str| a.eq_ignore_ascii_case(b);
    for s in &cat.subprograms {
        // A routine computed from a stored point (`get_pose`) passes its arguments on; one
        // computed from other results (`MM_Get_PlanJps`) has code of its own.
        let from_point = || {
            cat.kawasaki_computing(&s.name)
                .filter(|k| k.shape == crate::catalog::ProgramShape::GetPose)
        };
        let Some(k) = s.kawasaki().or_else(from_point) else {
            continue;
        };
        let takes = |q: &crate::catalog::Param| {
            k.params
                .iter()
                .any(|p| p.kuka.as_deref().is_some_and(|kp| is(kp, q.ident())))
        };
        for q in s
            .params
            .iter()
            .filter(|q| q.dir == crate::catalog::Direction::Out)
        {
            let set = k.sets.iter().any(|set| is(&set.kuka, q.ident()));
            assert!(takes(q) || set, "{} of {}", q.ident(), s.name);
        }
    }
}
