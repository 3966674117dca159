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
    let mut names: Vec<_> = cat
        .subprograms
        .iter()
        .map(|s| s.name.to_ascii_lowercase())
        .collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), cat.subprograms.len());
    for s in &cat.subprograms {
        assert!(s.name.len() <= cat.limits.krl_identifier_max, "{}", s.name);
        for p in &s.params {
            assert!(p.ident().len() <= cat.limits.krl_identifier_max);
        }
    }
}

#[test]
fn references_resolve() {
    let cat = catalog();
    for s in &cat.subprograms {
        for c in &s.commands {
            let cmd = cat
                .command(*c)
                .unwrap_or_else(|| panic!("{}: command {c}", s.name));
            let ok = cmd
                .success
                .unwrap_or_else(|| panic!("{}: command {c} has no success code", s.name));
            assert!(cat.status(ok).is_some_and(|st| st.ok));
        }
        for other in s.after.iter().chain(&s.before) {
            assert!(cat.subprogram(other).is_some(), "{}: {other}", s.name);
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
    let mut codes: Vec<u32> = cat.statuses.iter().map(|s| s.code).collect();
    codes.sort();
    let n = codes.len();
    codes.dedup();
    assert_eq!(codes.len(), n);
    let mut names: Vec<&str> = cat
        .statuses
        .iter()
        .filter_map(|s| s.name.as_deref())
        .collect();
    for s in &cat.statuses {
        assert!(
            s.origin != Origin::Package || s.name.is_some(),
            "{}",
            s.code
        );
    }
    let n = names.len();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), n, "status names must be unique");
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
