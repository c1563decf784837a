//! The safety checker: validates a parsed GLOC file against its header and
//! the active sensor list, builds the resolved [`Program`], and runs the
//! control-flow analysis (cycle safety, worst-case instructions per cycle,
//! unreachable code).

use std::collections::HashMap;
use std::sync::Arc;

use crate::diagnostic::{Diagnostic, Span};
use crate::gloc::ast::{DirectiveKind, Instruction, LineKind, Opcode, Operand, OperandKind};
use crate::gloc::cfg;
use crate::gloc::{CheckOptions, Checked, Parsed, Stats};
use crate::program::{Instr, Pc, Program, Reg};
use crate::sensors::{Access, SensorId, SensorList};

/// Largest `nregs` accepted; keeps a hostile header from allocating gigabytes.
pub const MAX_REGISTERS: u64 = 1 << 16;
/// Largest `nblbs` accepted.
pub const MAX_LABELS: u64 = 1 << 20;
/// Largest `nmem` accepted (16 MiB of values).
pub const MAX_MEMORY: u64 = 1 << 20;

pub fn check_parsed(parsed: &Parsed, sensors: &SensorList, options: &CheckOptions) -> Checked {
    if parsed
        .diagnostics
        .iter()
        .any(|diagnostic| diagnostic.code == super::SOURCE_TOO_LARGE)
    {
        // Nothing was read: the header and body errors would only be noise.
        return Checked {
            program: None,
            diagnostics: parsed.diagnostics.clone(),
            stats: Stats::default(),
        };
    }
    let mut checker = Checker {
        diagnostics: parsed.diagnostics.clone(),
        sensors,
    };
    let header = checker.header(parsed);
    let statement_count = parsed.file.statements().count() as u64;
    let mut stats = Stats {
        registers: header.registers.map_or(0, |(value, _)| value as u32),
        labels: header.labels.map_or(0, |(value, _)| value as u32),
        memory: header.memory.map_or(0, |(value, _)| value as u32),
        statements: statement_count as u32,
        instructions: 0,
        worst_case: None,
    };
    if let Some((declared, span)) = header.statements {
        if declared != statement_count {
            checker.diagnostics.push(
                Diagnostic::error(
                    crate::codes::gloc::NINSTR_MISMATCH,
                    span,
                    format!(
                        "`ninstr {declared}` does not match the body: it has {statement_count} \
                         line{} after the header (labels count)",
                        if statement_count == 1 { "" } else { "s" }
                    ),
                )
                .with_help(format!("write `ninstr {statement_count}`"))
                .with_fix(
                    format!("set ninstr to {statement_count}"),
                    span,
                    statement_count.to_string(),
                ),
            );
        }
    }
    let program = checker.build(parsed, &header);
    checker.diagnostics.extend(super::identity::check_identity(
        parsed,
        sensors,
        options.written_for.as_deref(),
    ));
    stats.instructions = program.instrs.len().saturating_sub(1) as u32;
    let has_errors = checker.diagnostics.iter().any(Diagnostic::is_error);
    if has_errors || header.incomplete() {
        checker
            .diagnostics
            .sort_by_key(|diagnostic| diagnostic.span.start);
        return Checked {
            program: None,
            diagnostics: checker.diagnostics,
            stats,
        };
    }
    let analysis = cfg::analyze(&program, options);
    checker.diagnostics.extend(analysis.diagnostics);
    stats.worst_case = Some(analysis.worst_case);
    let has_errors = checker.diagnostics.iter().any(Diagnostic::is_error);
    checker
        .diagnostics
        .sort_by_key(|diagnostic| diagnostic.span.start);
    Checked {
        program: (!has_errors).then(|| Arc::new(program)),
        diagnostics: checker.diagnostics,
        stats,
    }
}

struct Checker<'a> {
    diagnostics: Vec<Diagnostic>,
    sensors: &'a SensorList,
}

/// Each header value with the span of its number.
#[derive(Default)]
struct Header {
    registers: Option<(u64, Span)>,
    labels: Option<(u64, Span)>,
    statements: Option<(u64, Span)>,
    memory: Option<(u64, Span)>,
}

