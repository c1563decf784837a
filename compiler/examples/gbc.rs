//! Development helper: compile a GBASIC file and print the GLOC or the diagnostics.
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).cloned().unwrap_or_default();
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    let optimize = args.iter().any(|arg| arg == "-O");
    let sensors = gloc_engine::sensors::SensorList::embedded();
    let compiled =
        gloc_compiler::compile(&text, &sensors, &gloc_compiler::CompileOptions { optimize });
    let index = gloc_engine::LineIndex::new(&text);
    for diagnostic in &compiled.diagnostics {
        let (line, column) = index.line_col(&text, diagnostic.span.start as usize);
        println!(
            "{line}:{column} {} {} {:?}",
            diagnostic.code, diagnostic.message, diagnostic.help
        );
    }
    print!("{}", compiled.gloc_text.unwrap_or_default());
    println!("{:?}", compiled.stats);
}
