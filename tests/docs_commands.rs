//! Every command line documented in README.md and docs/*.md works (issue 17).
//!
//! A documented command is a line of a fenced code block that runs dynray: `dynray …`,
//! `target/release/dynray …` or `cargo run --release [--features F] -- …` (continuation
//! lines, indented, are joined; a trailing `# comment` is dropped). Three kinds:
//! - a **synopsis** (it has `[`, `…` or an upper-case placeholder such as `FILE`): every
//!   option it names must be one the subcommand's `--help` lists, and every value of a
//!   `--flag a|b|c` list must appear there too, so synopses cannot drift from the code;
//! - a **run** (`render`, `info`, `trace-rays`): executed as written, in a scratch folder
//!   beside a link to `../shared` and to `examples/`, where the placeholder-like files the
//!   docs use exist (`scene.scn` is the Whitted example, `mesh.ply` the bunny, `rays.npy`
//!   the two rays of docs/trace-rays.md's numpy snippet). Renders without a size get
//!   `--width 64 --height 48` appended to keep the suite fast; nothing else is changed;
//! - a **parse check** for `bench` (minutes per run) and `view` (a window; tests/view_cli.rs
//!   runs it under Xvfb): the line with `--help` appended must exit 0, which clap allows
//!   only when every option and value before it is valid.
//!
//! The test fails when it finds fewer commands than the docs hold today, so a change of
//! the extraction cannot make it pass by finding nothing.

mod support;

use npyz::WriterBuilder;
use std::path::{Path, PathBuf};
use std::process::Command;
use support::{root, scenes_dir};

/// A documented command: where it is and its arguments after the program name.
#[derive(Debug)]
struct Documented {
    at: String,
    args: Vec<String>,
}

/// The lines of fenced blocks in `text` that run dynray, with their arguments.
fn commands_in(file: &str, text: &str) -> Vec<Documented> {
    let mut out: Vec<Documented> = Vec::new();
    let mut in_block = false;
    let mut last_was_command = false;
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            last_was_command = false;
            continue;
        }
        if !in_block {
            continue;
        }
        let code = strip_comment(line);
        let trimmed = code.trim();
        if let Some(args) = dynray_args(trimmed) {
            out.push(Documented { at: format!("{file}:{}", i + 1), args });
            last_was_command = true;
        } else if last_was_command && line.starts_with(' ') && trimmed.starts_with('[') {
            // A synopsis continued on the next line.
            out.last_mut().unwrap().args.extend(trimmed.split_whitespace().map(str::to_string));
        } else {
            last_was_command = false;
        }
    }
    out
}

/// `line` without a trailing `# comment` (a `#` after whitespace).
fn strip_comment(line: &str) -> &str {
    match line.find(" #") {
        Some(k) => &line[..k],
        None => line,
    }
}

/// The arguments after the program when `line` runs dynray.
fn dynray_args(line: &str) -> Option<Vec<String>> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let rest = match words.first()? {
        &"dynray" | &"target/release/dynray" => &words[1..],
        &"cargo" if words.get(1) == Some(&"run") => {
            let sep = words.iter().position(|w| *w == "--")?;
            &words[sep + 1..]
        }
        _ => return None,
    };
    Some(rest.iter().map(|s| s.to_string()).collect())
}

fn is_synopsis(args: &[String]) -> bool {
    args.iter().any(|a| {
        a.contains('[') || a.contains('…') || {
            let w = a.trim_matches(|c: char| !c.is_ascii_alphanumeric());
            w.len() >= 2 && w.chars().all(|c| c.is_ascii_uppercase() || c == '_')
        }
    })
}

/// The subcommand: the first argument that is not an option or an option's value.
fn subcommand(args: &[String]) -> Option<&str> {
    let mut skip = false;
    for a in args {
        let a = a.trim_matches(|c| c == '[' || c == ']');
        if skip {
            skip = false;
            continue;
        }
        if a == "--threads" {
            skip = true;
            continue;
        }
        if !a.starts_with('-') {
            return Some(a);
        }
    }
    None
}

fn help_of(sub: Option<&str>) -> String {
    let mut c = Command::new(env!("CARGO_BIN_EXE_dynray"));
    if let Some(s) = sub {
        c.arg(s);
    }
    let o = c.arg("--help").output().expect("run dynray --help");
    assert!(o.status.success());
    String::from_utf8(o.stdout).unwrap()
}

/// The word after subcommand `sub` when it names a nested subcommand (lower-case
/// letters only, as `build` in `dynray adf build MESH`).
fn nested_subcommand<'a>(args: &'a [String], sub: &str) -> Option<&'a str> {
    let at = args.iter().position(|a| a == sub)?;
    let next = args.get(at + 1)?;
    (!next.is_empty() && next.chars().all(|c| c.is_ascii_lowercase())).then_some(next.as_str())
}

fn help_of_nested(sub: &str, nested: &str) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_dynray")).args([sub, nested, "--help"]).output().expect("run dynray");
    if o.status.success() {
        String::from_utf8(o.stdout).unwrap()
    } else {
        String::new()
    }
}

