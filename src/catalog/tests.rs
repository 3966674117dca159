//! Catalog self-checks: the data agree with the seed and with themselves.

use super::*;

/// The 22 subprograms of seed 000 with their signatures exactly as the seed prints them
/// (MM_Get_DoList/MM_Set_DoList take no parameters).
const SEED_SIGNATURES: &[&str] = &[
    "MM_Init_Socket(XML_Name[]:IN,Alive_Flag:IN,Recv_Flag:IN,Time_Out:IN)",
    "MM_Start_Vis(Job:IN,Pos_Num_Need:IN,SendPos_Type:IN,MM_J:IN)",
    "MM_Get_VisData(Job:IN,Last_Data:OUT,Pos_Num:OUT,MM_Status:OUT)",
    "MM_Start_Viz(SendPos_Type:IN,MM_J:IN)",
    "MM_Get_VizData(Jps_Pos:IN,Last_Data:OUT,Pos_Num:OUT,VisPos_Num:OUT,MM_Status:OUT)",
    "MM_Get_Pose(Serial:IN,MM_P:OUT,MM_Label:OUT,MM_Speed:OUT)",
    "MM_Get_Jps(Serial:IN,MM_J:OUT,MM_Label:OUT,MM_Speed:OUT)",
    "MM_Switch_Model(Job:IN,Model_Number:IN)",
    "MM_Set_Branch(Branch_Num:IN,Export_Num:IN)",
    "MM_Set_Index(Skill_Num:IN,Index_Num:IN)",
    "MM_Get_Status(MM_Status:OUT)",
    "MM_Set_BoxSize(Job:IN,Lenght:IN,Width:IN,Height:IN)",
    "MM_Get_DoList()",
    "MM_Set_DoList()",
    "MM_Set_Pos(Out_Pos:IN)",
    "MM_CALIB(Move_Type:IN,PosJps:IN,WaitTime:IN,E1:IN)",
    "MM_Get_Dy_Data(Job:IN,Pos_Num:OUT,MM_Status:OUT)",
    "MM_Get_DyPose(Serial:IN,MM_P:OUT,MM_Label:OUT)",
    "MM_Get_PlanData(Jps_Pos:IN,Pos_Num:OUT,VisPos_Num:OUT,MM_Status:OUT)",
    "MM_Get_PlanJps(Serial:IN,Jps_Pos:IN,MM_J:OUT,MM_MoveType:OUT,MM_ToolNum:OUT,MM_Speed:OUT)",
    "MM_Get_PlanPose(Serial:IN,Jps_Pos:IN,MM_P:OUT,MM_MoveType:OUT,MM_ToolNum:OUT,MM_Speed:OUT)",
    "MM_Get_VisPath(Job:IN,Jps_Pos:IN,Last_Data:OUT,Pos_Num:OUT,VisPos_Num:OUT,MM_Status:OUT)",
];

