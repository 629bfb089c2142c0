//! `deploy/slurm/animate.sbatch` on a live one-node Slurm cluster (Debian's `slurm-wlm`
//! and `munge`, started by `deploy/slurm/local-cluster.sh`): an array job of three tasks
//! gives one process's frames byte for byte; a task cancelled part-way and requeued
//! finishes its frames and the set is still identical; `merge.sbatch` joins the timings.
//!
//! Needs the packages and root (the daemons run as root). Without them the test says so
//! and passes, unless `DYNRAY_REQUIRE_SLURM=1` (what `.ci/run` sets after installing
//! them) makes that a failure.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};
use support::{dynray, ok, root, scenes_dir, skipped};

/// The cluster of one test, stopped when dropped.
struct Cluster {
    dir: PathBuf,
    conf: PathBuf,
}

impl Cluster {
    /// Starts a cluster under `dir`, or says why it cannot.
    fn start(dir: &Path) -> Result<Cluster, String> {
        let tools = ["munged", "slurmctld", "slurmd", "sbatch", "squeue", "scancel", "scontrol"];
        if let Some(missing) = tools.iter().find(|t| which(t).is_none()) {
            return Err(format!("{missing} is not installed (apt-get install slurm-wlm munge)"));
        }
        let uid = Command::new("id").arg("-u").output().map_err(|e| e.to_string())?;
        if String::from_utf8_lossy(&uid.stdout).trim() != "0" {
            return Err("the Slurm daemons run as root and this test is not".into());
        }
        // Ports of our own, away from a cluster someone may already run on 6817/6818.
        let port = 20_000 + (std::process::id() % 10_000) * 2;
        let script = root().join("deploy/slurm/local-cluster.sh");
        let o = Command::new(&script)
            .arg("start")
            .arg(dir)
            .env("SLURMCTLD_PORT", port.to_string())
            .env("SLURMD_PORT", (port + 1).to_string())
            .output()
            .map_err(|e| format!("{}: {e}", script.display()))?;
        if !o.status.success() {
            return Err(format!("local-cluster.sh start failed: {}", String::from_utf8_lossy(&o.stderr)));
        }
        Ok(Cluster { dir: dir.to_path_buf(), conf: dir.join("slurm.conf") })
    }

    /// A Slurm command against this cluster, run in `cwd` (where jobs write their logs).
    fn command(&self, program: &str, cwd: &Path) -> Command {
        let mut c = Command::new(program);
        c.current_dir(cwd).env("SLURM_CONF", &self.conf).env("DYNRAY", env!("CARGO_BIN_EXE_dynray"));
        c
    }

    /// Runs `program args` and returns its stdout, failing the test on an error.
    fn run(&self, program: &str, args: &[&str], cwd: &Path) -> String {
        let o = self.command(program, cwd).args(args).output().unwrap_or_else(|e| panic!("{program}: {e}"));
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(o.status.success(), "{program} {args:?}: {}\n{text}{}", o.status, String::from_utf8_lossy(&o.stderr));
        text
    }

    /// Array tasks of `job` still pending or running.
    fn live_tasks(&self, job: &str, cwd: &Path) -> Vec<String> {
        let out = self.run("squeue", &["-h", "-r", "-j", job, "-t", "PD,R,CG,CF,RQ,RS,S", "-o", "%i %T"], cwd);
        out.lines().map(str::to_string).collect()
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(root().join("deploy/slurm/local-cluster.sh")).arg("stop").arg(&self.dir).output();
    }
}

fn which(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .chain(["/usr/sbin", "/sbin"].map(PathBuf::from))
        .map(|d| d.join(program))
        .find(|p| p.is_file())
}

/// CesiumMan's walk, 18 frames path traced on one thread each: about a third of a
/// second a frame, so a task is still running when the test cancels it.
fn options() -> Vec<String> {
    ["--frames", "0..17", "--width", "192", "--height", "144", "--spp", "32", "--integrator", "path"]
        .map(str::to_string)
        .to_vec()
}

fn scene() -> String {
    scenes_dir().join("CesiumMan/glTF/CesiumMan.gltf").to_string_lossy().into_owned()
}

fn frame(dir: &Path, k: u32) -> PathBuf {
    dir.join(format!("frame_{k:04}.png"))
}

fn frames(dir: &Path) -> Vec<Vec<u8>> {
    (0..18).map(|k| std::fs::read(frame(dir, k)).unwrap_or_else(|e| panic!("frame {k}: {e}"))).collect()
}

