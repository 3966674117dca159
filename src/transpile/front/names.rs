//! Deterministic renaming of KRL identifiers for a target's naming rules.
//!
//! The target name of a KRL name is a pure function of the name (lower case, invalid characters
//! replaced, reserved words suffixed, long names cut and given a short hash of the full name),
//! so the same KRL name becomes the same target name in every file. Only when two different
//! names of one namespace would still meet does the later one (in source order) get a counter.
//!
//! [`Namer`] names everything of one translation (routines, globals, each routine's parameters,
//! locals and labels) and records the renames (TR003 and the output's name map); the targets
//! differ only in their [`NameRules`], which are data.

use compact_str::CompactString;
use rustc_hash::{FxHashMap, FxHashSet};

use crate::diag::Span;
use crate::transpile::front::report::{FileId, Report};
use crate::transpile::ir::{self, RoutineId, Scope, VarId};

/// A target language's identifier rules.
#[derive(Debug, Clone, Copy)]
pub struct NameRules {
    /// Longest allowed name (without sigils or scope markers).
    pub max_len: usize,
    /// Whether a lower-case name is a reserved word of the target.
    pub is_reserved: fn(&str) -> bool,
    /// The language's name in findings and the name map (`AS`, `Python`).
    pub language: &'static str,
    /// What a routine is called in the target (`program`, `routine`).
    pub routine: &'static str,
    /// Routines and globals share one namespace (a Python module); otherwise each has its own.
    pub routines_with_globals: bool,
    /// Globals of the generated KUKA package → the target's spelling of them.
    pub package: &'static [(&'static str, &'static str)],
}

/// Why a name had to change.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Reason {
    /// Longer than the target allows.
    TooLong,
    /// A reserved word of the target.
    Reserved,
    /// Characters the target does not allow in names.
    Chars,
    /// Another name already maps to the same target name.
    Clash,
}

impl Reason {
    pub fn describe(self, rules: &NameRules) -> String {
        let mut s = String::new();
        self.describe_into(rules, &mut s);
        s
    }

    /// [`Reason::describe`] appended to `out`.
    fn describe_into(self, rules: &NameRules, out: &mut String) {
        match self {
            Reason::TooLong => {
                // Writing to a `String` does not fail.
                let _ = std::fmt::Write::write_fmt(
                    out,
                    format_args!("longer than {} characters", rules.max_len),
                );
            }
            Reason::Reserved => out.push_str("a reserved word"),
            Reason::Chars => out.push_str("characters not allowed in names"),
            Reason::Clash => out.push_str("clashes with another name"),
        }
    }
}

/// The target spelling of `krl` under `rules`, and why it differs (beyond case).
pub fn target_name(krl: &str, rules: &NameRules) -> (String, Vec<Reason>) {
    let (name, reasons) = spelled(krl, rules);
    (name.into_string(), reasons)
}

/// [`target_name`] inline (a name of up to 24 bytes is no allocation).
fn spelled(krl: &str, rules: &NameRules) -> (CompactString, Vec<Reason>) {
    let mut reasons = Vec::new();
    // Every character becomes one ASCII byte: the name is ASCII, cut anywhere.
    let mut name = CompactString::with_capacity(krl.len() + 1);
    let mut replaced = false;
    for c in krl.chars() {
        if c.is_ascii_alphanumeric() || c == '_' {
            name.push(c.to_ascii_lowercase());
        } else {
            name.push('_');
            replaced = true;
        }
    }
    if replaced {
        reasons.push(Reason::Chars);
    }
    if !name.starts_with(|c: char| c.is_ascii_alphabetic()) {
        name.insert(0, 'x');
        if !reasons.contains(&Reason::Chars) {
            reasons.push(Reason::Chars);
        }
    }
    if (rules.is_reserved)(&name) {
        name.push('_');
        reasons.push(Reason::Reserved);
    }
    if name.len() > rules.max_len {
        // The kept start without its trailing `_`s, `_`, the hash: in place.
        let keep = rules.max_len.saturating_sub(4);
        let cut = name[..keep].trim_end_matches('_').len();
        name.truncate(cut);
        name.push('_');
        name.extend(hash3(krl).map(char::from));
        reasons.push(Reason::TooLong);
    }
    (name, reasons)
}

