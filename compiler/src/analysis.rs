//! What the language server needs from a GBASIC text in one call: diagnostics,
//! symbols with definitions, references and types, sensors read and written, block
//! ranges for folding, and the compiled GLOC. Byte offsets throughout.

use gloc_engine::sensors::SensorList;
use gloc_engine::{Diagnostic, Occurrences, Span};

use crate::ast;
use crate::parser::KEYWORDS;
use crate::typed::Ty;
use crate::{check, parser, CompileOptions};

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SymbolKind {
    Variable,
    Array,
    Constant,
    Label,
    Sensor,
}

#[derive(Clone, Debug, PartialEq)]
pub struct SymbolInfo {
    pub name: String,
    pub kind: SymbolKind,
    /// `None` for labels (they have no type).
    pub ty: Option<Ty>,
    /// A one-line description for hover, e.g. `dim depths(40) as float`.
    pub detail: String,
    /// Where it is declared (no definition for a sensor) and used.
    pub occurrences: Occurrences,
    /// `Some` exactly for a sensor.
    pub sensor: Option<SensorAccess>,
}

/// A sensor symbol's place in the active list and the uses that write it.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorAccess {
    /// The index in the active sensor list.
    pub index: u32,
    /// Where the program writes it (a subset of the symbol's references).
    pub writes: Vec<Span>,
}

/// A foldable block: `if … endif`, `while … wend`, `do … loop`, `for … next`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Block {
    pub kind: &'static str,
    /// From the opening keyword to the end of the closing line.
    pub span: Span,
}

#[derive(Clone, Debug, Default)]
pub struct Analysis {
    pub diagnostics: Vec<Diagnostic>,
    pub symbols: Vec<SymbolInfo>,
    pub blocks: Vec<Block>,
}

impl Analysis {
    /// The symbol defined or referenced at byte `offset`.
    pub fn symbol_at(&self, offset: usize) -> Option<&SymbolInfo> {
        self.symbols
            .iter()
            .find(|symbol| symbol.occurrences.at(offset).is_some())
    }

    /// Sensors the program reads, with the spans of the reads.
    pub fn sensors_read(&self) -> impl Iterator<Item = &SymbolInfo> {
        self.symbols.iter().filter(|symbol| {
            symbol
                .sensor
                .as_ref()
                .is_some_and(|sensor| symbol.occurrences.references.len() > sensor.writes.len())
        })
    }

    /// Sensors the program writes.
    pub fn sensors_written(&self) -> impl Iterator<Item = &SymbolInfo> {
        self.symbols.iter().filter(|symbol| {
            symbol
                .sensor
                .as_ref()
                .is_some_and(|sensor| !sensor.writes.is_empty())
        })
    }
}

/// GBASIC's keywords, for completion and highlighting.
pub fn keywords() -> &'static [&'static str] {
    KEYWORDS
}

pub fn analyze(text: &str, sensors: &SensorList, options: &CompileOptions) -> Analysis {
    analyze_compiled(text, sensors, options).0
}

/// [`analyze`] and [`crate::load_script`] of the same GBASIC text from one parse, one
/// check and one code generation: what the language server needs on every edit.
pub fn analyze_and_load(
    text: &str,
    sensors: &SensorList,
    options: &crate::LoadOptions,
) -> (Analysis, crate::LoadedScript) {
    let (analysis, compiled) = analyze_compiled(
        text,
        sensors,
        &CompileOptions {
            optimization: options.optimization,
        },
    );
    let loaded = crate::loader::load_compiled(text, compiled, sensors, options);
    (analysis, loaded)
}

