//! The constants a position sees, with their numeric values (for rules that reason about
//! values, such as loop bounds and array sizes).

use rustc_hash::FxHashMap;

use super::scope::Scope;
use super::{ConstValue, ModuleId, Position, RobotId, RoutineId, Sema, SymbolId, SymbolKind};

/// The constants with a numeric literal value, by the scope that declares them: one pass over
/// the symbols, so a query costs what it returns (a scan of every symbol per file was
/// quadratic in a workspace of many files).
#[derive(Debug, Default)]
pub(crate) struct ConstIndex {
    routine: FxHashMap<RoutineId, Vec<(SymbolId, f64)>>,
    module: FxHashMap<ModuleId, Vec<(SymbolId, f64)>>,
    /// GLOBAL ones and `$config.dat`'s.
    robot: FxHashMap<RobotId, Vec<(SymbolId, f64)>>,
}

impl ConstIndex {
    fn of(sema: &Sema) -> ConstIndex {
        let mut c = ConstIndex::default();
        for (id, s) in sema.symbols() {
            if s.kind != SymbolKind::Constant {
                continue;
            }
            let Some(v) = sema.symbol_value(id).and_then(ConstValue::as_f64) else {
                continue;
            };
            match s.scope {
                Scope::Routine(r) => c.routine.entry(r).or_default().push((id, v)),
                Scope::Module(m) => c.module.entry(m).or_default().push((id, v)),
                Scope::Global(r) | Scope::Config(r) => c.robot.entry(r).or_default().push((id, v)),
                Scope::System => {}
            }
        }
        c
    }
}

impl Sema {
    /// Every constant with a numeric literal value visible at `at`: the routine's own (when
    /// `at` is in one), its module's `.dat`, the robot's GLOBAL ones and `$config.dat`; not
    /// the system's. In symbol order.
    pub fn visible_constants(&self, at: Position) -> Vec<(SymbolId, f64)> {
        let c = self.consts.get_or_init(|| ConstIndex::of(self));
        let routine = at.routine.and_then(|r| c.routine.get(&r));
        let mut all: Vec<(SymbolId, f64)> = routine
            .into_iter()
            .chain(c.module.get(&at.module))
            .chain(c.robot.get(&at.robot))
            .flatten()
            .copied()
            .collect();
        all.sort_unstable_by_key(|(id, _)| *id);
        all
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
