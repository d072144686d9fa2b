//! "Did you mean …?" for unknown commands: the known command nearest to a
//! mistyped name by edit distance (insertions, deletions, substitutions and swaps of two
//! neighbouring letters each count 1).

/// The optimal-string-alignment distance between `a` and `b`.
pub fn distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for j in 0..=b.len() {
        d[0][j] = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = best;
        }
    }
    d[a.len()][b.len()]
}

/// The candidate nearest to `name`, if one is close enough to be a likely typo: at most a
/// third of the name's letters wrong (at least one), or `name` a prefix of exactly one of
/// them. Ties go to the first candidate.
pub fn nearest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (name.chars().count() / 3).max(1);
    let candidates: Vec<&str> = candidates.into_iter().filter(|c| *c != name).collect();
    let best = candidates
        .iter()
        .map(|c| (distance(name, c), *c))
        .min_by_key(|(d, _)| *d)
        .filter(|(d, _)| *d <= limit)
        .map(|(_, c)| c);
    best.or_else(|| {
        let mut prefixed = candidates.iter().filter(|c| c.starts_with(name));
        match (prefixed.next(), prefixed.next()) {
            (Some(c), None) if !name.is_empty() => Some(*c),
            _ => None,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        assert_eq!(distance("", "abc"), 3);
        assert_eq!(distance("render_btf", "render_btf"), 0);
        assert_eq!(distance("rendr_btf", "render_btf"), 1);
        assert_eq!(distance("colromap", "colormap"), 1);
        assert_eq!(distance("kitten", "sitting"), 3);
    }

    #[test]
    fn typos_find_their_command() {
        let commands = [
            "render_btf",
            "render_ftb",
            "colormap",
            "alphamap",
            "output",
            "puts",
        ];
        assert_eq!(nearest("rendr_btf", commands), Some("render_btf"));
        assert_eq!(nearest("colourmap", commands), Some("colormap"));
        assert_eq!(nearest("alphmap", commands), Some("alphamap"));
        assert_eq!(nearest("outptu", commands), Some("output"));
        assert_eq!(nearest("alpha", commands), Some("alphamap"));
        assert_eq!(nearest("render", commands), None);
        assert_eq!(nearest("zzzzzz", commands), None);
    }
}
