//! `dynray view`: the live window, run by the dynray-view crate over the engine's live
//! job.

use crate::cli::ViewArgs;
use anyhow::Result;

#[cfg(feature = "view")]
pub fn run(a: ViewArgs) -> Result<()> {
    let job = a.image.job();
    // Option combinations fail at once, before the scene is read or a window opens.
    super::usage(job.check())?;
    dynray_view::run(dynray_view::ViewOptions {
        scene: a.scene,
        job,
        policy: a.update,
        threads: None,
        play: a.play,
        show: a.show,
        script: a.script,
        exit_after: a.exit_after,
        screenshot: a.screenshot,
        no_overlay: a.no_overlay,
        timings: a.timings,
        record: a.record,
        scale: a.scale,
    })
}

#[cfg(not(feature = "view"))]
pub fn run(_: ViewArgs) -> Result<()> {
    anyhow::bail!("this dynray was built without the window (the `view` feature): rebuild with default features")
}