impl Header {
    fn incomplete(&self) -> bool {
        self.registers.is_none() || self.labels.is_none() || self.statements.is_none()
    }
}

impl Checker<'_> {
    fn header(&mut self, parsed: &Parsed) -> Header {
        let mut header = Header::default();
        let mut first_defined: HashMap<&'static str, Span> = HashMap::new();
        let mut seen_statement = false;
        for line in &parsed.file.lines {
            let directive = match &line.kind {
                LineKind::Directive(directive) => directive,
                kind if kind.is_statement() => {
                    seen_statement = true;
                    continue;
                }
                _ => continue,
            };
            let span = directive.keyword_span.cover(directive.value_span);
            let canonical = if directive.kind.is_label_count() {
                "nblbs"
            } else {
                directive.kind.keyword()
            };
            if seen_statement {
                self.diagnostics.push(
                    Diagnostic::error(
                        crate::codes::gloc::MISPLACED_HEADER,
                        span,
                        format!(
                            "`{}` must come in the header, before the first label or instruction",
                            directive.kind.keyword()
                        ),
                    )
                    .with_help("move it to the top of the file"),
                );
                continue;
            }
            if let Some(first) = first_defined.get(canonical) {
                self.diagnostics.push(
                    Diagnostic::error(
                        crate::codes::gloc::MISPLACED_HEADER,
                        span,
                        format!("the header declares `{canonical}` twice"),
                    )
                    .with_label(*first, "first declared here")
                    .with_help("remove one of the two lines"),
                );
                continue;
            }
            first_defined.insert(canonical, span);
            let limit = match directive.kind {
                DirectiveKind::Nregs => Some(MAX_REGISTERS),
                DirectiveKind::Nblbs | DirectiveKind::Nlbls => Some(MAX_LABELS),
                DirectiveKind::Nmem => Some(MAX_MEMORY),
                DirectiveKind::Ninstr => None,
            };
            if let Some(limit) = limit {
                if directive.value > limit {
                    self.diagnostics.push(Diagnostic::error(
                        crate::codes::gloc::HEADER_OVER_LIMIT,
                        directive.value_span,
                        format!(
                            "`{} {}` is more than this engine allows ({limit})",
                            directive.kind.keyword(),
                            directive.value
                        ),
                    ));
                    continue;
                }
            }
            let entry = Some((directive.value, directive.value_span));
            match directive.kind {
                DirectiveKind::Nregs => header.registers = entry,
                DirectiveKind::Nblbs | DirectiveKind::Nlbls => header.labels = entry,
                DirectiveKind::Ninstr => header.statements = entry,
                DirectiveKind::Nmem => header.memory = entry,
            }
        }
        let missing: Vec<&str> = [
            (
                "nregs",
                header.registers.is_none() && !first_defined.contains_key("nregs"),
            ),
            (
                "nblbs",
                header.labels.is_none() && !first_defined.contains_key("nblbs"),
            ),
            (
                "ninstr",
                header.statements.is_none() && !first_defined.contains_key("ninstr"),
            ),
        ]
        .into_iter()
        .filter_map(|(name, missing)| missing.then_some(name))
        .collect();
        if !missing.is_empty() {
            let empty = parsed
                .file
                .lines
                .iter()
                .all(|line| matches!(line.kind, LineKind::Blank));
            let span = parsed.file.lines.first().map_or(Span::default(), |line| {
                Span::new(line.span.start as usize, line.span.start as usize)
            });
            let message = if empty {
                "empty file: a GLOC script starts with the header `nregs N`, `nblbs N`, `ninstr N`"
                    .to_string()
            } else {
                format!("the header is missing `{}`", missing.join("`, `"))
            };
            self.diagnostics.push(
                Diagnostic::error(crate::codes::gloc::MISSING_HEADER, span, message).with_help(
                    "start the file with `nregs N` (registers), `nblbs N` (labels) and `ninstr N` \
                     (lines after the header)",
                ),
            );
        }
        header
    }

    fn build(&mut self, parsed: &Parsed, header: &Header) -> Program {
        let register_limit = header.registers.map(|(value, _)| value);
        let label_limit = header.labels.map(|(value, _)| value);
        let memory_size = header.memory.map_or(0, |(value, _)| value);
        let label_table_size = label_limit.unwrap_or(0) as usize;
        let mut label_pcs: Vec<Option<Pc>> = vec![None; label_table_size];
        let mut label_spans: HashMap<u32, Span> = HashMap::new();
        let mut instrs = Vec::new();
        let mut spans = Vec::new();
        let mut lines = Vec::new();
        let mut texts: Vec<Box<str>> = Vec::new();
        let mut stored_sensors = Vec::new();
        let mut loaded_sensors = Vec::new();
        // Jump targets are resolved after every label is known.
        let mut pending_targets: Vec<(usize, u32, Span)> = Vec::new();
        let mut last_line = 1;

        for line in &parsed.file.lines {
            last_line = line.number;
            match &line.kind {
                LineKind::Label(label) => {
                    if !self.label_in_range(label.number, label.number_span, label_limit, header) {
                        continue;
                    }
                    if let Some(first) = label_spans.get(&label.number) {
                        self.diagnostics.push(
                            Diagnostic::error(
                                crate::codes::gloc::LABEL_DEFINED_TWICE,
                                label.number_span,
                                format!("label {} is defined twice", label.number),
                            )
                            .with_label(*first, "first defined here")
                            .with_help("give this label a number of its own"),
                        );
                        continue;
                    }
                    label_spans.insert(label.number, label.number_span);
                    if let Some(slot) = label_pcs.get_mut(label.number as usize) {
                        *slot = Some(Pc(instrs.len() as u32));
                    }
                }
                LineKind::Instruction(instruction) => {
                    let span = instruction.opcode_span.cover(
                        instruction
                            .operands
                            .last()
                            .map_or(instruction.opcode_span, |operand| operand.span),
                    );
                    let pc = instrs.len();
                    let mut resolver = Resolver {
                        checker: self,
                        header,
                        register_limit,
                        label_limit,
                        memory_size,
                        pending_targets: &mut pending_targets,
                        pc,
                    };
                    let instr = resolver.instruction(
                        instruction,
                        &mut texts,
                        &mut stored_sensors,
                        &mut loaded_sensors,
                    );
                    instrs.push(instr);
                    spans.push(span);
                    lines.push(line.number);
                }
                _ => {}
            }
        }
        let end = parsed
            .file
            .lines
            .last()
            .map_or(0, |line| line.span.end as usize);
        instrs.push(Instr::Halt);
        spans.push(Span::new(end, end));
        lines.push(last_line);

        let has_invalid_lines = parsed
            .file
            .lines
            .iter()
            .any(|line| matches!(line.kind, LineKind::Invalid { .. }));
        for (pc, label, span) in pending_targets {
            match label_pcs.get(label as usize).copied().flatten() {
                Some(target) => patch_target(&mut instrs[pc], label, target),
                None => {
                    // Out-of-range labels were reported already, and a line that
                    // failed to parse may be the missing `label`: one typo, one error.
                    if label_limit.is_some_and(|limit| u64::from(label) < limit)
                        && !has_invalid_lines
                    {
                        self.diagnostics.push(
                            Diagnostic::error(
                                crate::codes::gloc::UNDEFINED_LABEL,
                                span,
                                format!("label {label} is never defined"),
                            )
                            .with_help(format!(
                                "add `label {label}` where execution should continue"
                            )),
                        );
                    }
                }
            }
        }
        Program {
            instrs,
            spans,
            lines,
            label_pcs,
            texts,
            register_count: register_limit.unwrap_or(0) as u32,
            memory_size: memory_size as u32,
            stored_sensors,
            loaded_sensors,
        }
    }

    fn label_in_range(
        &mut self,
        label: u32,
        span: Span,
        limit: Option<u64>,
        header: &Header,
    ) -> bool {
        let Some(limit) = limit else {
            return false;
        };
        if u64::from(label) < limit {
            return true;
        }
        let mut diagnostic = Diagnostic::error(
            crate::codes::gloc::LABEL_OUT_OF_RANGE,
            span,
            format!(
                "label {label} is out of range: `nblbs {limit}` allows labels 0 to {}",
                limit.saturating_sub(1)
            ),
        )
        .with_help(format!(
            "raise `nblbs` to {} or use a lower label number",
            u64::from(label) + 1
        ));
        if limit == 0 {
            diagnostic.message =
                format!("label {label} is out of range: `nblbs 0` allows no labels");
        }
        if let Some((_, header_span)) = header.labels {
            diagnostic = diagnostic.with_label(header_span, "label count declared here");
        }
        self.diagnostics.push(diagnostic);
        false
    }
}

