//! Minimal glob matching for `[[override]]` patterns: `*` matches any run of characters
//! (including none), `?` exactly one character; everything else matches itself. Case-sensitive.

/// Whether `text` matches `pattern` as a whole. Linear-time backtracking (no exponential blow-up).
pub fn glob_match(pattern: &str, text: &str) -> bool {
    let p: Vec<char> = pattern.chars().collect();
    let t: Vec<char> = text.chars().collect();
    let (mut pi, mut ti) = (0usize, 0usize);
    // position of the last `*` in the pattern and the text position it currently absorbs up to
    let mut star: Option<(usize, usize)> = None;
    while ti < t.len() {
        if pi < p.len() && (p[pi] == '?' || (p[pi] != '*' && p[pi] == t[ti])) {
            pi += 1;
            ti += 1;
        } else if pi < p.len() && p[pi] == '*' {
            star = Some((pi, ti));
            pi += 1;
        } else if let Some((sp, st)) = star {
            // let the last star absorb one more character
            pi = sp + 1;
            ti = st + 1;
            star = Some((sp, st + 1));
        } else {
            return false;
        }
    }
    p[pi..].iter().all(|&c| c == '*')
}

#[cfg(test)]
mod tests {
    use super::glob_match;

    #[test]
    fn globs() {
        assert!(glob_match("*", ""));
        assert!(glob_match("*", "anything"));
        assert!(glob_match("a*c", "abbbc"));
        assert!(glob_match("a*c", "ac"));
        assert!(!glob_match("a*c", "acb"));
        assert!(glob_match("?at", "cat"));
        assert!(!glob_match("?at", "at"));
        assert!(glob_match("model.obj:*:glass*", "model.obj:Cube:glass_clear"));
        assert!(!glob_match("model.obj:*:glass*", "model.obj:Cube:metal"));
        assert!(glob_match("exact", "exact"));
        assert!(!glob_match("exact", "exactly"));
        assert!(glob_match("*a*a*a*a*a*b", &format!("{}b", "a".repeat(60))));
        assert!(!glob_match("*a*a*a*a*a*b", &"a".repeat(60)));
        assert!(glob_match("ä?", "äö"));
    }
}
