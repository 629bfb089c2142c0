//! Physics checkpoints and the array job's pieces through the binary (docs/animate.md,
//! "Physics checkpoints", "Shards and resumption"): a `--checkpoints-only` pass followed
//! by `--shard K/N:blocks` tasks gives a full run's frames byte for byte; a resumed run
//! continues from the last checkpoint; damaged or foreign checkpoints are refused naming
//! the file; `--merge` refuses an incomplete set and joins the tasks' timings.

mod support;

use std::path::Path;
use support::{dynray, fails_with, ok};

const SCENE: &str = "examples/physics/soft_box_on_sphere.scn";

fn animate(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["animate", SCENE, "--out", out.to_str().unwrap(), "--width", "40", "--height", "30"];
    args.extend_from_slice(&["--spp", "1"]);
    if !extra.contains(&"--frames") {
        args.extend_from_slice(&["--frames", "0..7"]);
    }
    args.extend_from_slice(extra);
    dynray(&args)
}

fn frames(dir: &Path) -> Vec<Vec<u8>> {
    (0..8).map(|k| std::fs::read(dir.join(format!("frame_{k:04}.png"))).unwrap()).collect()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn blocks_from_a_simulation_pass_and_a_resumed_run_give_a_full_runs_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    ok(animate(&full, &["--checkpoint-every", "0"]));
    assert!(!full.join("checkpoints").exists(), "--checkpoint-every 0 wrote checkpoints");
    let want = frames(&full);
    assert_ne!(want[1], want[7], "nothing moves: the test would prove nothing");

    // The chain: simulate once (a checkpoint every 3 frames), then two blocks.
    let chain = tmp.path().join("chain");
    let sim = ok(animate(&chain, &["--checkpoints-only", "--checkpoint-every", "3"]));
    assert!(stderr(&sim).contains("3 checkpoints written"), "{}", stderr(&sim));
    let names: Vec<String> = {
        let mut v: Vec<String> = std::fs::read_dir(chain.join("checkpoints"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(names, ["state_0000.bin", "state_0003.bin", "state_0006.bin"]);
    assert!(!chain.join("frame_0000.png").exists(), "--checkpoints-only rendered");
    // Block 1 of 2 is frames 4..=7: it starts from frame 3's checkpoint, not time 0.
    let second = ok(animate(&chain, &["--shard", "1/2:blocks", "--checkpoint-every", "3"]));
    assert!(stderr(&second).contains("continues from the checkpoint of frame 3"), "{}", stderr(&second));
    ok(animate(&chain, &["--shard", "0/2:blocks", "--checkpoint-every", "3"]));
    assert_eq!(frames(&chain), want, "blocks from checkpoints differ from one run");

    // A run that stopped after frame 4: the resumed run starts from frame 3's checkpoint.
    let resumed = tmp.path().join("resumed");
    ok(animate(&resumed, &["--checkpoint-every", "3"]));
    for k in 5..8 {
        std::fs::remove_file(resumed.join(format!("frame_{k:04}.png"))).unwrap();
    }
    std::fs::remove_file(resumed.join("checkpoints/state_0006.bin")).unwrap();
    let again = ok(animate(&resumed, &["--checkpoint-every", "3", "--resume"]));
    assert!(stderr(&again).contains("continues from the checkpoint of frame 3"), "{}", stderr(&again));
    assert_eq!(frames(&resumed), want, "the resumed run differs from one run");
}

#[test]
fn damaged_or_foreign_checkpoints_are_refused_naming_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    ok(animate(&out, &["--frames", "0..2", "--checkpoints-only"]));
    let state = out.join("checkpoints/state_0002.bin");
    let mut bytes = std::fs::read(&state).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x40;
    std::fs::write(&state, &bytes).unwrap();
    let o = animate(&out, &["--frames", "2..3"]);
    fails_with(o, "state_0002.bin");
    let o = animate(&out, &["--frames", "2..3"]);
    assert!(stderr(&o).contains("checksum"), "{}", stderr(&o));

    // Another scene's state: the same file name, a different world.
    let other = tmp.path().join("other");
    let drop = "examples/physics/plastic_dent.scn";
    ok(dynray(&["animate", drop, "--out", other.to_str().unwrap(), "--frames", "0..1", "--checkpoints-only"]));
    std::fs::copy(other.join("checkpoints/state_0001.bin"), out.join("checkpoints/state_0001.bin")).unwrap();
    let o = animate(&out, &["--frames", "1..1"]);
    assert!(stderr(&o).contains("another scene"), "{}", stderr(&o));
    assert!(!o.status.success());

    // A scene without physics has nothing to checkpoint.
    let still = tmp.path().join("still");
    let o = dynray(&["animate", "examples/animated.scn", "--out", still.to_str().unwrap(), "--checkpoints-only"]);
    fails_with(o, "no physics to checkpoint");
}

#[test]
fn merge_refuses_missing_frames_and_joins_every_tasks_timings() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    ok(animate(&out, &["--shard", "0/3"]));
    ok(animate(&out, &["--shard", "2/3"]));
    let o = animate(&out, &["--merge"]);
    fails_with(o, "frame_0001.png");
    ok(animate(&out, &["--shard", "1/3"]));
    std::fs::remove_file(out.join("preview.gif")).unwrap();
    let o = ok(animate(&out, &["--merge"]));
    assert!(stderr(&o).contains("8 frames 0..=7 complete; 8 timing rows from 3 files"), "{}", stderr(&o));
    let csv = std::fs::read_to_string(out.join("timings.csv")).unwrap();
    let order: Vec<u32> = csv.lines().skip(1).map(|l| l.split(',').next().unwrap().parse().unwrap()).collect();
    assert_eq!(order, (0..8).collect::<Vec<_>>());
    assert!(out.join("preview.gif").is_file());
    // A file that is not a timings file is named, not skipped.
    std::fs::write(out.join("timings_shard_9_of_9.csv"), "frame;time\n1;2\n").unwrap();
    fails_with(animate(&out, &["--merge"]), "timings_shard_9_of_9.csv");
}

#[test]
fn blocks_awaiting_a_simulation_beside_them_and_a_wait_that_times_out_give_one_runs_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    ok(animate(&full, &["--checkpoint-every", "0"]));
    let want = frames(&full);

    // The simulation job and the second block started together: the block waits for
    // each checkpoint instead of simulating to its first frame.
    let pipe = tmp.path().join("pipe");
    let bin = env!("CARGO_BIN_EXE_dynray");
    let args = |extra: &[&str]| {
        let mut a: Vec<String> = ["animate", SCENE, "--out", pipe.to_str().unwrap(), "--width", "40", "--height", "30"]
            .map(str::to_string)
            .to_vec();
        a.extend(["--spp", "1", "--frames", "0..7"].map(str::to_string));
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let block = std::process::Command::new(bin)
        .current_dir(support::root())
        .args(args(&["--shard", "1/2:blocks", "--await-checkpoints", "60"]))
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    ok(dynray(&args(&["--checkpoints-only"]).iter().map(String::as_str).collect::<Vec<_>>()));
    let o = block.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("continues from the checkpoint of frame 4"), "{}", stderr(&o));
    ok(animate(&pipe, &["--shard", "0/2:blocks"]));
    assert_eq!(frames(&pipe), want, "blocks that awaited checkpoints differ from one run");

    // Nothing writes checkpoints: the wait times out once and the run simulates itself.
    let alone = tmp.path().join("alone");
    let started = std::time::Instant::now();
    ok(animate(&alone, &["--checkpoint-every", "0", "--await-checkpoints", "2"]));
    // Eight frames: waiting for each would take 16 s.
    assert!(started.elapsed() < std::time::Duration::from_secs(10), "waited more than once");
    assert_eq!(frames(&alone), want);
}
