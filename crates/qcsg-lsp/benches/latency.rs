//! Editor latency on a generated 10,000-line program: diagnostics after an edit (a full re-check,
//! which is what the server does per change), the evaluation that follows it (runtime
//! diagnostics, and the geometry hover uses), and hover, semantic tokens, completion and
//! formatting on the result. Run with `cargo bench -p qcsg-ide --bench latency`; the numbers are
//! recorded in `docs/lsp.md`.

use std::hint::black_box;
use std::time::{Duration, Instant};

use qcsg_diag::LineIndex;
use qcsg_ide::{Analysis, CheckOptions, FsLoader, HoverExtension};
use qcsg_lsp::geometry::{Geometry, editor_limits};

/// A program of about `lines` lines: parameters, functions, modules and their instantiations.
fn program(lines: usize) -> String {
    let mut text = String::from("/// Base size.\nbase = 2;\n");
    let mut i = 0;
    while text.lines().count() < lines {
        text.push_str(&format!(
            "/// Part {i}.\nwidth_{i} = base * {i} + 1;\nfunction grow_{i}(x) = x * width_{i};\nmodule part_{i}(size = 1, center = false) {{\n    translate([{i}, 0, 0]) cube([size, grow_{i}(size), 2], center = center);\n    sphere(r = width_{i} / 2);\n}}\npart_{i}(base);\n\n"
        ));
        i += 1;
    }
    text
}

fn median(mut samples: Vec<Duration>) -> Duration {
    samples.sort();
    samples[samples.len() / 2]
}

fn time(runs: usize, mut f: impl FnMut()) -> Duration {
    median(
        (0..runs)
            .map(|_| {
                let start = Instant::now();
                f();
                start.elapsed()
            })
            .collect(),
    )
}

fn main() {
    let text = program(10_000);
    let lines = text.lines().count();
    let analyze = |text: &str| {
        Analysis::new(
            "bench.qcsg",
            text.to_owned(),
            &CheckOptions::default(),
            &FsLoader,
        )
    };
    let middle = text.len() / 2;
    let edit_at = text[middle..]
        .find("base)")
        .map(|i| middle + i)
        .expect("an instantiation");
    let edited = format!("{}base + 1{}", &text[..edit_at], &text[edit_at + 4..]);

    let diagnostics = time(15, || {
        let analysis = analyze(black_box(&edited));
        black_box(analysis.diagnostics());
    });
    let analysis = analyze(&edited);
    let index = LineIndex::new(&edited);
    let hover_at = index.line_col(
        &edited,
        edited[middle..]
            .find("width_")
            .map(|i| middle + i + 2)
            .expect("a name"),
    );
    let hover = time(51, || {
        black_box(analysis.hover(black_box(hover_at)));
    });
    let evaluation = time(15, || {
        let geometry =
            Geometry::evaluate(&analysis, black_box(&editor_limits())).expect("evaluates");
        black_box(geometry.diagnostics(&analysis));
    });
    let geometry = Geometry::evaluate(&analysis, &editor_limits()).expect("evaluates");
    let call_at = index.line_col(
        &edited,
        edited[middle..]
            .find("\npart_")
            .map(|i| middle + i + 3)
            .expect("an instantiation"),
    );
    let geometry_hover = time(51, || {
        let hover = analysis.hover_with(black_box(call_at), Some(&geometry as &dyn HoverExtension));
        assert!(hover.is_some_and(|h| h.markdown.contains("**geometry**")));
    });
    let tokens = time(15, || {
        black_box(analysis.semantic_tokens());
    });
    let completion = time(15, || {
        black_box(analysis.completions(black_box(hover_at)));
    });
    let format = time(15, || {
        black_box(qcsg_ide::format::format(black_box(&edited)).ok());
    });
    println!("program: {lines} lines, {} bytes", edited.len());
    println!("diagnostics after an edit (parse + check + convert): {diagnostics:.2?}");
    println!("evaluation + runtime diagnostics (editor limits): {evaluation:.2?}");
    println!("hover: {hover:.2?}");
    println!("hover on a module instantiation, with its geometry: {geometry_hover:.2?}");
    println!("semantic tokens (full): {tokens:.2?}");
    println!("completion: {completion:.2?}");
    println!("formatting: {format:.2?}");
}