/// The 2.x subprograms with their signatures as a public engineering note compiled from the
/// vendor's 2.2.1 KUKA page lists them (protocol reference 2.5 [S]), directions added (the
/// note gives them only for MM_Get_PlanPose; every status is an output). Differences from the
/// note: MM_Get_VisPath and MM_CALIB keep their 1.x spelling (KRL names are case-insensitive),
/// MM_Get_PlanJps is not in the note and keeps its 1.x signature, and the DyPose array is
/// written `MM_UserData[]` as a KRL array parameter must be.
const V2_SIGNATURES: &[&str] = &[
    "MM_Init_Socket(XML_Name[]:IN,Alive_Flag:IN,Recv_Flag:IN,Time_Out:IN)",
    "MM_Start_Vis(Job:IN,Pos_Num_Need:IN,SendPos_Type:IN,MM_J:IN,MM_Status:OUT)",
    "MM_Get_VisData(Job:IN,Pos_Num:OUT,MM_Status:OUT)",
    "MM_Get_Pose(Serial:IN,MM_P:OUT,MM_Label:OUT,MM_ToolId:OUT)",
    "MM_Get_Jps(Serial:IN,MM_J:OUT,MM_Label:OUT,MM_ToolId:OUT)",
    "MM_Switch_Model(Job:IN,Model_Number:IN,MM_Status:OUT)",
    "MM_Get_VisPath(Job:IN,Jps_Pos:IN,Pos_Num:OUT,VisPos_Num:OUT,MM_Status:OUT)",
    "MM_Get_Dy_Data(Job:IN,Pos_Num:OUT,MM_Status:OUT)",
    "MM_Get_DyPose(Serial:IN,MM_P:OUT,MM_Label:OUT,MM_UserData[]:OUT)",
    "MM_Get_DoList(Resource:IN,BlockNum:IN,MM_Status:OUT)",
    "MM_Set_DoList(LoopIndex:IN)",
    "MM_Start_Viz(SendPos_Type:IN,MM_J:IN,MM_Status:OUT)",
    "MM_Set_Branch(Branch_Num:IN,Export_Num:IN,MM_Status:OUT)",
    "MM_Set_Index(Skill_Num:IN,Index_Num:IN,MM_Status:OUT)",
    "MM_Get_VizData(Jps_Pos:IN,Pos_Num:OUT,VisPos_Num:OUT,MM_Status:OUT)",
    "MM_Get_PlanData(Resource:IN,Jps_Pos:IN,Pos_Num:OUT,VisPos_Num:OUT,MM_Status:OUT)",
    "MM_Get_PlanJps(Serial:IN,Jps_Pos:IN,MM_J:OUT,MM_MoveType:OUT,MM_ToolNum:OUT,MM_Speed:OUT)",
    "MM_Get_PlanPose(Serial:IN,Jps_Pos:IN,MM_P:OUT,MM_MoveType:OUT,MM_ToolNum:OUT,MM_Speed:OUT)",
    "MM_Get_Property(Get_Id:IN,MM_Status:OUT,Viz_Prop:OUT)",
    "MM_Set_Property(Set_id:IN,MM_Status:OUT)",
    "MM_Set_BoxSize(Job:IN,Length:IN,Width:IN,Height:IN,MM_Status:OUT)",
    "MM_Get_Notify(MM_Notify:OUT,MM_Status:OUT)",
    "MM_CALIB(Move_Type:IN,PosJps:IN,WaitTime:IN,E1:IN)",
    "MM_Stop_Viz(MM_Status:OUT)",
    "MM_Get_Status(MM_Status:OUT)",
    "MM_Get_Wobj(Serial:IN,MM_Frame_num:IN,MM_Label:OUT,MM_ToolId:OUT)",
];

#[test]
fn every_subprogram_name_has_the_interface_prefix() {
    let cat = catalog();
    for s in cat.subprograms.iter().chain(&cat.subprograms_v2) {
        assert!(has_interface_prefix(&s.name), "{}", s.name);
    }
    assert!(has_interface_prefix("mm_start_vis"));
    assert!(!has_interface_prefix("MM"));
    assert!(!has_interface_prefix("MMX_Start"));
}

#[test]
fn every_v2_subprogram_is_present_with_its_signature() {
    let cat = catalog();
    let got: Vec<String> = cat
        .subprograms_of(Interface::V2)
        .iter()
        .map(Subprogram::signature)
        .collect();
    assert_eq!(got, V2_SIGNATURES);
    assert!(
        cat.subprograms_v2
            .iter()
            .all(|s| s.interface == Interface::V2)
    );
    assert!(cat.subprograms.iter().all(|s| s.interface == Interface::V1));
}

#[test]
fn the_v2_interface_differs_from_1x_as_documented() {
    let cat = catalog();
    let v2 = |n: &str| cat.subprogram_in(Interface::V2, n).unwrap();
    // No Last_Data anywhere, MM_Set_Pos is gone, the new routines exist.
    assert!(
        cat.subprograms_v2
            .iter()
            .all(|s| s.param("Last_Data").is_none())
    );
    assert!(cat.subprogram_in(Interface::V2, "MM_Set_Pos").is_none());
    for new in [
        "MM_Get_Property",
        "MM_Set_Property",
        "MM_Get_Notify",
        "MM_Stop_Viz",
        "MM_Get_Wobj",
    ] {
        assert!(cat.subprogram(new).is_none(), "{new} is 2.x only");
        v2(new);
    }
    // Every routine that sends a command reports a status, as an output or (MM_CALIB has none
    // in either version) in MM_Last_Status.
    for s in &cat.subprograms_v2 {
        if !s.commands.is_empty() {
            assert!(
                s.status_param().is_some() || s.name == "MM_CALIB",
                "{} sends without a status output",
                s.name
            );
        }
    }
    // The 8th field of a point: speed in 1.x, tool ID in 2.x.
    for code in [102, 105, 205] {
        let rec = |i| cat.command_in(i, code).unwrap().record[7].clone();
        assert_eq!(rec(Interface::V1), "speed");
        assert_eq!(rec(Interface::V2), "tool_id");
    }
    assert!(v2("MM_Get_Pose").param("MM_ToolId").is_some());
    // 502 is gone, 202 is new, 901 answers 9100.
    assert!(cat.command_in(Interface::V2, 502).is_none());
    assert!(cat.command_in(Interface::V1, 202).is_none());
    assert_eq!(
        cat.command_in(Interface::V1, 901).unwrap().success,
        Some(1101)
    );
    assert_eq!(
        cat.command_in(Interface::V2, 901).unwrap().success,
        Some(9100)
    );
    // Same code, different meaning.
    let meaning = |i, c| cat.status_in(i, c).unwrap().meaning.clone();
    assert_eq!(meaning(Interface::V1, 2006), "Collision detected");
    assert_eq!(meaning(Interface::V2, 2006), "Invalid start parameter");
    assert!(cat.status_in(Interface::V1, 9100).is_none());
    assert!(cat.status_in(Interface::V2, 2101).is_none());
    assert_eq!(cat.plan_results_len_in(Interface::V1), 20);
    assert_eq!(cat.plan_results_len_in(Interface::V2), 21);
    let plan = |i| {
        cat.globals_of(i)
            .find(|g| g.name == "MM_Plan_Results")
            .and_then(|g| g.size)
    };
    assert_eq!(plan(Interface::V1), Some(20));
    assert_eq!(plan(Interface::V2), Some(21));
}