fn wait_for(what: &str, limit: Duration, mut done: impl FnMut() -> bool) {
    let start = Instant::now();
    while !done() {
        assert!(start.elapsed() < limit, "waited {limit:?} for {what}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// `sbatch` arguments submitting `animate.sbatch` as a 3-task array, one CPU a task.
fn array_job(out: &Path, scene: &str, opts: &[String]) -> Vec<String> {
    let script = root().join("deploy/slurm/animate.sbatch");
    let mut args: Vec<String> = ["--parsable", "--cpus-per-task", "1", "--array=0-2"].map(str::to_string).to_vec();
    args.extend([script.to_string_lossy().into_owned(), scene.to_string(), out.to_string_lossy().into_owned()]);
    args.extend(opts.iter().cloned());
    args
}

#[test]
fn an_array_job_and_a_cancelled_requeued_task_give_one_processs_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let cluster = match Cluster::start(&tmp.path().join("cluster")) {
        Ok(c) => c,
        Err(why) if std::env::var_os("DYNRAY_REQUIRE_SLURM").is_some_and(|v| v == "1") => {
            panic!("DYNRAY_REQUIRE_SLURM=1 but no Slurm cluster could be started: {why}")
        }
        Err(why) => {
            skipped(&format!("no Slurm cluster on this machine: {why}"));
            return;
        }
    };
    let scene = scene();
    let opts = options();
    let reference = tmp.path().join("one-process");
    let mut args = vec!["animate", &scene, "--out", reference.to_str().unwrap()];
    args.extend(opts.iter().map(String::as_str));
    ok(dynray(&args));
    let want = frames(&reference);
    let jobs = tmp.path().to_path_buf();

    // Three tasks, submitted and waited for as docs/animate.md shows.
    let out = tmp.path().join("array");
    let mut args = array_job(&out, &scene, &opts);
    args.insert(0, "--wait".into());
    cluster.run("sbatch", &args.iter().map(String::as_str).collect::<Vec<_>>(), &jobs);
    assert_eq!(frames(&out), want, "the array job's frames differ from one process's");
    for k in 0..3 {
        assert!(out.join(format!("timings_shard_{k}_of_3.csv")).is_file(), "task {k} wrote no timings");
    }
    let merge = root().join("deploy/slurm/merge.sbatch");
    let mut args = vec!["--wait", merge.to_str().unwrap(), &scene, out.to_str().unwrap()];
    args.extend(opts.iter().map(String::as_str));
    cluster.run("sbatch", &args, &jobs);
    let csv = std::fs::read_to_string(out.join("timings.csv")).unwrap();
    assert_eq!(csv.lines().count(), 19, "timings.csv: a header and 18 rows expected:\n{csv}");
    assert!(out.join("preview.gif").is_file());

    // Task 1 (frames 1, 4, …, 16) cancelled after its first frame, then requeued.
    let out = tmp.path().join("cancelled");
    let args = array_job(&out, &scene, &opts);
    let job = cluster.run("sbatch", &args.iter().map(String::as_str).collect::<Vec<_>>(), &jobs);
    let job = job.trim().to_string();
    let task = format!("{job}_1");
    wait_for("task 1's first frame", Duration::from_secs(120), || frame(&out, 1).is_file());
    cluster.run("scancel", &[&task], &jobs);
    wait_for("task 1 to stop", Duration::from_secs(60), || {
        !cluster.live_tasks(&job, &jobs).iter().any(|t| t.starts_with(&format!("{task} ")))
    });
    let left: Vec<u32> = (1..18).step_by(3).filter(|&k| !frame(&out, k).is_file()).collect();
    assert!(!left.is_empty(), "task 1 finished before it was cancelled: the test proved nothing");
    // Requeued tasks wait out a delay before they may start again; start it now.
    cluster.run("scontrol", &["requeue", &task], &jobs);
    cluster.run("scontrol", &["update", &format!("jobid={task}"), "StartTime=now"], &jobs);
    wait_for("every task to end", Duration::from_secs(300), || cluster.live_tasks(&job, &jobs).is_empty());
    assert_eq!(frames(&out), want, "after a cancelled and requeued task the frames differ from one process's");
    let log = std::fs::read_to_string(jobs.join(format!("dynray-animate-{job}_1.log"))).unwrap_or_default();
    assert!(log.contains("restart 1"), "task 1's log shows no restart:\n{log}");
    assert!(log.contains(&format!("resuming: {} of 6 frames already there", 6 - left.len())), "{log}");
}
