//! Scopes in KRL's lookup order: routine → module → GLOBAL/PUBLIC → `$config.dat` → system.

use super::ids::{ModuleId, RobotId, RoutineId};

/// Where a declaration lives (and so where it is visible).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scope {
    /// The KSS environment (`kss.toml`) and the system data lists (`$machine.dat`, `$custom.dat`
    /// … : DEFDATs whose name starts with `$`, other than `$config`).
    System,
    /// `$config.dat`: every declaration in it is visible everywhere, GLOBAL or not.
    Config(RobotId),
    /// `GLOBAL` declarations and routines, and the variables of PUBLIC DEFDATs declared GLOBAL.
    Global(RobotId),
    /// The module's `.dat` and its routines (a module's main routine is also callable from
    /// every module of the robot).
    Module(ModuleId),
    /// Parameters and declarations of one routine.
    Routine(RoutineId),
}