/// Sets the jump targets of a branch or jump whose label is now known.
fn patch_target(instr: &mut Instr, label: u32, target: Pc) {
    let placeholder = Pc(PLACEHOLDER_BIT | label);
    match instr {
        Instr::Jump { target: slot } if *slot == placeholder => *slot = target,
        Instr::Branch {
            if_true, if_false, ..
        } => {
            if *if_true == placeholder {
                *if_true = target;
            }
            if *if_false == placeholder {
                *if_false = target;
            }
        }
        _ => {}
    }
}

/// Until resolved, a target holds `PLACEHOLDER_BIT | label` (labels are below 2^20).
const PLACEHOLDER_BIT: u32 = 1 << 31;

struct Resolver<'c, 'a, 'h> {
    checker: &'c mut Checker<'a>,
    header: &'h Header,
    register_limit: Option<u64>,
    label_limit: Option<u64>,
    memory_size: u64,
    pending_targets: &'c mut Vec<(usize, u32, Span)>,
    pc: usize,
}

/// The index of `text` in the program's text table, added when new.
fn intern_text(texts: &mut Vec<Box<str>>, text: &str) -> u32 {
    let index = texts.iter().position(|known| &**known == text);
    index.unwrap_or_else(|| {
        texts.push(text.into());
        texts.len() - 1
    }) as u32
}