#[test]
fn every_field_has_a_hex_kind_and_frames_are_sized_from_the_batch() {
    let cat = catalog();
    let mut used = std::collections::BTreeSet::new();
    for c in &cat.commands {
        for f in c.request.iter().chain(&c.reply).chain(&c.record) {
            assert!(
                cat.hex.kind(f).is_some(),
                "{}: field `{f}` has no HEX kind",
                c.code
            );
            used.insert(f.as_str());
        }
    }
    for f in cat.hex.float_fields.iter().chain(&cat.hex.int_fields) {
        assert!(used.contains(f.as_str()), "[hex] names unused field `{f}`");
        assert!(
            !(cat.hex.float_fields.contains(f) && cat.hex.int_fields.contains(f)),
            "`{f}` is both int32 and float32"
        );
    }
    // The settled layout: counts, labels, speed and tool are int32, poses float32.
    for f in ["status", "count", "label", "speed", "tool_id"] {
        assert_eq!(cat.hex.kind(f), Some(HexKind::Int32), "{f}");
    }
    for f in ["x", "c", "p1", "j6"] {
        assert_eq!(cat.hex.kind(f), Some(HexKind::Float32), "{f}");
    }
    assert_eq!(cat.hex_frame_bytes(20), 660);
    assert_eq!(cat.hex_frame_bytes(1), 660);
    assert_eq!(cat.hex_frame_bytes(30), 980);
    assert!(cat.hex_frame_bytes(cat.limits.batch_max) <= cat.limits.eki_raw_size_max);
    // The largest request (101 with joints and flange pose) fits the other brands' 64 bytes.
    assert_eq!(cat.hex.request_bytes, 4 * 16);
}

#[test]
fn every_seed_subprogram_is_present_with_its_signature() {
    let cat = catalog();
    assert_eq!(cat.subprograms.len(), SEED_SIGNATURES.len());
    for (sub, want) in cat.subprograms.iter().zip(SEED_SIGNATURES) {
        assert_eq!(&sub.signature(), want);
    }
}

/// The text of the seed whose file name starts with `prefix`, from the nearest `shared/seeds`
/// above the crate (the repository keeps `shared/` beside its checkouts, which may be nested).
pub(super) fn seed_text(prefix: &str) -> Option<String> {
    let crate_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = crate_dir
        .ancestors()
        .map(|a| a.join("shared/seeds"))
        .find(|d| d.is_dir())?;
    let entry = std::fs::read_dir(dir)
        .ok()?
        .filter_map(Result::ok)
        .find(|e| e.file_name().to_string_lossy().starts_with(prefix))?;
    std::fs::read_to_string(entry.path()).ok()
}

#[test]
fn the_seed_document_contains_every_signature() {
    // Guards the hand-typed list above against the seed itself, where the seed is at hand.
    let Some(text) = seed_text("000_") else {
        return;
    };
    for sig in SEED_SIGNATURES {
        assert!(text.contains(sig), "seed lacks {sig}");
    }
}

#[test]
fn names_are_unique_and_fit_krl_limits() {
    let cat = catalog();
    for iface in Interface::ALL {
        let subs = cat.subprograms_of(iface);
        let mut names: Vec<_> = subs.iter().map(|s| s.name.to_ascii_lowercase()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), subs.len());
        for s in subs {
            assert!(s.name.len() <= cat.limits.krl_identifier_max, "{}", s.name);
            for p in &s.params {
                assert!(p.ident().len() <= cat.limits.krl_identifier_max);
            }
        }
    }
}

