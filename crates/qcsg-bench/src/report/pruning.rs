//! What pruning left out: per pass and per construction rule, the terms and literals removed,
//! and each scene built and sampled with every rule on, each off alone, and all off.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use qcsg_bench::pipeline::compile_file;
use qcsg_bench::reference::diagonal;
use qcsg_csg::dnf::Pruning;
use qcsg_csg::{Dnf, DnfOptions};

use crate::{Config, Scene, count, ms, one_thread, timed_sample};

pub fn pruning(
    md: &mut String,
    scenes: &[Scene],
    cfg: &Config,
    scene_dir: &Path,
) -> Result<(), String> {
    // The benchmark scenes, and one made to give the passes work.
    let mut cases: Vec<(String, PathBuf)> = scenes
        .iter()
        .map(|s| (s.name.clone(), s.path.clone()))
        .collect();
    cases.push(("pruning".into(), scene_dir.join("pruning.scad")));
    let mut compiled = Vec::new();
    for (name, path) in &cases {
        let c = compile_file(path, &DnfOptions::default())?;
        let codes = c.error_codes();
        let unpruned = c.unpruned;
        let dnf = c.dnf.ok_or_else(|| format!("{name}: errors {codes:?}"))?;
        compiled.push((name.clone(), path.clone(), dnf, unpruned));
    }
    let _ = writeln!(md, "## 7. What pruning left out\n");
    let _ = writeln!(
        md,
        "The DNF builder prunes while it builds (terms outside an operand's box, empty boxes, \
         terms outside a literal, duplicates and subsumed terms, literals that cannot matter) and \
         then runs passes over the finished DNF. Per pass, the terms and literals it removed; \
         then, per scene, the DNF built and sampled at r = {} diag with every rule on, with \
         each rule turned off alone (`DnfOptions::pruning`, `Pruning::without`), with the \
         construction rules or the final passes off together, and with all of them off \
         (`Pruning::none`). Single rules mostly back each other up (what one leaves, another \
         removes), so a row differs from \"all on\" only where no other rule covers it. The \
         size of the DNF multiplied out with no pruning at all (De Morgan and distribution over \
         the evaluated DAG) is counted first, without building it.\n",
        cfg.radii[cfg.radii.len() / 2]
    );
    let _ = writeln!(
        md,
        "| scene | multiplied out, no pruning: terms | literals | built: terms | literals | \
         quadrics |"
    );
    let _ = writeln!(md, "|---|---:|---:|---:|---:|---:|");
    for (name, _, dnf, unpruned) in &compiled {
        let (t, l) = unpruned.map_or(("–".into(), "–".into()), |u| {
            (count(u.terms), count(u.literals))
        });
        let _ = writeln!(
            md,
            "| {name} | {t} | {l} | {} | {} | {} |",
            dnf.terms.len(),
            dnf.literal_count(),
            dnf.quadrics.len()
        );
    }
    let _ = writeln!(md);
    let _ = writeln!(
        md,
        "| scene | dropped while building (outside operand box / empty box / outside a literal / duplicate / subsumed terms; literals inside / duplicate) | peak terms |"
    );
    let _ = writeln!(md, "|---|---|---:|");
    for (name, _, dnf, _) in &compiled {
        let c = &dnf.stats.construction;
        let _ = writeln!(
            md,
            "| {} | {} / {} / {} / {} / {}; {} / {} | {} |",
            name,
            c.terms_outside_operand_bounds,
            c.terms_empty_bounds,
            c.terms_outside_literal,
            c.terms_duplicate,
            c.terms_subsumed,
            c.literals_inside,
            c.literals_duplicate,
            c.peak_terms
        );
    }
    let _ = writeln!(
        md,
        "\n| scene | pass | terms before → after | literals before → after | quadrics before → after |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|");
    for (name, _, dnf, _) in &compiled {
        for p in &dnf.stats.passes {
            let _ = writeln!(
                md,
                "| {} | {} | {} → {} | {} → {} | {} → {} |",
                name,
                p.pass,
                p.terms_before,
                p.terms_after,
                p.literals_before,
                p.literals_after,
                p.quadrics_before,
                p.quadrics_after
            );
        }
    }
    pruning_switches(md, &compiled, cfg.radii[cfg.radii.len() / 2])?;
    let _ = writeln!(md);
    Ok(())
}

