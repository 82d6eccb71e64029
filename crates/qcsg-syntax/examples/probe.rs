//! Prints the tree and diagnostics of a file or of standard input (a debugging aid).

use std::io::Read as _;

fn main() {
    let mut text = String::new();
    match std::env::args().nth(1) {
        Some(path) => text = std::fs::read_to_string(path).expect("readable file"),
        None => {
            std::io::stdin()
                .read_to_string(&mut text)
                .expect("readable input");
        }
    }
    if std::env::var_os("PROBE_TIME").is_some() {
        for _ in 0..5 {
            let start = std::time::Instant::now();
            let lexed = qcsg_syntax::lexer::lex(&text, qcsg_syntax::FileId::default());
            let lexed_at = start.elapsed();
            let parse = qcsg_syntax::parse(&text, qcsg_syntax::FileId::default());
            let total = start.elapsed();
            eprintln!(
                "lex {lexed_at:?}, lex+parse {:?}, {} tokens, {} diagnostics",
                total - lexed_at,
                lexed.tokens.len(),
                parse.diagnostics.len()
            );
        }
        return;
    }
    let parse = qcsg_syntax::parse(&text, qcsg_syntax::FileId::default());
    print!("{}", qcsg_syntax::sexpr::file_to_sexpr(&parse.file));
    for d in &parse.diagnostics {
        println!(
            "{} {:?} {:?}: {}",
            d.code,
            d.span.range(),
            &text[d.span.range()],
            d.message
        );
    }
}