/// Three base-36 characters of FNV-1a over `s` in upper case (ASCII letters only, as
/// `str::to_ascii_uppercase`).
fn hash3(s: &str) -> [u8; 3] {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in s.bytes() {
        h ^= u64::from(b.to_ascii_uppercase());
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    const DIGITS: &[u8; 36] = b"0123456789abcdefghijklmnopqrstuvwxyz";
    [0, 1, 2].map(|i| DIGITS[((h >> (i * 12)) % 36) as usize])
}

/// A renamed identifier, for the TR003 diagnostic and the name map.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Renamed {
    pub krl: CompactString,
    pub target: CompactString,
    pub reasons: Vec<Reason>,
}

/// One namespace of the target (e.g. programs, globals, one program's locals or labels).
#[derive(Debug, Default, Clone)]
pub struct Namespace {
    /// Upper-case KRL name → target name (names fit inline: no allocation per name).
    map: FxHashMap<CompactString, CompactString>,
    /// Target name → upper-case KRL name (or "" for names the translator made up).
    taken: FxHashMap<CompactString, CompactString>,
    /// (kept prefix, digits of the counter) → the counter [`Namespace::free_variant`] tries
    /// first: every smaller one of as many digits makes a taken name (names are never given
    /// back), so the thousands of cut names that share a prefix are not searched from 2 each
    /// time (that made a file of many long names quadratic).
    next_counter: FxHashMap<(String, usize), usize>,
}

impl Namespace {
    /// The target name of `krl`. `Some(renamed)` the first time a name is seen and had to
    /// change beyond case.
    pub fn name(&mut self, krl: &str, rules: &NameRules) -> (CompactString, Option<Renamed>) {
        self.name_spelled(krl, rules, None)
    }

    /// [`Namespace::name`], the target spelling of a name not seen in this namespace taken
    /// from `spellings` when given (the same as [`target_name`] gives).
    fn name_spelled(
        &mut self,
        krl: &str,
        rules: &NameRules,
        spellings: Option<&mut Spellings>,
    ) -> (CompactString, Option<Renamed>) {
        let mut key = CompactString::from(krl);
        key.make_ascii_uppercase();
        // Names fit inline: a name asked again costs no allocation.
        if let Some(t) = self.map.get(&key) {
            return (t.clone(), None);
        }
        let (mut target, mut reasons) = match spellings {
            Some(s) => s.spell(&key, rules),
            None => spelled(krl, rules),
        };
        if self.taken.get(&target).is_some_and(|k| *k != key) {
            target = self.free_variant(&target, rules.max_len).into();
            reasons.push(Reason::Clash);
        }
        self.taken.insert(target.clone(), key.clone());
        self.map.insert(key, target.clone());
        let renamed = (!reasons.is_empty()).then(|| Renamed {
            krl: krl.into(),
            target: target.clone(),
            reasons,
        });
        (target, renamed)
    }

    /// Room for `n` more names.
    fn reserve(&mut self, n: usize) {
        self.map.reserve(n);
        self.taken.reserve(n);
    }

    /// The namespace with no name, its maps kept for reuse when they are small (emptying a
    /// large one costs its capacity again for every small routine after it).
    fn emptied(mut self) -> Option<Namespace> {
        if self.map.capacity() > 256 || self.taken.capacity() > 256 {
            return None;
        }
        self.map.clear();
        self.taken.clear();
        self.next_counter.clear();
        Some(self)
    }

    /// The target name already assigned to `krl`, if any.
    pub fn get(&self, krl: &str) -> Option<&str> {
        let mut key = CompactString::from(krl);
        key.make_ascii_uppercase();
        self.map.get(&key).map(CompactString::as_str)
    }

    /// A name the translator needs (`base`, else `base2`, `base3`, …) that no KRL name uses.
    pub fn fresh(&mut self, base: &str, max_len: usize) -> String {
        let base = &base[..base.len().min(max_len)];
        let name = if self.taken.contains_key(base) {
            self.free_variant(base, max_len)
        } else {
            base.to_owned()
        };
        self.taken
            .insert(CompactString::from(&name), CompactString::default());
        name
    }

