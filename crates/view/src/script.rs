//! `--script FILE`: input events for tests and demos, one per line, played one frame
//! after another. `wait N` lets N frames pass, `key NAME` presses a key (the names of
//! [`crate::keys`]), `drag X0 Y0 X1 Y1` drags with the left button in window pixels,
//! `scroll N` turns the wheel N notches (positive: towards the scene); `#` starts a
//! comment.

use anyhow::{bail, Context, Result};
use std::path::Path;

/// One scripted event.
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    /// Let this many frames pass.
    Wait(u32),
    /// Press (and release) the key of this name.
    Key(String),
    /// A left-button drag from one window position to another.
    Drag {
        /// Where the button goes down, window pixels.
        from: (f32, f32),
        /// Where it comes up.
        to: (f32, f32),
    },
    /// Wheel notches.
    Scroll(f32),
}

/// Most lines a script may have: a script is typed by a person, and a longer file is
/// more likely a mistake than a demo.
const MAX_LINES: usize = 100_000;

/// A parsed script and where it has got to.
#[derive(Clone, Debug, Default)]
pub struct Script {
    events: Vec<Event>,
    next: usize,
    /// Frames still to wait before the next event.
    waiting: u32,
}

impl Script {
    /// Reads `path`; errors name the file and line.
    pub fn load(path: &Path) -> Result<Self> {
        let meta = std::fs::metadata(path).with_context(|| format!("{}: cannot read the script", path.display()))?;
        if !meta.is_file() {
            bail!("{}: not a regular file", path.display());
        }
        if meta.len() > 16 << 20 {
            bail!("{}: {} bytes is too long for a script (16 MiB at most)", path.display(), meta.len());
        }
        let text =
            std::fs::read_to_string(path).with_context(|| format!("{}: cannot read the script", path.display()))?;
        Self::parse(&text).with_context(|| path.display().to_string())
    }

    /// Parses script text; errors give the line.
    pub fn parse(text: &str) -> Result<Self> {
        let mut events = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            if i >= MAX_LINES {
                bail!("more than {MAX_LINES} lines");
            }
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let event = parse_line(line).with_context(|| format!("line {}: `{line}`", i + 1))?;
            events.push(event);
        }
        Ok(Script { events, next: 0, waiting: 0 })
    }

    /// The events of this frame: everything up to the next `wait` (which then holds the
    /// following events back for its frames).
    pub fn frame_events(&mut self) -> Vec<Event> {
        let mut out = Vec::new();
        if self.waiting > 0 {
            self.waiting -= 1;
            return out;
        }
        while let Some(e) = self.events.get(self.next) {
            self.next += 1;
            match e {
                Event::Wait(n) if *n > 0 => {
                    self.waiting = n - 1;
                    break;
                }
                Event::Wait(_) => {}
                other => out.push(other.clone()),
            }
        }
        out
    }

    /// True when every event has been played.
    pub fn finished(&self) -> bool {
        self.next >= self.events.len() && self.waiting == 0
    }
}

fn parse_line(line: &str) -> Result<Event> {
    let mut words = line.split_whitespace();
    let verb = words.next().unwrap_or_default();
    let args: Vec<&str> = words.collect();
    let numbers = |n: usize| -> Result<Vec<f32>> {
        if args.len() != n {
            bail!("`{verb}` takes {n} number{}, got {}", if n == 1 { "" } else { "s" }, args.len());
        }
        args.iter()
            .map(|a| match a.parse::<f32>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => bail!("`{a}` is not a finite number"),
            })
            .collect()
    };
    Ok(match verb {
        "wait" => {
            let [n] = args[..] else { bail!("`wait` takes a frame count") };
            Event::Wait(n.parse().map_err(|_| anyhow::anyhow!("`{n}` is not a frame count"))?)
        }
        "key" => {
            let [name] = args[..] else { bail!("`key` takes one key name") };
            if crate::keys::Command::of_key(name).is_none() {
                bail!("unknown key `{name}` (keys: {})", crate::keys::NAMES.join(", "));
            }
            Event::Key(name.to_ascii_lowercase())
        }
        "drag" => {
            let v = numbers(4)?;
            Event::Drag { from: (v[0], v[1]), to: (v[2], v[3]) }
        }
        "scroll" => Event::Scroll(numbers(1)?[0]),
        _ => bail!("unknown event `{verb}` (expected wait, key, drag or scroll)"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_come_a_frame_at_a_time_with_waits_between() {
        let mut s = Script::parse("# orbit a bit\nkey space\ndrag 10 20 30 40\nwait 2\nscroll -1.5 # out\n").unwrap();
        assert_eq!(
            s.frame_events(),
            [Event::Key("space".into()), Event::Drag { from: (10.0, 20.0), to: (30.0, 40.0) }]
        );
        assert!(s.frame_events().is_empty(), "the second of the two waited frames");
        assert!(!s.finished());
        assert_eq!(s.frame_events(), [Event::Scroll(-1.5)]);
        assert!(s.finished());
        assert!(s.frame_events().is_empty());
    }

    #[test]
    fn wait_zero_waits_for_nothing() {
        let mut s = Script::parse("key r\nwait 0\nkey 2").unwrap();
        assert_eq!(s.frame_events().len(), 2);
    }

    #[test]
    fn mistakes_name_the_line() {
        for (text, want) in [
            ("key r\njump 3", "line 2: `jump 3`"),
            ("drag 1 2 3", "line 1"),
            ("wait -1", "frame count"),
            ("key nosuchkey", "unknown key `nosuchkey`"),
            ("scroll nan", "not a finite number"),
        ] {
            let e = format!("{:#}", Script::parse(text).unwrap_err());
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }
}
