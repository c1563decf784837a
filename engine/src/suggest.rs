//! "Did you mean …?": the closest candidate by edit distance.

/// The candidate closest to `word` (case-insensitive), if it is close enough
/// to be a plausible typo: at most one edit per three characters, and at least one.
pub fn closest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let word = word.to_ascii_lowercase();
    if word.is_empty() || word.len() > 64 {
        return None;
    }
    let limit = (word.chars().count() / 3).max(1);
    let mut best: Option<(usize, &str)> = None;
    for candidate in candidates {
        if candidate.len().abs_diff(word.len()) > limit {
            continue;
        }
        let distance = edit_distance(&word, &candidate.to_ascii_lowercase());
        if distance <= limit && best.is_none_or(|(best_distance, _)| distance < best_distance) {
            best = Some((distance, candidate));
        }
    }
    best.map(|(_, candidate)| candidate)
}

/// Edit distance over characters (optimal string alignment: insertions, deletions,
/// substitutions, and a swap of two neighbours, `yeild` → `yield`, each count one).
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // Rows i - 2, i - 1 and i of the table.
    let mut before: Vec<usize> = vec![0; b.len() + 1];
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    let mut current = vec![0; b.len() + 1];
    for (i, a_char) in a.iter().enumerate() {
        current[0] = i + 1;
        for (j, b_char) in b.iter().enumerate() {
            let substitution = previous[j] + usize::from(a_char != b_char);
            let mut best = substitution.min(previous[j + 1] + 1).min(current[j] + 1);
            if i > 0 && j > 0 && *a_char == b[j - 1] && a[i - 1] == *b_char {
                best = best.min(before[j - 1] + 1);
            }
            current[j + 1] = best;
        }
        std::mem::swap(&mut before, &mut previous);
        std::mem::swap(&mut previous, &mut current);
    }
    previous[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_close_name_and_rejects_far_ones() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(closest("lodd", ["loadd", "loadi", "add"]), Some("loadd"));
        assert_eq!(closest("M_DEPHT", ["m_depth", "m_pitch"]), Some("m_depth"));
        assert_eq!(closest("xyzzy", ["loadd", "add"]), None);
        // A swap of two neighbouring letters is one edit, as a typist makes it.
        assert_eq!(edit_distance("yeild", "yield"), 1);
        assert_eq!(edit_distance("ab", "ba"), 1);
        assert_eq!(edit_distance("abc", "ca"), 3);
        assert_eq!(closest("yeild", ["yield", "halt"]), Some("yield"));
    }
}
