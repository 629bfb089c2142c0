//! The viewer's keys: one table from key names (what `--script` writes and the help
//! lists) to commands, shared by the keyboard and scripts.

use winit::keyboard::{Key, NamedKey};

/// What a key does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// Play or pause the animation.
    TogglePlay,
    /// One timeline frame forward.
    StepForward,
    /// One timeline frame back.
    StepBack,
    /// Back to the scene's camera.
    ResetCamera,
    /// Fly along the view (+1 forward, -1 back), right (+1) / left, up (+1) / down.
    Fly(i8, i8, i8),
    /// Show the image.
    ShowImage,
    /// Show the traversal-cost heat map.
    ShowHeatmap,
    /// Draw the structure's boxes over the image.
    ShowBoxes,
    /// One level deeper (+1) or shallower (-1) of boxes.
    BoxDepth(i8),
    /// Save the image as PNG.
    SavePng,
    /// Save the image as EXR (linear radiance).
    SaveExr,
    /// Write the frame timings so far.
    WriteTimings,
    /// Switch to the next structure (every kind in turn, default parameters).
    NextStructure,
    /// Show or hide the panel and statistics.
    ToggleOverlay,
    /// Close the window.
    Quit,
}

/// Every key name with its command, in the order the help lists them.
const TABLE: &[(&str, Command)] = &[
    ("space", Command::TogglePlay),
    ("right", Command::StepForward),
    ("left", Command::StepBack),
    ("r", Command::ResetCamera),
    ("w", Command::Fly(1, 0, 0)),
    ("s", Command::Fly(-1, 0, 0)),
    ("a", Command::Fly(0, -1, 0)),
    ("d", Command::Fly(0, 1, 0)),
    ("e", Command::Fly(0, 0, 1)),
    ("q", Command::Fly(0, 0, -1)),
    ("1", Command::ShowImage),
    ("2", Command::ShowHeatmap),
    ("3", Command::ShowBoxes),
    ("plus", Command::BoxDepth(1)),
    ("minus", Command::BoxDepth(-1)),
    ("p", Command::SavePng),
    ("x", Command::SaveExr),
    ("t", Command::WriteTimings),
    ("n", Command::NextStructure),
    ("tab", Command::ToggleOverlay),
    ("escape", Command::Quit),
];

/// The key names scripts may use.
pub const NAMES: &[&str] = &[
    "space", "right", "left", "r", "w", "s", "a", "d", "e", "q", "1", "2", "3", "plus", "minus", "p", "x", "t", "n",
    "tab", "escape",
];

impl Command {
    /// The command of key `name` (case-insensitive).
    pub fn of_key(name: &str) -> Option<Command> {
        let name = name.to_ascii_lowercase();
        TABLE.iter().find(|(n, _)| *n == name).map(|&(_, c)| c)
    }

    /// The command of a pressed key.
    pub fn of_winit(key: &Key) -> Option<Command> {
        let name = match key {
            Key::Named(NamedKey::Space) => "space",
            Key::Named(NamedKey::ArrowRight) => "right",
            Key::Named(NamedKey::ArrowLeft) => "left",
            Key::Named(NamedKey::Tab) => "tab",
            Key::Named(NamedKey::Escape) => "escape",
            Key::Character(c) => match c.as_str() {
                "+" | "=" => "plus",
                "-" | "_" => "minus",
                s => return Command::of_key(s),
            },
            _ => return None,
        };
        Command::of_key(name)
    }
}

/// One line per key for the panel's help: `space  play / pause`.
pub fn help() -> Vec<(&'static str, &'static str)> {
    TABLE
        .iter()
        .map(|&(name, c)| {
            let what = match c {
                Command::TogglePlay => "play / pause",
                Command::StepForward => "next frame",
                Command::StepBack => "previous frame",
                Command::ResetCamera => "the scene's camera",
                Command::Fly(1, _, _) => "fly forward",
                Command::Fly(-1, _, _) => "fly back",
                Command::Fly(_, -1, _) => "fly left",
                Command::Fly(_, 1, _) => "fly right",
                Command::Fly(_, _, 1) => "fly up",
                Command::Fly(_, _, _) => "fly down",
                Command::ShowImage => "image",
                Command::ShowHeatmap => "heat map",
                Command::ShowBoxes => "boxes",
                Command::BoxDepth(1) => "deeper boxes",
                Command::BoxDepth(_) => "shallower boxes",
                Command::SavePng => "save PNG",
                Command::SaveExr => "save EXR",
                Command::WriteTimings => "write timings",
                Command::NextStructure => "next structure",
                Command::ToggleOverlay => "panel on / off",
                Command::Quit => "quit",
            };
            (name, what)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_has_a_command_and_the_lists_agree() {
        assert_eq!(NAMES.len(), TABLE.len());
        for (n, (t, _)) in NAMES.iter().zip(TABLE) {
            assert_eq!(n, t);
            assert!(Command::of_key(n).is_some());
        }
        assert_eq!(Command::of_key("W"), Some(Command::Fly(1, 0, 0)));
        assert_eq!(Command::of_winit(&Key::Character("=".into())), Some(Command::BoxDepth(1)));
        assert_eq!(help().len(), TABLE.len());
    }
}