#[test]
fn references_resolve() {
    let cat = catalog();
    for s in cat.subprograms.iter().chain(&cat.subprograms_v2) {
        let iface = s.interface;
        for c in &s.commands {
            let cmd = cat
                .command_in(iface, *c)
                .unwrap_or_else(|| panic!("{}: command {c}", s.name));
            // 601 answers without a status field (MM_Get_Notify in 2.x).
            if cmd.reply.first().is_some_and(|f| f == "status") {
                let ok = cmd
                    .success
                    .unwrap_or_else(|| panic!("{}: command {c} has no success code", s.name));
                assert!(cat.status_in(iface, ok).is_some_and(|st| st.ok), "{ok}");
            }
        }
        for other in s.after.iter().chain(&s.before) {
            assert!(
                cat.subprogram_in(iface, other).is_some(),
                "{}: {other}",
                s.name
            );
        }
        for p in &s.params {
            if let (Some(a), Some(b)) = (p.min, p.max) {
                assert!(a <= b, "{}.{}", s.name, p.name);
            }
            assert!(p.status == (p.dir == Direction::Out && p.name == "MM_Status"));
        }
        assert!(
            !(s.status_global && s.status_param().is_some()),
            "{} has both a status output and a global status",
            s.name
        );
    }
}

#[test]
fn status_codes_are_unique_and_package_codes_are_named() {
    let cat = catalog();
    for iface in Interface::ALL {
        let mut codes: Vec<u32> = cat.statuses_of(iface).map(|s| s.code).collect();
        codes.sort();
        let n = codes.len();
        codes.dedup();
        assert_eq!(codes.len(), n, "{iface}: codes must be unique");
        let mut names: Vec<&str> = cat
            .statuses_of(iface)
            .filter_map(|s| s.name.as_deref())
            .collect();
        let n = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), n, "{iface}: status names must be unique");
        let mut cmds: Vec<u32> = cat.commands_of(iface).map(|c| c.code).collect();
        let n = cmds.len();
        cmds.sort();
        cmds.dedup();
        assert_eq!(cmds.len(), n, "{iface}: one layout per command");
    }
    for s in &cat.statuses {
        assert!(
            s.origin != Origin::Package || (s.name.is_some() && s.interface.is_none()),
            "{}",
            s.code
        );
    }
    assert_eq!(cat.package_code("NO_CONNECTION"), 3099);
}

#[test]
fn ranges_read_well() {
    let cat = catalog();
    let start = cat.subprogram("mm_start_vis").unwrap();
    assert_eq!(start.param("Job").unwrap().range_text().unwrap(), "1 to 99");
    assert!(!start.param("Job").unwrap().in_range(120.0));
    let jps = cat.subprogram("MM_Get_PlanJps").unwrap();
    assert_eq!(
        jps.param("Jps_Pos").unwrap().range_text().unwrap(),
        "1 or 3"
    );
    assert!(!jps.param("Jps_Pos").unwrap().in_range(2.0));
    let boxsize = cat.subprogram("MM_Set_BoxSize").unwrap();
    assert!(!boxsize.param("Width").unwrap().in_range(0.0));
    assert_eq!(
        cat.nearest_subprogram("MM_Start_Viss").unwrap().name,
        "MM_Start_Vis"
    );
}

#[test]
fn a_routine_without_a_shape_does_not_load() {
    for (entry, shape) in [
        ("name = \"MM_Get_Pose\"\n", "shape = \"get_pose\"\n"),
        ("name = \"mm_get_pose\"\n", "shape = \"get_pose\"\n"),
    ] {
        let at = CATALOG_TOML.find(entry).expect("entry") + entry.len();
        assert!(CATALOG_TOML[at..].starts_with(shape), "{entry}");
        let without = format!(
            "{}{}",
            &CATALOG_TOML[..at],
            &CATALOG_TOML[at + shape.len()..]
        );
        let err = toml::from_str::<Catalog>(&without).expect_err("no shape");
        assert!(err.to_string().contains("missing field `shape`"), "{err}");
        let unknown = without.replacen(entry, &format!("{entry}shape = \"teleport\"\n"), 1);
        let err = toml::from_str::<Catalog>(&unknown).expect_err("unknown shape");
        assert!(
            err.to_string().contains("unknown variant `teleport`"),
            "{err}"
        );
    }
}

#[test]
fn only_calibration_moves_the_robot() {
    let moving: Vec<&str> = catalog()
        .subprograms
        .iter()
        .filter(|s| s.shape.moves())
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(moving, ["MM_CALIB"]);
}
