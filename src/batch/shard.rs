//! `--shard K/N`: the K-th of N slices of the sorted inputs, so N machines share a library.

use super::error::BatchError;
use super::inputs::Input;

/// `--shard K/N`: the inputs whose 0-based index `i` in the sorted list has `i mod N = K − 1`
/// (K counts from 1, as Slurm array indices and `parallel`'s `{%}` may be made to). The N
/// shards are disjoint, their union is every input, and their sizes differ by at most one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 1-based shard number.
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = BatchError;
    fn from_str(s: &str) -> Result<Shard, BatchError> {
        let bad = || BatchError::Shard(s.to_string());
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if k == 0 || n == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl Shard {
    /// This shard's inputs, in order.
    pub fn select(&self, inputs: Vec<Input>) -> Vec<Input> {
        inputs
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % self.n == self.k - 1)
            .map(|(_, x)| x)
            .collect()
    }

    /// The file name of this shard's summary: `summary.K-of-N.json` (or `.csv`), so shards
    /// sharing one output folder do not overwrite each other's.
    pub fn summary_name(&self, ext: &str) -> String {
        format!("summary.{}-of-{}.{ext}", self.k, self.n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_are_disjoint_balanced_and_cover_everything() {
        let inputs: Vec<Input> = (0..11)
            .map(|i| Input {
                path: format!("p{i:02}.step").into(),
                out_rel: format!("p{i:02}").into(),
            })
            .collect();
        for n in 1..=5 {
            let mut all = vec![];
            let mut sizes = vec![];
            for k in 1..=n {
                let s = Shard { k, n }.select(inputs.clone());
                sizes.push(s.len());
                all.extend(s);
            }
            all.sort_by(|a, b| a.path.cmp(&b.path));
            assert_eq!(all, inputs, "n = {n}");
            assert!(sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1);
        }
        assert_eq!(
            Shard { k: 2, n: 3 }.select(inputs.clone())[0].path,
            inputs[1].path
        );
    }

    #[test]
    fn shard_specs_parse() {
        assert_eq!("3/8".parse::<Shard>().unwrap(), Shard { k: 3, n: 8 });
        for bad in ["0/4", "5/4", "1/0", "1", "a/b", "1/2/3", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
