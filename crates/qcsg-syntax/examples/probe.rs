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