fn analyze_compiled(
    text: &str,
    sensors: &SensorList,
    options: &CompileOptions,
) -> (Analysis, crate::Compiled) {
    let parsed = parser::parse(text);
    let checked = check::check(&parsed.program, sensors);
    let mut blocks = Vec::new();
    collect_blocks(&parsed.program.body, &mut blocks);
    // The tree is not needed past here: not kept beside the code and the analysis.
    let parser::Parsed {
        program,
        mut diagnostics,
    } = parsed;
    drop(program);
    let check::Checked {
        program,
        symbols: checked_symbols,
        diagnostics: check_diagnostics,
    } = checked;
    diagnostics.extend(check_diagnostics);
    let compiled = crate::compile_checked(
        text,
        diagnostics,
        program,
        &checked_symbols,
        sensors,
        options,
    );
    let mut symbols = Vec::new();
    for variable in &checked_symbols.variables {
        let (kind, detail) = match variable.size {
            Some(size) => (
                SymbolKind::Array,
                format!("dim {}({size}) as {}", variable.name, variable.ty.name()),
            ),
            None => (
                SymbolKind::Variable,
                format!("dim {} as {}", variable.name, variable.ty.name()),
            ),
        };
        symbols.push(SymbolInfo {
            name: variable.name.clone(),
            kind,
            ty: Some(variable.ty),
            detail,
            occurrences: Occurrences {
                definition: Some(variable.definition),
                references: variable.references.clone(),
            },
            sensor: None,
        });
    }
    for constant in &checked_symbols.constants {
        symbols.push(SymbolInfo {
            name: constant.name.clone(),
            kind: SymbolKind::Constant,
            ty: Some(constant.ty),
            detail: format!("const {} = {}", constant.name, constant.value),
            occurrences: Occurrences {
                definition: Some(constant.definition),
                references: constant.references.clone(),
            },
            sensor: None,
        });
    }
    for (number, label) in checked_symbols.labels.iter().enumerate() {
        symbols.push(SymbolInfo {
            name: label.name.clone(),
            kind: SymbolKind::Label,
            ty: None,
            detail: format!("label: {} (GLOC label {number})", label.name),
            occurrences: Occurrences {
                definition: Some(label.definition),
                references: label.references.clone(),
            },
            sensor: None,
        });
    }
    for sensor in &checked_symbols.sensors {
        let units = sensors
            .get(gloc_engine::sensors::SensorId(sensor.sensor))
            .map_or(String::new(), |info| info.units.clone());
        let mut references: Vec<Span> =
            sensor.reads.iter().chain(&sensor.writes).copied().collect();
        references.sort_by_key(|span| span.start);
        symbols.push(SymbolInfo {
            name: sensor.name.clone(),
            kind: SymbolKind::Sensor,
            ty: Some(Ty::Float),
            detail: format!("sensor {} ({units}), index {}", sensor.name, sensor.sensor),
            occurrences: Occurrences {
                definition: None,
                references,
            },
            sensor: Some(SensorAccess {
                index: sensor.sensor,
                writes: sensor.writes.clone(),
            }),
        });
    }
    let analysis = Analysis {
        diagnostics: compiled.diagnostics.clone(),
        symbols,
        blocks,
    };
    (analysis, compiled)
}

fn collect_blocks(body: &[ast::Stmt], blocks: &mut Vec<Block>) {
    for stmt in body {
        let (kind, end) = match &stmt.kind {
            ast::StmtKind::If {
                arms,
                else_body,
                end_span,
            } => {
                for arm in arms {
                    collect_blocks(&arm.body, blocks);
                }
                if let Some(body) = else_body {
                    collect_blocks(body, blocks);
                }
                ("if", *end_span)
            }
            ast::StmtKind::While { body, end_span, .. } => {
                collect_blocks(body, blocks);
                ("while", *end_span)
            }
            ast::StmtKind::Do { body, end_span, .. } => {
                collect_blocks(body, blocks);
                ("do", *end_span)
            }
            ast::StmtKind::For { body, end_span, .. } => {
                collect_blocks(body, blocks);
                ("for", *end_span)
            }
            _ => continue,
        };
        if let Some(end) = end {
            blocks.push(Block {
                kind,
                span: stmt.span.cover(end),
            });
        }
    }
    blocks.sort_by_key(|block| block.span.start);
}