    /// `base` with the smallest counter from 2 on whose name is free, the base cut so the name
    /// fits `max_len`.
    fn free_variant(&mut self, base: &str, max_len: usize) -> String {
        let mut n = 2usize;
        loop {
            let digits = n.to_string().len();
            let keep = max_len.saturating_sub(digits).min(base.len());
            let key = (base[..keep].to_owned(), digits);
            let end = 10usize.saturating_pow(digits as u32);
            let from = self.next_counter.get(&key).map_or(n, |&c| c.max(n));
            let free = (from..end)
                .map(|m| (m, format!("{}{m}", key.0)))
                .find(|(_, name)| !self.taken.contains_key(name.as_str()));
            match free {
                Some((m, name)) => {
                    // The caller takes the name.
                    self.next_counter.insert(key, m + 1);
                    return name;
                }
                None if end == usize::MAX => return String::new(),
                None => {
                    self.next_counter.insert(key, end);
                    n = end;
                }
            }
        }
    }
}

/// The target spellings of names asked before ([`target_name`] of the upper-case name: it is
/// a pure function of the name, and case changes nothing of it). Every routine's locals are
/// named again in a namespace of their own, mostly the same few names in thousands of
/// routines: each is spelled once. Emptied when it holds [`Spellings::MAX`] names, so a
/// program of ever new names keeps no more.
#[derive(Debug, Default)]
struct Spellings {
    map: FxHashMap<CompactString, (CompactString, Vec<Reason>)>,
}

impl Spellings {
    const MAX: usize = 4096;

    /// [`target_name`] of `key`, an upper-case name.
    fn spell(&mut self, key: &CompactString, rules: &NameRules) -> (CompactString, Vec<Reason>) {
        if let Some((t, r)) = self.map.get(key) {
            return (t.clone(), r.clone());
        }
        if self.map.len() >= Self::MAX {
            self.map.clear();
        }
        let spelled = spelled(key, rules);
        self.map.insert(key.clone(), spelled.clone());
        spelled
    }
}

/// The target's spelling of a global of the KUKA package, if it has one.
pub fn package_name(rules: &NameRules, krl: &str) -> Option<&'static str> {
    let found = rules
        .package
        .iter()
        .find(|(k, _)| k.eq_ignore_ascii_case(krl));
    found.map(|(_, t)| *t)
}

/// Where a named variable lives in the target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Home {
    /// A parameter or local of its routine.
    Local,
    /// A global of the translation (module level).
    Global,
    /// A global of the target's Mech-Mind package, spelled by [`NameRules::package`].
    Package,
}

/// A rename kept for the name map: what kind of name, the KRL name, the target name (inline:
/// a file of many routines renames a hundred thousand names).
type MapEntry = (&'static str, CompactString, CompactString);

/// A TR003 for a name that had to change, recorded for the name map too.
fn note(
    renamed: &mut Vec<MapEntry>,
    rules: &NameRules,
    rep: &mut Report,
    kind: &'static str,
    file: FileId,
    span: Span,
    r: Option<Renamed>,
) {
    let Some(r) = r else { return };
    // `{kind} `{krl}` is renamed `{target}` in {language} ({reasons joined by ", "})`, written
    // in place (a file of many routines renames a hundred thousand names).
    let mut message = String::with_capacity(96);
    for part in [kind, " `", &r.krl, "` is renamed `", &r.target, "` in "] {
        message.push_str(part);
    }
    message.push_str(rules.language);
    message.push_str(" (");
    for (i, x) in r.reasons.iter().enumerate() {
        if i > 0 {
            message.push_str(", ");
        }
        x.describe_into(rules, &mut message);
    }
    message.push(')');
    rep.renamed(file, span, message);
    renamed.push((kind, r.krl, r.target));
}

/// The names of one translation under one target's rules.
pub struct Namer<'a> {
    rules: &'static NameRules,
    ir: &'a ir::Program,
    routines: Namespace,
    /// Each routine's target name by id, as [`Namer::declare_program`] gave it (`None`: not
    /// named there, a synthetic routine): a routine is named at its `DEF` and every call, and a
    /// probe of a map of every routine's name missed the cache ever more often.
    routine_names: Vec<Option<CompactString>>,
    globals: Namespace,
    /// The namespaces of the routine being rendered (and of any other asked about since it
    /// began): a routine's are dropped when the next one is declared, so a file of many
    /// routines keeps one routine's names, not all of them ([`Namer::declare_locals`]).
    locals: FxHashMap<RoutineId, Namespace>,
    labels: FxHashMap<RoutineId, Namespace>,
    /// The routine whose locals were declared last.
    current: Option<RoutineId>,
    /// `current` when its names were made without its namespace (none clashed: nearly every
    /// routine), which is made, the same way, only when asked for ([`Namer::declare_locals`]).
    unmade: Option<RoutineId>,
    /// An ended routine's namespace, emptied, for the next one made.
    spare: Option<Namespace>,
    /// The upper-case names of `current`'s variables while they are declared.
    keys: Vec<CompactString>,
    /// The target names of `current`'s parameters and locals, in its `vars_of` order: a
    /// variable is named at every use, and these are asked most.
    current_names: Vec<CompactString>,
    /// Routines whose namespaces were dropped, one bit each by id: asked again, they are made
    /// again the same way. (A set of ids grew with every routine, its lookups missing the
    /// cache ever more often.)
    ended: Vec<u64>,
    /// Locals' spellings, made once for every routine that declares the same name.
    spellings: Spellings,
    /// Each routine's parameters and locals, in declaration order.
    vars_of: super::grouped::Grouped<VarId>,
    /// Every rename, in the order found, with what kind of name it is.
    renamed: Vec<MapEntry>,
}

