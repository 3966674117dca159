//! The constants a position sees, with their numeric values (for rules that reason about
//! values, such as loop bounds and array sizes).

use super::scope::Scope;
use super::{ConstValue, Position, Sema, SymbolId, SymbolKind};

impl Sema {
    /// Every constant with a numeric literal value visible at `at`: the routine's own (when
    /// `at` is in one), its module's `.dat`, the robot's GLOBAL ones and `$config.dat`; not
    /// the system's. In symbol order.
    pub fn visible_constants(&self, at: Position) -> Vec<(SymbolId, f64)> {
        self.symbols()
            .filter(|(_, s)| match s.scope {
                Scope::Routine(r) => at.routine == Some(r),
                Scope::Module(m) => m == at.module,
                Scope::Global(r) | Scope::Config(r) => r == at.robot,
                Scope::System => false,
            })
            .filter(|(_, s)| s.kind == SymbolKind::Constant)
            .filter_map(|(id, s)| Some((id, s.value.as_ref().and_then(ConstValue::as_f64)?)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::analysis;

    #[test]
    fn constants_of_the_module_the_robot_and_config_not_another_module() {
        let a = analysis(&[
            (
                "R1/System/$config.dat",
                "DEFDAT $CONFIG\nDECL CONST INT cfg_n = 3\nENDDAT\n",
            ),
            ("R1/Program/cell.src", "DEF cell()\nEND\n"),
            (
                "R1/Program/cell.dat",
                "DEFDAT cell PUBLIC\nDECL CONST INT mine = 4\nDECL GLOBAL CONST REAL g = 2.5\n\
                     DECL CONST CHAR c = \"x\"\nENDDAT\n",
            ),
            (
                "R1/Program/other.dat",
                "DEFDAT other\nDECL CONST INT theirs = 5\nENDDAT\n",
            ),
        ]);
        let f = a.sema.file_id("R1/Program/cell.src").expect("file");
        let at = a.sema.position(f, 0);
        let mut got: Vec<(String, f64)> = a
            .sema
            .visible_constants(at)
            .into_iter()
            .map(|(s, v)| (a.sema.name(a.sema.symbol(s).name).to_string(), v))
            .collect();
        got.sort_by(|x, y| x.0.cmp(&y.0));
        assert_eq!(
            got,
            [
                ("cfg_n".to_string(), 3.0),
                ("g".into(), 2.5),
                ("mine".into(), 4.0)
            ]
        );
    }
}