/// Literal occurrences above which a DNF built with some pruning off is not sampled: the
/// sampler's cost grows with them, and the report must stay quick.
const SWITCH_SAMPLING_LITERALS: usize = 5_000;

/// Per scene, one row per pruning setting: all on, each rule off alone, all off. A setting
/// whose DNF equals one already sampled reuses that measurement instead of sampling again.
fn pruning_switches(
    md: &mut String,
    compiled: &[(String, PathBuf, Dnf, Option<qcsg_csg::DnfSize>)],
    rel: f64,
) -> Result<(), String> {
    let mut settings: Vec<(String, Pruning)> = vec![("all on".into(), Pruning::all())];
    for rule in Pruning::RULES {
        let off = Pruning::without(rule).ok_or_else(|| format!("no pruning rule {rule}"))?;
        settings.push((format!("{rule} off"), off));
    }
    let mut construction_off = Pruning::none();
    let mut final_off = Pruning::all();
    for rule in Pruning::RULES.iter().filter(|r| r.starts_with("final_")) {
        construction_off.set(rule, true);
        final_off.set(rule, false);
    }
    settings.push(("construction rules off".into(), construction_off));
    settings.push(("final passes off".into(), final_off));
    settings.push(("all off".into(), Pruning::none()));
    let _ = writeln!(
        md,
        "\nWith each rule off, at r = {rel} diag of the scene (one thread). A row that builds the \
         same DNF as an earlier row repeats that row's sampling (marked =); DNFs over {} literal \
         occurrences are not sampled; \"over the term limit\" is the builder's diagnostic at the \
         default limit of {} terms.",
        SWITCH_SAMPLING_LITERALS,
        qcsg_csg::DEFAULT_TERM_LIMIT
    );
    for (name, path, pruned, _) in compiled {
        let diag = diagonal(pruned);
        let _ = writeln!(md, "\n**{name}**\n");
        let _ = writeln!(
            md,
            "| pruning | terms | literals | quadrics | samples | distance queries | sampling ms |"
        );
        let _ = writeln!(md, "|---|---:|---:|---:|---:|---:|---:|");
        // Built DNFs already sampled, with their sampling cells and the row that sampled them.
        let mut sampled: Vec<(Dnf, String, String)> = Vec::new();
        for (label, pruning) in &settings {
            let options = DnfOptions {
                pruning: *pruning,
                ..DnfOptions::default()
            };
            let c = compile_file(path, &options)?;
            let codes = c.error_codes();
            let Some(dnf) = c.dnf else {
                if codes.contains(&qcsg_csg::codes::TERM_LIMIT) {
                    let _ = writeln!(md, "| {label} | over the term limit | – | – | – | – | – |");
                    continue;
                }
                return Err(format!("{name} with {label}: errors {codes:?}"));
            };
            let same = sampled
                .iter()
                .find(|(d, _, _)| d.terms == dnf.terms && d.quadrics == dnf.quadrics);
            let cells = if let Some((_, cells, row)) = same {
                format!("{cells} (= {row})")
            } else if dnf.literal_count() > SWITCH_SAMPLING_LITERALS {
                "not sampled | – | –".to_string()
            } else {
                let (sampling, t) = one_thread(|| timed_sample(&dnf, rel * diag))??;
                let cells = format!(
                    "{} | {} | {}",
                    sampling.samples.len(),
                    sampling.stats.subdivision.distance_queries,
                    ms(t)
                );
                sampled.push((dnf.clone(), cells.clone(), label.clone()));
                cells
            };
            let _ = writeln!(
                md,
                "| {label} | {} | {} | {} | {cells} |",
                dnf.terms.len(),
                dnf.literal_count(),
                dnf.quadrics.len()
            );
        }
    }
    Ok(())
}
