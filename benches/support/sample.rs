//! Shared by the parse and fmt benchmarks: a realistic synthetic controller file and a CPU clock.

/// A typical mix: headers, folds with inline-form metadata, motions, logic, DAT aggregates.
/// Compared with a corpus of 993 real controller files it has about the same bytes per line
/// (38.7 against 37.9), more DAT aggregate bytes (44% against 19%), fewer assignments, and about
/// seven times their share of `INTERRUPT DECL` and motion-with-`WITH` lines; both measure alike.
pub fn synthetic(routines: usize) -> String {
    let mut s = String::from("&ACCESS RVP\r\n&REL 3\r\n&PARAM EDITMASK = *\r\n");
    for r in 0..routines {
        s.push_str(&format!(
            "GLOBAL DEF cell_{r}(count:IN, done:OUT)\r\n  DECL INT i, count\r\n  DECL BOOL done\r\n"
        ));
        s.push_str(";FOLD INI;%{PE}\r\n  ;FOLD BASISTECH INI\r\n    GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )\r\n    INTERRUPT ON 3\r\n    BAS (#INITMOV,0 )\r\n  ;ENDFOLD (BASISTECH INI)\r\n;ENDFOLD (INI)\r\n\r\n");
        for p in 0..4 {
            s.push_str(&format!(";FOLD PTP P{p} Vel=100 % PDAT{p} Tool[1] Base[0];%{{PE}}%R 8.3.31,%MKUKATPBASIS,%CMOVE,%VPTP,%P 1:PTP, 2:P{p}, 3:, 5:100, 7:PDAT{p}\r\n$BWDSTART=FALSE\r\nPDAT_ACT=PPDAT{p}\r\nFDAT_ACT=FP{p}\r\nBAS(#PTP_PARAMS,100)\r\nPTP XP{p} \r\n;ENDFOLD\r\n"));
        }
        s.push_str("  FOR i = 1 TO count STEP 1\r\n    IF $IN[i] AND NOT done THEN\r\n      $OUT[i] = TRUE ; set output\r\n      LIN_REL {Z -10.5} C_DIS #TOOL\r\n    ELSE\r\n      WAIT FOR $IN[i+1] OR $TIMER_FLAG[1]\r\n    ENDIF\r\n  ENDFOR\r\n");
        s.push_str("  SWITCH count\r\n  CASE 1, 2\r\n    SLIN XP1 WITH $VEL = SVEL_CP(2.0, , LCPDAT1), $TOOL = STOOL2(FP1) C_SPL\r\n  DEFAULT\r\n    WAIT SEC 0.2\r\n  ENDSWITCH\r\n  done = TRUE\r\nEND\r\n\r\n");
    }
    s.push_str("DEFDAT bench PUBLIC\r\n");
    for p in 0..routines * 4 {
        s.push_str(&format!("DECL E6POS XP{p}={{X 1064.2,Y -18.7,Z 1276.5,A 12.5,B 45.0,C -170.1,S 6,T 27,E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}}\r\n"));
        s.push_str(&format!("DECL FDAT FP{p}={{TOOL_NO 1,BASE_NO 0,IPO_FRAME #BASE,POINT2[] \" \",TQ_STATE FALSE}}\r\n"));
        s.push_str(&format!(
            "DECL PDAT PPDAT{p}={{VEL 100.000,ACC 100.000,APO_DIST 100.000,APO_MODE #CDIS}}\r\n"
        ));
    }
    s.push_str("ENDDAT\r\n");
    s
}

/// On-CPU nanoseconds of this thread (Linux `schedstat`), so a loaded machine does not skew the
/// figure the way wall time does.
pub fn cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}