/// The instruction `opcode a,b,dst` for the three-register opcodes.
fn three_register_shape(opcode: Opcode) -> Option<fn(Reg, Reg, Reg) -> Instr> {
    Some(match opcode {
        Opcode::Add => |a, b, dst| Instr::Add { a, b, dst },
        Opcode::Sub => |a, b, dst| Instr::Sub { a, b, dst },
        Opcode::Mul => |a, b, dst| Instr::Mul { a, b, dst },
        Opcode::Div => |a, b, dst| Instr::Div { a, b, dst },
        Opcode::Mod => |a, b, dst| Instr::Mod { a, b, dst },
        Opcode::Min => |a, b, dst| Instr::Min { a, b, dst },
        Opcode::Max => |a, b, dst| Instr::Max { a, b, dst },
        Opcode::And => |a, b, dst| Instr::And { a, b, dst },
        Opcode::Or => |a, b, dst| Instr::Or { a, b, dst },
        Opcode::Xor => |a, b, dst| Instr::Xor { a, b, dst },
        Opcode::Cmpeq => |a, b, dst| Instr::CmpEq { a, b, dst },
        Opcode::Cmpne => |a, b, dst| Instr::CmpNe { a, b, dst },
        Opcode::Cmplt => |a, b, dst| Instr::CmpLt { a, b, dst },
        Opcode::Cmple => |a, b, dst| Instr::CmpLe { a, b, dst },
        Opcode::Cmpgt => |a, b, dst| Instr::CmpGt { a, b, dst },
        Opcode::Cmpge => |a, b, dst| Instr::CmpGe { a, b, dst },
        _ => return None,
    })
}

