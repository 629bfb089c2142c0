//! Where rays are traced: `--backend cpu|gpu` on `render`, `trace-rays` and `bench`.

/// The processor a command traces on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Backend {
    /// The CPU structures, in parallel with rayon.
    #[default]
    Cpu,
    /// This crate's kernels on the adapter [`crate::GpuContext`] opens.
    Gpu,
}

impl Backend {
    /// The names `--backend` accepts.
    pub const NAMES: [&'static str; 2] = ["cpu", "gpu"];

    /// The `--backend` spelling.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
        }
    }
}

impl std::str::FromStr for Backend {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "cpu" => Ok(Backend::Cpu),
            "gpu" => Ok(Backend::Gpu),
            _ => Err(format!("unknown backend `{s}` (expected one of: cpu, gpu)")),
        }
    }
}

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
