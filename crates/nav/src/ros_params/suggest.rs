//! "Did you mean": the known name nearest to a misspelt one.

/// Levenshtein distance between `a` and `b`, counting characters.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (diag + usize::from(ca != cb)).min(row[j] + 1).min(row[j + 1] + 1);
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// The candidate nearest to `name` (ignoring case), if it is near enough to be a slip: at most
/// a third of the name's length away (and at least 2 edits are always allowed).
pub(crate) fn nearest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let lower = name.to_ascii_lowercase();
    let limit = (name.chars().count() / 3).max(2);
    candidates
        .into_iter()
        .map(|c| (distance(&lower, &c.to_ascii_lowercase()), c))
        .filter(|&(d, c)| d <= limit && c != name)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_names_are_suggested_and_far_ones_are_not() {
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("", "abc"), 3);
        let names = ["max_vel_x", "min_vel_x", "vth_samples", "vx_samples", "DWAPlannerROS"];
        assert_eq!(nearest("max_vel_X", names), Some("max_vel_x"));
        assert_eq!(nearest("max_vl_x", names), Some("max_vel_x"));
        assert_eq!(nearest("vtheta_samples", names), Some("vth_samples"));
        assert_eq!(nearest("DWAPlannerRos", names), Some("DWAPlannerROS"));
        assert_eq!(nearest("publish_frequency", names), None);
    }
}
