//! Which frames of a timeline one task of an array job renders (`--shard K/N` and
//! `--shard K/N:blocks`, docs/animate.md, "Shards and resumption").

use std::fmt;
use std::str::FromStr;

/// How the frames are dealt to the `N` tasks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShardLayout {
    /// Task `K` renders the frames `k` with `k % N == K`: the tasks finish together
    /// whatever each frame costs.
    #[default]
    Interleaved,
    /// Task `K` renders the `K`-th of `N` contiguous, near-equal ranges: with physics,
    /// each task starts from the checkpoint nearest its first frame instead of stepping
    /// through the other tasks' frames.
    Blocks,
}

/// Task `index` of `count`, and how frames are dealt.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// `K`, below `count`.
    pub index: u32,
    /// `N`, at least 1.
    pub count: u32,
    /// Interleaved or blocks.
    pub layout: ShardLayout,
}

impl Shard {
    /// The whole timeline in one task.
    pub const WHOLE: Shard = Shard { index: 0, count: 1, layout: ShardLayout::Interleaved };

    /// How many frames of `first..=last` are this task's, without listing them (a
    /// timeline of 2^32 frames must not become a list first).
    pub fn frame_count(&self, first: u32, last: u32) -> u64 {
        match self.layout {
            ShardLayout::Interleaved => {
                let (k, n) = (self.index as u64, self.count as u64);
                // Frames of 0..=x that are the shard's.
                let upto = |x: u64| if x < k { 0 } else { (x - k) / n + 1 };
                upto(last as u64) - if first == 0 { 0 } else { upto(first as u64 - 1) }
            }
            ShardLayout::Blocks => {
                let (a, b) = self.block(first, last);
                b - a
            }
        }
    }

    /// This task's frames of `first..=last`, in order.
    pub fn frames(&self, first: u32, last: u32) -> Vec<u32> {
        match self.layout {
            ShardLayout::Interleaved => (first..=last).filter(|k| k % self.count == self.index).collect(),
            ShardLayout::Blocks => {
                let (a, b) = self.block(first, last);
                (a..b).map(|k| k as u32).collect()
            }
        }
    }

    /// The half-open block `[a, b)` of `first..=last` that is task `index`'s: block
    /// boundaries at `first + ⌊i T / N⌋`, so sizes differ by at most one frame.
    fn block(&self, first: u32, last: u32) -> (u64, u64) {
        let total = last as u64 - first as u64 + 1;
        let at = |i: u64| first as u64 + i * total / self.count as u64;
        (at(self.index as u64), at(self.index as u64 + 1))
    }

    /// The timings file of this task.
    pub fn timings_name(&self) -> String {
        if self.count == 1 {
            "timings.csv".to_string()
        } else {
            format!("timings_shard_{}_of_{}.csv", self.index, self.count)
        }
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)?;
        if self.layout == ShardLayout::Blocks {
            f.write_str(":blocks")?;
        }
        Ok(())
    }
}

impl FromStr for Shard {
    type Err = String;

    /// `K/N`, `K/N:interleaved` or `K/N:blocks`, with `0 <= K < N`.
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("`{s}`: expected K/N or K/N:blocks with 0 <= K < N, as in 0/4");
        let (kn, layout) = match s.split_once(':') {
            None => (s, ShardLayout::Interleaved),
            Some((kn, "interleaved")) => (kn, ShardLayout::Interleaved),
            Some((kn, "blocks")) => (kn, ShardLayout::Blocks),
            Some((_, other)) => return Err(format!("`{s}`: unknown shard layout `{other}` (interleaved or blocks)")),
        };
        let (k, n) = kn.split_once('/').ok_or_else(bad)?;
        let (index, count) = (k.trim().parse::<u32>().map_err(|_| bad())?, n.trim().parse::<u32>().map_err(|_| bad())?);
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count, layout })
    }
}

#[cfg(test)]
mod tests {
    use super::{Shard, ShardLayout};

    #[test]
    fn counts_agree_with_the_lists_and_the_tasks_cover_every_frame_once() {
        for (first, last) in [(0, 0), (0, 9), (3, 17), (5, 5), (7, 100)] {
            for count in 1..6 {
                for layout in [ShardLayout::Interleaved, ShardLayout::Blocks] {
                    let mut all = Vec::new();
                    for index in 0..count {
                        let s = Shard { index, count, layout };
                        let mine = s.frames(first, last);
                        assert_eq!(s.frame_count(first, last), mine.len() as u64, "{first}..={last} {s}");
                        all.extend(mine);
                    }
                    all.sort_unstable();
                    assert_eq!(all, (first..=last).collect::<Vec<_>>(), "{first}..={last} over {count} {layout:?}");
                }
            }
        }
        assert_eq!(Shard::WHOLE.frame_count(0, u32::MAX), 1 << 32);
        let half = Shard { index: 1, count: 2, layout: ShardLayout::Blocks };
        assert_eq!(half.frame_count(0, u32::MAX), 1 << 31);
    }

    #[test]
    fn blocks_are_contiguous_and_near_equal() {
        let sizes: Vec<usize> =
            (0..4).map(|index| Shard { index, count: 4, layout: ShardLayout::Blocks }.frames(0, 9).len()).collect();
        assert_eq!(sizes, [2, 3, 2, 3]);
        assert_eq!(Shard { index: 1, count: 4, layout: ShardLayout::Blocks }.frames(0, 9), [2, 3, 4]);
    }

    #[test]
    fn parses_and_prints_back() {
        for s in ["0/1", "2/3", "1/4:blocks"] {
            assert_eq!(s.parse::<Shard>().unwrap().to_string(), s);
        }
        assert_eq!("2/3:interleaved".parse::<Shard>().unwrap().to_string(), "2/3");
        for bad in ["3/3", "1/0", "1", "a/b", "1/2:stripes", "-1/2"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
