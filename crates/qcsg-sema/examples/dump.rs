//! Prints the diagnostics of the files given on the command line.
fn main() {
    for path in std::env::args().skip(1) {
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let analysis = qcsg_sema::check_file(
            &path,
            text,
            &qcsg_sema::CheckOptions::default(),
            &qcsg_sema::FsLoader,
        );
        for d in &analysis.diagnostics {
            let source = analysis.sources.get(d.file);
            let lc = source
                .line_index
                .line_col(&source.text, d.span.start as usize);
            let snippet = source.text.get(d.span.range()).unwrap_or("");
            println!(
                "{}:{}:{} {}[{}] {} `{}` help={:?} labels={}",
                source.name,
                lc.line + 1,
                lc.character + 1,
                d.severity.as_str(),
                d.code,
                d.message,
                snippet,
                d.help,
                d.labels.len()
            );
        }
        println!(
            "{} definitions, {} references",
            analysis.definitions.len(),
            analysis.references.len()
        );
    }
}