/// Checks a synopsis against `--help`; returns what is wrong.
fn check_synopsis(d: &Documented) -> Vec<String> {
    let sub = subcommand(&d.args);
    let mut help = format!("{}\n{}", help_of(sub), help_of(None));
    // A nested subcommand (`adf build`): its own options too.
    if let Some(nested) = sub.and_then(|s| nested_subcommand(&d.args, s)) {
        help.push_str(&help_of_nested(sub.unwrap_or(""), nested));
    }
    let mut wrong = Vec::new();
    let words: Vec<String> = d
        .args
        .iter()
        .map(|a| a.trim_matches(|c| c == '[' || c == ']' || c == ',').to_string())
        .filter(|a| !a.is_empty())
        .collect();
    for (k, w) in words.iter().enumerate() {
        for flag in w.split('|').filter(|f| f.starts_with('-')) {
            let name = flag.split(['=', '[']).next().unwrap();
            if !help.split(|c: char| c.is_whitespace() || c == ',').any(|h| h == name) {
                wrong.push(format!("option `{name}` is not in `dynray {} --help`", sub.unwrap_or("")));
            }
        }
        if w.starts_with("--") {
            if let Some(values) = words.get(k + 1).filter(|v| v.contains('|') && !v.starts_with('-')) {
                for v in values.split('|') {
                    if !help.contains(v) {
                        wrong.push(format!("value `{v}` of `{w}` is not in `dynray {} --help`", sub.unwrap_or("")));
                    }
                }
            }
        }
    }
    wrong
}

/// A scratch folder laid out like the checkout for the documented relative paths.
struct Scratch {
    _dir: tempfile::TempDir,
    cwd: PathBuf,
}

fn scratch() -> Scratch {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path().join("work");
    std::fs::create_dir(&cwd).unwrap();
    let shared = scenes_dir().join("..");
    std::os::unix::fs::symlink(
        shared.canonicalize().expect("../shared beside the checkout"),
        dir.path().join("shared"),
    )
    .unwrap();
    std::os::unix::fs::symlink(root().join("examples"), cwd.join("examples")).unwrap();
    std::fs::copy(root().join("examples/whitted.scn"), cwd.join("scene.scn")).unwrap();
    std::os::unix::fs::symlink(scenes_dir().join("bunny/bun_zipper.ply"), cwd.join("mesh.ply")).unwrap();
    // docs/trace-rays.md's numpy snippet: two rays from (0, 0.1, 1) along -z, tmax inf.
    let row = [0.0f32, 0.1, 1.0, 0.0, 0.0, -1.0, 0.0, f32::INFINITY];
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[2, 8])
        .writer(std::fs::File::create(cwd.join("rays.npy")).unwrap())
        .begin_nd()
        .unwrap();
    w.extend(row.iter().chain(&row).copied()).unwrap();
    w.finish().unwrap();
    Scratch { _dir: dir, cwd }
}

fn run(d: &Documented, cwd: &Path) -> Result<(), String> {
    let mut args = d.args.clone();
    let sub = subcommand(&args).unwrap_or("").to_string();
    if sub == "render" && !args.iter().any(|a| a == "--width" || a == "--height") {
        args.extend(["--width", "64", "--height", "48"].map(String::from));
    }
    if sub == "bench" || sub == "view" {
        args.push("--help".into());
    }
    let o = Command::new(env!("CARGO_BIN_EXE_dynray")).current_dir(cwd).args(&args).output().expect("run dynray");
    if o.status.success() {
        Ok(())
    } else {
        Err(format!("`dynray {}` exited with {}: {}", args.join(" "), o.status, String::from_utf8_lossy(&o.stderr)))
    }
}

fn documented() -> Vec<Documented> {
    let mut files = vec![root().join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
        .iter()
        .flat_map(|f| {
            let name = f.strip_prefix(root()).unwrap().display().to_string();
            commands_in(&name, &std::fs::read_to_string(f).unwrap())
        })
        .collect()
}

#[test]
fn every_documented_command_line_works() {
    let all = documented();
    assert!(all.len() >= 15, "found only {} documented commands: {all:?}", all.len());
    let scratch = scratch();
    let mut failures = Vec::new();
    let (mut synopses, mut runs) = (0, 0);
    for d in &all {
        if is_synopsis(&d.args) {
            synopses += 1;
            failures.extend(check_synopsis(d).into_iter().map(|w| format!("{}: {w}", d.at)));
        } else {
            runs += 1;
            if let Err(e) = run(d, &scratch.cwd) {
                failures.push(format!("{}: {e}", d.at));
            }
        }
    }
    eprintln!("{} documented commands: {synopses} synopses, {runs} runs", all.len());
    assert!(synopses >= 5 && runs >= 8, "{synopses} synopses, {runs} runs");
    assert!(failures.is_empty(), "{} documented commands fail:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn the_extraction_sees_synopses_runs_and_continuations() {
    let text = "intro `dynray render x` inline is not a command\n\
        ```sh\n\
        dynray render -o a.png --spp 1     # comment\n\
        dynray info FILE [--accel NAME]\n\
        \x20            [--more]\n\
        cargo run --release --features compare -- bench --quick\n\
        cargo test --workspace\n\
        ```\n";
    let found = commands_in("t.md", text);
    assert_eq!(found.len(), 3, "{found:?}");
    assert_eq!(found[0].args, ["render", "-o", "a.png", "--spp", "1"]);
    assert!(!is_synopsis(&found[0].args));
    assert!(is_synopsis(&found[1].args) && found[1].args.last().unwrap() == "[--more]");
    assert_eq!(found[2].args, ["bench", "--quick"]);
    assert_eq!(subcommand(&["--threads".into(), "2".into(), "bench".into()]), Some("bench"));
    // A synopsis naming an option the binary lacks is caught.
    let bogus = Documented { at: "t".into(), args: vec!["render".into(), "[--no-such-option]".into()] };
    assert_eq!(check_synopsis(&bogus).len(), 1);
    let bad_value =
        Documented { at: "t".into(), args: vec!["render".into(), "[--aov".into(), "depth|sparkle]".into()] };
    assert_eq!(check_synopsis(&bad_value).len(), 1, "{:?}", check_synopsis(&bad_value));
}