/// The instruction `opcode src,dst` for the two-register opcodes.
fn two_register_shape(opcode: Opcode) -> Option<fn(Reg, Reg) -> Instr> {
    Some(match opcode {
        Opcode::Mov => |src, dst| Instr::Move { src, dst },
        Opcode::Neg => |src, dst| Instr::Neg { src, dst },
        Opcode::Abs => |src, dst| Instr::Abs { src, dst },
        Opcode::Sqrt => |src, dst| Instr::Sqrt { src, dst },
        Opcode::I2d => |src, dst| Instr::IntToFloat { src, dst },
        Opcode::D2i => |src, dst| Instr::FloatToInt { src, dst },
        Opcode::Not => |src, dst| Instr::Not { src, dst },
        _ => return None,
    })
}

impl Resolver<'_, '_, '_> {
    fn instruction(
        &mut self,
        instruction: &Instruction,
        texts: &mut Vec<Box<str>>,
        stored: &mut Vec<SensorId>,
        loaded: &mut Vec<SensorId>,
    ) -> Instr {
        let operands = &instruction.operands;
        let register = |resolver: &mut Self, position: usize| -> Reg {
            match operands
                .get(position)
                .map(|operand| (&operand.kind, operand.span))
            {
                Some((OperandKind::Register(register), span)) => resolver.register(*register, span),
                _ => Reg(0),
            }
        };
        let integer = |position: usize| -> i64 {
            match operands.get(position).map(|operand| &operand.kind) {
                Some(OperandKind::Integer(value)) => *value,
                _ => 0,
            }
        };
        let span_of = |position: usize| {
            operands
                .get(position)
                .map_or(instruction.opcode_span, |operand| operand.span)
        };
        let three = |resolver: &mut Self| {
            (
                register(resolver, 0),
                register(resolver, 1),
                register(resolver, 2),
            )
        };
        let two = |resolver: &mut Self| (register(resolver, 0), register(resolver, 1));
        if let Some(make) = three_register_shape(instruction.opcode) {
            let (a, b, dst) = three(self);
            return make(a, b, dst);
        }
        if let Some(make) = two_register_shape(instruction.opcode) {
            let (src, dst) = two(self);
            return make(src, dst);
        }
        match instruction.opcode {
            Opcode::Loads => {
                let sensor = self.sensor_operand(operands.first(), None);
                if !loaded.contains(&sensor) {
                    loaded.push(sensor);
                }
                Instr::LoadSensor {
                    sensor,
                    dst: register(self, 1),
                }
            }
            Opcode::Stores => {
                let src = register(self, 0);
                let sensor = self.sensor_operand(operands.get(1), Some(instruction.opcode_span));
                if !stored.contains(&sensor) {
                    stored.push(sensor);
                }
                Instr::StoreSensor { src, sensor }
            }
            Opcode::Loadi => Instr::LoadInt {
                value: integer(0),
                dst: register(self, 1),
            },
            Opcode::Loadd => {
                let value = match operands.first().map(|operand| &operand.kind) {
                    Some(OperandKind::Float(value)) => *value,
                    Some(OperandKind::Integer(value)) => *value as f64,
                    _ => 0.0,
                };
                Instr::LoadFloat {
                    value,
                    dst: register(self, 1),
                }
            }
            // The register-only shapes were built above.
            Opcode::Add
            | Opcode::Sub
            | Opcode::Mul
            | Opcode::Div
            | Opcode::Mod
            | Opcode::Min
            | Opcode::Max
            | Opcode::And
            | Opcode::Or
            | Opcode::Xor
            | Opcode::Cmpeq
            | Opcode::Cmpne
            | Opcode::Cmplt
            | Opcode::Cmple
            | Opcode::Cmpgt
            | Opcode::Cmpge
            | Opcode::Mov
            | Opcode::Neg
            | Opcode::Abs
            | Opcode::Sqrt
            | Opcode::I2d
            | Opcode::D2i
            | Opcode::Not => {
                unreachable!("register-only opcodes are built before this match")
            }
            Opcode::Loadm | Opcode::Storem => self.memory_instruction(instruction),
            Opcode::Cbr => {
                let cond = register(self, 0);
                let if_true = self.target(integer(1), span_of(1));
                let if_false = self.target(integer(2), span_of(2));
                Instr::Branch {
                    cond,
                    if_true,
                    if_false,
                }
            }
            Opcode::Jumpi => Instr::Jump {
                target: self.target(integer(0), span_of(0)),
            },
            Opcode::Jump => Instr::JumpIndirect {
                register: register(self, 0),
            },
            Opcode::Yield => Instr::Yield,
            Opcode::Halt => Instr::Halt,
            Opcode::Nop => Instr::Nop,
            Opcode::Write => Instr::Write {
                src: register(self, 0),
            },
            Opcode::Print => Instr::Print {
                src: register(self, 0),
            },
            Opcode::Writes | Opcode::Prints => {
                let text = match operands.first().map(|operand| &operand.kind) {
                    Some(OperandKind::Text(text)) => text.as_str(),
                    _ => "",
                };
                let index = intern_text(texts, text);
                if instruction.opcode == Opcode::Writes {
                    Instr::WriteText { text: index }
                } else {
                    Instr::PrintText { text: index }
                }
            }
        }
    }

    /// `loadm addr,dst` / `storem src,addr`: an address register, or a constant address.
    fn memory_instruction(&mut self, instruction: &Instruction) -> Instr {
        let operands = &instruction.operands;
        let register = |resolver: &mut Self, position: usize| match operands.get(position) {
            Some(Operand {
                kind: OperandKind::Register(register),
                span,
            }) => Some(resolver.register(*register, *span)),
            _ => None,
        };
        let address = |resolver: &mut Self, position: usize| {
            let (value, span) = match operands.get(position) {
                Some(Operand {
                    kind: OperandKind::Integer(value),
                    span,
                }) => (*value, *span),
                Some(operand) => (0, operand.span),
                None => (0, instruction.opcode_span),
            };
            resolver.address(value, span)
        };
        if instruction.opcode == Opcode::Loadm {
            let dst = register(self, 1).unwrap_or(Reg(0));
            match register(self, 0) {
                Some(addr) => Instr::LoadMem { addr, dst },
                None => Instr::LoadMemAt {
                    addr: address(self, 0),
                    dst,
                },
            }
        } else {
            let src = register(self, 0).unwrap_or(Reg(0));
            match register(self, 1) {
                Some(addr) => Instr::StoreMem { src, addr },
                None => Instr::StoreMemAt {
                    src,
                    addr: address(self, 1),
                },
            }
        }
    }

    fn register(&mut self, register: u32, span: Span) -> Reg {
        if let Some(limit) = self.register_limit {
            if u64::from(register) >= limit {
                let mut diagnostic = Diagnostic::error(
                    crate::codes::gloc::REGISTER_OUT_OF_RANGE,
                    span,
                    if limit == 0 {
                        format!("register r{register} is out of range: `nregs 0` allows no registers")
                    } else {
                        format!(
                            "register r{register} is out of range: `nregs {limit}` allows r0 to r{}",
                            limit - 1
                        )
                    },
                )
                .with_help(format!("raise `nregs` to {} or use a lower register", u64::from(register) + 1));
                if let Some((_, header_span)) = self.header.registers {
                    diagnostic = diagnostic.with_label(header_span, "register count declared here");
                }
                self.checker.diagnostics.push(diagnostic);
                return Reg(0);
            }
        }
        Reg(register)
    }

    /// Resolves a sensor operand, an index or a name; `store` is the `stores`
    /// mnemonic's span when writing. A name is looked up in the active list
    /// (by `SensorList::lookup`, the one name rule), with "did you mean" when absent.
    fn sensor_operand(&mut self, operand: Option<&Operand>, store: Option<Span>) -> SensorId {
        let Some(operand) = operand else {
            return SensorId(0);
        };
        match &operand.kind {
            OperandKind::Integer(index) => self.sensor(*index, operand.span, store),
            OperandKind::Name(name) => {
                let sensors = self.checker.sensors;
                match sensors.lookup(name) {
                    Some(id) => self.sensor(i64::from(id.0), operand.span, store),
                    None => {
                        let mut diagnostic = Diagnostic::error(
                            crate::codes::gloc::UNKNOWN_SENSOR_NAME,
                            operand.span,
                            format!(
                                "no sensor `{name}` in the active sensor list ({} sensors)",
                                sensors.len()
                            ),
                        );
                        let names = sensors.iter().map(|(_, sensor)| sensor.name.as_str());
                        diagnostic = match crate::suggest::closest(name, names) {
                            Some(suggestion) => diagnostic
                                .with_help(format!("did you mean `{suggestion}`?"))
                                .with_fix(
                                    format!("replace with `{suggestion}`"),
                                    operand.span,
                                    suggestion,
                                ),
                            None => diagnostic.with_help(
                                "check the name against the masterdata of the glider (`--masterdata FILE`)",
                            ),
                        };
                        self.checker.diagnostics.push(diagnostic);
                        SensorId(0)
                    }
                }
            }
            // The parser admits only an index or a name here.
            _ => SensorId(0),
        }
    }

    /// Resolves a sensor index; `store` is the `stores` mnemonic's span when writing.
    fn sensor(&mut self, index: i64, span: Span, store: Option<Span>) -> SensorId {
        let sensors = self.checker.sensors;
        let id = SensorId(u32::try_from(index).unwrap_or(u32::MAX));
        let Some(sensor) = sensors.get(id) else {
            self.checker.diagnostics.push(
                Diagnostic::error(
                    crate::codes::gloc::UNKNOWN_SENSOR_INDEX,
                    span,
                    format!(
                        "sensor {index} does not exist: the active sensor list has {} sensors (0 to {})",
                        sensors.len(),
                        sensors.len().saturating_sub(1)
                    ),
                )
                .with_help("check the index against the masterdata of the glider (`--masterdata FILE`)"),
            );
            return SensorId(0);
        };
        if store.is_none() {
            return id;
        }
        let name = &sensor.name;
        let diagnostic = match sensor.access() {
            Access::ReadOnly => Diagnostic::error(
                crate::codes::gloc::STORE_TO_READ_ONLY,
                span,
                format!("sensor {index} `{name}` is read-only: scripts may not store to `m_` and `x_` sensors"),
            )
            .with_help("store to a `c_`, `u_` or `sci_` sensor instead"),
            Access::Factory => Diagnostic::warning(
                crate::codes::gloc::STORE_TO_FACTORY,
                span,
                format!("sensor {index} `{name}` is a factory setting (`f_`); changing it from a script is risky"),
            ),
            Access::Writable => return id,
        };
        self.checker.diagnostics.push(diagnostic);
        id
    }

    fn address(&mut self, address: i64, span: Span) -> u32 {
        let in_range = u64::try_from(address).is_ok_and(|address| address < self.memory_size);
        if !in_range {
            let mut diagnostic = Diagnostic::error(
                crate::codes::gloc::MEMORY_OUT_OF_RANGE,
                span,
                if self.memory_size == 0 {
                    format!(
                        "memory address {address} is out of range: the script declares no memory"
                    )
                } else {
                    format!(
                        "memory address {address} is out of range: `nmem {}` allows 0 to {}",
                        self.memory_size,
                        self.memory_size - 1
                    )
                },
            )
            .with_help("declare the memory size in the header with `nmem N`");
            if let Some((_, header_span)) = self.header.memory {
                diagnostic = diagnostic.with_label(header_span, "memory size declared here");
            }
            self.checker.diagnostics.push(diagnostic);
            return 0;
        }
        address as u32
    }

    /// A label operand: checked against `nblbs` now, resolved to a pc later.
    fn target(&mut self, label: i64, span: Span) -> Pc {
        let label = u32::try_from(label).unwrap_or(u32::MAX);
        let header = self.header;
        if self
            .checker
            .label_in_range(label, span, self.label_limit, header)
        {
            self.pending_targets.push((self.pc, label, span));
        }
        Pc(PLACEHOLDER_BIT | label)
    }
}
