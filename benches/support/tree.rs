//! A synthetic controller tree shared by the check and lsp benchmarks: a `$config.dat` and cell
//! modules (`.src` with folds, motions, logic and `MM_` calls in interface order, `.dat` with
//! inline-form data) until the tree reaches the requested size.

use krlkit::lint::Input;

/// One cell module: a main routine with motions, logic, a local subroutine and `MM_` calls in
/// the order the interface expects, plus its `.dat`.
pub fn module(i: usize, points: usize) -> [Input; 2] {
    let mut src = format!(
        "&ACCESS RVP\r\n&REL 1\r\nDEF cell_{i}( )\r\n  DECL INT k, status, count\r\n  DECL BOOL done\r\n\
         ;FOLD INI;%{{PE}}\r\n  ;FOLD BASISTECH INI\r\n    GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )\r\n\
         \x20   INTERRUPT ON 3\r\n    BAS (#INITMOV,0 )\r\n  ;ENDFOLD (BASISTECH INI)\r\n;ENDFOLD (INI)\r\n\
         \x20 MM_Init_Socket(\"XML_Kuka_MMIND\",873,871,60)\r\n  done = FALSE\r\n"
    );
    for p in 0..points {
        src.push_str(&format!(
            ";FOLD PTP P{p} Vel=100 % PDAT{p} Tool[1] Base[0];%{{PE}}%R 8.3.31,%MKUKATPBASIS,%CMOVE,%VPTP,%P 1:PTP, 2:P{p}, 3:, 5:100, 7:PDAT{p}\r\n\
             $BWDSTART=FALSE\r\nPDAT_ACT=PPDAT{p}\r\nFDAT_ACT=FP{p}\r\nBAS(#PTP_PARAMS,100)\r\nPTP XP{p}\r\n;ENDFOLD\r\n"
        ));
    }
    src.push_str(
        "  WHILE NOT done\r\n    MM_Start_Vis(1,0,2,status)\r\n    IF status <> 1102 THEN\r\n      HALT\r\n    ENDIF\r\n\
         \x20   MM_Get_VisData(1,count,status)\r\n    FOR k = 1 TO count STEP 1\r\n      pick_one(k)\r\n    ENDFOR\r\n\
         \x20   SWITCH count\r\n    CASE 0\r\n      done = TRUE\r\n    DEFAULT\r\n      WAIT SEC 0.2\r\n    ENDSWITCH\r\n  ENDWHILE\r\nEND\r\n\r\n\
         DEF pick_one(n:IN)\r\n  DECL INT n\r\n  LIN_REL {Z 50.0} C_DIS #TOOL\r\n  $OUT[n] = TRUE\r\n  WAIT FOR $IN[n] OR $TIMER_FLAG[1]\r\nEND\r\n",
    );
    let mut dat = format!("&ACCESS RVP\r\nDEFDAT cell_{i}\r\n");
    for p in 0..points {
        dat.push_str(&format!(
            "DECL E6POS XP{p}={{X 1064.2,Y -18.7,Z 1276.5,A 12.5,B 45.0,C -170.1,S 6,T 27,E1 0.0,E2 0.0,E3 0.0,E4 0.0,E5 0.0,E6 0.0}}\r\n\
             DECL FDAT FP{p}={{TOOL_NO 1,BASE_NO 0,IPO_FRAME #BASE,POINT2[] \" \",TQ_STATE FALSE}}\r\n\
             DECL PDAT PPDAT{p}={{VEL 100.000,ACC 100.000,APO_DIST 100.000,APO_MODE #CDIS}}\r\n"
        ));
    }
    dat.push_str("ENDDAT\r\n");
    [
        Input {
            path: format!("R1/Program/cell_{i}.src"),
            text: src,
        },
        Input {
            path: format!("R1/Program/cell_{i}.dat"),
            text: dat,
        },
    ]
}

pub fn tree(bytes: usize) -> Vec<Input> {
    tree_with(bytes, 12)
}

/// [`tree`] with `points` taught points per module (12: about 3 KB per file; 40: about 8 KB).
pub fn tree_with(bytes: usize, points: usize) -> Vec<Input> {
    let mut config = String::from("DEFDAT  $CONFIG\r\n");
    for g in 0..500 {
        config.push_str(&format!("DECL GLOBAL INT cell_counter_{g}=0\r\n"));
    }
    config.push_str("ENDDAT\r\n");
    let mut inputs = vec![Input {
        path: "R1/System/$config.dat".into(),
        text: config,
    }];
    let mut total = 0;
    let mut i = 0;
    while total < bytes {
        for input in module(i, points) {
            total += input.text.len();
            inputs.push(input);
        }
        i += 1;
    }
    inputs
}