impl<'a> Namer<'a> {
    pub fn new(rules: &'static NameRules, ir: &'a ir::Program) -> Namer<'a> {
        let vars_of =
            super::grouped::Grouped::new(ir.vars.iter().enumerate().filter_map(|(i, v)| {
                match v.scope {
                    Scope::Param(r) | Scope::Local(r) => Some((r.0 as usize, VarId(i as u32))),
                    _ => None,
                }
            }));
        Namer {
            rules,
            ir,
            routines: Namespace::default(),
            routine_names: Vec::new(),
            globals: Namespace::default(),
            locals: FxHashMap::default(),
            labels: FxHashMap::default(),
            current: None,
            unmade: None,
            spare: None,
            keys: Vec::new(),
            current_names: Vec::new(),
            ended: Vec::new(),
            spellings: Spellings::default(),
            vars_of,
            renamed: Vec::new(),
        }
    }

    pub fn rules(&self) -> &'static NameRules {
        self.rules
    }

    fn globals_ns(&mut self) -> &mut Namespace {
        if self.rules.routines_with_globals {
            &mut self.routines
        } else {
            &mut self.globals
        }
    }

    /// A TR003 for a name that had to change (`kind`: `variable`, `label` …).
    fn note(
        &mut self,
        rep: &mut Report,
        kind: &'static str,
        file: FileId,
        span: Span,
        r: Option<Renamed>,
    ) {
        note(&mut self.renamed, self.rules, rep, kind, file, span, r);
    }

    /// The target name of a routine (of this file or of another module).
    pub fn routine(&mut self, rep: &mut Report, krl: &str, span: Span) -> String {
        let (name, r) = self.routines.name(krl, self.rules);
        self.note(rep, self.rules.routine, FileId::Src, span, r);
        name.into()
    }

    /// The target name given to a routine before.
    pub fn routine_of(&self, krl: &str) -> Option<&str> {
        self.routines.get(krl)
    }

    /// [`Namer::routine_of`] the name of routine `id` of the program (a routine's name never
    /// changes once given: the one [`Namer::declare_program`] kept, else a lookup).
    pub fn routine_of_id(&self, id: RoutineId) -> Option<&str> {
        match self.routine_names.get(id.0 as usize) {
            Some(Some(n)) => Some(n.as_str()),
            _ => self.routine_of(&self.ir.routine(id).name),
        }
    }

    /// Names what the program declares before anything is rendered — its routines, then its
    /// globals, in declaration order — so TR003 points at declarations and names made up later
    /// never take a user's.
    pub fn declare_program(&mut self, rep: &mut Report) {
        let ir = self.ir;
        // Every routine is named here: the maps are grown once, not doubled again and again.
        self.routines.reserve(ir.routines.len());
        self.routine_names.reserve_exact(ir.routines.len());
        for r in &ir.routines {
            let name = (!r.synthetic).then(|| {
                let (name, renamed) = self.routines.name(&r.name, self.rules);
                self.note(rep, self.rules.routine, FileId::Src, r.name_span, renamed);
                name
            });
            self.routine_names.push(name);
        }
        self.declare_globals(rep);
    }

    /// Names the globals in declaration order, so TR003 points at their declarations.
    pub fn declare_globals(&mut self, rep: &mut Report) {
        let (ir, rules) = (self.ir, self.rules);
        for v in &ir.vars {
            if v.scope == Scope::Global {
                let (_, r) = self.globals_ns().name(&v.name, rules);
                self.note(rep, "variable", v.file, v.decl, r);
            }
        }
    }

    /// Names the parameters and locals of `id` (parameters, then declarations), so TR003
    /// points at their declarations and made-up names never take a user's. The routine
    /// declared before ends here: its namespaces are dropped (renderers render one routine
    /// after another).
    pub fn declare_locals(&mut self, rep: &mut Report, id: RoutineId) {
        if let Some(prev) = self.current.replace(id)
            && prev != id
        {
            // The ended routine's maps, emptied, serve the next (one allocation per routine
            // less).
            if let Some(ns) = self.locals.remove(&prev).and_then(Namespace::emptied) {
                self.spare = Some(ns);
            }
            if self.unmade == Some(prev) {
                self.unmade = None;
            }
            self.labels.remove(&prev);
            self.end(prev);
        }
        // A routine no name was asked of yet whose names do not meet: named without a
        // namespace (a map of its names and one of the target names, five probes a name).
        if self.unmade != Some(id) && !self.locals.contains_key(&id) && self.declare_apart(rep, id)
        {
            self.unmade = Some(id);
            return;
        }
        self.make_unmade(id);
        let ir = self.ir;
        let vars = self.vars_of.get(id.0 as usize);
        let spare = &mut self.spare;
        let ns = self
            .locals
            .entry(id)
            .or_insert_with(|| spare.take().unwrap_or_default());
        self.current_names.clear();
        for &v in vars {
            let var = ir.var(v);
            let (n, r) = ns.name_spelled(&var.name, self.rules, Some(&mut self.spellings));
            self.current_names.push(n);
            note(
                &mut self.renamed,
                self.rules,
                rep,
                "variable",
                var.file,
                var.decl,
                r,
            );
        }
    }

    /// [`Namer::declare_locals`] of a routine without a namespace yet, when no two of its
    /// variables have the same name or target name (what a namespace would find: then nothing
    /// is named and it is false). The names and findings are those of a new namespace.
    fn declare_apart(&mut self, rep: &mut Report, id: RoutineId) -> bool {
        /// More variables than this are named in a namespace (the search here is linear).
        const MANY: usize = 32;
        let (ir, rules) = (self.ir, self.rules);
        let vars = self.vars_of.get(id.0 as usize);
        if vars.len() > MANY {
            return false;
        }
        self.keys.clear();
        self.current_names.clear();
        let mut renamed = Vec::new();
        for (i, &v) in vars.iter().enumerate() {
            let mut key = CompactString::from(ir.var(v).name.as_str());
            key.make_ascii_uppercase();
            if self.keys.contains(&key) {
                return false;
            }
            let (target, reasons) = self.spellings.spell(&key, rules);
            if self.current_names.contains(&target) {
                return false;
            }
            self.keys.push(key);
            self.current_names.push(target);
            if !reasons.is_empty() {
                renamed.push((i, reasons));
            }
        }
        for (i, reasons) in renamed {
            let var = ir.var(vars[i]);
            let r = Renamed {
                krl: var.name.clone(),
                target: self.current_names[i].clone(),
                reasons,
            };
            note(
                &mut self.renamed,
                rules,
                rep,
                "variable",
                var.file,
                var.decl,
                Some(r),
            );
        }
        true
    }

    /// The namespace of `id` when its names were made without it ([`Namer::declare_apart`]):
    /// made now as a namespace makes them (no finding again) — from the names made, each new
    /// and none clashing (RAPID asks for its temporaries' names in most routines).
    fn make_unmade(&mut self, id: RoutineId) {
        if self.unmade != Some(id) {
            return;
        }
        self.unmade = None;
        let mut ns = self.spare.take().unwrap_or_default();
        let vars = self.vars_of.get(id.0 as usize);
        if self.current == Some(id)
            && self.keys.len() == vars.len()
            && self.current_names.len() == vars.len()
        {
            ns.reserve(vars.len());
            for (key, target) in self.keys.iter().zip(&self.current_names) {
                ns.taken.insert(target.clone(), key.clone());
                ns.map.insert(key.clone(), target.clone());
            }
        } else {
            for &v in vars {
                ns.name_spelled(&self.ir.var(v).name, self.rules, Some(&mut self.spellings));
            }
        }
        self.locals.insert(id, ns);
    }

    /// Names the labels of `id` in source order.
    pub fn declare_labels(&mut self, rep: &mut Report, id: RoutineId) {
        let (ir, rules) = (self.ir, self.rules);
        for (krl, span) in &ir.routine(id).labels {
            let (_, r) = self.labels_ns(id).name(krl, rules);
            self.note(rep, "label", FileId::Src, *span, r);
        }
    }

    /// Whether `id`'s namespaces were dropped ([`Namer::declare_locals`]).
    fn has_ended(&self, id: RoutineId) -> bool {
        let i = id.0 as usize;
        self.ended
            .get(i / 64)
            .is_some_and(|w| w & (1 << (i % 64)) != 0)
    }

    /// `id`'s namespaces were dropped.
    fn end(&mut self, id: RoutineId) {
        let i = id.0 as usize;
        if self.ended.len() <= i / 64 {
            self.ended.resize(i / 64 + 1, 0);
        }
        self.ended[i / 64] |= 1 << (i % 64);
    }

    /// The locals' namespace of `id`; one of a routine that ended is made again as its
    /// [`Namer::declare_locals`] made it (same names, findings not repeated).
    fn locals_ns(&mut self, id: RoutineId) -> &mut Namespace {
        self.remake_locals(id);
        self.locals.entry(id).or_default()
    }

    /// Makes the locals' namespace of an ended routine again (see [`Namer::locals_ns`]).
    fn remake_locals(&mut self, id: RoutineId) {
        self.make_unmade(id);
        if !self.locals.contains_key(&id) && self.has_ended(id) {
            let mut ns = Namespace::default();
            for &v in self.vars_of.get(id.0 as usize) {
                ns.name_spelled(&self.ir.var(v).name, self.rules, Some(&mut self.spellings));
            }
            self.locals.insert(id, ns);
        }
    }

    /// The labels' namespace of `id`, made again for a routine that ended.
    fn labels_ns(&mut self, id: RoutineId) -> &mut Namespace {
        if !self.labels.contains_key(&id) && self.has_ended(id) {
            let mut ns = Namespace::default();
            for (krl, _) in &self.ir.routine(id).labels {
                ns.name(krl, self.rules);
            }
            self.labels.insert(id, ns);
        }
        self.labels.entry(id).or_default()
    }

    /// A variable's target name (without sigils) and where it lives (inline: no allocation).
    pub fn var(&mut self, rep: &mut Report, v: VarId, used_at: Span) -> (CompactString, Home) {
        let (ir, rules) = (self.ir, self.rules);
        let var = ir.var(v);
        let (ns, home) = match var.scope {
            Scope::Local(r) | Scope::Param(r) => {
                // The routine being rendered: its names were all made when it was declared
                // (asked again, a name is the same and makes no finding).
                if self.current == Some(r)
                    && let Ok(i) = self.vars_of.get(r.0 as usize).binary_search(&v)
                    && let Some(n) = self.current_names.get(i)
                {
                    return (n.clone(), Home::Local);
                }
                self.remake_locals(r);
                let ns = self.locals.entry(r).or_default();
                let (n, renamed) = ns.name_spelled(&var.name, rules, Some(&mut self.spellings));
                self.note(rep, "variable", FileId::Src, used_at, renamed);
                return (n, Home::Local);
            }
            Scope::Package => {
                if let Some(g) = package_name(rules, &var.name) {
                    return (g.into(), Home::Package);
                }
                (self.globals_ns(), Home::Global)
            }
            Scope::Global | Scope::Assumed => (self.globals_ns(), Home::Global),
        };
        let (n, r) = ns.name(&var.name, rules);
        self.note(rep, "variable", FileId::Src, used_at, r);
        (n, home)
    }

    /// A global's target name, without a finding (its declaration had one).
    pub fn global(&mut self, krl: &str) -> String {
        let rules = self.rules;
        self.globals_ns().name(krl, rules).0.into()
    }

    /// A label of the KRL routine `id`.
    pub fn label(&mut self, id: RoutineId, krl: &str) -> String {
        let rules = self.rules;
        self.labels_ns(id).name(krl, rules).0.into()
    }

    /// A label the translator needs in routine `id`.
    pub fn fresh_label(&mut self, id: RoutineId, base: &str) -> String {
        let max = self.rules.max_len;
        self.labels_ns(id).fresh(base, max)
    }

    /// A local the translator needs in routine `id` (without sigils).
    pub fn fresh_local(&mut self, id: RoutineId, base: &str) -> String {
        let max = self.rules.max_len;
        self.locals_ns(id).fresh(base, max)
    }

    /// A routine the translator adds (a RAPID TRAP), named apart from every routine and global.
    pub fn fresh_routine(&mut self, base: &str) -> String {
        let max = self.rules.max_len;
        self.routines.fresh(base, max)
    }

    /// The name map for the output's header: a title, then `kind krl -> target` per rename.
    pub fn name_map(&self) -> Option<(String, Vec<String>)> {
        if self.renamed.is_empty() {
            return None;
        }
        // Keys inline and borrowed: no allocation per rename.
        let mut seen = FxHashSet::default();
        let entries = self
            .renamed
            .iter()
            .filter(|(kind, krl, target)| {
                let mut upper = krl.clone();
                upper.make_ascii_uppercase();
                seen.insert((*kind, upper, target.as_str()))
            })
            .map(|(kind, krl, target)| format!("{kind} {krl} -> {target}"))
            .collect();
        Some((
            format!("Name map (KRL -> {}):", self.rules.language),
            entries,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An integer local `name` of routine `r`.
    fn local(name: &str, r: u32) -> ir::Var {
        ir::Var {
            name: name.into(),
            ty: ir::Ty::Int,
            dims: 0,
            scope: Scope::Local(RoutineId(r)),
            constant: false,
            decl: Span::new(0, 1),
            file: FileId::Src,
        }
    }

    fn rules() -> NameRules {
        NameRules {
            max_len: 15,
            is_reserved: |n| matches!(n, "speed" | "home"),
            language: "AS",
            routine: "program",
            routines_with_globals: false,
            package: &[],
        }
    }

    #[test]
    fn short_names_keep_their_spelling_in_lower_case() {
        assert_eq!(
            target_name("Pick_Pos", &rules()),
            ("pick_pos".into(), vec![])
        );
    }

    #[test]
    fn long_names_are_cut_with_a_stable_hash() {
        let (a, r) = target_name("Approach_Position_Left", &rules());
        assert_eq!(r, vec![Reason::TooLong]);
        assert_eq!(a.len(), 15);
        assert!(a.starts_with("approach_po_"));
        assert_eq!(a, target_name("APPROACH_POSITION_LEFT", &rules()).0);
        assert_ne!(a, target_name("Approach_Position_Right", &rules()).0);
    }

    #[test]
    fn reserved_and_invalid_names() {
        assert_eq!(target_name("Speed", &rules()).0, "speed_");
        assert_eq!(
            target_name("a$b", &rules()),
            ("a_b".into(), vec![Reason::Chars])
        );
        assert_eq!(target_name("_x", &rules()).0, "x_x");
    }

    #[test]
    fn clashes_get_a_counter_in_source_order() {
        let mut ns = Namespace::default();
        let r = rules();
        assert_eq!(ns.name("a$b", &r).0, "a_b");
        let (t, renamed) = ns.name("a_b", &r);
        assert_eq!(t, "a_b2");
        assert_eq!(renamed.expect("renamed").reasons, vec![Reason::Clash]);
        assert_eq!(ns.name("A$B", &r), ("a_b".into(), None));
        assert_eq!(ns.fresh("a_b", 15), "a_b3");
        assert_eq!(ns.fresh("tmp", 15), "tmp");
        assert_eq!(ns.fresh("tmp", 15), "tmp2");
        assert_eq!(ns.fresh("mm_a_very_long_scratch", 15), "mm_a_very_long_");
    }

    /// The counters skip what is taken but never a free name: the same names as a search from
    /// 2 each time, across digit counts and bases that share a cut prefix.
    #[test]
    fn clash_counters_are_the_smallest_free() {
        let mut ns = Namespace::default();
        let mut plain: FxHashSet<String> = Default::default();
        let slow = |taken: &FxHashSet<String>, base: &str, max: usize| {
            (2..)
                .map(|n: usize| {
                    let suffix = n.to_string();
                    let keep = max.saturating_sub(suffix.len()).min(base.len());
                    format!("{}{suffix}", &base[..keep])
                })
                .find(|c| !taken.contains(c))
                .unwrap_or_default()
        };
        for i in 0..400 {
            let base = ["abcdefgh", "abcdefghi", "abcdefgx", "ab"][i % 4];
            let want = if plain.contains(base) {
                slow(&plain, base, 10)
            } else {
                base.to_owned()
            };
            let got = ns.fresh(base, 10);
            assert_eq!(got, want, "{i}");
            plain.insert(got);
        }
    }

    /// A routine whose names do not meet is named without a namespace; one is made when a
    /// name is made up, as declaring in a namespace made it: the made-up name avoids the
    /// user's, and declaring again repeats no finding.
    #[test]
    fn locals_named_apart_get_their_namespace_when_asked() {
        let program = ir::Program {
            vars: vec![local("Speed", 0), local("tmp", 0), local("x", 1)],
            ..ir::Program::default()
        };
        let rules: &'static NameRules = Box::leak(Box::new(rules()));
        let mut names = Namer::new(rules, &program);
        let mut rep = Report::default();
        names.declare_locals(&mut rep, RoutineId(0));
        assert_eq!(names.unmade, Some(RoutineId(0)));
        assert!(!names.locals.contains_key(&RoutineId(0)));
        assert_eq!(names.renamed.len(), 1);
        assert_eq!(names.var(&mut rep, VarId(0), Span::new(2, 3)).0, "speed_");
        assert_eq!(names.fresh_local(RoutineId(0), "speed_"), "speed_2");
        assert_eq!(names.fresh_local(RoutineId(0), "tmp"), "tmp2");
        assert!(names.locals.contains_key(&RoutineId(0)));
        names.declare_locals(&mut rep, RoutineId(0));
        assert_eq!(names.renamed.len(), 1);
        assert_eq!(names.var(&mut rep, VarId(1), Span::new(2, 3)).0, "tmp");
        names.declare_locals(&mut rep, RoutineId(1));
        assert_eq!(names.var(&mut rep, VarId(0), Span::new(4, 5)).0, "speed_");
        assert_eq!(names.fresh_local(RoutineId(0), "tmp"), "tmp2");
        assert_eq!(names.renamed.len(), 1);
    }

    /// A routine's name by its id is the one its name looks up: clashing and repeated names
    /// too, and a synthetic routine named only later.
    #[test]
    fn routine_names_by_id_are_those_by_name() {
        let routine = |name: &str, synthetic: bool| ir::Routine {
            name: name.into(),
            name_span: Span::new(0, 1),
            kind: ir::RoutineKind::Def,
            ret: None,
            params: Vec::new(),
            result: None,
            locals: Vec::new(),
            temps: Vec::new(),
            labels: Vec::new(),
            closed: true,
            header_error: None,
            duplicate_param: None,
            span: Span::new(0, 1),
            end: 1,
            synthetic,
        };
        let program = ir::Program {
            routines: vec![
                routine("a$b", false),
                routine("a_b", false),
                routine("A$B", false),
                routine("speed", false),
                routine("top", true),
            ],
            ..ir::Program::default()
        };
        let rules: &'static NameRules = Box::leak(Box::new(rules()));
        let mut names = Namer::new(rules, &program);
        let mut rep = Report::default();
        names.declare_program(&mut rep);
        assert_eq!(names.routine_of_id(RoutineId(4)), None);
        names.routine(&mut rep, "top", Span::new(0, 1));
        let by_id: Vec<_> = (0..5).map(|i| names.routine_of_id(RoutineId(i))).collect();
        let by_name: Vec<_> = program
            .routines
            .iter()
            .map(|r| names.routine_of(&r.name))
            .collect();
        assert_eq!(by_id, by_name);
        assert_eq!(
            by_id,
            [
                Some("a_b"),
                Some("a_b2"),
                Some("a_b"),
                Some("speed_"),
                Some("top")
            ]
        );
    }

    /// A routine's names are dropped when the next routine is declared; asked again, they
    /// come back as they were (clash counters included), without a second TR003.
    #[test]
    fn an_ended_routines_locals_keep_their_names() {
        let program = ir::Program {
            vars: vec![local("a$b", 0), local("a_b", 0), local("x", 1)],
            ..ir::Program::default()
        };
        let rules: &'static NameRules = Box::leak(Box::new(rules()));
        let mut names = Namer::new(rules, &program);
        let mut rep = Report::default();
        names.declare_locals(&mut rep, RoutineId(0));
        let before = names.var(&mut rep, VarId(1), Span::new(5, 6));
        names.declare_locals(&mut rep, RoutineId(1));
        assert!(!names.locals.contains_key(&RoutineId(0)));
        let findings = names.renamed.len();
        assert_eq!(names.var(&mut rep, VarId(1), Span::new(7, 8)), before);
        assert_eq!(before.0, "a_b2");
        assert_eq!(names.renamed.len(), findings);
    }
}
